/* Hostile numbers (issue 42, "Checks that must hold"): every numeric
   keyword and argument of every style, fix and compute of the package -
   each position of a multi-value keyword on its own - is fed the values
   1e999, -1e999, 1e-400, nan, inf, 2^31, 2^32 + 1, twenty 9s (beyond a
   64-bit integer) and a word that is no number.  None may end the program
   in a signal or an exception other than LAMMPS's own error:
   - 1e999, -1e999, 1e-400, nan, inf and the word: a LAMMPS ERROR whose
     first line names the keyword (or the field) and the value as typed
     (an overflow may be shown as inf);
   - 2^31, 2^32 + 1 and twenty 9s: an ERROR on a count, seed, step interval
     or type (and on the positions that take no number at all), naming the
     keyword and the value; on a real-valued position either an ERROR (one
     raised by the command names the keyword and the value; at the run,
     where LAMMPS itself may refuse a cutoff beyond the box, any ERROR
     line), or the deck runs two steps with a finite energy and forces.
   Values that LAMMPS reads for the package (a temperature variable, the
   set command) need only name the keyword: LAMMPS may show them evaluated.
   Each position's deck first runs with its valid value.  One test per
   position (a crash takes down only that position under ctest), each
   value on a fresh LAMMPS instance: a small block of 4^3 points (4^2 in
   2D), SI units, horizon 3.01 spacings.  NOSPD_HOSTILE_VERBOSE=1 prints
   what each value did. */

#include "nospd_test_util.h"

#include "gmock/gmock.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include <unistd.h>

#ifndef NOSPD_UMAT_DIR
#define NOSPD_UMAT_DIR "umat"
#endif

using namespace nospdtest;

namespace {

// what a position may do with 2^31, 2^32 + 1 and twenty 9s
enum class Kind {
  REAL,      // a real value: an error, or a run with finite energy
  STRICT     // a count, seed, interval, or no number at all: an error
};

// where the value is checked: by the package when it reads its input, or
// by LAMMPS (a variable, the set command) and the package at the run
enum class Naming {
  VALUE,      // the error's first line shows the value as typed
  KEYWORD     // the value may come back as LAMMPS evaluated it: the keyword suffices
};

struct Case {
  std::string name;                 // test name (letters, digits, _)
  int dim;                          // 3, or 2 for 2D-only keywords
  std::vector<std::string> pre;     // setup after the geometry (must succeed)
  std::string line;                 // the command; {v}: the position, v a valid value
  std::vector<std::string> post;    // after an accepted command (pair_coeff, run)
  Kind kind;
  std::string expect;               // the error names one of these ('|' between)
  Naming naming = Naming::VALUE;
  std::string file;                 // a material file's body, {v} as above ("" = none)
};

// gtest shows a parameter by this (not as raw bytes)
void PrintTo(const Case &c, std::ostream *os) { *os << c.name << ": " << c.line; }

// the values, and an integer beyond a 64-bit long (std::stol and
// std::stoll throw on it: LAMMPS's utils::bounds does, for a type range)
const std::string LONG_OVERFLOW = "99999999999999999999";
const std::vector<std::string> VALUES = {"1e999", "-1e999",     "1e-400",     "nan",         "inf",
                                         "2147483648", "4294967297", LONG_OVERFLOW, "x1"};

bool is_big_integer(const std::string &v)
{
  return v == "2147483648" || v == "4294967297" || v == LONG_OVERFLOW;
}

const std::string D = "0.00301";    // horizon, 3.01 spacings
const std::string ELASTIC = "pair_coeff * * 200e9 0.3 " + D;
const std::string RUN = "run 2";
const std::string JC = "johnson_cook 792e6 510e6 0.26 0.014 1.0 1.03 293 1793";
const std::string JCF = "jc_failure 0.05 3.44 -2.12 0.002 0.61";
const std::string NEOHOOKE = "0.5*mu*(I1-3) - mu*log(J) + 0.5*lambda*log(J)^2";
const std::string LAMBDA = "115384615384.61539";    // 200e9, 0.3
const std::string MU = "76923076923.076920";
const std::string MATERIAL_FILE_NAME =
    "nospd_hostile_numbers." + std::to_string(getpid()) + ".nospd";
const std::string HEADER = "# DATE: 2026-11-29 UNITS: si CONTRIBUTOR: test\n";

std::string umat_lib(const char *name) { return std::string(NOSPD_UMAT_DIR) + "/" + name; }

// "a b c" with word k (0-based) marked as the position: "a {b} c"
std::string with_hole(const std::string &words, size_t k)
{
  std::istringstream in(words);
  std::string w, out;
  for (size_t m = 0; in >> w; m++) out += (out.empty() ? "" : " ") + (m == k ? "{" + w + "}" : w);
  return out;
}

std::vector<Case> make_cases()
{
  std::vector<Case> cs;
  const std::vector<std::string> elastic_run = {ELASTIC, RUN};

  // ---- pair_style peri/nospd and peri/nospd/hs settings
  for (const std::string style : {"peri/nospd", "peri/nospd/hs"}) {
    const std::string tag = style == "peri/nospd" ? "nospd_" : "hs_";
    cs.push_back({tag + "stabilization_silling_G", 3, {},
                  "pair_style " + style + " stabilization silling {0.5}", elastic_run, Kind::REAL,
                  "silling"});
    cs.push_back({tag + "stabilization_hourglass_C", 3, {},
                  "pair_style " + style + " stabilization hourglass {0.05}", elastic_run,
                  Kind::REAL, "hourglass"});
    for (const auto &kv : {std::make_pair("singular_tol", "1e-3"),
                           std::make_pair("damaged_tol", "0.2"),
                           std::make_pair("damaged_leverage", "0.5")}) {
      const std::string key = kv.first;
      cs.push_back({tag + key, 3, {}, "pair_style " + style + " " + key + " {" + kv.second + "}",
                    elastic_run, Kind::REAL, key});
    }
    cs.push_back({tag + "thickness_2d", 2, {}, "pair_style " + style + " thickness {1}",
                  elastic_run, Kind::REAL, "thickness"});
    cs.push_back({tag + "plane_stress_thickness_2d", 2, {},
                  "pair_style " + style + " plane stress thickness {1}", elastic_run,
                  Kind::REAL, "thickness"});
  }
  cs.push_back({"hs_ratio", 3, {}, "pair_style peri/nospd/hs ratio {1.5}", elastic_run, Kind::REAL,
                "ratio"});
  // form takes I, II (or 1, 2): any other word, numbers included, is refused
  cs.push_back({"hs_form", 3, {}, "pair_style peri/nospd/hs form {II}", elastic_run, Kind::STRICT,
                "form"});

  // ---- pair_coeff: the inline material, the cross pair, the type range
  const std::vector<std::string> ps = {"pair_style peri/nospd"};
  const std::vector<std::string> run = {RUN};
  cs.push_back({"coeff_E", 3, ps, "pair_coeff * * {200e9} 0.3 " + D, run, Kind::REAL,
                "Young's modulus|material potential file"});    // a word there is a file name
  cs.push_back({"coeff_nu", 3, ps, "pair_coeff * * 200e9 {0.3} " + D, run, Kind::REAL, "Poisson"});
  cs.push_back({"coeff_delta", 3, ps, "pair_coeff * * 200e9 0.3 {" + D + "}", run, Kind::REAL,
                "horizon"});
  cs.push_back({"coeff_cross_delta", 3, {"pair_style peri/nospd", ELASTIC},
                "pair_coeff 1 2 {" + D + "}", run, Kind::REAL, "horizon"});
  cs.push_back({"coeff_type_I", 3, ps, "pair_coeff {*} * 200e9 0.3 " + D, run, Kind::STRICT,
                "range|index|type"});
  cs.push_back({"coeff_type_J", 3, ps, "pair_coeff * {*} 200e9 0.3 " + D, run, Kind::STRICT,
                "range|index|type"});

  // ---- inelastic keywords of pair_coeff, each value position
  struct Kw {
    std::string name, prefix, words, expect;
  };
  const std::vector<Kw> inelastic = {
      {"yield", "", "yield 250e6", "yield"},
      {"hardening_linear", "yield 250e6", "hardening linear 2e9", "hardening"},
      {"hardening_power", "yield 250e6", "hardening power 1e9 0.3", "hardening"},
      {"kinematic", "yield 250e6", "kinematic 1e9", "kinematic"},
      {"johnson_cook", "", JC, "johnson_cook"},
      {"thermal", "", "thermal 1.2e-5 293", "thermal"},
      {"heat", "yield 250e6", "heat 460 0.9", "heat"},
      {"jc_failure", JC, JCF, "jc_failure"},
      {"drucker_prager", "", "drucker_prager 30 10 5e6 1e9", "drucker_prager"},
      {"conduction", "", "conduction 400 385", "conduction"},
  };
  for (const auto &kw : inelastic) {
    std::istringstream in(kw.words);
    std::vector<std::string> w;
    for (std::string s; in >> s;) w.push_back(s);
    for (size_t k = 1; k < w.size(); k++) {
      if (w[k] == "linear" || w[k] == "power") continue;
      const std::string extra = (kw.prefix.empty() ? "" : kw.prefix + " ") + with_hole(kw.words, k);
      cs.push_back({"coeff_" + kw.name + "_" + std::to_string(k), 3, ps,
                    ELASTIC + " " + extra, run, Kind::REAL, kw.expect});
    }
  }

  // ---- user materials: a formula's constants, a UMAT's PROPS and NSTATV
  const std::string formula = "energy \"" + NEOHOOKE + "\" param lambda " + LAMBDA;
  cs.push_back({"formula_param_value", 3, {"pair_style peri/nospd strain formula"},
                ELASTIC + " " + formula + " param mu {" + MU + "}", run, Kind::REAL, "param"});
  // a number inside the formula itself (Lepton reads it at the run)
  cs.push_back({"formula_number_in_W", 3, {"pair_style peri/nospd strain formula"},
                ELASTIC + " energy \"{1}*(" + NEOHOOKE + ")\" param lambda " + LAMBDA +
                    " param mu " + MU,
                run, Kind::REAL, "W = |energy|formula"});
  const std::string umat = "umat " + umat_lib("umat_elastic.so");
  cs.push_back({"umat_props_N", 3, {"pair_style peri/nospd strain umat"},
                ELASTIC + " " + umat + " props {2} 200e9 0.3", run, Kind::STRICT, "props"});
  cs.push_back({"umat_props_1", 3, {"pair_style peri/nospd strain umat"},
                ELASTIC + " " + umat + " props 2 {200e9} 0.3", run, Kind::REAL, "props"});
  cs.push_back({"umat_props_2", 3, {"pair_style peri/nospd strain umat"},
                ELASTIC + " " + umat + " props 2 200e9 {0.3}", run, Kind::REAL, "props"});
  for (const std::string style : {"peri/nospd", "peri/nospd/hs"})
    cs.push_back({std::string(style == "peri/nospd" ? "" : "hs_") + "umat_statev_N", 3,
                  {"pair_style " + style + " strain umat"},
                  ELASTIC + " " + umat + " props 2 200e9 0.3 statev {2}", run, Kind::STRICT,
                  "statev"});
  cs.push_back({"umat_finite_statev_N", 3, {"pair_style peri/nospd strain umat/finite"},
                ELASTIC + " " + umat + " props 2 200e9 0.3 statev {2}", run, Kind::STRICT,
                "statev"});

  // ---- a material file entry: its four numbers and keywords after them
  const std::string from_file = "pair_coeff * * " + MATERIAL_FILE_NAME + " foo " + D;
  const char *fields[] = {"E", "nu", "density", "G0"};
  const char *field_names[] = {"E|Young's modulus", "nu|Poisson", "density", "G0"};
  for (int k = 0; k < 4; k++)
    cs.push_back({std::string("file_") + fields[k], 3, ps, from_file, run, Kind::REAL,
                  field_names[k], Naming::VALUE,
                  with_hole("foo 200e9 0.3 7850 100", k + 1) + "\n"});
  cs.push_back({"file_yield", 3, ps, from_file, run, Kind::REAL, "yield", Naming::VALUE,
                "foo 200e9 0.3 7850 100 yield {250e6}\n"});
  cs.push_back({"file_hardening_linear", 3, ps, from_file, run, Kind::REAL, "hardening",
                Naming::VALUE, "foo 200e9 0.3 7850 100 yield 250e6 hardening linear {2e9}\n"});
  cs.push_back({"file_johnson_cook_B", 3, ps, from_file, run, Kind::REAL, "johnson_cook",
                Naming::VALUE, "foo 200e9 0.3 7850 100 " + with_hole(JC, 2) + "\n"});
  cs.push_back({"file_umat_statev_N", 3, {"pair_style peri/nospd strain umat"}, from_file, run,
                Kind::STRICT, "statev", Naming::VALUE,
                "foo 200e9 0.3 7850 100 " + umat + " props 2 200e9 0.3 statev {2}\n"});
  cs.push_back({"file_umat_props_N", 3, {"pair_style peri/nospd strain umat"}, from_file, run,
                Kind::STRICT, "props", Naming::VALUE,
                "foo 200e9 0.3 7850 100 " + umat + " props {2} 200e9 0.3\n"});

  // ---- temperatures of plastic materials: a variable, a per-atom property
  // (LAMMPS reads these numbers; the package meets them at the run)
  cs.push_back({"temperature_variable", 3,
                {"pair_style peri/nospd temperature v_T", ELASTIC + " " + JC},
                "variable T atom {300}", run, Kind::REAL, "temperature|ariable",
                Naming::KEYWORD});
  cs.push_back({"temperature_property", 3,
                {"fix tprop all property/atom d_T", "pair_style peri/nospd temperature d_T",
                 ELASTIC + " " + JC},
                "set group all d_T {300}", run, Kind::REAL, "temperature|loating point|d_T",
                Naming::KEYWORD});

  // ---- fix nospd/damage
  const std::vector<std::string> plastic = {"pair_style peri/nospd",
                                            ELASTIC + " yield 250e6"};
  const std::string fix = "fix dmg all nospd/damage ";
  struct Fx {
    std::string name, args, expect;
    Kind kind;
  };
  const std::vector<Fx> fixes = {
      {"stretch", "stretch {0.01}", "stretch", Kind::REAL},
      {"energy", "energy {1e20}", "energy", Kind::REAL},
      {"stretch_g0", "stretch g0 {100}", "g0|unknown keyword", Kind::REAL},
      {"energy_g0", "energy g0 {100}", "g0|unknown keyword", Kind::REAL},
      {"stress_principal", "stress principal {1e9}", "stress principal|critical stress",
       Kind::REAL},
      {"stress_vonmises", "stress vonmises {1e9}", "stress vonmises|critical stress", Kind::REAL},
      {"strain_principal", "strain principal {0.01}", "strain principal|critical strain",
       Kind::REAL},
      {"eqps", "eqps {0.5}", "eqps|plastic strain", Kind::REAL},
      {"scatter_width", "stretch 0.01 scatter {0.1} 4321", "scatter", Kind::REAL},
      {"scatter_seed", "stretch 0.01 scatter 0.1 {4321}", "scatter", Kind::STRICT},
      {"alpha", "stretch 0.01 alpha {0.25}", "alpha", Kind::REAL},
      {"contact_stiffness", "stretch 0.01 contact yes contact/stiffness {15}", "contact/stiffness",
       Kind::REAL},
      {"contact_radius", "stretch 0.01 contact yes contact/radius {0.0005}",
       "contact/radius|contact radius", Kind::REAL},
      {"every", "stretch 0.01 every {1}", "every", Kind::STRICT},
  };
  for (const auto &f : fixes)
    cs.push_back({"damage_" + f.name, 3, plastic, fix + f.args, run, f.kind, f.expect});
  // a pre-crack's corners, each coordinate (inside the shrink-wrapped box,
  // about 0 .. 3 mm)
  const std::string p3 = "0.0015 0.0001 0.0001 0.0015 0.0029 0.0001 0.0015 0.0001 0.0029";
  for (size_t k = 0; k < 9; k++)
    cs.push_back({"damage_precrack_3d_" + std::to_string(k + 1), 3, plastic,
                  fix + "none precrack " + with_hole(p3, k), run, Kind::REAL, "precrack"});
  const std::string p2 = "0.0015 0.0001 0.0015 0.0029";
  for (size_t k = 0; k < 4; k++)
    cs.push_back({"damage_precrack_2d_" + std::to_string(k + 1), 2, plastic,
                  fix + "none precrack " + with_hole(p2, k), run, Kind::REAL, "precrack"});

  // ---- fix nospd/heat (on a conducting material)
  const std::vector<std::string> conducting = {"pair_style peri/nospd",
                                               ELASTIC + " conduction 400 385"};
  const std::vector<Fx> heats = {
      {"initial", "initial {300}", "initial", Kind::REAL},
      {"fixed", "fixed all {350}", "fixed", Kind::REAL},
      {"convection_h", "convection all {100} 300", "convection", Kind::REAL},
      {"convection_T", "convection all 100 {300}", "convection", Kind::REAL},
      {"flux", "flux all {1e4}", "flux", Kind::REAL},
      {"source", "source {1e6}", "source", Kind::REAL},
      {"substeps", "substeps {2}", "substeps", Kind::STRICT},
  };
  for (const auto &f : heats)
    cs.push_back({"heat_" + f.name, 3, conducting, "fix heat all nospd/heat " + f.args, run,
                  f.kind, f.expect});
  // the same numbers through the variables the fix evaluates (LAMMPS reads
  // them; the fix meets them at the run)
  for (const std::string kw : {"initial", "source"}) {
    auto pre = conducting;
    pre.push_back("fix heat all nospd/heat " + kw + " v_H");
    cs.push_back({"heat_" + kw + "_variable", 3, pre, "variable H atom {300}", run, Kind::REAL,
                  "nospd/heat|ariable", Naming::KEYWORD});
  }

  // ---- the computes take no number: a number where a quantity goes is refused
  cs.push_back({"compute_atom_quantity", 3, {"pair_style peri/nospd", ELASTIC},
                "compute c all nospd/atom {stress}", run, Kind::STRICT, "unknown quantity"});
  cs.push_back({"compute_bond_local_quantity", 3, {"pair_style peri/nospd", ELASTIC},
                "compute c all nospd/bond/local {id}", run, Kind::STRICT, "unknown quantity"});
  return cs;
}

// a block of 4^3 points (4^2 in 2D), 1 mm apart, two atom types (type 2
// empty: the cross-pair horizon), displaced a little so that it is strained
void geometry(LAMMPS *lmp, int dim)
{
  cmd(lmp, "units si");
  cmd(lmp, "dimension " + std::to_string(dim));
  cmd(lmp, dim == 2 ? "boundary s s p" : "boundary s s s");
  cmd(lmp, "atom_style peri");
  cmd(lmp, "atom_modify map array");
  cmd(lmp, dim == 2 ? "lattice sq 0.001" : "lattice sc 0.001");
  cmd(lmp, std::string("region box block -0.25 3.75 -0.25 3.75 ") +
               (dim == 2 ? "-0.5 0.5" : "-0.25 3.75"));
  cmd(lmp, "create_box 2 box");
  cmd(lmp, "create_atoms 1 box");
  cmd(lmp, "set group all density 7850");
  cmd(lmp, std::string("set group all volume ") + (dim == 2 ? "1e-6" : "1e-9"));
  cmd(lmp, "displace_atoms all random 2e-6 2e-6 " + std::string(dim == 2 ? "0" : "2e-6") +
               " 4711 units box");
  cmd(lmp, "timestep 1e-8");
  cmd(lmp, "thermo_modify norm no");
}

std::string replace_all(std::string s, const std::string &from, const std::string &to)
{
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// the template with its position {v} given `value` (the valid v: "")
std::string at_position(const std::string &text, const std::string &value)
{
  const size_t open = text.find('{'), close = text.find('}', open);
  if (open == std::string::npos || close == std::string::npos) return text;
  const std::string v = value.empty() ? text.substr(open + 1, close - open - 1) : value;
  return text.substr(0, open) + v + text.substr(close + 1);
}

std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string first_line(const std::string &msg) { return msg.substr(0, msg.find('\n')); }

// the ways an error may show a hostile value
std::vector<std::string> renderings(const std::string &v)
{
  if (v == "1e999") return {"1e999", "1e+999", "inf"};
  if (v == "-1e999") return {"-1e999", "-1e+999", "-inf"};
  if (v == "2147483648") return {"2147483648", "2.147483648e+09"};
  if (v == "4294967297") return {"4294967297", "4.294967297e+09"};
  if (v == LONG_OVERFLOW) return {LONG_OVERFLOW, "1e+20"};
  return {v};
}

bool contains_any(const std::string &text, const std::string &alternatives)
{
  std::istringstream in(alternatives);
  for (std::string alt; std::getline(in, alt, '|');)
    if (text.find(alt) != std::string::npos) return true;
  return false;
}

// what one value did: the error (and the command that raised it) or a run
struct Outcome {
  std::string stage;        // the command that raised the error or exception
  std::string error;        // LAMMPS's error text ("" if none)
  std::string exception;    // another exception's type and text ("" if none)
  double pe = 0.0;
  bool finite_forces = true;
};

Outcome run_value(const Case &c, const std::string &value)
{
  Outcome o;
  if (!c.file.empty()) {
    std::ofstream out(MATERIAL_FILE_NAME);
    out << HEADER << at_position(c.file, value);
  }
  LAMMPS *lmp = open_lammps();
  auto step = [&](const std::string &line) {
    if (!o.error.empty() || !o.exception.empty()) return false;
    o.stage = line;
    try {
      o.error = error_of(lmp, line);
    } catch (std::exception &e) {
      o.exception = std::string(typeid(e).name()) + ": " + e.what();
    } catch (...) {
      o.exception = "an exception that is not a std::exception";
    }
    return o.error.empty() && o.exception.empty();
  };
  bool ok = true;
  try {
    geometry(lmp, c.dim);
  } catch (std::exception &e) {
    ok = false;
    o.stage = "setup: geometry";
    o.exception = e.what();
  }
  for (const auto &line : c.pre)
    if (ok && !step(line)) {
      ok = false;
      o.stage = "setup: " + line;
    }
  if (ok && step(at_position(c.line, value)))
    for (const auto &line : c.post)
      if (!step(line)) break;
  if (ok && o.error.empty() && o.exception.empty()) {
    o.stage = "";
    try {
      o.pe = potential_energy(lmp);
    } catch (std::exception &e) {
      o.exception = std::string("potential_energy: ") + e.what();
    }
    for (int i = 0; i < lmp->atom->nlocal; i++)
      for (int k = 0; k < 3; k++)
        if (!std::isfinite(lmp->atom->f[i][k])) o.finite_forces = false;
  }
  try {
    delete lmp;
  } catch (std::exception &e) {
    if (o.exception.empty()) o.exception = std::string("at delete: ") + e.what();
  }
  if (!c.file.empty()) std::remove(MATERIAL_FILE_NAME.c_str());
  return o;
}

class HostileNumbers : public ::testing::TestWithParam<Case> {};

TEST_P(HostileNumbers, ErrorNotCrash)
{
  const Case &c = GetParam();
  {
    // the deck with the position's valid value runs: what the values below
    // provoke is theirs, not the deck's
    const Outcome o = run_value(c, "");
    ASSERT_EQ(o.error + o.exception, "")
        << "case " << c.name << " fails with its valid value, at '" << o.stage
        << "': it does not test its position";
    ASSERT_TRUE(std::isfinite(o.pe)) << "case " << c.name << " with its valid value";
  }
  for (const auto &value : VALUES) {
    const std::string line = at_position(c.line, value);
    SCOPED_TRACE("case " + c.name + ", value " + value + ": " +
                 (c.file.empty() ? line : line + "  [file: " + at_position(c.file, value) +
                                              "]"));
    const Outcome o = run_value(c, value);
    // NOSPD_HOSTILE_VERBOSE=1: what each value did, for reading the table
    if (std::getenv("NOSPD_HOSTILE_VERBOSE"))
      printf("%s | %s | %s\n", c.name.c_str(), value.c_str(),
             !o.exception.empty() ? ("EXCEPTION at " + o.stage + ": " + o.exception).c_str()
             : !o.error.empty()   ? ("error at " + o.stage + ": " + first_line(o.error)).c_str()
                                  : ("ran, pe = " + num(o.pe)).c_str());
    ASSERT_EQ(o.stage.rfind("setup", 0), std::string::npos)
        << "the deck before the command failed: " << o.stage << ": " << o.error << o.exception;
    EXPECT_EQ(o.exception, "") << "an exception that is not a LAMMPS error, at '" << o.stage
                               << "'";
    if (!o.exception.empty()) continue;
    const bool may_run = c.kind == Kind::REAL && is_big_integer(value);
    if (o.error.empty()) {
      if (may_run) {
        EXPECT_TRUE(std::isfinite(o.pe)) << "accepted, and ran to pe = " << o.pe;
        EXPECT_TRUE(o.finite_forces) << "accepted, and ran to non-finite forces";
      } else {
        ADD_FAILURE() << "accepted silently: the deck ran, pe = " << o.pe;
      }
      continue;
    }
    const std::string head = first_line(o.error);
    EXPECT_EQ(head.rfind("ERROR", 0), 0u) << "not a LAMMPS ERROR line: " << head;
    // a large real the command accepted may still be refused by the run,
    // by LAMMPS itself (a cutoff beyond the box): any ERROR line will do
    if (may_run && o.stage != line) continue;
    EXPECT_TRUE(contains_any(head, c.expect))
        << "the error (at '" << o.stage << "') does not name '" << c.expect << "': " << head;
    if (c.naming == Naming::VALUE) {
      bool named = false;
      for (const auto &r : renderings(value))
        if (lower(head).find(lower(r)) != std::string::npos) named = true;
      EXPECT_TRUE(named) << "the error (at '" << o.stage << "') does not name the value "
                         << value << ": " << head;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Positions, HostileNumbers, ::testing::ValuesIn(make_cases()),
                         [](const ::testing::TestParamInfo<Case> &info) {
                           return info.param.name;
                         });

// every position listed once (a name twice would hide one from gtest)
TEST(HostileNumbersTable, NamesUnique)
{
  auto cs = make_cases();
  std::vector<std::string> names;
  for (const auto &c : cs) names.push_back(c.name);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
  EXPECT_GE(cs.size(), 80u);
}

}    // namespace

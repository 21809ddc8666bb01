/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Materials the user brings: strain-energy formulas and UMAT libraries.
------------------------------------------------------------------------- */

#include "nospd_user_material.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "platform.h"
#include "utils.h"

#include "nospd_formula.h"
#include "nospd_input.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <dlfcn.h>
#include <stdexcept>

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;

// NPROPS and NSTATV: far beyond any published UMAT; per point (and per bond
// of the bond-associated style), so a slip of digits cannot exhaust memory
static constexpr int USER_COUNT_MAX = 10000;

/* ----------------------------------------------------------------------
   Abaqus's error utilities, for UMATs that call them.  LAMMPS loads this
   plugin with RTLD_GLOBAL, so a UMAT library opened later resolves these.
   They record the request; the caller stops the run after the UMAT
   returns (no unwinding through Fortran frames).
     CALL STDB_ABQERR(LOP, STRING, INTV, REALV, CHARV)   LOP = -2, -3: stop
     CALL XIT
------------------------------------------------------------------------- */

extern "C" {
void stdb_abqerr_(int *lop, const char *string, int *intv, double *realv, const char *charv,
                  size_t len_string, size_t len_charv)
{
  // expand %I, %R, %S in turn, as Abaqus does
  std::string in(string, len_string), out;
  int ni = 0, nr = 0, ns = 0;
  for (size_t k = 0; k < in.size(); k++) {
    if (in[k] == '%' && k + 1 < in.size()) {
      const char c = in[k + 1];
      if (c == 'I' || c == 'i') {
        out += std::to_string(intv[ni++]);
        k++;
        continue;
      } else if (c == 'R' || c == 'r') {
        out += fmt::format("{:.6g}", realv[nr++]);
        k++;
        continue;
      } else if (c == 'S' || c == 's') {
        std::string s(charv + 8 * ns++, 8);
        out += utils::trim(s);
        k++;
        continue;
      }
    }
    out += in[k];
  }
  (void) len_charv;
  out = utils::trim(out);
  // -2 and -3 are errors (Abaqus stops after the increment or at once);
  // 1 (information) and -1 (warning) are not shown
  if (*lop == -3 || *lop == -2) {
    NOSPD::umat_report().abort = true;
    NOSPD::umat_report().message = out;
  }
}

void xit_()
{
  NOSPD::umat_report().abort = true;
  if (NOSPD::umat_report().message.empty()) NOSPD::umat_report().message = "the UMAT called XIT";
}
}

/* ---------------------------------------------------------------------- */

NospdUserMaterials::NospdUserMaterials(LAMMPS *lmp) : Pointers(lmp) {}

NospdUserMaterials::~NospdUserMaterials()
{
  formulas.clear();
  for (auto &h : handles)
    if (h.second) dlclose(h.second);
}

void NospdUserMaterials::resize(int ntypes)
{
  specs.assign(ntypes + 1, Spec());
  formulas.clear();
  formulas.resize(ntypes + 1);
  umats.assign(ntypes + 1, NOSPD::UmatMaterial());
  umat_open.assign(ntypes + 1, 0);
}

/* ----------------------------------------------------------------------
   energy "W"                  strain formula: W of I1 I2 J I1b I2b l1 l2 l3
   param name value            a named constant of W (repeatable)
   umat path                   strain umat: the UMAT shared library
   symbol name                 its entry point (default umat_, gfortran's UMAT)
   props N p1 ... pN           PROPS
   statev N                    NSTATV
------------------------------------------------------------------------- */

bool NospdUserMaterials::parse(const std::vector<std::string> &words, size_t &k, Spec &s,
                               const std::string &where) const
{
  const std::string key = words[k];
  auto need = [&](size_t n) {
    if (k + n >= words.size()) error->all(FLERR, "{}: keyword {} needs {} value(s)", where, key, n);
  };
  auto number = [&](const std::string &w) {
    return NOSPD_INPUT::real(error, where, "keyword " + key, w);
  };
  auto count = [&](const std::string &w) {
    return NOSPD_INPUT::integer(error, where, "keyword " + key, w, 0, USER_COUNT_MAX);
  };
  if (key == "energy") {
    need(1);
    s.energy = words[k + 1];
    if (utils::trim(s.energy).empty()) error->all(FLERR, "{}: energy needs a formula, got ''", where);
    k += 2;
  } else if (key == "param") {
    need(2);
    const std::string name = words[k + 1];
    if (!utils::is_id(name) || std::isdigit(name[0]))
      error->all(FLERR, "{}: param name '{}' is not a valid name", where, name);
    if (NOSPD::FormulaLaw::is_variable(name))
      error->all(FLERR, "{}: param {} names a variable of W ({}), not a constant", where, name,
                 NOSPD::FormulaLaw::variable_list());
    const double v = number(words[k + 2]);
    // a material file entry's params, then the pair_coeff line's, which
    // replace them; one list naming a constant twice is a mistake
    if (std::find(s.listed.begin(), s.listed.end(), name) != s.listed.end())
      error->all(FLERR, "{}: param {} given twice (the second: {})", where, name, words[k + 2]);
    s.listed.push_back(name);
    bool replaced = false;
    for (auto &p : s.params)
      if (p.first == name) {
        p.second = v;
        replaced = true;
      }
    if (!replaced) s.params.emplace_back(name, v);
    k += 3;
  } else if (key == "umat") {
    need(1);
    s.library = words[k + 1];
    k += 2;
  } else if (key == "symbol") {
    need(1);
    s.symbol = words[k + 1];
    k += 2;
  } else if (key == "props") {
    need(1);
    const int n = count(words[k + 1]);
    if (k + 1 + n >= words.size())
      error->all(FLERR, "{}: props {} needs {} values, got {}", where, n, n,
                 words.size() - k - 2);
    s.props.clear();
    for (int m = 0; m < n; m++) s.props.push_back(number(words[k + 2 + m]));
    k += 2 + n;
  } else if (key == "statev") {
    need(1);
    s.nstatev = count(words[k + 1]);
    k += 2;
  } else
    return false;
  return true;
}

/* ---------------------------------------------------------------------- */

void NospdUserMaterials::setup(Law law, Plane plane, const int *active,
                               std::vector<NOSPD::Lame> &lame, const double *youngs,
                               const double *poisson, const std::vector<std::string> &names)
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  const bool umat_law = (law == Law::UMAT_SMALL || law == Law::UMAT_FINITE);
  for (int i = 1; i < (int) specs.size(); i++) {
    umat_open[i] = 0;
    if (!active[i]) continue;
    const Spec &s = specs[i];
    if (law == Law::USER) {
      if (!s.library.empty())
        error->all(FLERR, "{}: type {} has umat {} but the strain law is formula (use strain "
                   "umat or umat/finite)", cmd, i, s.library);
      if (s.energy.empty())
        error->all(FLERR, "{}: strain formula needs an energy for type {}: pair_coeff {} {} E nu "
                   "delta energy \"W(I1,I2,J,...)\"", cmd, i, i, i);
      setup_formula(i, plane, lame[i], youngs[i], poisson[i]);
    } else if (umat_law) {
      if (!s.energy.empty())
        error->all(FLERR, "{}: type {} has an energy formula but the strain law is umat", cmd, i);
      if (s.library.empty())
        error->all(FLERR, "{}: strain umat needs a library for type {}: pair_coeff {} {} E nu "
                   "delta umat path/libumat.so props N ... statev N", cmd, i, i, i);
      check_restored(i);
      setup_umat(i, law, plane, names[i]);
    } else if (s.any()) {
      error->all(FLERR, "{}: type {} has {} but the strain law is neither formula nor umat",
                 cmd, i, s.energy.empty() ? "a umat library" : "an energy formula");
    }
  }
  restored.clear();    // later runs carry this run's state
}

/* ---------------------------------------------------------------------- */

void NospdUserMaterials::setup_formula(int itype, Plane plane, NOSPD::Lame &m, double E, double nu)
{
  const std::string where = fmt::format("pair_coeff ({}) type {}", force->pair_style, itype);
  const Spec &s = specs[itype];
  try {
    formulas[itype] = std::make_unique<NOSPD::FormulaLaw>(s.energy, s.params);
  } catch (std::invalid_argument &e) {
    error->all(FLERR, "{}: {}", where, e.what());
  }
  const NOSPD::FormulaLaw &f = *formulas[itype];
  m.user = &f;

  // the reference state must be stress-free
  Mat3 P;
  double W;
  const Mat3 I = Mat3::Identity();
  const double scale = m.lambda + 2.0 * m.mu;
  if (!f.first_piola(I, P, W))
    error->all(FLERR, "{}: W = '{}' is not finite at F = I (W = {})", where, s.energy, W);
  if (P.cwiseAbs().maxCoeff() > 1e-8 * scale)
    error->all(FLERR, "{}: W = '{}' has stress at F = I (P11 = {:.6g}, P12 = {:.6g}): the "
               "reference state must be stress-free (Neo-Hooke needs its -mu ln J term)",
               where, s.energy, P(0, 0), P(0, 1));

  // its small-strain moduli from the analytic P by central differences,
  // held against E and nu, which set the stabilization and time step
  const double h = 1e-6;
  Mat3 Pp, Pm;
  Mat3 Fp = I, Fm = I;
  Fp(0, 0) += h;
  Fm(0, 0) -= h;
  f.first_piola(Fp, Pp, W);
  f.first_piola(Fm, Pm, W);
  const double c11 = (Pp(0, 0) - Pm(0, 0)) / (2 * h), c12 = (Pp(1, 1) - Pm(1, 1)) / (2 * h);
  const double mu = 0.5 * (c11 - c12), lambda = c12;
  const double E_w = mu * (3 * lambda + 2 * mu) / (lambda + mu);
  const double nu_w = lambda / (2 * (lambda + mu));
  // an unstable or undefined linearization is not a mismatch to warn about:
  // the body would collapse or fill with NaN at the first step
  if (!(std::isfinite(lambda) && std::isfinite(mu) && mu > 0.0 && 3 * lambda + 2 * mu > 0.0))
    error->all(FLERR, "{}: W = '{}' linearizes to shear modulus mu = {:.6g} and bulk modulus "
               "K = {:.6g} at F = I; a solid needs both finite and > 0", where, s.energy, mu,
               lambda + 2.0 * mu / 3.0);
  if (!(std::abs(E_w - E) <= 1e-3 * E) || !(std::abs(nu_w - nu) <= 1e-3)) {
    // the constants it was evaluated with: a param may replace the formula's own
    std::string with;
    for (const auto &p : s.params)
      with += fmt::format("{}{} = {:.6g}", with.empty() ? " with " : ", ", p.first, p.second);
    error->warning(FLERR, "{}: W = '{}'{} linearizes to E = {:.6g}, nu = {:.6g}, but pair_coeff "
                   "gives E = {:.6g}, nu = {:.6g}; E and nu set the stabilization and the "
                   "time step estimate", where, s.energy, with, E_w, nu_w, E, nu);
  }
  if (plane == Plane::STRESS && !(nu < 0.5))
    error->all(FLERR, "{}: plane stress needs nu < 0.5 for the F33 solve, got {}", where, nu);
}

/* ---------------------------------------------------------------------- */

void *NospdUserMaterials::open_library(int itype, std::string &path)
{
  path = utils::trim(specs[itype].library);
  auto it = handles.find(path);
  if (it != handles.end()) return it->second;
  // a name without a slash: dlopen's search (LD_LIBRARY_PATH, ...) after
  // the working directory, as a user expects of a file name in an input
  std::string tryfirst = path;
  if (path.find('/') == std::string::npos && platform::file_is_readable(path)) tryfirst = "./" + path;
  void *h = dlopen(tryfirst.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    const char *why = dlerror();
    error->all(FLERR, "pair_coeff ({}) type {}: cannot open UMAT library {}: {}", force->pair_style,
               itype, path, why ? why : "unknown reason");
  }
  handles[path] = h;
  return h;
}

void NospdUserMaterials::setup_umat(int itype, Law law, Plane plane, const std::string &name)
{
  const std::string where = fmt::format("pair_coeff ({}) type {}", force->pair_style, itype);
  const Spec &s = specs[itype];
  if (plane == Plane::STRESS)
    error->all(FLERR, "{}: strain umat supports 3D and plane strain, not plane stress (a UMAT "
               "for plane stress receives NTENS = 3 in Abaqus; not offered)", where);
  std::string path;
  void *h = open_library(itype, path);
  const std::string sym = symbol(itype);
  dlerror();
  void *fn = dlsym(h, sym.c_str());
  if (!fn)
    error->all(FLERR, "{}: UMAT library {} has no symbol '{}' (gfortran names SUBROUTINE UMAT "
               "umat_; a C UMAT may use another name: give it with 'symbol name')", where, path,
               sym);
  NOSPD::UmatMaterial &m = umats[itype];
  m.fn = reinterpret_cast<NOSPD::UmatFunction>(fn);
  m.props = s.props;
  m.nstatev = s.nstatev;
  m.ntens = (plane == Plane::STRAIN) ? 4 : 6;
  m.finite = (law == Law::UMAT_FINITE);
  m.set_name(name.empty() || name == "inline" ? fmt::format("TYPE{}", itype) : name);
  umat_open[itype] = 1;
}

int NospdUserMaterials::history_size() const
{
  int n = 0;
  for (size_t i = 1; i < specs.size(); i++)
    if (umat_open[i]) n = std::max(n, NOSPD::UmatHist::size(umats[i].nstatev));
  return n;
}

/* ----------------------------------------------------------------------
   restart: each type's definitions field by field (strings as length and
   bytes), so a read_restart run gets the same formulas and libraries back
------------------------------------------------------------------------- */

namespace {
void write_string(FILE *fp, const std::string &s)
{
  const int n = static_cast<int>(s.size());
  fwrite(&n, sizeof(int), 1, fp);
  fwrite(s.data(), 1, n, fp);
}

void write_doubles(FILE *fp, const std::vector<double> &v)
{
  const int n = static_cast<int>(v.size());
  fwrite(&n, sizeof(int), 1, fp);
  fwrite(v.data(), sizeof(double), n, fp);
}
}    // namespace

void NospdUserMaterials::write_restart(FILE *fp) const
{
  for (size_t i = 1; i < specs.size(); i++) {
    const Spec &s = specs[i];
    write_string(fp, s.energy);
    const int np = static_cast<int>(s.params.size());
    fwrite(&np, sizeof(int), 1, fp);
    for (const auto &p : s.params) {
      write_string(fp, p.first);
      fwrite(&p.second, sizeof(double), 1, fp);
    }
    write_string(fp, s.library);
    write_string(fp, s.symbol);
    write_doubles(fp, s.props);
    fwrite(&s.nstatev, sizeof(int), 1, fp);
  }
}

void NospdUserMaterials::read_restart(FILE *fp)
{
  const bool me0 = (comm->me == 0);
  auto read_int = [&]() {
    int n = 0;
    if (me0) utils::sfread(FLERR, &n, sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&n, 1, MPI_INT, 0, world);
    return n;
  };
  auto read_string = [&]() {
    const int n = read_int();
    std::string s(n, ' ');
    if (me0 && n > 0) utils::sfread(FLERR, &s[0], 1, n, fp, nullptr, error);
    if (n > 0) MPI_Bcast(&s[0], n, MPI_CHAR, 0, world);
    return s;
  };
  auto read_doubles = [&](int n) {
    std::vector<double> v(n);
    if (me0 && n > 0) utils::sfread(FLERR, v.data(), sizeof(double), n, fp, nullptr, error);
    if (n > 0) MPI_Bcast(v.data(), n, MPI_DOUBLE, 0, world);
    return v;
  };
  for (size_t i = 1; i < specs.size(); i++) {
    Spec s;
    s.energy = read_string();
    const int np = read_int();
    for (int k = 0; k < np; k++) {
      const std::string name = read_string();
      s.params.emplace_back(name, read_doubles(1)[0]);
    }
    s.library = read_string();
    s.symbol = read_string();
    s.props = read_doubles(read_int());
    s.nstatev = read_int();
    specs[i] = s;
  }
  restored = specs;
}

/* ----------------------------------------------------------------------
   the first run after a restart: a UMAT type whose NSTATV differs from the
   file's would read its state variables at the wrong places; another
   library with the same count may be a rebuilt one (warned)
------------------------------------------------------------------------- */

void NospdUserMaterials::check_restored(int itype)
{
  if (itype >= (int) restored.size() || restored[itype].library.empty()) return;
  const Spec &was = restored[itype], &now = specs[itype];
  if (was.nstatev != now.nstatev)
    error->all(FLERR, "pair_coeff ({}) type {}: the restart file's state comes from UMAT {} with "
               "statev {}, but this run declares statev {} (UMAT {}): its state variables would "
               "be read at the wrong places; keep the UMAT and its statev", force->pair_style,
               itype, was.library, was.nstatev, now.nstatev, now.library);
  if ((was.library != now.library || symbol(itype) != (was.symbol.empty() ? "umat_" : was.symbol)) &&
      comm->me == 0)
    error->warning(FLERR, "pair_coeff ({}) type {}: the restart file's state variables were "
                   "written by UMAT {}, this run reads them with {}", force->pair_style, itype,
                   was.library, now.library);
}

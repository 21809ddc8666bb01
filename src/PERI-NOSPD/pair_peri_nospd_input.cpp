/* ----------------------------------------------------------------------
   PERI-NOSPD: the input of pair_coeff -- the inelastic keywords of a
   material (J2, Johnson-Cook, thermal, heating, failure, Drucker-Prager,
   user materials) and the material files of potentials/ -- read into the
   style's per-type material table.  Every number through nospd_input.h.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_base.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "fix_nospd_bonds.h"
#include "modify.h"
#include "error.h"
#include "force.h"
#include "tokenizer.h"
#include "update.h"

#include "nospd_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;

// a whole word read by strtod: a number, inf and nan included
static bool parses_as_number(const char *word)
{
  char *end = nullptr;
  strtod(word, &end);
  return end != word && *end == '\0';
}

/* ----------------------------------------------------------------------
   inelastic keywords of a material (doc/pair_peri_nospd.rst):
     yield sigma_y0                      J2 plasticity, initial yield stress
     hardening linear H | power K n      isotropic hardening (default linear 0)
     kinematic Hk                        linear kinematic hardening (strain small)
     johnson_cook A B n C rate0 m T_ref T_melt
     thermal alpha T_ref                 isotropic thermal expansion
     heat cp chi                         adiabatic heating (Taylor-Quinney chi)
     conduction k c                      conductivity, capacity (fix nospd/heat)
     jc_failure D1 D2 D3 D4 D5           Johnson-Cook failure strain (damage)
     drucker_prager phi psi c H          Drucker-Prager plasticity (instead of yield)
   and those of user materials (nospd_user_material.cpp):
     energy "W" [param name value ...]   strain formula
     umat lib [symbol s] [props N ...] [statev N]   strain umat
------------------------------------------------------------------------- */

void PairPeriNospdBase::parse_inelastic(const std::vector<std::string> &words, NOSPD::FlowLaw &fl,
                                    NOSPD::ThermalLaw &th, NOSPD::DruckerPrager &dp,
                                    NospdUserMaterials::Spec &us,
                                    bool &thermal_ref_given, const std::string &where) const
{
  flow_law_exclusions(words, fl, dp, where);
  us.listed.clear();    // this list's params may replace the file's, not each other
  std::vector<std::string> seen;    // keywords of this list (param has its own rule)
  size_t k = 0;
  while (k < words.size()) {
    const std::string key = words[k];
    if (key != "param") {
      if (std::find(seen.begin(), seen.end(), key) != seen.end())
        error->all(FLERR, "{}: keyword {} given twice in one list (a later pair_coeff line may "
                   "override a material file's, but one list names each keyword once)", where, key);
      seen.push_back(key);
    }
    auto values = [&](size_t n) { return keyword_values(words, k, n, key, where); };
    if (key == "yield") {
      const auto v = values(1);
      if (!(v[0] > 0.0)) error->all(FLERR, "{}: yield stress must be > 0, got {}", where, v[0]);
      fl.active = true;
      fl.sigma_y0 = v[0];
    } else if (key == "hardening") {
      k = hardening_of(words, k, fl, where);
    } else if (key == "kinematic") {
      const auto v = values(1);
      if (!(v[0] >= 0.0)) error->all(FLERR, "{}: kinematic hardening modulus must be >= 0, got {}", where, v[0]);
      fl.Hkin = v[0];
    } else if (key == "johnson_cook") {
      fl = johnson_cook_of(values(8), fl.Hkin, where);
      if (!thermal_ref_given) th.T_ref = fl.T_ref;
    } else if (key == "thermal") {
      const auto v = values(2);
      if (!(v[1] > 0.0)) error->all(FLERR, "{}: thermal T_ref must be > 0 (absolute), got {}", where, v[1]);
      th.alpha = v[0];
      th.T_ref = v[1];
      thermal_ref_given = true;
    } else if (key == "heat") {
      const auto v = values(2);
      if (!(v[0] > 0.0)) error->all(FLERR, "{}: heat cp must be > 0, got {}", where, v[0]);
      if (!(v[1] >= 0.0 && v[1] <= 1.0))
        error->all(FLERR, "{}: heat Taylor-Quinney fraction must be in [0,1], got {}", where, v[1]);
      th.cp = v[0];
      th.chi = v[1];
    } else if (key == "conduction") {
      const auto v = values(2);
      if (!(v[0] > 0.0) || !std::isfinite(v[0]))
        error->all(FLERR, "{}: conduction k (conductivity) must be > 0 and finite, got {}", where, v[0]);
      if (!(v[1] > 0.0) || !std::isfinite(v[1]))
        error->all(FLERR, "{}: conduction c (specific heat) must be > 0 and finite, got {}", where, v[1]);
      th.k = v[0];
      th.c = v[1];
    } else if (key == "drucker_prager") {
      dp = drucker_prager_of(values(4), where);
    } else if (key == "jc_failure") {
      const auto v = values(5);
      check_jc_failure(v, where);
      th.failure = true;
      for (int m = 0; m < 5; m++) th.D[m] = v[m];
    } else if (!user_materials->parse(words, k, us, where))
      error->all(FLERR, "{}: unknown keyword '{}' (yield, hardening, kinematic, johnson_cook, "
                 "thermal, heat, conduction, jc_failure, drucker_prager, energy, param, umat, symbol, props, "
                 "statev)",
                 where, key);
  }
  check_flow_law(fl, th, dp, where);
}

/* ----------------------------------------------------------------------
   the n numbers after words[k] (keyword key); k moves past them
------------------------------------------------------------------------- */

std::vector<double> PairPeriNospdBase::keyword_values(const std::vector<std::string> &words,
                                                  size_t &k, size_t n, const std::string &key,
                                                  const std::string &where) const
{
  if (k + n >= words.size()) error->all(FLERR, "{}: keyword {} needs {} value(s)", where, key, n);
  std::vector<double> v(n);
  for (size_t m = 0; m < n; m++)
    v[m] = NOSPD_INPUT::real(error, where, "keyword " + key, words[k + 1 + m]);
  k += n + 1;
  return v;
}

/* ----------------------------------------------------------------------
   the flow law: J2 (yield, hardening) and Johnson-Cook exclude each other
   within one list, in any order; a list that names either replaces the
   other law of an earlier list (the line's keywords override the file's);
   drucker_prager and the J2 laws replace each other the same way
------------------------------------------------------------------------- */

void PairPeriNospdBase::flow_law_exclusions(const std::vector<std::string> &words,
                                        NOSPD::FlowLaw &fl, NOSPD::DruckerPrager &dp,
                                        const std::string &where) const
{
  using NOSPD::Hardening;
  auto has = [&](const char *kw) { return std::find(words.begin(), words.end(), kw) != words.end(); };
  const bool has_jc = has("johnson_cook"), has_yield = has("yield");
  if (has_jc && (has_yield || has("hardening")))
    error->all(FLERR, "{}: johnson_cook excludes yield and hardening (A is the yield stress, "
               "B and n the hardening)", where);
  if (has("drucker_prager") && (has_jc || has_yield))
    error->all(FLERR, "{}: drucker_prager excludes yield and johnson_cook (one flow law)", where);
  if (has("drucker_prager")) fl = NOSPD::FlowLaw();
  if (has_jc || has_yield) dp = NOSPD::DruckerPrager();
  if (has_jc || (has_yield && fl.kind == Hardening::JOHNSON_COOK)) {
    const double hkin = fl.Hkin;
    fl = NOSPD::FlowLaw();
    fl.Hkin = hkin;
  }
  if (has("hardening") && !has_yield && fl.kind == Hardening::JOHNSON_COOK)
    error->all(FLERR, "{}: hardening applies to a yield stress (keyword yield); johnson_cook "
               "has its own (B, n)", where);
}

/* ----------------------------------------------------------------------
   hardening linear H | power K n at words[k]: the index after its values
------------------------------------------------------------------------- */

size_t PairPeriNospdBase::hardening_of(const std::vector<std::string> &words, size_t k,
                                   NOSPD::FlowLaw &fl, const std::string &where) const
{
  using NOSPD::Hardening;
  const std::string key = words[k];
  auto values = [&](size_t n) { return keyword_values(words, k, n, key, where); };
  if (k + 1 >= words.size()) error->all(FLERR, "{}: hardening needs linear H or power K n", where);
  const std::string kind = words[k + 1];
  k++;
  if (kind == "linear") {
    const auto v = values(1);
    if (!(v[0] >= 0.0))
      error->all(FLERR, "{}: hardening linear H = {} would make the flow stress fall; "
                 "H must be >= 0", where, v[0]);
    fl.kind = Hardening::LINEAR;
    fl.H = v[0];
  } else if (kind == "power") {
    const auto v = values(2);
    if (!(v[0] >= 0.0))
      error->all(FLERR, "{}: hardening power K = {} would make the flow stress fall; "
                 "K must be >= 0", where, v[0]);
    if (!(v[1] > 0.0)) error->all(FLERR, "{}: hardening power exponent n must be > 0, got {}", where, v[1]);
    fl.kind = Hardening::POWER;
    fl.K = v[0];
    fl.n = v[1];
  } else
    error->all(FLERR, "{}: unknown hardening '{}' (linear H, power K n)", where, kind);
  return k;
}

/* ----------------------------------------------------------------------
   the flow law as a whole: keywords that need another one
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_flow_law(const NOSPD::FlowLaw &fl, const NOSPD::ThermalLaw &th,
                                   const NOSPD::DruckerPrager &dp, const std::string &where) const
{
  using NOSPD::Hardening;
  if (fl.kind == Hardening::JOHNSON_COOK && (fl.H != 0.0))
    error->all(FLERR, "{}: hardening and johnson_cook exclude each other", where);
  if (!fl.active && (fl.H != 0.0 || fl.K != 0.0 || fl.Hkin != 0.0))
    error->all(FLERR, "{}: hardening/kinematic need a yield stress (keyword yield)", where);
  if (!fl.active && (th.cp > 0.0 || th.failure))
    error->all(FLERR, "{}: heat and jc_failure need plasticity (keyword yield or johnson_cook)", where);
  if (th.k > 0.0 && th.cp > 0.0 && th.cp != th.c)
    error->all(FLERR, "{}: heat cp {} and conduction c {} are one specific heat: give the same "
               "value", where, th.cp, th.c);
  if (dp.active && (fl.H != 0.0 || fl.K != 0.0 || fl.Hkin != 0.0 || th.alpha != 0.0))
    error->all(FLERR, "{}: drucker_prager has its own hardening (its H) and no thermal strain: "
               "hardening, kinematic and thermal do not apply to it", where);
}

/* ----------------------------------------------------------------------
   johnson_cook A B n C rate0 m T_ref T_melt (kinematic hardening kept)
------------------------------------------------------------------------- */

NOSPD::FlowLaw PairPeriNospdBase::johnson_cook_of(const std::vector<double> &v, double Hkin,
                                              const std::string &where) const
{
  if (!(v[0] > 0.0)) error->all(FLERR, "{}: johnson_cook A (yield stress) must be > 0, got {}", where, v[0]);
  if (!(v[1] >= 0.0)) error->all(FLERR, "{}: johnson_cook B = {} would make the flow stress fall; B must be >= 0", where, v[1]);
  if (!(v[2] > 0.0)) error->all(FLERR, "{}: johnson_cook n must be > 0, got {}", where, v[2]);
  if (!(v[3] >= 0.0)) error->all(FLERR, "{}: johnson_cook C must be >= 0, got {}", where, v[3]);
  if (!(v[4] > 0.0)) error->all(FLERR, "{}: johnson_cook reference rate must be > 0, got {}", where, v[4]);
  if (!(v[5] > 0.0)) error->all(FLERR, "{}: johnson_cook m must be > 0, got {}", where, v[5]);
  if (!(v[7] > v[6]))
    error->all(FLERR, "{}: johnson_cook T_melt = {} must exceed T_ref = {}", where, v[7], v[6]);
  NOSPD::FlowLaw fl;
  fl.Hkin = Hkin;
  fl.active = true;
  fl.kind = NOSPD::Hardening::JOHNSON_COOK;
  fl.sigma_y0 = v[0];
  fl.K = v[1];
  fl.n = v[2];
  fl.C = v[3];
  fl.rate0 = v[4];
  fl.m = v[5];
  fl.T_ref = v[6];
  fl.T_melt = v[7];
  return fl;
}

/* ----------------------------------------------------------------------
   jc_failure D1..D5: D1 + D2 exp(D3 s*) at the reference rate and
   temperature, in pure shear (s* = 0) and uniaxial tension (s* = 1/3): a
   failure strain <= 0 there breaks every yielding bond at its first
   plastic increment
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_jc_failure(const std::vector<double> &v, const std::string &where) const
{
  for (double sstar : {0.0, 1.0 / 3.0}) {
    const double ef = v[0] + v[1] * std::exp(v[2] * sstar);
    if (!(ef > 0.0))
      error->all(FLERR, "{}: jc_failure D1..D5 = {} {} {} {} {} give a failure strain {:.6g} "
                 "<= 0 at triaxiality {:.3g} (D1 + D2 exp(D3 s*)): every yielding point "
                 "would fail at once", where, v[0], v[1], v[2], v[3], v[4], ef, sstar);
  }
}

/* ----------------------------------------------------------------------
   drucker_prager phi psi c H: friction and dilatancy angles (degrees),
   cohesion and its hardening modulus (nospd_drucker_prager.h)
------------------------------------------------------------------------- */

NOSPD::DruckerPrager PairPeriNospdBase::drucker_prager_of(const std::vector<double> &v,
                                                      const std::string &where) const
{
  if (!(v[0] > 0.0 && v[0] < 90.0))
    error->all(FLERR, "{}: drucker_prager friction angle phi must be in (0, 90) degrees, got {}",
               where, v[0]);
  if (!(v[1] >= 0.0 && v[1] <= v[0]))
    error->all(FLERR, "{}: drucker_prager dilatancy angle psi must be in [0, phi = {}] degrees, "
               "got {}", where, v[0], v[1]);
  if (!(v[2] > 0.0)) error->all(FLERR, "{}: drucker_prager cohesion c must be > 0, got {}", where, v[2]);
  if (!(v[3] >= 0.0))
    error->all(FLERR, "{}: drucker_prager hardening H = {} would make the cohesion fall; H must "
               "be >= 0", where, v[3]);
  const double deg = M_PI / 180.0;
  return NOSPD::DruckerPrager::from_angles(v[0] * deg, v[1] * deg, v[2], v[3]);
}

/* ----------------------------------------------------------------------
   words of a material-file line, "..." or '...' quoting one word (an
   energy formula with spaces).  Not utils::split_words: in LAMMPS
   4 Jul 2026 it shifts the words that follow a second quoted word.
------------------------------------------------------------------------- */

static std::vector<std::string> split_quoted(const std::string &text)
{
  std::vector<std::string> words;
  size_t k = 0;
  const size_t n = text.size();
  while (k < n) {
    while (k < n && isspace(static_cast<unsigned char>(text[k]))) k++;
    if (k >= n) break;
    std::string w;
    while (k < n && !isspace(static_cast<unsigned char>(text[k]))) {
      const char q = text[k];
      if (q == '"' || q == '\'') {
        const size_t end = text.find(q, k + 1);
        const size_t stop = (end == std::string::npos) ? n : end;
        w += text.substr(k + 1, stop - k - 1);
        k = (end == std::string::npos) ? n : end + 1;
      } else
        w += text[k++];
    }
    words.push_back(w);
  }
  return words;
}

/* ----------------------------------------------------------------------
   Material files are read here, line by line with std::getline, not with
   LAMMPS's PotentialFileReader: its 1024-byte line buffer hung on a longer
   comment line, joined the rest of a long comment to the next entry and
   cut a long entry without a word.  The grammar is the one that reader
   gave: '#' starts a comment anywhere (in quotes too); an entry with fewer
   than five words continues on the next line with words; the first line's
   DATE: and UNITS: tags are logged and checked; the file is looked up as
   given, then in $LAMMPS_POTENTIALS.  Only rank 0 reads.
------------------------------------------------------------------------- */

namespace {

constexpr const char *MATERIAL_FILE = "peri/nospd material potential file";
constexpr int MATERIAL_WORDS = 5;    // name E nu density G0
const char *const MATERIAL_FIELDS[] = {"E", "nu", "density", "G0"};

// the word after `tag` on a potential file's first line ("" if none)
std::string header_tag(const std::string &first, const std::string &tag)
{
  Tokenizer words(first);
  while (words.has_next())
    if (words.next() == tag && words.has_next()) return words.next();
  return "";
}

// an entry's words (joined over its lines) and the lines it spans
struct FileEntry {
  std::vector<std::string> words;
  int first = 0, last = 0;
};

class MaterialFile {
 public:
  MaterialFile(LAMMPS *lmp, const std::string &file, const std::string &cmd) :
      lmp(lmp), file(file), cmd(cmd)
  {
    open();
  }
  bool next(FileEntry &entry);
  void numbers(const FileEntry &entry, double *vals) const;
  void check_quotes(const FileEntry &entry) const;
  [[noreturn]] void entry_error(const FileEntry &entry, const std::string &what) const;

 private:
  LAMMPS *lmp;
  std::string file, cmd;
  std::ifstream in;
  int line = 0;
  void open();
  void check_header(const std::string &path);
};

void MaterialFile::open()
{
  const std::string path = utils::get_potential_file_path(file);
  if (path.empty())
    lmp->error->one(FLERR, "cannot open {} {}: {}", MATERIAL_FILE, file, utils::getsyserror());
  // a directory opens (fopen, ifstream) but reads as empty: say so, not
  // that the material is not in it
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    lmp->error->one(FLERR, "{}: material file {} is a directory, not a file", cmd, path);
  check_header(path);
  in.open(path);
  if (!in) lmp->error->one(FLERR, "cannot open {} {}: {}", MATERIAL_FILE, file,
                           utils::getsyserror());
}

void MaterialFile::check_header(const std::string &path)
{
  std::ifstream head(path);
  std::string first;
  std::getline(head, first);
  if (head.bad())
    lmp->error->one(FLERR, "{}: cannot read material file {}: {}", cmd, path, utils::getsyserror());
  const std::string date = header_tag(first, "DATE:"), units = header_tag(first, "UNITS:");
  const std::string style = lmp->update->unit_style;
  if (!date.empty())
    utils::logmesg(lmp, "Reading {} {} with DATE: {}\n", MATERIAL_FILE, file, date);
  if (!units.empty() && units != style)
    lmp->error->one(FLERR, "{} {} requires {} units but {} units are in use", MATERIAL_FILE, file,
                    units, style);
}

// the next entry; false at the end of the file
bool MaterialFile::next(FileEntry &entry)
{
  entry = FileEntry();
  std::string text;
  while (std::getline(in, text)) {
    line++;
    text.resize(std::min(text.size(), text.find('#')));
    for (auto &w : Tokenizer(text).as_vector()) entry.words.push_back(w);
    if (entry.words.empty()) continue;
    if (entry.first == 0) entry.first = line;
    entry.last = line;
    if ((int) entry.words.size() >= MATERIAL_WORDS) return true;
  }
  if (in.bad())
    lmp->error->one(FLERR, "{}: cannot read material file {} after line {}: {}", cmd, file, line,
                    utils::getsyserror());
  if (!entry.words.empty())
    entry_error(entry, fmt::format("the file ends after {} of its {} words (name E nu density "
                                   "G0)", entry.words.size(), MATERIAL_WORDS));
  return false;
}

// E, nu, density, G0 of an entry: finite numbers in a double's range
void MaterialFile::numbers(const FileEntry &entry, double *vals) const
{
  for (int k = 0; k < MATERIAL_WORDS - 1; k++) {
    const std::string &w = entry.words[k + 1];
    const NOSPD::Parsed p = NOSPD::parse_real(w, vals[k]);
    if (p == NOSPD::Parsed::NOT_FINITE) vals[k] = strtod(w.c_str(), nullptr);    // named later
    else if (p != NOSPD::Parsed::OK)
      entry_error(entry, fmt::format("{} = '{}' is {}", MATERIAL_FIELDS[k], w,
                                     p == NOSPD::Parsed::NOT_A_NUMBER ? "not a number"
                                                                      : NOSPD::parse_reason(p)));
  }
}

// a quote opened in an entry's keywords closes in the same entry: an
// unclosed one would take the rest of the entry into one word (an energy
// formula that Lepton could only refuse at the first run)
void MaterialFile::check_quotes(const FileEntry &entry) const
{
  std::string text;    // the keywords as split_quoted() reads them
  for (size_t k = MATERIAL_WORDS; k < entry.words.size(); k++) text += entry.words[k] + " ";
  char open = 0;
  size_t at = 0;
  for (size_t c = 0; c < text.size(); c++) {
    if (open && text[c] == open) open = 0;
    else if (!open && (text[c] == '"' || text[c] == '\'')) {
      open = text[c];
      at = c;
    }
  }
  if (open)
    entry_error(entry, fmt::format("the quote {} before '{}' is never closed (a quoted keyword "
                                   "value ends within its entry)", open,
                                   utils::trim(text.substr(at + 1, 24))));
}

void MaterialFile::entry_error(const FileEntry &entry, const std::string &what) const
{
  const std::string lines = entry.last > entry.first
      ? fmt::format("lines {}-{}: an entry with fewer than {} words continues on the next line",
                    entry.first, entry.last, MATERIAL_WORDS)
      : fmt::format("line {}", entry.first);
  lmp->error->one(FLERR, "{}: material file {}, entry '{}' ({}): {}", cmd, file, entry.words[0],
                  lines, what);
}

}    // namespace

/* ----------------------------------------------------------------------
   the entry `name` of a material file, read on rank 0, on every rank
------------------------------------------------------------------------- */

PairPeriNospdBase::FileMaterial PairPeriNospdBase::read_material_file(const std::string &file,
                                                              const std::string &name)
{
  const std::string cmd = std::string("pair_coeff (") + force->pair_style + ")";
  double vals[4] = {0.0, 0.0, 0.0, 0.0};
  int where[2] = {0, 0};    // found, line
  std::string rest;
  if (comm->me == 0) {
    MaterialFile reader(lmp, file, cmd);
    FileEntry e;
    // the whole file: a name defined twice is ambiguous, not "first wins"
    while (reader.next(e)) {
      if (e.words[0] != name) continue;
      if (where[0])
        reader.entry_error(e, fmt::format("material '{}' is defined twice in the file (lines {} "
                                          "and {}): rename or remove one", name, where[1],
                                          e.first));
      reader.numbers(e, vals);
      reader.check_quotes(e);
      for (size_t k = MATERIAL_WORDS; k < e.words.size(); k++) rest += e.words[k] + " ";
      where[0] = 1;
      where[1] = e.first;
    }
  }
  MPI_Bcast(where, 2, MPI_INT, 0, world);
  if (!where[0])
    error->all(FLERR, "{}: material '{}' not found in file {}", cmd, name, file);
  MPI_Bcast(vals, 4, MPI_DOUBLE, 0, world);
  int len = rest.size();
  MPI_Bcast(&len, 1, MPI_INT, 0, world);
  rest.resize(len);
  MPI_Bcast(&rest[0], len, MPI_CHAR, 0, world);
  FileMaterial m;
  m.E = vals[0];
  m.nu = vals[1];
  m.density = vals[2];
  m.G0 = vals[3];
  m.line = where[1];
  m.extra = split_quoted(rest);    // the keywords, quotes joining words again
  return m;
}

/* ----------------------------------------------------------------------
   the numbers of a file entry other than nu (checked with the settings).
   The density is not applied (set ... density), but a file entry with a
   non-finite or non-positive one is broken.  G0 = 0 means no fracture
   energy (fix nospd/damage ... g0 then needs its own).
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_file_material(const std::string &where, const FileMaterial &m) const
{
  if (!(std::isfinite(m.density) && m.density > 0.0))
    error->all(FLERR, "{}: density must be finite and > 0, got {}", where, m.density);
  if (!(std::isfinite(m.G0) && m.G0 >= 0.0))
    error->all(FLERR, "{}: fracture energy G0 must be finite and >= 0 (0: none), got {}", where,
               m.G0);
}

/* ----------------------------------------------------------------------
   Young's modulus, inline or from a file.  No solid is stiffer than about
   1e12 Pa (1e13 in cgs, less in the other unit styles); a modulus past
   E_MAX is a typo, and its products with the horizon's inverse powers
   overflow a double into NaN forces at the first step.
------------------------------------------------------------------------- */

static constexpr double E_MAX = 1.0e100;

void PairPeriNospdBase::check_modulus(const std::string &where, double E) const
{
  if (!std::isfinite(E))
    error->all(FLERR, "{}: Young's modulus E must be finite, got {}", where, E);
  if (!(E > 0.0)) error->all(FLERR, "{}: Young's modulus E must be > 0, got {}", where, E);
  if (E > E_MAX)
    error->all(FLERR, "{}: Young's modulus E = {} is beyond any material (at most {:g}): its "
               "forces would overflow", where, E, E_MAX);
}

/* ----------------------------------------------------------------------
   a number of the inline form: inf and nan are numbers (not a file name,
   not LAMMPS's "expected floating point" about a valid-looking word)
------------------------------------------------------------------------- */

double PairPeriNospdBase::inline_number(const std::string &cmd, const char *what, const char *arg) const
{
  return NOSPD_INPUT::real(error, cmd, what, arg);
}

/* ----------------------------------------------------------------------
   Poisson's ratio against the plane and strain settings: at pair_coeff and
   again at init, since a later pair_style line may change those settings
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_poisson(const std::string &where, double nu) const
{
  if (!(nu > -1.0 && nu < 0.5) && plane_mode != Plane::STRESS)
    error->all(FLERR, "{}: Poisson ratio nu must be in (-1, 0.5), got {}", where, nu);
  if (!(nu > -1.0 && nu < 1.0))
    error->all(FLERR, "{}: Poisson ratio nu must be in (-1, 1) in plane stress, got {}", where, nu);
  if (plane_mode == Plane::STRESS && strain_law != Law::SMALL && !(nu < 0.5))
    error->all(FLERR, "{}: finite-strain plane stress needs nu < 0.5, got {}", where, nu);
}

/* ----------------------------------------------------------------------
   pair_coeff I J E nu delta [keyword values ...]
   pair_coeff I J file name delta [keyword values ...]   (material from a potentials/ file)
   pair_coeff I J delta                                  (horizon of a cross pair only)
   A material belongs to a type: it applies to the types in both ranges.
   The keywords (inelastic laws) may also follow the numbers of a material
   file entry; those on the pair_coeff line come after and override them.
------------------------------------------------------------------------- */

void PairPeriNospdBase::coeff(int narg, char **arg)
{
  const std::string cmd = std::string("pair_coeff (") + force->pair_style + ")";
  if (narg != 3 && narg < 5)
    error->all(FLERR, "{}: expected 'I J E nu delta', 'I J file name delta' or 'I J delta'", cmd);
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  NOSPD_INPUT::check_type_range(error, cmd, arg[0]);
  NOSPD_INPUT::check_type_range(error, cmd, arg[1]);
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  const int idelta = (narg == 3) ? 2 : 4;
  const double delta = NOSPD_INPUT::real(error, cmd, "horizon delta", arg[idelta]);
  if (!(delta > 0.0)) error->all(FLERR, "{}: horizon delta must be > 0, got {}", cmd, arg[idelta]);

  bool has_material = (narg >= 5);
  double E = 0.0, nu = 0.0, G0 = 0.0;
  std::string name;
  NOSPD::FlowLaw fl;
  NOSPD::ThermalLaw th;
  NOSPD::DruckerPrager dp;
  NospdUserMaterials::Spec us;
  bool thermal_ref_given = false;    // by a thermal keyword of the file or the line
  if (has_material) {
    std::string where = cmd;    // names the file entry the numbers come from
    if (utils::is_double(arg[2]) || parses_as_number(arg[2])) {
      E = inline_number(cmd, "Young's modulus E", arg[2]);
      nu = inline_number(cmd, "Poisson ratio nu", arg[3]);
      name = "inline";
    } else {
      name = arg[3];
      const FileMaterial m = read_material_file(arg[2], name);
      where = fmt::format("{}: material '{}' of file {} (line {})", cmd, name, arg[2], m.line);
      check_file_material(where, m);
      E = m.E;
      nu = m.nu;
      G0 = m.G0;
      if (!m.extra.empty())
        parse_inelastic(m.extra, fl, th, dp, us, thermal_ref_given,
                        fmt::format("material {} in {}", name, arg[2]));
    }
    check_modulus(where, E);
    check_poisson(where, nu);
    const std::vector<std::string> words(arg + 5, arg + narg);
    parse_inelastic(words, fl, th, dp, us, thermal_ref_given, cmd);
  }

  int count = 0, nmat = 0;
  for (int i = ilo; i <= ihi; i++) {
    if (has_material && i >= jlo && i <= jhi) {
      youngs[i] = E;
      poisson[i] = nu;
      g0[i] = G0;
      material_name[i] = name;
      flow[i] = fl;
      thermal[i] = th;
      drucker_prager[i] = dp;
      user_materials->spec(i) = us;
      nmat++;
    }
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      cut[i][j] = delta;
      setflag[i][j] = 1;
      count++;
    }
  }
  if (count == 0) error->all(FLERR, "{}: no type pairs in '{} {}'", cmd, arg[0], arg[1]);
  if (has_material && nmat == 0)
    error->all(FLERR, "{}: a material belongs to one type: use 'I I' or '* *'; for the cross "
               "pair {} {} give only the horizon", cmd, arg[0], arg[1]);
  ensure_bonds_fix();
}

/* ----------------------------------------------------------------------
   an inelastic type needs a law that has an inelastic form
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_inelastic(int itype) const
{
  const auto &fl = flow[itype];
  const auto &th = thermal[itype];
  if (drucker_prager[itype].active && strain_law != Law::SMALL && strain_law != Law::HENCKY)
    error->all(FLERR, "pair_style {}: type {} has drucker_prager but strain {} has no inelastic "
               "form: use strain small or strain hencky", force->pair_style, itype,
               NOSPD::law_keyword(strain_law));
  if (!fl.active && th.alpha == 0.0) return;
  if (strain_law != Law::SMALL && strain_law != Law::HENCKY)
    error->all(FLERR, "pair_style {}: type {} has {} but strain {} has no inelastic form: use "
               "strain small (additive) or strain hencky (multiplicative, finite)",
               force->pair_style, itype, fl.active ? "plasticity" : "thermal expansion",
               NOSPD::law_keyword(strain_law));
  if (fl.Hkin > 0.0 && strain_law != Law::SMALL)
    error->all(FLERR, "pair_style {}: type {}: kinematic hardening is implemented for strain "
               "small only, not strain hencky", force->pair_style, itype);
}

/* ----------------------------------------------------------------------
   The correspondence pair style of this run, alone or inside pair hybrid,
   under its name or its alias without "peri" (which keeps LAMMPS's own
   PERI_NEIGH fix, matching "peri", unambiguous beside peri/lps).
------------------------------------------------------------------------- */

PairPeriNospdBase *PairPeriNospdBase::find(Force *force)
{
  for (const char *name : {"^peri/nospd", "^nospd"})
    if (auto *p = dynamic_cast<PairPeriNospdBase *>(force->pair_match(name, 0))) return p;
  return nullptr;
}

/* ----------------------------------------------------------------------
   LAMMPS's PERI_NEIGH fix (made by peri/pmb, peri/lps, peri/ves, peri/eps)
   finds its pair with force->pair_match("peri", 0), which returns nothing
   when two sub-styles of pair hybrid contain "peri", and the fix then
   dereferences it in its setup.  Stop here, before that, and name the alias.
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_hybrid_names()
{
  if (!utils::strmatch(force->pair_style, "^hybrid")) return;
  // one bonds fix holds one bond model (horizons, influence, the owned
  // types): a second correspondence sub-style would silently replace it
  if (!force->pair_match("nospd", 0))
    error->all(FLERR, "pair_style {}: more than one PERI-NOSPD sub-style ({}); use one and give "
               "each atom type its own pair_coeff line", force->pair_style,
               force->pair_match_ptr(this));
  const char *mine = force->pair_match_ptr(this);
  if (!mine || !utils::strmatch(mine, "peri")) return;
  const std::string rest = std::string(mine).substr(5);    // "nospd" or "nospd/hs"
  for (const char *theirs : {"peri/pmb", "peri/lps", "peri/ves", "peri/eps"})
    if (force->pair_match(theirs, 1))
      error->all(FLERR, "pair_style {}: {} beside {}: LAMMPS's PERI styles find their pair by "
                 "the name 'peri', which two sub-styles cannot share; use the alias {} "
                 "(pair_style {} {} ... {} ...)",
                 force->pair_style, mine, theirs, rest, force->pair_style, rest, theirs);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::check_material(int itype) const
{
  if (!(youngs[itype] > 0.0))
    error->all(FLERR, "pair_coeff ({}): no material for atom type {}: give 'pair_coeff {} {} "
               "E nu delta' or a material file", force->pair_style, itype, itype, itype);
}

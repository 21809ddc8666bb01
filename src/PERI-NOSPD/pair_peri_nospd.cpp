/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Classical correspondence pair style with zero-energy-mode control.
------------------------------------------------------------------------- */

#include "pair_peri_nospd.h"

#include "atom.h"
#include "citeme.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "input.h"
#include "lattice.h"
#include "memory.h"
#include "modify.h"
#include "tokenizer.h"
#include "update.h"
#include "variable.h"

#include "nospd_bond_sums.h"
#include "nospd_input.h"
#include "nospd_simd.h"
#include "nospd_threads.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;
using NOSPD::Stab;

static const char cite_nospd[] =
    "pair peri/nospd: doi:10.1007/s10659-007-9125-1\n\n"
    "@Article{Silling07,\n"
    " author = {S. A. Silling and M. Epton and O. Weckner and J. Xu and E. Askari},\n"
    " title = {Peridynamic States and Constitutive Modeling},\n"
    " journal = {J.~Elasticity},\n"
    " year =    2007,\n"
    " volume =  88,\n"
    " pages =   {151--184}\n"
    "}\n\n";

static constexpr const char *BONDS_FIX_ID = "NOSPD_BONDS";

// first value of the settings in a restart file: the layout of what follows
// (files written before it existed start with the strain law, 0..8); the
// layout before damaged_leverage (0x4e530002) is read as without that limit,
// those before drucker_prager (up to 0x4e530003) without it
static constexpr int RESTART_LAYOUT = 0x4e530004;
static constexpr int RESTART_LAYOUT_V4 = 0x4e530004;
static constexpr int RESTART_LAYOUT_V3 = 0x4e530003;
static constexpr int RESTART_LAYOUT_V2 = 0x4e530002;
static constexpr double BIG = 1.0e300;

/* ----------------------------------------------------------------------
   a whole word read by strtod: a number, inf and nan included
------------------------------------------------------------------------- */

static bool parses_as_number(const char *word)
{
  char *end = nullptr;
  strtod(word, &end);
  return end != word && *end == '\0';
}

// a law's name as the strain keyword gives it, for messages
static const char *law_keyword(Law law)
{
  static const char *names[] = {"small", "finite", "svk", "neohookean", "hencky", "formula",
                                "umat", "umat/finite"};
  return names[static_cast<int>(law)];
}

/* ---------------------------------------------------------------------- */

PairPeriNospd::PairPeriNospd(LAMMPS *lmp) :
    Pair(lmp), fix_bonds(nullptr), strain_law(Law::SMALL), plane_mode(Plane::NONE),
    stab(Stab::SILLING), stab_param(0.5), fit_quadratic(false),
    influence(NospdBondModel::CONSTANT), thickness(1.0), singular_tol(1.0e-4), damaged_tol(0.1),
    damaged_leverage(0.5),
    youngs(nullptr), poisson(nullptr), g0(nullptr), stab_scalar(nullptr), cut(nullptr),
    nmax_work(0), bmat(nullptr), tmat(nullptr), moments(nullptr), qmat(nullptr), qsums(nullptr),
    comm_tensors(1)
{
  user_materials = std::make_unique<NospdUserMaterials>(lmp);
  temperature_kind = TEMP_NONE;
  temperature_index = -1;
  temperature_base = nullptr;
  if (lmp->citeme) lmp->citeme->add(cite_nospd);
  single_enable = 0;
  restartinfo = 1;
  one_coeff = 0;
  manybody_flag = 1;
  no_virial_fdotr_compute = 1;
  comm_forward = NOSPD::BREC;
}

/* ---------------------------------------------------------------------- */

PairPeriNospd::~PairPeriNospd()
{
  if (fix_bonds && modify->get_fix_by_id(BONDS_FIX_ID)) modify->delete_fix(BONDS_FIX_ID);
  memory->destroy(bmat);
  memory->destroy(tmat);
  memory->destroy(moments);
  memory->destroy(temperature_base);
  memory->destroy(qmat);
  memory->destroy(qsums);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(cut);
    memory->destroy(youngs);
    memory->destroy(poisson);
    memory->destroy(g0);
    memory->destroy(stab_scalar);
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  memory->create(cutsq, n, n, "pair:cutsq");
  memory->create(cut, n, n, "pair:cut");
  memory->create(youngs, n, "pair:youngs");
  memory->create(poisson, n, "pair:poisson");
  memory->create(g0, n, "pair:g0");
  memory->create(stab_scalar, n, "pair:stab_scalar");
  for (int i = 0; i < n; i++) {
    youngs[i] = poisson[i] = g0[i] = stab_scalar[i] = 0.0;
    for (int j = 0; j < n; j++) {
      setflag[i][j] = 0;
      cut[i][j] = 0.0;
    }
  }
  lame.assign(n, NOSPD::Lame{0.0, 0.0, 0.0});
  material_name.assign(n, std::string());
  flow.assign(n, NOSPD::FlowLaw());
  thermal.assign(n, NOSPD::ThermalLaw());
  drucker_prager.assign(n, NOSPD::DruckerPrager());
  inelastic.assign(n, 0);
  user_materials->resize(atom->ntypes);
}

/* ----------------------------------------------------------------------
   pair_style peri/nospd keyword value ...
------------------------------------------------------------------------- */

void PairPeriNospd::settings(int narg, char **arg)
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  // a pair_style command naming the style in place calls settings() again on
  // the same instance: every keyword not given takes its default again, so
  // that a line means the same model whatever came before it
  strain_law = Law::SMALL;
  plane_mode = Plane::NONE;
  stab = Stab::SILLING;
  stab_param = 0.5;
  fit_quadratic = false;
  influence = NospdBondModel::CONSTANT;
  thickness = 1.0;
  singular_tol = 1.0e-4;
  damaged_tol = 0.1;
  damaged_leverage = 0.5;
  temperature_kind = TEMP_NONE;
  temperature_name.clear();
  int iarg = 0;
  bool plane_given = false, thickness_given = false, singular_given = false,
       damaged_given = false;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    auto need = [&](int n) {
      if (iarg + n >= narg) error->all(FLERR, "{}: keyword {} needs {} value(s)", cmd, key, n);
    };
    if (key == "strain") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "small") strain_law = Law::SMALL;
      else if (v == "finite" || v == "corotational") strain_law = Law::COROTATIONAL;
      else if (v == "svk") strain_law = Law::SVK;
      else if (v == "neohookean") strain_law = Law::NEOHOOKE;
      else if (v == "hencky") strain_law = Law::HENCKY;
      else if (v == "formula") strain_law = Law::USER;
      else if (v == "umat") strain_law = Law::UMAT_SMALL;
      else if (v == "umat/finite") strain_law = Law::UMAT_FINITE;
      else error->all(FLERR, "{}: unknown strain '{}' (small, finite, svk, neohookean, hencky, "
                      "formula, umat, umat/finite)", cmd, v);
      iarg += 2;
    } else if (key == "stabilization") {
      need(1);
      const std::string v = arg[iarg + 1];
      iarg += 2;
      if (v == "none") stab = Stab::NONE;
      else if (v == "wan") stab = Stab::WAN;
      else if (v == "silling" || v == "hourglass") {
        if (iarg >= narg) error->all(FLERR, "{}: stabilization {} needs a value", cmd, v);
        stab = (v == "silling") ? Stab::SILLING : Stab::HOURGLASS;
        stab_param = NOSPD_INPUT::real(error, cmd, "stabilization " + v, arg[iarg]);
        if (!(stab_param > 0.0))
          error->all(FLERR, "{}: stabilization {} value must be > 0, got {}", cmd, v, arg[iarg]);
        iarg++;
      } else
        error->all(FLERR, "{}: unknown stabilization '{}' (none, silling G, hourglass C, wan)",
                   cmd, v);
    } else if (key == "stabilization/fit") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "linear") fit_quadratic = false;
      else if (v == "quadratic") fit_quadratic = true;
      else error->all(FLERR, "{}: unknown stabilization/fit '{}' (linear, quadratic)", cmd, v);
      iarg += 2;
    } else if (key == "influence") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "constant") influence = NospdBondModel::CONSTANT;
      else if (v == "inverse") influence = NospdBondModel::INVERSE;
      else error->all(FLERR, "{}: unknown influence '{}' (constant, inverse)", cmd, v);
      iarg += 2;
    } else if (key == "plane") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "strain") plane_mode = Plane::STRAIN;
      else if (v == "stress") plane_mode = Plane::STRESS;
      else error->all(FLERR, "{}: unknown plane '{}' (strain, stress)", cmd, v);
      plane_given = true;
      iarg += 2;
    } else if (key == "thickness") {
      need(1);
      thickness = NOSPD_INPUT::real(error, cmd, key, arg[iarg + 1]);
      if (!(thickness > 0.0)) error->all(FLERR, "{}: thickness must be > 0, got {}", cmd, arg[iarg + 1]);
      thickness_given = true;
      iarg += 2;
    } else if (key == "singular_tol" || key == "damaged_tol") {
      need(1);
      const double tol = NOSPD_INPUT::real(error, cmd, key, arg[iarg + 1]);
      if (!(tol > 0.0 && tol < 1.0))
        error->all(FLERR, "{}: {} must be in (0,1), got {}", cmd, key, arg[iarg + 1]);
      (key == "singular_tol" ? singular_tol : damaged_tol) = tol;
      (key == "singular_tol" ? singular_given : damaged_given) = true;
      iarg += 2;
    } else if (key == "damaged_leverage") {
      need(1);
      damaged_leverage = NOSPD_INPUT::real(error, cmd, key, arg[iarg + 1]);
      if (!(damaged_leverage > 0.0 && damaged_leverage <= 1.0))
        error->all(FLERR, "{}: damaged_leverage must be in (0,1] (1: no limit), got {}", cmd,
                   arg[iarg + 1]);
      iarg += 2;
    } else if (key == "temperature") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "none") {
        temperature_kind = TEMP_NONE;
      } else if (utils::strmatch(v, "^d_.") && v.find(':') == std::string::npos) {
        temperature_kind = TEMP_PROPERTY;
      } else if (utils::strmatch(v, "^v_.")) {
        temperature_kind = TEMP_VARIABLE;
      } else
        error->all(FLERR, "{}: temperature needs d_name (a per-atom property of fix "
                   "property/atom), v_name (an atom-style variable) or none, got '{}'", cmd, v);
      temperature_name = (temperature_kind == TEMP_NONE) ? "" : v.substr(2);
      iarg += 2;
    } else
      error->all(FLERR, "{}: unknown keyword '{}'{}", cmd, key,
                 (key == "form" || key == "ratio") ? " (a keyword of peri/nospd/hs)" : "");
  }
  // a family that lost bonds is held to at least the intact families'
  // tolerance; singular_tol alone sets both (one tolerance, as given)
  if (!damaged_given && singular_given) damaged_tol = singular_tol;
  if (damaged_given && damaged_tol < singular_tol)
    error->all(FLERR, "{}: damaged_tol {} is below singular_tol {}: a family that lost bonds "
               "is held to at least the intact families' tolerance", cmd, damaged_tol,
               singular_tol);
  damaged_tol = std::max(damaged_tol, singular_tol);
  if (fit_quadratic && stab != Stab::SILLING)
    error->all(FLERR, "{}: stabilization/fit quadratic applies to stabilization silling (its "
               "springs), not to stabilization {}", cmd,
               stab == Stab::NONE ? "none" : (stab == Stab::WAN ? "wan" : "hourglass"));
  // a 3D point volume is a volume: a thickness would be ignored without a word
  for (const auto &given : {std::make_pair("plane", plane_given),
                            std::make_pair("thickness", thickness_given)})
    if (domain->dimension == 3 && given.second)
      error->all(FLERR, "{}: keyword {} applies to 2D only (dimension 2)", cmd, given.first);
  if (domain->dimension == 2 && !plane_given) plane_mode = Plane::STRAIN;
  if (domain->dimension == 3) plane_mode = Plane::NONE;
}

/* ---------------------------------------------------------------------- */

std::string PairPeriNospd::not_a_potential() const
{
  return stab == Stab::HOURGLASS ? "stabilization hourglass is not a potential" : "";
}

/* ----------------------------------------------------------------------
   Poisson's ratio against the plane and strain settings: at pair_coeff and
   again at init, since a later pair_style line may change those settings
------------------------------------------------------------------------- */

void PairPeriNospd::check_poisson(const std::string &where, double nu) const
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

void PairPeriNospd::coeff(int narg, char **arg)
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

void PairPeriNospd::check_inelastic(int itype) const
{
  const auto &fl = flow[itype];
  const auto &th = thermal[itype];
  if (drucker_prager[itype].active && strain_law != Law::SMALL && strain_law != Law::HENCKY)
    error->all(FLERR, "pair_style {}: type {} has drucker_prager but strain {} has no inelastic "
               "form: use strain small or strain hencky", force->pair_style, itype,
               law_keyword(strain_law));
  if (!fl.active && th.alpha == 0.0) return;
  if (strain_law != Law::SMALL && strain_law != Law::HENCKY)
    error->all(FLERR, "pair_style {}: type {} has {} but strain {} has no inelastic form: use "
               "strain small (additive) or strain hencky (multiplicative, finite)",
               force->pair_style, itype, fl.active ? "plasticity" : "thermal expansion",
               law_keyword(strain_law));
  if (fl.Hkin > 0.0 && strain_law != Law::SMALL)
    error->all(FLERR, "pair_style {}: type {}: kinematic hardening is implemented for strain "
               "small only, not strain hencky", force->pair_style, itype);
}

/* ----------------------------------------------------------------------
   The correspondence pair style of this run, alone or inside pair hybrid,
   under its name or its alias without "peri" (which keeps LAMMPS's own
   PERI_NEIGH fix, matching "peri", unambiguous beside peri/lps).
------------------------------------------------------------------------- */

PairPeriNospd *PairPeriNospd::find(Force *force)
{
  for (const char *name : {"^peri/nospd", "^nospd"})
    if (auto *p = dynamic_cast<PairPeriNospd *>(force->pair_match(name, 0))) return p;
  return nullptr;
}

/* ----------------------------------------------------------------------
   LAMMPS's PERI_NEIGH fix (made by peri/pmb, peri/lps, peri/ves, peri/eps)
   finds its pair with force->pair_match("peri", 0), which returns nothing
   when two sub-styles of pair hybrid contain "peri", and the fix then
   dereferences it in its setup.  Stop here, before that, and name the alias.
------------------------------------------------------------------------- */

void PairPeriNospd::check_hybrid_names()
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

void PairPeriNospd::check_material(int itype) const
{
  if (!(youngs[itype] > 0.0))
    error->all(FLERR, "pair_coeff ({}): no material for atom type {}: give 'pair_coeff {} {} "
               "E nu delta' or a material file", force->pair_style, itype, itype, itype);
}

/* ---------------------------------------------------------------------- */

double PairPeriNospd::init_one(int i, int j)
{
  check_material(i);
  check_material(j);
  if (setflag[i][j] == 0) cut[i][j] = MAX(cut[i][i], cut[j][j]);
  cut[j][i] = cut[i][j];
  return cut[i][j];
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::init_style()
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  check_hybrid_names();
  if (!atom->peri_flag) error->all(FLERR, "{} requires atom_style peri", cmd);
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "{} requires an atom map: add 'atom_modify map array' before the box",
               cmd);
  // force densities are stress / length and the stable time step is taken
  // with f = m a: both hold only where pressure is force per area and force
  // is mass times acceleration without conversion factors
  if (force->nktv2p != 1.0 || force->ftm2v != 1.0)
    error->all(FLERR, "{} requires a unit style without pressure or force conversion factors "
               "(si, cgs, micro, nano, lj), not units {}", cmd, update->unit_style);
  const int dim = domain->dimension;
  if (dim == 2 && domain->zperiodic == 0)
    error->all(FLERR, "{}: 2D runs need a periodic z", cmd);
  warn_barostats(cmd);
  // CG and its line searches assume f = -grad pe: say once when it is not
  const std::string why = update->whichflag == 2 && !utils::strmatch(update->minimize_style, "^fire")
      ? not_a_potential() : "";
  if (!why.empty() && !minimize_warned && comm->me == 0)
    error->warning(FLERR, "minimize with {} ({}): CG and the line searches need forces that "
                   "are the gradient of the energy; use min_style fire (or damped dynamics)",
                   cmd, why);
  if (!why.empty()) minimize_warned = true;

  // the types this style owns: under pair hybrid, only those given to it
  active.assign(atom->ntypes + 1, 0);
  for (int i = 1; i <= atom->ntypes; i++) active[i] = (setflag[i][i] && youngs[i] > 0.0);

  // volumes and densities: a zero one would make K or the mass vanish
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  double *vfrac = atom->vfrac, *rmass = atom->rmass;
  int bad = -1;
  double badval = 0.0;
  const char *what = "";
  for (int i = 0; i < nlocal && bad < 0; i++) {
    if (!active[type[i]]) continue;
    if (!(vfrac[i] > 0.0)) { bad = i; badval = vfrac[i]; what = "volume (vfrac)"; }
    else if (!(rmass[i] > 0.0)) { bad = i; badval = rmass[i]; what = "density (rmass)"; }
  }
  int anybad = (bad >= 0), allbad;
  MPI_Allreduce(&anybad, &allbad, 1, MPI_INT, MPI_MAX, world);
  if (allbad) {
    if (bad >= 0)
      error->one(FLERR, "{}: atom {} has {} = {}, must be > 0 (set it with the set command)",
                 cmd, atom->tag[bad], what, badval);
    error->all(FLERR, "{}: atoms with zero volume or density", cmd);
  }

  // the horizon must reach beyond the nearest points; estimate their
  // spacing from the smallest volume
  double vmin = BIG, vmin_all;
  for (int i = 0; i < nlocal; i++)
    if (active[type[i]]) vmin = MIN(vmin, vfrac[i]);
  MPI_Allreduce(&vmin, &vmin_all, 1, MPI_DOUBLE, MPI_MIN, world);
  if (vmin_all < BIG) {
    const double spacing = (dim == 3) ? cbrt(vmin_all) : sqrt(vmin_all / thickness);
    if (dim == 2) check_one_plane(spacing);
    for (int i = 1; i <= atom->ntypes; i++)
      if (active[i] && cut[i][i] < 0.999 * spacing)
        error->all(FLERR, "{}: horizon {} of type {} is smaller than the point spacing {:.6g} "
                   "(from the smallest volume{}): families would be empty",
                   cmd, cut[i][i], i, spacing, dim == 2 ? " and the thickness" : "");
  }
  if (domain->lattice && domain->lattice->style != 0)
    for (int i = 1; i <= atom->ntypes; i++)
      if (active[i] && cut[i][i] < domain->lattice->xlattice)
        error->all(FLERR, "{}: horizon {} of type {} is smaller than the lattice spacing {}", cmd,
                   cut[i][i], i, domain->lattice->xlattice);

  // per-type constants of the law and of the stabilization
  for (int i = 1; i <= atom->ntypes; i++) {
    stab_scalar[i] = 0.0;
    if (!active[i]) continue;
    lame[i] = NOSPD::Lame::from_young(youngs[i], poisson[i]);
    const double c = NOSPD::micromodulus(dim, plane_mode, youngs[i], poisson[i], cut[i][i],
                                         thickness);
    if (stab == Stab::SILLING) stab_scalar[i] = stab_param * c / cut[i][i];
    else if (stab == Stab::HOURGLASS) stab_scalar[i] = stab_param * c;
  }
  comm_tensors = (stab == Stab::WAN || stab == Stab::HOURGLASS) ? 2 : 1;
  comm_forward = NOSPD::BREC + 9 * (comm_tensors - 1) + (quadratic_active() ? NOSPD::QREC : 0);
  raise_hybrid_comm_forward();

  // inelastic types: history in the bonds fix, a temperature source
  // user materials: formula laws go into lame[i].user, UMATs are opened
  user_materials->setup(strain_law, plane_mode, active.data(), lame, youngs, poisson,
                        material_name);
  int history_size = 0;
  for (int i = 1; i <= atom->ntypes; i++) {
    inelastic[i] = POINT_ELASTIC;
    if (!active[i]) continue;
    check_inelastic(i);
    if (user_materials->is_umat(i)) inelastic[i] = POINT_UMAT;
    else if (flow[i].active || thermal[i].alpha != 0.0 || drucker_prager[i].active)
      inelastic[i] = POINT_PLASTIC;
    if (inelastic[i] == POINT_PLASTIC) history_size = MAX(history_size, NOSPD::Hist::SIZE);
  }
  history_size = MAX(history_size, user_materials->history_size());
  build_materials();
  if (temperature_kind == TEMP_PROPERTY) {
    int flag, cols;
    temperature_index = atom->find_custom(temperature_name.c_str(), flag, cols);
    if (temperature_index < 0 || flag != 1 || cols != 0)
      error->all(FLERR, "{}: temperature d_{} is not a per-atom floating-point property; define "
                 "it with 'fix ID all property/atom d_{}' and set it with 'set ... d_{} value'",
                 cmd, temperature_name, temperature_name, temperature_name);
  } else if (temperature_kind == TEMP_VARIABLE) {
    temperature_index = input->variable->find(temperature_name.c_str());
    if (temperature_index < 0)
      error->all(FLERR, "{}: temperature variable {} does not exist", cmd, temperature_name);
    if (!input->variable->atomstyle(temperature_index))
      error->all(FLERR, "{}: temperature variable {} is not atom-style", cmd, temperature_name);
  }

  ensure_bonds_fix();
  fix_bonds->adopt_style(family_kind());
  if (history_size) fix_bonds->set_history_size(history_size);
  check_history_law();
  // no type reads history any more (the check let no plastic state go):
  // keep none, as a fresh run would not (the hs style's families too)
  bool reads_history = false;
  for (int i = 1; i <= atom->ntypes; i++) reads_history = reads_history || has_history(i) || is_umat(i);
  if (!reads_history && fix_bonds->nhistory) fix_bonds->drop_history();
  NospdBondModel model;
  model.horizon = cut;
  model.influence = influence;
  model.dim = dim;
  model.singular_tol = singular_tol;
  model.damaged_tol = damaged_tol;
  model.damaged_leverage = damaged_leverage;
  model.active = active.data();
  model.thickness = thickness;
  model.quadratic = quadratic_active();
  for (int i = 1; i <= atom->ntypes; i++)
    if (active[i] && youngs[i] > 0.0)
      check_poisson(fmt::format("pair_style {} (type {}'s material)", force->pair_style, i),
                    poisson[i]);
  wave_c.assign(atom->ntypes + 1, 0.0);
  for (int i = 1; i <= atom->ntypes; i++)
    if (active[i])
      wave_c[i] = NOSPD::pwave_micromodulus(dim, plane_mode, lame[i], cut[i][i], thickness);
  model.wave_micromodulus = wave_c.data();
  set_stiffness_bound(model);
  fix_bonds->set_model(model);
  fix_bonds->vote_pair_order(pair_order_usable());
  // no neighbor list: the families are fixed and live in the fix; the
  // ghost cutoff follows from the pair cutoff (horizon) plus the skin
}

/* ----------------------------------------------------------------------
   what the bonds fix needs to bound the stiffness of pass 2 for the stable
   time step (FixNospdBonds::bound_stable_timesteps): the norm of the
   linearized C on tensors, its largest eigenvalue, 3 lambda + 2 mu (a
   dilatation; in 2D 2 lambda + 2 mu with plane stress's lambda), and the
   stabilization's bond stiffness.  The bound is the classical force's; the
   bond-associated style gives its own (family_row_bound).
------------------------------------------------------------------------- */

void PairPeriNospd::set_stiffness_bound(NospdBondModel &m)
{
  const int ntypes = atom->ntypes;
  stress_norm.assign(ntypes + 1, 0.0);
  for (int i = 1; i <= ntypes; i++) {
    if (!active[i]) continue;
    const NOSPD::Lame &l = lame[i];
    const double lam = (domain->dimension == 2 && plane_mode == NOSPD::Plane::STRESS) ? l.lambda_ps
                                                                                        : l.lambda;
    stress_norm[i] = std::max(domain->dimension * lam + 2.0 * l.mu, 2.0 * l.mu);
  }
  m.stress_norm = stress_norm.data();
  m.spring = stab_scalar;
  switch (stab) {
    case Stab::SILLING: m.spring_kind = NospdBondModel::PER_WEIGHT; break;
    case Stab::HOURGLASS: m.spring_kind = NospdBondModel::PER_LENGTH; break;
    case Stab::WAN: m.spring_kind = NospdBondModel::WAN; break;
    default: m.spring_kind = NospdBondModel::NONE;
  }
  m.family_rows = family_row_bound();
  m.bound_margin = bound_margin();
}

/* ----------------------------------------------------------------------
   fixes that hold a pressure act on LAMMPS's pressure, which here is the
   body's stress divided by the point volume (forces are densities)
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   Comm sizes its buffers from force->pair->comm_forward at its init, which
   follows this one.  Under pair hybrid that is the hybrid's, the largest of
   its sub-styles' taken at its settings, before this style knew its
   record (the stabilization's tensors, the quadratic fit's Q): raise it.
------------------------------------------------------------------------- */

void PairPeriNospd::raise_hybrid_comm_forward()
{
  if (force->pair && force->pair != this)
    force->pair->comm_forward = MAX(force->pair->comm_forward, comm_forward);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::warn_barostats(const std::string &cmd)
{
  if (comm->me != 0) return;
  for (const auto *f : modify->get_fix_list())
    if (utils::strmatch(f->style, "^box/relax") || utils::strmatch(f->style, "^np[th]") ||
        utils::strmatch(f->style, "^nph") || utils::strmatch(f->style, "^press/"))
      error->warning(FLERR, "{}: fix {} ({}) controls LAMMPS's pressure, which under this style "
                     "is the stress divided by the point volume (forces are force densities): "
                     "give it the target stress divided by the point volume", cmd, f->id, f->style);
}

/* ----------------------------------------------------------------------
   2D: the bond sums take xi and Y whole, so every point of the body must
   lie in one plane z = const, in the reference and now (points at mixed z
   would give bonds an out-of-plane part: energy and z forces at rest)
------------------------------------------------------------------------- */

void PairPeriNospd::check_one_plane(double spacing)
{
  double lo[2] = {BIG, BIG}, hi[2] = {-BIG, -BIG};    // z of x, of x0
  for (int i = 0; i < atom->nlocal; i++) {
    if (!active[atom->type[i]]) continue;
    const double z[2] = {atom->x[i][2], atom->x0[i][2]};
    for (int k = 0; k < 2; k++) lo[k] = MIN(lo[k], z[k]), hi[k] = MAX(hi[k], z[k]);
  }
  double lo_all[2], hi_all[2];
  MPI_Allreduce(lo, lo_all, 2, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(hi, hi_all, 2, MPI_DOUBLE, MPI_MAX, world);
  for (int k = 0; k < 2; k++)
    if (hi_all[k] - lo_all[k] > 1.0e-9 * spacing)
      error->all(FLERR, "pair_style {}: 2D body with points at {} z from {} to {}: all its points "
                 "must lie in one plane", force->pair_style, k ? "reference (x0)" : "current",
                 lo_all[k], hi_all[k]);
}

/* ----------------------------------------------------------------------
   A type whose atoms carry plastic state from an earlier run (the plastic
   strain, eqps and back stress of plasticity; a UMAT's state variables)
   must keep a law that reads that state: an elastic law would drop it
   (the body springs back towards its reference shape, creating energy),
   small and hencky store different plastic strains, a UMAT its own.
   The law per type is kept in the bonds fix, which a pair_style command
   repeating the style keeps (another style starts new families, and a
   restart file does not hold the law: nothing to check then).
------------------------------------------------------------------------- */

void PairPeriNospd::check_history_law()
{
  const int ntypes = atom->ntypes;
  std::vector<int> &last = fix_bonds->history_law;
  // 0: elastic; else 1 + the strain law (plasticity: small or hencky; UMATs)
  const int umat_code = 1 + static_cast<int>(Law::UMAT_SMALL);
  std::vector<int> now(ntypes + 1, 0);
  for (int t = 1; t <= ntypes; t++)
    if (active[t] && inelastic[t] != POINT_ELASTIC) now[t] = 1 + static_cast<int>(strain_law);
  if ((int) last.size() == ntypes + 1 && fix_bonds->nhistory) {
    // the lowest ID of an atom whose plastic state the law it has now would
    // not read: its type's law changed (pair_coeff), or the atom changed
    // type (set type) to one of another law
    const int *type = atom->type;
    const tagint *tag = atom->tag;
    double **h = fix_bonds->history;
    bigint first = MAXBIGINT;
    int info[2] = {0, 0}, info_all[2];    // the atom's type then and now
    for (int i = 0; i < atom->nlocal; i++) {
      const int t = type[i];
      int was = fix_bonds->type_of_history(i);
      if (was <= 0 || was > ntypes) was = t;
      if (!active[t] || !last[was] || last[was] == now[t] || tag[i] >= first) continue;
      const int n = last[was] >= umat_code ? fix_bonds->nhist_atom : NOSPD::Hist::BACK + 6;
      for (int k = 0; k < n; k++)
        if (h[i][k] != 0.0) {
          first = tag[i];
          info[0] = was, info[1] = t;
          break;
        }
    }
    bigint first_all;
    MPI_Allreduce(&first, &first_all, 1, MPI_LMP_BIGINT, MPI_MIN, world);
    if (first_all != MAXBIGINT) {
      if (first != first_all) info[0] = info[1] = 0;
      MPI_Allreduce(info, info_all, 2, MPI_INT, MPI_MAX, world);
      const int was = info_all[0], t = info_all[1];
      auto law_name = [&](int code) -> std::string {
        if (!code) return "an elastic law";
        if (code >= umat_code) return "a UMAT";
        return fmt::format("plasticity under strain {}", law_keyword(static_cast<Law>(code - 1)));
      };
      if (was == t)
        error->all(FLERR, "pair_coeff {} {}: the atoms of type {} carry plastic state from {} "
                   "of an earlier run, which {} would not read: keep the type's law", t, t, t,
                   law_name(last[t]), law_name(now[t]));
      error->all(FLERR, "set type: atom {} changed from type {} to type {} after an earlier run "
                 "and carries plastic state from {} (type {}), which {} (type {}) would not "
                 "read: give it a type of the same law", first_all, was, t, law_name(last[was]),
                 was, law_name(now[t]), t);
    }
  }
  last.resize(ntypes + 1, 0);
  for (int t = 1; t <= ntypes; t++)
    if (active[t]) last[t] = now[t];
}

/* ----------------------------------------------------------------------
   The fix that owns families and state: created with the first pair_coeff
   (so that thermo_style can name f_NOSPD_BONDS) or at init after a
   restart, under one ID so that it gets its restart data back.
------------------------------------------------------------------------- */

void PairPeriNospd::ensure_bonds_fix()
{
  auto *f = modify->get_fix_by_id(BONDS_FIX_ID);
  if (fix_bonds) {
    if (f == fix_bonds) return;
    error->all(FLERR, "pair_style {}: fix {} was deleted (unfix): it holds the bond families "
               "and their state, and lives as long as the pair style (a new pair_style "
               "command starts new families)", force->pair_style, BONDS_FIX_ID);
  }
  if (!f) {
    struct Making {    // the flag falls back also when add_fix throws
      Making() { FixNospdBonds::made_by_pair_style = true; }
      ~Making() { FixNospdBonds::made_by_pair_style = false; }
    } making;
    f = modify->add_fix(fmt::format("{} all PERI_NEIGH/NOSPD", BONDS_FIX_ID));
  }
  fix_bonds = dynamic_cast<FixNospdBonds *>(f);
  if (!fix_bonds)
    error->all(FLERR, "pair_style {}: fix {} exists but is not a PERI_NEIGH/NOSPD fix",
               force->pair_style, BONDS_FIX_ID);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::grow_work()
{
  // the quadratic fit's arrays come with the setting, grown with the rest
  if (atom->nmax <= nmax_work && (qmat != nullptr) == quadratic_active()) return;
  nmax_work = atom->nmax;
  memory->destroy(bmat);
  memory->destroy(tmat);
  memory->destroy(moments);
  memory->destroy(temperature_base);
  memory->create(temperature_base, nmax_work, "pair:temperature_base");
  // T^T with a spare row: the bond sums read a double past the last atom
  memory->create(bmat, nmax_work, NOSPD::BREC, "pair:bmat");
  memory->create(tmat, nmax_work + 1, 9, "pair:tmat");
  memset(bmat[0], 0, sizeof(double) * NOSPD::BREC * nmax_work);
  memset(tmat[0], 0, sizeof(double) * 9 * (nmax_work + 1));
  memory->create(moments, nmax_work, 6, "pair:moments");
  memory->destroy(qmat);
  memory->destroy(qsums);
  qmat = qsums = nullptr;
  if (quadratic_active()) {
    // Q's loads read a double past the last atom: a spare row
    memory->create(qmat, nmax_work + 1, NOSPD::QREC, "pair:qmat");
    memset(qmat[0], 0, sizeof(double) * NOSPD::QREC * (nmax_work + 1));
    memory->create(qsums, nmax_work, NOSPD::QSUMS, "pair:qsums");
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  grow_work();

  const bool linear_stab = (stab == Stab::SILLING || stab == Stab::WAN);
  double **mom = (eflag && linear_stab) ? moments : nullptr;
  positions = fix_bonds->padded_positions();
  for_ranges(atom->nlocal, true, [&](int from, int to, int, Tally &) {
    fix_bonds->compute_deformation(positions, mom, from, to);
  });
  if (quadratic_active()) quadratic_pass();
  constitutive_pass(eflag);
  comm->forward_comm(this);

  const bool virial = vflag_either;
  switch (stab) {
    case Stab::NONE:
      virial ? force_pass<NOSPD::StabPass::NONE, 1>(eflag) : force_pass<NOSPD::StabPass::NONE, 0>(eflag);
      break;
    case Stab::SILLING:
      if (quadratic_active()) virial ? force_pass<NOSPD::StabPass::SILLING_QUADRATIC, 1>(eflag) : force_pass<NOSPD::StabPass::SILLING_QUADRATIC, 0>(eflag);
      else virial ? force_pass<NOSPD::StabPass::SILLING, 1>(eflag) : force_pass<NOSPD::StabPass::SILLING, 0>(eflag);
      break;
    case Stab::HOURGLASS:
      virial ? force_pass<NOSPD::StabPass::HOURGLASS, 1>(eflag) : force_pass<NOSPD::StabPass::HOURGLASS, 0>(eflag);
      break;
    case Stab::WAN:
      virial ? force_pass<NOSPD::StabPass::WAN, 1>(eflag) : force_pass<NOSPD::StabPass::WAN, 0>(eflag);
      break;
  }
}

/* ----------------------------------------------------------------------
   per owned atom: P(F), W(F), and what pass 2 needs of it and its partners:
   B = P K^-1 - S H, plus S (Wan) or H (hourglass)
------------------------------------------------------------------------- */

void PairPeriNospd::constitutive_pass(int eflag)
{
  if (fix_bonds->nhistory) fill_base_temperature();
  // user laws keep scratch space (formulas) or may not be reentrant (UMATs)
  for_ranges(atom->nlocal, !user_law(),
             [&](int from, int to, int, Tally &t) { constitutive_range(from, to, eflag, t); });
  if (fix_bonds->nhistory) fix_bonds->trial_history_ready();
}

void PairPeriNospd::constitutive_range(int from, int to, int eflag, Tally &t)
{
  const int *type = atom->type;
  const int *singular = fix_bonds->singular;
  double **defgrad = fix_bonds->defgrad;
  double **kinv = fix_bonds->kinv;
  double **pk1 = fix_bonds->pk1;
  double *wdens = fix_bonds->energy_density;
  const int nhist = fix_bonds->nhistory;
  double **hist = fix_bonds->history;
  double **hist_trial = fix_bonds->history_trial;
  const bool minimizing = (update->whichflag == 2);
  NOSPD::PointEnv env;
  env.dt = minimizing ? 0.0 : update->dt;    // a minimize step is quasi-static: no rate

  for (int i = from; i < to; i++) {
    const int itype = type[i];
    const bool history_point = nhist && inelastic[itype];
    if (nhist && (!history_point || singular[i]))
      for (int k = 0; k < nhist; k++) hist_trial[i][k] = hist[i][k];
    if (singular[i]) {
      // no force state of its own: no stress, no stabilization
      for (int k = 0; k < 9; k++) tmat[i][k] = pk1[i][k] = 0.0;
      for (int k = 0; k < NOSPD::BREC; k++) bmat[i][k] = 0.0;
      if (qmat)
        for (int k = 0; k < NOSPD::QREC; k++) qmat[i][k] = 0.0;
      wdens[i] = 0.0;
      continue;
    }
    Mat3 F = NOSPD::load(defgrad[i]);
    const Mat3 H = F - Mat3::Identity();
    const Mat3 Ki = NOSPD::load(kinv[i]);
    Mat3 P;
    double W = 0.0;
    point_stress(i, F, P, W, env);
    NOSPD::store(F, defgrad[i]);
    NOSPD::store(P, pk1[i]);
    const Mat3 A = P * Ki;

    Mat3 B = A;
    double e2 = 0.0;    // with the quadratic fit: sum_j w |z2|^2
    if (stab == Stab::SILLING && qmat) {
      Mat3 H2;
      quadratic_spring(i, H, H2, e2, eflag);
      B -= stab_scalar[itype] * H2;
    } else if (stab == Stab::SILLING) {
      B -= stab_scalar[itype] * H;
    } else if (stab == Stab::WAN) {
      const Mat3 S = NOSPD::wan_tensor(lame[itype], domain->dimension, plane_mode, Ki);
      B -= S * H;
      store_transposed(S, tmat[i]);
    } else if (stab == Stab::HOURGLASS) {
      // c H: pass 2 needs the two ends' H xi only scaled by their c
      store_transposed(Mat3(stab_scalar[itype] * H), tmat[i]);
    }
    store_transposed(B, bmat[i]);
    bmat[i][STAB_SCALAR] = stab_scalar[itype];

    if (eflag) {
      double e = W;
      if (stab == Stab::SILLING || stab == Stab::WAN) {
        // 1/2 sum_j w z.S z = 1/2 S : Z
        const Mat3 Z = nonaffine_moment(i, H, Ki);
        if (stab == Stab::SILLING && qmat) e += 0.5 * stab_scalar[itype] * e2;
        else if (stab == Stab::SILLING) e += 0.5 * stab_scalar[itype] * Z.trace();
        else e += 0.5 * NOSPD::load(tmat[i]).cwiseProduct(Z).sum();    // S^T : Z = S : Z, Z symmetric
      }
      wdens[i] = e;
      // minimize solves one load step of the plasticity: its energy is the
      // step's incremental potential, W_e plus the dissipation of the step,
      // whose gradient the returned stress is (nospd_plasticity.h)
      if (minimizing && inelastic[itype] == POINT_PLASTIC)
        e += hist_trial[i][NOSPD::Hist::WORK] - hist[i][NOSPD::Hist::WORK];
      tally_energy(i, e, t);
    }
  }
}

/* ----------------------------------------------------------------------
   P and W of owned atom i at F (F33 written back in plane stress): by the
   type's law alone, the built-in inelastic point or its UMAT
------------------------------------------------------------------------- */

void PairPeriNospd::point_stress(int i, Mat3 &F, Mat3 &P, double &W, const NOSPD::PointEnv &env0)
{
  const NOSPD::Material &law = *materials[atom->type[i]];
  NOSPD::MaterialEnv env;
  env.dt = env0.dt;
  const bool history = fix_bonds->nhistory > 0;
  if (history) {
    env.T = temperature_base[i];
    env.rho = atom->rmass[i];
  }
  NOSPD::UmatPoint pt;
  if (law.wants_point_data()) {
    pt = umat_env(i);
    env.umat = &pt;
  }
  const NOSPD::PointStatus st =
      law.stress(F, history ? fix_bonds->history[i] : nullptr,
                 history ? fix_bonds->history_trial[i] : nullptr, env, P, W);
  if (!st.ok()) material_failure(i, st, F);
}

/* ----------------------------------------------------------------------
   each active type's law behind the material-point interface
   (nospd_material.h): the one place a law is chosen
------------------------------------------------------------------------- */

void PairPeriNospd::build_materials()
{
  materials.clear();
  materials.resize(atom->ntypes + 1);
  for (int i = 1; i <= atom->ntypes; i++) {
    if (!active[i]) continue;
    if (inelastic[i] == POINT_UMAT)
      materials[i] = std::make_unique<NOSPD::UmatPointMaterial>(user_materials->umat(i));
    else if (drucker_prager[i].active)
      materials[i] = std::make_unique<NOSPD::DruckerPragerMaterial>(strain_law, plane_mode,
                                                                    lame[i], drucker_prager[i]);
    else if (inelastic[i] == POINT_PLASTIC)
      materials[i] = std::make_unique<NOSPD::J2Material>(strain_law, plane_mode, lame[i],
                                                         flow[i], thermal[i]);
    else
      materials[i] = std::make_unique<NOSPD::ElasticMaterial>(strain_law, plane_mode, lame[i]);
  }
}

// the message of a law that failed at owned atom i
void PairPeriNospd::material_failure(int i, NOSPD::PointStatus st, const Mat3 &F) const
{
  if (st.family == NOSPD::PointStatus::UMAT) umat_failure(i, static_cast<NOSPD::UmatStatus>(st.code), F);
  if (st.family == NOSPD::PointStatus::RETURN)
    inelastic_failure(i, static_cast<NOSPD::ReturnStatus>(st.code), F);
  law_failure(i, F);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::law_failure(int i, const Mat3 &F) const
{
  const double J = F.determinant();
  if (strain_law == Law::USER && J > 0.0)
    error->one(FLERR, "pair_style {}: the energy formula of type {} (W = '{}') gives a "
               "non-finite stress at atom {} on step {} (det F = {:.6g}){}", force->pair_style,
               atom->type[i], user_materials->spec(atom->type[i]).energy, atom->tag[i],
               update->ntimestep, J, fix_bonds->user_law_cause("formula"));
  error->one(FLERR, "pair_style {}: atom {} on step {} has det F = {:.6g}: the "
             "finite-strain law is undefined for an inverted or collapsed family{}",
             force->pair_style, atom->tag[i], update->ntimestep, J, fix_bonds->unstable_cause());
}

/* ----------------------------------------------------------------------
   one UMAT increment of owned atom i from its accepted history
------------------------------------------------------------------------- */


/* ----------------------------------------------------------------------
   what a UMAT's material point at owned atom i needs besides F
------------------------------------------------------------------------- */

NOSPD::UmatPoint PairPeriNospd::umat_env(int i) const
{
  NOSPD::UmatPoint pt;
  pt.dt = update->dt;
  // TIME at the start of the increment, as Abaqus passes it (the setup's
  // evaluation of the accepted state takes no increment: its own time)
  const double t_now = update->atime + (update->ntimestep - update->atimestep) * update->dt;
  pt.time = update->setupflag ? t_now : t_now - update->dt;
  pt.temperature = temperature_base[i];
  for (int d = 0; d < 3; d++) pt.coords[d] = atom->x[i][d];
  pt.celent = (domain->dimension == 3) ? cbrt(atom->vfrac[i]) : sqrt(atom->vfrac[i] / thickness);
  pt.noel = static_cast<int>(atom->tag[i]);
  pt.kinc = static_cast<int>(update->ntimestep);
  return pt;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::umat_failure(int i, NOSPD::UmatStatus st, const Mat3 &F) const
{
  const int itype = atom->type[i];
  const std::string lib = user_materials->library(itype);
  if (st == NOSPD::UmatStatus::ABORT)
    error->one(FLERR, "pair_style {}: the UMAT of type {} ({}) stopped at atom {} on step {}: {}",
               force->pair_style, itype, lib, atom->tag[i], update->ntimestep,
               NOSPD::umat_report().message);
  if (st == NOSPD::UmatStatus::STATEV_OVERFLOW)
    error->one(FLERR, "pair_style {}: the UMAT of type {} ({}, symbol {}) wrote past its NSTATV "
               "= {} state variables (statev {}) at atom {} on step {}: declare as many as it "
               "writes with 'statev N'", force->pair_style, itype, lib,
               user_materials->symbol(itype), user_materials->umat(itype).nstatev,
               user_materials->umat(itype).nstatev, atom->tag[i], update->ntimestep);
  if (st == NOSPD::UmatStatus::NONFINITE)
    error->one(FLERR, "pair_style {}: the UMAT of type {} ({}) returned a non-finite stress, "
               "energy or state variable at atom {} on step {}{}", force->pair_style, itype, lib,
               atom->tag[i], update->ntimestep, fix_bonds->user_law_cause("UMAT"));
  law_failure(i, F);
}

/* ----------------------------------------------------------------------
   the user's temperature of each owned atom (before adiabatic heating)
------------------------------------------------------------------------- */

void PairPeriNospd::fill_base_temperature()
{
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  if (temperature_kind == TEMP_VARIABLE) {
    // LAMMPS's evaluation lets std::stod's out_of_range out (a constant 1e999)
    try {
      input->variable->compute_atom(temperature_index, 0, temperature_base, 1, 0);
    } catch (std::out_of_range &e) {
      error->one(FLERR, "pair_style {}: temperature v_{}: a number out of a double's range "
                 "({})", force->pair_style, temperature_name, e.what());
    }
  } else if (temperature_kind == TEMP_PROPERTY) {
    const double *t = atom->dvector[temperature_index];
    for (int i = 0; i < nlocal; i++) temperature_base[i] = t[i];
  } else {
    for (int i = 0; i < nlocal; i++) temperature_base[i] = thermal[type[i]].T_ref;
  }
  // the plastic and thermal laws read an absolute temperature (T_ref > 0 is
  // already required); a UMAT may take any scale, but not a non-finite one
  for (int i = 0; i < nlocal; i++) {
    const double T = temperature_base[i];
    const bool absolute = inelastic[type[i]] == POINT_PLASTIC;
    if (inelastic[type[i]] && !(std::isfinite(T) && (T > 0.0 || !absolute)))
      error->one(FLERR, "pair_style {}: step {}: atom {} has temperature {} from {}{}{}",
                 force->pair_style, update->ntimestep, atom->tag[i], T,
                 temperature_kind == TEMP_VARIABLE ? "v_" : "d_", temperature_name,
                 std::isfinite(T) ? " (the temperature of a plastic or thermal law is absolute: "
                                    "it must be > 0)" : "");
  }
}

/* ---------------------------------------------------------------------- */

double PairPeriNospd::temperature(int i) const
{
  const int nhist = fix_bonds ? fix_bonds->nhistory : 0;
  if (!nhist || !temperature_base || i >= nmax_work) return thermal[atom->type[i]].T_ref;
  return temperature_base[i] + (nhist ? fix_bonds->history[i][NOSPD::Hist::HEAT] : 0.0);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::inelastic_failure(int i, NOSPD::ReturnStatus st, const Mat3 &F) const
{
  if (st == NOSPD::ReturnStatus::BAD_TEMPERATURE) {
    const NOSPD::ThermalLaw &th = thermal[atom->type[i]];
    const double T = temperature(i), eth = th.alpha * (T - th.T_ref);
    error->one(FLERR, "pair_style {}: atom {} on step {} has temperature {:.6g}, where the "
               "thermal {} of type {} (thermal {:.6g} {:.6g}) is {:.6g}: the law is undefined "
               "there; check the temperature (its variable or property) and the thermal law",
               force->pair_style, atom->tag[i], update->ntimestep, T,
               strain_law == NOSPD::Law::SMALL ? "strain alpha (T - T_ref)"
                                               : "stretch 1 + alpha (T - T_ref)",
               atom->type[i], th.alpha, th.T_ref,
               strain_law == NOSPD::Law::SMALL ? eth : 1.0 + eth);
  }
  if (st == NOSPD::ReturnStatus::BAD_DEFORMATION)
    error->one(FLERR, "pair_style {}: atom {} on step {} has det F = {:.6g}: the finite-strain "
               "law is undefined for an inverted or collapsed family{}",
               force->pair_style, atom->tag[i], update->ntimestep, F.determinant(),
               fix_bonds->unstable_cause());
  if (drucker_prager[atom->type[i]].active)
    error->one(FLERR, "pair_style {}: atom {} on step {}: a Drucker-Prager state beyond the "
               "cone's apex (hydrostatic tension above its strength) cannot return without "
               "dilatancy: give the type a dilatancy angle psi > 0", force->pair_style,
               atom->tag[i], update->ntimestep);
  error->one(FLERR, "pair_style {}: the plastic return mapping did not converge at atom {} on "
             "step {} (equivalent plastic strain {:.6g}, temperature {:.6g}); the strain "
             "increment may be too large (time step) or the flow law ill-posed",
             force->pair_style, atom->tag[i], update->ntimestep,
             fix_bonds->history[i][NOSPD::Hist::EQPS], temperature_base[i]);
}

/* ----------------------------------------------------------------------
   Z = sum_j w z (x) z with z = U - H xi, from the moments of pass 1:
   Z = M_UU - H K H^T, since sum_j w U (x) xi = H K
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   the quadratic fit (nospd_stabilization.h): its sums per owned atom
------------------------------------------------------------------------- */

namespace {
NOSPD_KERNEL_CLONES void quadratic_range_kernel(const NOSPD::Positions &p, const int *first,
                                                const int *bj, const double *bw, int from, int to,
                                                double *out)
{
  for (int i = from; i < to; i++)
    NOSPD::quadratic_sums(p, {bj, bw, first[i], first[i + 1]}, i, out + NOSPD::QSUMS * i);
}
}    // namespace

void PairPeriNospd::quadratic_pass()
{
  for_ranges(atom->nlocal, true, [&](int from, int to, int, Tally &) {
    quadratic_range_kernel(positions, fix_bonds->bond_first, fix_bonds->bond_j,
                           fix_bonds->bond_w, from, to, qsums[0]);
  });
}

/* atom i's fit A = [H2 | Q]: H2 for B, alpha Q into qmat (columns), and
   e2 = sum_j w |U - A phi|^2 = sum_j w |U|^2 - A : N2 (the moments of the
   energy pass, else 0).  Where the family has no quadratic fit, the linear
   one: H2 = H, Q = 0, e2 = sum_j w |U - H xi|^2. */
void PairPeriNospd::quadratic_spring(int i, const Mat3 &H, Mat3 &H2, double &e2, bool energy)
{
  const double *rec = fix_bonds->kinv2[i];
  const double alpha = stab_scalar[atom->type[i]];
  double *q = qmat[i];
  if (rec[NOSPD::QuadraticFit::PACKED] == 0.0) {
    H2 = H;
    for (int k = 0; k < NOSPD::QREC; k++) q[k] = 0.0;
    e2 = energy ? nonaffine_moment(i, H, NOSPD::load(fix_bonds->kinv[i])).trace() : 0.0;
    return;
  }
  const Eigen::Map<const Eigen::Matrix<double, 3, 9>> N2(qsums[i]);
  const Eigen::Matrix<double, 3, 9> A = NOSPD::quadratic_fit(N2, rec);
  H2 = A.leftCols<3>();
  for (int k = 0; k < 6; k++)
    for (int r = 0; r < 3; r++) q[3 * k + r] = alpha * A(r, 3 + k);
  e2 = 0.0;
  if (energy) e2 = moments[i][0] + moments[i][1] + moments[i][2] - A.cwiseProduct(N2).sum();
}

NOSPD::Mat3 PairPeriNospd::nonaffine_moment(int i, const Mat3 &H, const Mat3 &Ki) const
{
  const Mat3 M = NOSPD::load_sym(moments[i]);
  Mat3 K = Ki.inverse();
  if (domain->dimension == 2) K(2, 2) = 0.0;
  return M - H * K * H.transpose();
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::threaded_ranges(int nthreads, int n, const RangeFn &fn)
{
  const int nranges = NOSPD::range_count(nthreads, n);
  std::vector<Tally> tally(nranges);
  NOSPD::run_ranges(nranges, n, [&](int from, int to, int tid) { fn(from, to, tid, tally[tid]); });
  for (const Tally &t : tally) add_tally(t);
}

void PairPeriNospd::add_tally(const Tally &t)
{
  eng_vdwl += t.eng;
  for (int k = 0; k < 6; k++) virial[k] += t.virial[k];
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::tally_energy(int i, double e)
{
  if (eflag_global) eng_vdwl += e;
  if (eflag_atom) eatom[i] += e;
}

namespace {

// what pass 2 adds up per point, besides the bond lists
struct ForceOut {
  double *f;                 // 3 per atom (atom->f, flat)
  double *v;                 // 6 per atom in range order, with VIRIAL
};

// the hourglass pass over pairs (lists in pair order), points [from, to)
template <int VIRIAL>
NOSPD_KERNEL_CLONES void hourglass_pairs_kernel(const NOSPD::Positions &p,
                                                const NOSPD::PairOrder &po, const int *bj,
                                                const double *bw, const NOSPD::ForceTerms &ft,
                                                const double *vol, const double *inv_vol,
                                                int from, int to, double *f, double *v)
{
  NOSPD::hourglass_pair_sums<VIRIAL>(p, po, bj, bw, ft, vol, inv_vol, from, to, f, v);
}

/* forces of points [from, to); without VIRIAL the i-terms B_i sum_j w xi
   and S_i sum_j w U come from the moments rather than from every bond */
template <NOSPD::StabPass STAB, int VIRIAL>
NOSPD_KERNEL_CLONES void force_range_kernel(const NOSPD::Positions &p, const int *first,
                                            const int *bj, const double *bw,
                                            const NOSPD::ForceTerms &ft, const double *ximom,
                                            const double *umom, const double *qsums, int from,
                                            int to, const ForceOut &out)
{
  for (int i = from; i < to; i++) {
    double f[3], v[6];
    NOSPD::force_sums<STAB, VIRIAL>(p, {bj, bw, first[i], first[i + 1]}, ft, i, f, v);
    if (!VIRIAL) {
      // B and T are stored transposed: B(r, k) = Bt[3 k + r]
      const double *Bt = ft.B + NOSPD::BREC * i;
      const double *m = ximom + 3 * i;
      for (int r = 0; r < 3; r++) f[r] += Bt[r] * m[0] + Bt[3 + r] * m[1] + Bt[6 + r] * m[2];
      const double *u = umom + 3 * i;
      if (NOSPD::has_springs(STAB)) {
        const double si = Bt[9];    // the stabilization scalar
        for (int r = 0; r < 3; r++) f[r] += si * u[r];
      }
      if (STAB == NOSPD::StabPass::SILLING_QUADRATIC) {
        // - alpha_i Q_i sum_j w phi_q(xi)
        const double *Qi = ft.Q + NOSPD::QREC * i, *q = qsums + NOSPD::QSUMS * i + 27;
        for (int r = 0; r < 3; r++)
          for (int k = 0; k < 6; k++) f[r] -= Qi[3 * k + r] * q[k];
      } else if (STAB == NOSPD::StabPass::WAN) {
        const double *Tt = ft.T + 9 * i;
        for (int r = 0; r < 3; r++) f[r] += Tt[r] * u[0] + Tt[3 + r] * u[1] + Tt[6 + r] * u[2];
      }
    }
    for (int d = 0; d < 3; d++) out.f[3 * i + d] += f[d];
    if (VIRIAL)
      for (int k = 0; k < 6; k++) out.v[6 * (i - from) + k] = v[k];
  }
}

}    // namespace

/* ----------------------------------------------------------------------
   pass 2: f_i = sum_j w ((B_i + B_j) xi + (S_i + S_j) U)  [+ hourglass]
   (the bond sums: nospd_bond_sums.h)
------------------------------------------------------------------------- */

template <NOSPD::StabPass STAB, int VIRIAL> void PairPeriNospd::force_pass(int /*eflag*/)
{
  if (STAB == NOSPD::StabPass::HOURGLASS && fix_bonds->pairs_ordered()) return hourglass_pair_pass<VIRIAL>();
  for_ranges(atom->nlocal, true,
             [&](int from, int to, int, Tally &t) { force_range<STAB, VIRIAL>(from, to, t); });
}

template <NOSPD::StabPass STAB, int VIRIAL> void PairPeriNospd::force_range(int from, int to, Tally &t)
{
  if (to <= from) return;
  const NOSPD::ForceTerms ft{bmat[0], tmat[0], STAB == NOSPD::StabPass::SILLING_QUADRATIC ? qmat[0] : nullptr};
  std::vector<double> v(VIRIAL ? 6 * (to - from) : 0);
  force_range_kernel<STAB, VIRIAL>(positions, fix_bonds->bond_first, fix_bonds->bond_j,
                                   fix_bonds->bond_w, ft, fix_bonds->xi_moment[0],
                                   fix_bonds->u_moment[0], STAB == NOSPD::StabPass::SILLING_QUADRATIC ? qsums[0] : nullptr, from,
                                   to, {atom->f[0], v.data()});
  if (!VIRIAL) return;
  for (int i = from; i < to; i++) {
    const double *vi = v.data() + 6 * (i - from);
    if (vflag_global)
      for (int k = 0; k < 6; k++) t.virial[k] += vi[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom[i][k] += vi[k];
  }
}

/* ----------------------------------------------------------------------
   the hourglass pass visiting each pair of owned points once (one thread:
   the partner's force is a scatter); the lists are in the bonds fix's pair
   order, which this style asks for where it runs the hourglass on one
   thread (pair_order_usable)
------------------------------------------------------------------------- */

template <int VIRIAL> void PairPeriNospd::hourglass_pair_pass()
{
  const int nlocal = atom->nlocal;
  const double *vfrac = atom->vfrac;
  inv_volume.resize(nlocal);
  for (int i = 0; i < nlocal; i++) inv_volume[i] = vfrac[i] > 0.0 ? 1.0 / vfrac[i] : 0.0;
  std::vector<double> v(VIRIAL ? 6 * nlocal : 0, 0.0);
  const NOSPD::PairOrder po{fix_bonds->bond_first, fix_bonds->bond_pair, fix_bonds->bond_ghost};
  hourglass_pairs_kernel<VIRIAL>(positions, po, fix_bonds->bond_j, fix_bonds->bond_w,
                                 {bmat[0], tmat[0]}, vfrac, inv_volume.data(), 0, nlocal,
                                 atom->f[0], v.data());
  if (!VIRIAL) return;
  for (int i = 0; i < nlocal; i++) {
    const double *vi = v.data() + 6 * i;
    if (vflag_global)
      for (int k = 0; k < 6; k++) virial[k] += vi[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom[i][k] += vi[k];
  }
}

/* ---------------------------------------------------------------------- */

int PairPeriNospd::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                     int * /*pbc*/)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int i = list[ii];
    for (int k = 0; k < NOSPD::BREC; k++) buf[m++] = bmat[i][k];
    if (comm_tensors == 2)
      for (int k = 0; k < 9; k++) buf[m++] = tmat[i][k];
    if (qmat)
      for (int k = 0; k < NOSPD::QREC; k++) buf[m++] = qmat[i][k];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  const int last = first + n;
  for (int i = first; i < last; i++) {
    for (int k = 0; k < NOSPD::BREC; k++) bmat[i][k] = buf[m++];
    if (comm_tensors == 2)
      for (int k = 0; k < 9; k++) tmat[i][k] = buf[m++];
    if (qmat)
      for (int k = 0; k < NOSPD::QREC; k++) qmat[i][k] = buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    fwrite(&youngs[i], sizeof(double), 1, fp);
    fwrite(&poisson[i], sizeof(double), 1, fp);
    fwrite(&g0[i], sizeof(double), 1, fp);
    fwrite(&flow[i], sizeof(NOSPD::FlowLaw), 1, fp);
    fwrite(&thermal[i], sizeof(NOSPD::ThermalLaw), 1, fp);
    fwrite(&drucker_prager[i], sizeof(NOSPD::DruckerPrager), 1, fp);
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) fwrite(&cut[i][j], sizeof(double), 1, fp);
    }
  }
  // user materials only where the law needs them: older restarts stay readable
  if (user_law()) user_materials->write_restart(fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    if (me == 0) {
      utils::sfread(FLERR, &youngs[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &poisson[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &g0[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &flow[i], sizeof(NOSPD::FlowLaw), 1, fp, nullptr, error);
      utils::sfread(FLERR, &thermal[i], sizeof(NOSPD::ThermalLaw), 1, fp, nullptr, error);
      if (restart_layout >= RESTART_LAYOUT_V4)
        utils::sfread(FLERR, &drucker_prager[i], sizeof(NOSPD::DruckerPrager), 1, fp, nullptr,
                      error);
    }
    MPI_Bcast(&drucker_prager[i], sizeof(NOSPD::DruckerPrager), MPI_BYTE, 0, world);
    MPI_Bcast(&flow[i], sizeof(NOSPD::FlowLaw), MPI_BYTE, 0, world);
    MPI_Bcast(&thermal[i], sizeof(NOSPD::ThermalLaw), MPI_BYTE, 0, world);
    MPI_Bcast(&youngs[i], 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&poisson[i], 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&g0[i], 1, MPI_DOUBLE, 0, world);
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        if (me == 0) utils::sfread(FLERR, &cut[i][j], sizeof(double), 1, fp, nullptr, error);
        MPI_Bcast(&cut[i][j], 1, MPI_DOUBLE, 0, world);
      }
    }
  }
  if (user_law()) user_materials->read_restart(fp);
}

/* ---------------------------------------------------------------------- */


void PairPeriNospd::write_restart_settings(FILE *fp)
{
  const int layout = RESTART_LAYOUT;
  fwrite(&layout, sizeof(int), 1, fp);
  int iv[4] = {static_cast<int>(strain_law), static_cast<int>(plane_mode),
               static_cast<int>(stab), influence};
  // the quadratic fit in a bit of its own: files without it read as before
  if (fit_quadratic) iv[2] |= 32;
  double dv[5] = {stab_param, thickness, singular_tol, damaged_tol, damaged_leverage};
  fwrite(iv, sizeof(int), 4, fp);
  fwrite(dv, sizeof(double), 5, fp);
  int tv[2] = {static_cast<int>(temperature_kind), static_cast<int>(temperature_name.size())};
  fwrite(tv, sizeof(int), 2, fp);
  fwrite(temperature_name.data(), 1, tv[1], fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::read_restart_settings(FILE *fp)
{
  int layout = 0;
  if (comm->me == 0) utils::sfread(FLERR, &layout, sizeof(int), 1, fp, nullptr, error);
  MPI_Bcast(&layout, 1, MPI_INT, 0, world);
  if (layout != RESTART_LAYOUT && layout != RESTART_LAYOUT_V3 && layout != RESTART_LAYOUT_V2)
    error->all(FLERR, "read_restart: the {} settings in this file were written by an older "
               "PERI-NOSPD plugin, whose layout this one cannot read: write the file again "
               "with this plugin", force->pair_style);
  int iv[4];
  double dv[5] = {0.0, 0.0, 0.0, 0.0, 1.0};
  restart_layout = layout;
  const int ndv = (layout == RESTART_LAYOUT_V2) ? 4 : 5;
  if (comm->me == 0) {
    utils::sfread(FLERR, iv, sizeof(int), 4, fp, nullptr, error);
    utils::sfread(FLERR, dv, sizeof(double), ndv, fp, nullptr, error);
  }
  MPI_Bcast(iv, 4, MPI_INT, 0, world);
  MPI_Bcast(dv, 5, MPI_DOUBLE, 0, world);
  int tv[2] = {0, 0};
  if (comm->me == 0) utils::sfread(FLERR, tv, sizeof(int), 2, fp, nullptr, error);
  MPI_Bcast(tv, 2, MPI_INT, 0, world);
  std::string tname(tv[1], ' ');
  if (comm->me == 0 && tv[1] > 0) utils::sfread(FLERR, &tname[0], 1, tv[1], fp, nullptr, error);
  if (tv[1] > 0) MPI_Bcast(&tname[0], tv[1], MPI_CHAR, 0, world);
  temperature_kind = static_cast<decltype(temperature_kind)>(tv[0]);
  temperature_name = tname;
  strain_law = static_cast<Law>(iv[0]);
  plane_mode = static_cast<Plane>(iv[1]);
  stab = static_cast<Stab>(iv[2] & 31);
  fit_quadratic = (iv[2] & 32) != 0;
  influence = iv[3];
  stab_param = dv[0];
  thickness = dv[1];
  singular_tol = dv[2];
  damaged_tol = dv[3];
  damaged_leverage = dv[4];
}

/* ---------------------------------------------------------------------- */

double PairPeriNospd::memory_usage()
{
  // bmat (B^T and the stabilization scalar), tmat (with its spare row),
  // moments, temperature_base
  return ((double) nmax_work * (NOSPD::BREC + 9 + 6 + 1) + 9 + inv_volume.capacity()) *
      sizeof(double);
}

/* ---------------------------------------------------------------------- */

void *PairPeriNospd::extract(const char *name, int &dim)
{
  dim = 2;
  if (strcmp(name, "delta") == 0 || strcmp(name, "cut") == 0) return (void *) cut;
  return nullptr;
}

// the Silling and hourglass passes are also run by the bond-associated style
template void LAMMPS_NS::PairPeriNospd::force_pass<NOSPD::StabPass::SILLING, 0>(int);
template void LAMMPS_NS::PairPeriNospd::force_pass<NOSPD::StabPass::SILLING, 1>(int);
template void LAMMPS_NS::PairPeriNospd::force_pass<NOSPD::StabPass::HOURGLASS, 0>(int);
template void LAMMPS_NS::PairPeriNospd::force_pass<NOSPD::StabPass::HOURGLASS, 1>(int);

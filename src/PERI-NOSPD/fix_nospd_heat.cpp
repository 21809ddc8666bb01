/* ----------------------------------------------------------------------
   PERI-NOSPD: fix nospd/heat -- peridynamic heat conduction on the points
   of a correspondence body (kernel: nospd_heat.h; doc/fix_nospd_heat.rst).
------------------------------------------------------------------------- */

#include "fix_nospd_heat.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "group.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "pair_peri_nospd_base.h"
#include "region.h"
#include "respa.h"
#include "update.h"
#include "variable.h"

#include "nospd_heat.h"
#include "nospd_input.h"
#include "nospd_threads.h"

#include <cmath>
#include <array>
#include <cstring>
#include <limits>

using namespace LAMMPS_NS;
using namespace FixConst;

static const char *CMD = "fix nospd/heat";
static constexpr int MAX_SUBSTEPS = 1000000;
static constexpr int FRAME_CHECK_EVERY = 100;
static constexpr double FRAME_WARN_STRAIN = 0.1;
static constexpr double MOMENT_TOLERANCE = 1e-4;

/* ---------------------------------------------------------------------- */

FixNospdHeat::FixNospdHeat(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg), tfield(nullptr), aux(nullptr)
{
  scalar_flag = 1;
  extscalar = 1;
  vector_flag = 1;
  size_vector = 4;
  extvector = 0;
  peratom_flag = 1;
  size_peratom_cols = 0;
  peratom_freq = 1;
  restart_global = 1;
  restart_peratom = 1;
  comm_forward = 3;
  create_attribute = 1;
  nevery = 1;
  parse(narg, arg);

  FixNospdHeat::grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++) FixNospdHeat::set_arrays(i);
}

/* ---------------------------------------------------------------------- */

FixNospdHeat::~FixNospdHeat()
{
  // at LAMMPS's end Force goes first
  if (lmp->force && lmp->force->pair)
    if (auto *p = PairPeriNospdBase::find(lmp->force))
      if (p->attached_heat() == this) p->attach_heat(nullptr);
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(tfield);
  memory->destroy(aux);
}

/* ---------------------------------------------------------------------- */

int FixNospdHeat::setmask()
{
  return PRE_FORCE | PRE_FORCE_RESPA;
}

/* ----------------------------------------------------------------------
   fix ID group nospd/heat keyword values ...
     initial T | v_name          temperature of points without one (default T_ref)
     fixed where T | v_name      held temperature
     convection where h T_inf    surface loss h A (T - T_inf)
     flux where q | v_name       surface input q A (W/m^2)
   (where: a group-ID, or region region-ID)
     source s | v_name           volumetric source (W/m^3)
     substeps auto | N
     frame reference | current    where the bonds conduct (default reference)
------------------------------------------------------------------------- */

void FixNospdHeat::parse(int narg, char **arg)
{
  int i = 3;
  auto need = [&](int n, const char *key) {
    if (i + n >= narg) error->all(FLERR, "{}: keyword {} needs {} value(s)", CMD, key, n);
  };
  // group-ID, or region region-ID; i moves past it
  auto where = [&](Condition &c, const char *key) {
    if (strcmp(arg[i + 1], "region") == 0) {
      need(2, key);
      c.by_region = true;
      c.group = arg[i + 2];
      if (!domain->get_region_by_id(c.group))
        error->all(FLERR, "{}: {} region {} does not exist", CMD, key, c.group);
      i += 1;
    } else {
      c.group = arg[i + 1];
      const int g = group->find(c.group);
      if (g < 0) error->all(FLERR, "{}: {} group {} does not exist", CMD, key, c.group);
      c.groupbit = group->bitmask[g];
    }
  };
  while (i < narg) {
    const std::string key = arg[i];
    if (key == "initial") {
      need(1, "initial");
      initial = value_of(arg[i + 1], "initial", true);
      have_initial = true;
      i += 2;
    } else if (key == "fixed" || key == "flux") {
      need(2, key.c_str());
      Condition c;
      c.kind = key == "fixed" ? Condition::FIXED : Condition::FLUX;
      where(c, key.c_str());
      need(2, key.c_str());
      c.value = value_of(arg[i + 2], key.c_str(), true);
      conditions.push_back(c);
      i += 3;
    } else if (key == "convection") {
      need(3, "convection");
      Condition c;
      c.kind = Condition::CONVECTION;
      where(c, "convection");
      need(3, "convection");
      c.value = value_of(arg[i + 2], "convection h", false);
      if (!(c.value.number > 0.0))
        error->all(FLERR, "{}: convection h must be > 0 (W/m^2/K), got {}", CMD, arg[i + 2]);
      c.T_inf = NOSPD_INPUT::real(error, CMD, "convection T_inf", arg[i + 3]);
      conditions.push_back(c);
      i += 4;
    } else if (key == "source") {
      need(1, "source");
      source = value_of(arg[i + 1], "source", true);
      have_source = true;
      i += 2;
    } else if (key == "substeps") {
      need(1, "substeps");
      substeps_user = strcmp(arg[i + 1], "auto") == 0
          ? 0
          : NOSPD_INPUT::integer(error, CMD, "substeps", arg[i + 1], 1, MAX_SUBSTEPS);
      i += 2;
    } else if (key == "frame") {
      need(1, "frame");
      if (strcmp(arg[i + 1], "reference") == 0)
        current_frame = false;
      else if (strcmp(arg[i + 1], "current") == 0)
        current_frame = true;
      else
        error->all(FLERR, "{}: frame expects reference or current, got '{}'", CMD, arg[i + 1]);
      i += 2;
    } else
      error->all(FLERR, "{}: unknown keyword '{}' (initial, fixed, convection, flux, source, "
                 "substeps, frame)", CMD, key);
  }
}

FixNospdHeat::Value FixNospdHeat::value_of(const char *word, const char *what, bool allow_var)
{
  Value v;
  if (strncmp(word, "v_", 2) == 0) {
    if (!allow_var) error->all(FLERR, "{}: {} takes a number, not a variable ({})", CMD, what, word);
    v.var = word + 2;
  } else
    v.number = NOSPD_INPUT::real(error, CMD, what, word);
  return v;
}

/* ---------------------------------------------------------------------- */

void FixNospdHeat::resolve(Value &v, const char *what)
{
  if (v.var.empty()) return;
  v.index = input->variable->find(v.var.c_str());
  if (v.index < 0) error->all(FLERR, "{}: {} variable {} does not exist", CMD, what, v.var);
  if (input->variable->equalstyle(v.index))
    v.style = 1;
  else if (input->variable->atomstyle(v.index))
    v.style = 2;
  else
    error->all(FLERR, "{}: {} variable {} is neither equal- nor atom-style", CMD, what, v.var);
}

// a value per owned atom (out[i]); a non-finite one is an error
void FixNospdHeat::evaluate(const Value &v, std::vector<double> &out)
{
  const int nlocal = atom->nlocal;
  out.assign(nlocal, v.number);
  NOSPD_INPUT::variable_in_range(error, CMD, v.var, [&]() {
    if (v.style == 1)
      out.assign(nlocal, input->variable->compute_equal(v.index));
    else if (v.style == 2)
      input->variable->compute_atom(v.index, igroup, out.data(), 1, 0);
  });
  for (int i = 0; i < nlocal; i++)
    if ((atom->mask[i] & groupbit) && !std::isfinite(out[i]))
      error->one(FLERR, "{}: variable {} gives {} at atom {} on step {}", CMD, v.var, out[i],
                 atom->tag[i], update->ntimestep);
}

/* ---------------------------------------------------------------------- */

void FixNospdHeat::init()
{
  pair = PairPeriNospdBase::find(force);
  if (!pair)
    error->all(FLERR, "{} needs pair_style peri/nospd or peri/nospd/hs (alone or in pair "
               "hybrid): it conducts on their bond families", CMD);
  if (pair->temperature_given())
    error->all(FLERR, "{}: pair_style {} has its own temperature keyword; fix nospd/heat owns "
               "the temperature: drop the pair style's temperature keyword", CMD,
               force->pair_style);
  if (auto *other = pair->attached_heat(); other && other != this)
    error->all(FLERR, "{}: fix {} already owns the temperature; one fix nospd/heat per run",
               CMD, other->id);
  pair->attach_heat(this);
  nlevels_respa = 0;
  if (utils::strmatch(update->integrate_style, "^respa"))
    nlevels_respa = dynamic_cast<Respa *>(update->integrate)->nlevels;
  bonds = dynamic_cast<FixNospdBonds *>(modify->get_fix_by_id(FixNospdBonds::ID));
  if (!atom->rmass_flag || !atom->vfrac_flag)
    error->all(FLERR, "{} needs atom_style peri (density as rmass, volume as vfrac)", CMD);
  resolve(initial, "initial");
  resolve(source, "source");
  for (auto &c : conditions) {
    if (c.by_region) {
      c.region = domain->get_region_by_id(c.group);
      if (!c.region) error->all(FLERR, "{}: region {} was deleted", CMD, c.group);
      c.region->prematch();
    } else {
      const int g = group->find(c.group);
      if (g < 0) error->all(FLERR, "{}: group {} was deleted", CMD, c.group);
      c.groupbit = group->bitmask[g];
    }
    resolve(c.value, c.kind == Condition::FIXED ? "fixed" : "flux");
  }
  const int ntypes = atom->ntypes;
  k_type.assign(ntypes + 1, 0.0);
  c_type.assign(ntypes + 1, 0.0);
  for (int t = 1; t <= ntypes; t++) {
    if (!pair->owns_type(t)) continue;
    k_type[t] = pair->thermal_law(t).k;
    c_type[t] = pair->thermal_law(t).c;
  }
  check_types_and_groups();
  initialize_new_points();
  coef_version = -1;
}

/* ----------------------------------------------------------------------
   every point of the group conducts; every fixed group has points
------------------------------------------------------------------------- */

void FixNospdHeat::check_types_and_groups()
{
  const int ntypes = atom->ntypes;
  std::vector<int> bad(ntypes + 1, 0), all(ntypes + 1, 0);
  for (int i = 0; i < atom->nlocal; i++)
    if ((atom->mask[i] & groupbit) && !(k_type[atom->type[i]] > 0.0)) bad[atom->type[i]] = 1;
  MPI_Allreduce(bad.data(), all.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  for (int t = 1; t <= ntypes; t++)
    if (all[t])
      error->all(FLERR, "{}: atoms of type {} in group {} have no conduction: give "
                 "'conduction k c' in their pair_coeff (conductivity W/m/K, specific heat "
                 "J/kg/K)", CMD, t, group->names[igroup]);
  for (const auto &c : conditions) {
    bigint n = 0, nall = 0;
    for (int i = 0; i < atom->nlocal; i++)
      if (under(c, i)) n++;
    MPI_Allreduce(&n, &nall, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    if (nall > 0) continue;
    // a region may fill later (dynamic, or atoms moving into it)
    if (c.by_region) {
      if (comm->me == 0)
        error->warning(FLERR, "{}: region {} holds no atoms of group {} now; its condition "
                       "acts once atoms are inside", CMD, c.group, group->names[igroup]);
    } else
      error->all(FLERR, "{}: group {} has no atoms of group {}: its condition would do "
                 "nothing", CMD, c.group, group->names[igroup]);
  }
}

/* ----------------------------------------------------------------------
   points without a temperature (new, or the first run): initial, else the
   type's T_ref
------------------------------------------------------------------------- */

void FixNospdHeat::initialize_new_points()
{
  const int nlocal = atom->nlocal;
  int any = 0, anyall = 0;
  for (int i = 0; i < nlocal; i++)
    if (std::isnan(tfield[i])) any = 1;
  MPI_Allreduce(&any, &anyall, 1, MPI_INT, MPI_MAX, world);
  if (!anyall) return;
  std::vector<double> T0;
  if (have_initial) evaluate(initial, T0);
  for (int i = 0; i < nlocal; i++) {
    if (!std::isnan(tfield[i])) continue;
    const int t = atom->type[i];
    tfield[i] = have_initial ? T0[i] : (pair->owns_type(t) ? pair->thermal_law(t).T_ref : 0.0);
    aux[i][SEEN] = pair->adiabatic_heat(i);
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdHeat::setup(int /*vflag*/)
{
  if (!bonds || !bonds->bond_arrays_current())
    error->all(FLERR, "{}: the bond families are not built (a run of the pair style builds "
               "them before its first force)", CMD);
  calibrate();
  // (the moments' kappas are not taken again here: a restart's setup would
  // then differ from the run it continues)
  if (current_frame) step_geometry(false);
  comm->forward_comm(this);
  build_coefficients();
  dt_stable = stable_step();
  step_sources();
  apply_fixed();
  const double dt = update->dt;
  const double need = std::isfinite(dt_stable) ? std::ceil(dt / dt_stable) : 1.0;
  if (!substeps_user && !(need <= MAX_SUBSTEPS))
    error->all(FLERR, "{}: the stable thermal step {:.6g} is below timestep {:.6g} / {}: check "
               "conduction k, c, density and convection h, or reduce the timestep", CMD,
               dt_stable, dt, MAX_SUBSTEPS);
  nsub = substeps_user ? substeps_user : std::max(1, (int) need);
  if (comm->me == 0)
    utils::logmesg(lmp, "{}: stable thermal step {:.6g} (forward Euler bound), {} substep(s) "
                   "of {:.6g} per step of {:.6g}\n", CMD, dt_stable, nsub, dt / nsub, dt);
  if (dt / nsub > dt_stable && !warned_step) {
    warned_step = true;
    error->warning(FLERR, "{}: thermal step {:.6g} (timestep / substeps {}) is above the stable "
                   "bound {:.6g}: temperatures may oscillate and grow; use substeps auto or "
                   "substeps {} or more", CMD, dt / nsub, nsub, dt_stable,
                   (int) std::ceil(dt / dt_stable));
  }
}

/* ----------------------------------------------------------------------
   kappa and exposed area of points without them, from their families as
   built (a point created later calibrates at the next setup)
------------------------------------------------------------------------- */

void FixNospdHeat::calibrate()
{
  const int nlocal = atom->nlocal, dim = domain->dimension;
  const double t = bonds->get_model().thickness;
  const double *vfrac = atom->vfrac;
  std::vector<std::array<double, 3>> xi;
  for (int i = 0; i < nlocal; i++) {
    if (aux[i][KAPPA] >= 0.0) continue;
    if (!(atom->mask[i] & groupbit)) {
      aux[i][KAPPA] = 0.0;
      continue;
    }
    xi.clear();
    NOSPD::Mat3 M = NOSPD::Mat3::Zero();
    for (int b = bonds->bond_first[i]; b < bonds->bond_first[i + 1]; b++) {
      std::array<double, 3> v;
      bonds->bond_vector(i, b, v.data());
      xi.push_back(v);
      NOSPD::Heat::add_moment(M, v.data(), vfrac[bonds->bond_j[b]]);
    }
    aux[i][KAPPA] = NOSPD::Heat::micro_conductivity(k_type[atom->type[i]], M);
    const double V = vfrac[i];
    const double h = dim == 3 ? std::cbrt(V) : std::sqrt(V / t);
    aux[i][FACES] = NOSPD::Heat::exposed_faces(reinterpret_cast<const double(*)[3]>(xi.data()),
                                               (int) xi.size(), h, dim);
    aux[i][AREA0] = NOSPD::Heat::face_area(V, dim, t);
  }
}

/* ----------------------------------------------------------------------
   c_b of every bond of the owned points (nospd_heat.h); ghost kappas from
   the last forward communication.  Points outside the group have kappa 0.
------------------------------------------------------------------------- */

void FixNospdHeat::build_coefficients()
{
  const int nlocal = atom->nlocal;
  const double *vfrac = atom->vfrac;
  coef.assign(bonds->bond_first[nlocal], 0.0);
  rowsum.assign(nlocal, 0.0);
  for (int i = 0; i < nlocal; i++) {
    if (!(kappa_of(i) > 0.0)) continue;
    const double vi = current_frame ? vfrac[i] * jcur[i] : vfrac[i];
    for (int b = bonds->bond_first[i]; b < bonds->bond_first[i + 1]; b++) {
      const int j = bonds->bond_j[b];
      double len = 0.0;
      if (current_frame)
        len = blen[b];    // step_geometry's
      else {
        double v[3];
        bonds->bond_vector(i, b, v);
        len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      }
      const double vj = current_frame ? vfrac[j] * jcur[j] : vfrac[j];
      coef[b] = NOSPD::Heat::bond_coefficient(kappa_of(i), kappa_of(j), len, vi, vj);
      rowsum[i] += coef[b];
    }
  }
  coef_version = bonds->bond_version;
  coef_atoms = nlocal;
}

/* ----------------------------------------------------------------------
   frame current, once per MD step: kappa from the current family (current
   bonds, volumes J V), J, and the faces' current area (Nanson)
------------------------------------------------------------------------- */

void FixNospdHeat::step_geometry(bool retake)
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  kcur.resize(std::max<size_t>(kcur.size(), atom->nmax));
  jcur.resize(std::max<size_t>(jcur.size(), atom->nmax));
  area_now.resize(nlocal);
  double **x = atom->x;
  const double *vfrac = atom->vfrac;
  for (int i = 0; i < nlocal; i++) {
    const NOSPD::Mat3 F = NOSPD::load(bonds->defgrad[i]);
    const double J = F.determinant();
    jcur[i] = J > 0.0 ? J : 1.0;
  }
  // the partners' J (ghosts) before the moments that weigh by them
  comm_mode = 1;
  comm->forward_comm(this);
  comm_mode = 0;
  blen.resize(bonds->bond_first[nlocal]);
  for (int i = 0; i < nlocal; i++) {
    kcur[i] = 0.0;
    area_now[i] = 0.0;
    if (!(atom->mask[i] & groupbit) || !(aux[i][KAPPA] > 0.0)) continue;
    double m[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};    // xx yy zz xy xz yz
    for (int b = bonds->bond_first[i]; b < bonds->bond_first[i + 1]; b++) {
      const int j = bonds->bond_j[b];
      const double v0 = x[j][0] - x[i][0], v1 = x[j][1] - x[i][1], v2 = x[j][2] - x[i][2];
      const double len = std::sqrt(v0 * v0 + v1 * v1 + v2 * v2);
      blen[b] = len;
      const double w = len > 0.0 ? vfrac[j] * jcur[j] / len : 0.0;
      m[0] += w * v0 * v0, m[1] += w * v1 * v1, m[2] += w * v2 * v2;
      m[3] += w * v0 * v1, m[4] += w * v0 * v2, m[5] += w * v1 * v2;
    }
    // the eigenvalue again only where the moment moved (it costs as much as
    // the bond loop)
    double *mcal = aux[i] + MCAL, moved = 0.0;
    for (int k = 0; k < 6; k++) moved = std::max(moved, std::fabs(m[k] - mcal[k]));
    if (!(aux[i][KCUR] > 0.0) || (retake && !(moved <= MOMENT_TOLERANCE * (m[0] + m[1] + m[2])))) {
      NOSPD::Mat3 M;
      M << m[0], m[3], m[4], m[3], m[1], m[5], m[4], m[5], m[2];
      aux[i][KCUR] = NOSPD::Heat::micro_conductivity(k_type[atom->type[i]], M);
      for (int k = 0; k < 6; k++) mcal[k] = m[k];
    }
    kcur[i] = aux[i][KCUR];
    if (aux[i][FACES] != 0.0)
      area_now[i] = NOSPD::Heat::deformed_area((int) aux[i][FACES], aux[i][AREA0],
                                               NOSPD::load(bonds->defgrad[i]));
  }
  for (int i = nlocal; i < nall; i++) kcur[i] = 0.0;    // set by the next forward comm
  coef_version = -1;
}

// the exposed area of owned atom i this step
double FixNospdHeat::area(int i) const
{
  return current_frame ? area_now[i]
                       : NOSPD::Heat::face_count((int) aux[i][FACES]) * aux[i][AREA0];
}

bool FixNospdHeat::under(const Condition &c, int i) const
{
  if (!(atom->mask[i] & groupbit)) return false;
  if (c.by_region) return c.region && c.region->match(atom->x[i][0], atom->x[i][1], atom->x[i][2]);
  return (atom->mask[i] & c.groupbit) != 0;
}

double FixNospdHeat::capacity(int i) const
{
  return atom->rmass[i] * c_type[atom->type[i]] * atom->vfrac[i];
}

// the smallest bound over the group's points (global); breaks only raise it
double FixNospdHeat::stable_step() const
{
  const int nlocal = atom->nlocal;
  double lo = HUGE_VAL;
  for (int i = 0; i < nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    double cs = rowsum[i];    // build_coefficients'
    for (const auto &c : conditions)
      if (c.kind == Condition::CONVECTION && under(c, i))
        cs += c.value.number * area(i);
    lo = std::min(lo, NOSPD::Heat::step_bound(capacity(i), cs));
  }
  double all = lo;
  MPI_Allreduce(&lo, &all, 1, MPI_DOUBLE, MPI_MIN, world);
  return all;
}

/* ----------------------------------------------------------------------
   one MD step, before its forces: the last step's accepted heating into the
   field, then nsub explicit steps
------------------------------------------------------------------------- */

void FixNospdHeat::pre_force(int /*vflag*/)
{
  move_plastic_heat();
  step_sources();
  if (!bonds->bond_arrays_current())
    error->one(FLERR, "{}: the bond lists do not cover the atoms on step {}", CMD,
               update->ntimestep);
  if (current_frame) {
    step_geometry(true);
    comm->forward_comm(this);
    build_coefficients();
    dt_stable = stable_step();
    const double need = std::ceil(update->dt / dt_stable);
    if (!substeps_user && !(need <= MAX_SUBSTEPS))
      error->all(FLERR, "{}: step {}: the stable thermal step {:.6g} of the deformed body is "
                 "below timestep / {}", CMD, update->ntimestep, dt_stable, MAX_SUBSTEPS);
    nsub = substeps_user ? substeps_user : std::max(1, (int) need);
  } else if (update->ntimestep % FRAME_CHECK_EVERY == 0)
    check_frame();
  const double dts = update->dt / nsub;
  for (int s = 0; s < nsub; s++) substep(dts);
}

// run_style respa: once per outer step, before the outermost level's forces
void FixNospdHeat::pre_force_respa(int vflag, int ilevel, int /*iloop*/)
{
  if (ilevel == nlevels_respa - 1) pre_force(vflag);
}

/* ----------------------------------------------------------------------
   frame reference: conduction ignores the deformation; warn once where it
   is large
------------------------------------------------------------------------- */

void FixNospdHeat::check_frame()
{
  if (warned_frame) return;
  double big = 0.0, all = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    const NOSPD::Mat3 F = NOSPD::load(bonds->defgrad[i]);
    big = std::max(big, (F - NOSPD::Mat3::Identity()).norm());
  }
  MPI_Allreduce(&big, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (all > FRAME_WARN_STRAIN) {
    warned_frame = true;
    if (comm->me == 0)
      error->warning(FLERR, "{}: points deform by up to |F - I| = {:.3g} on step {}; conduction "
                     "in the reference frame (the default) sees the undeformed bonds, volumes "
                     "and faces: use frame current for large deformation", CMD, all,
                     update->ntimestep);
  }
}

// this step's values of the conditions and the source, per owned atom
void FixNospdHeat::step_sources()
{
  for (auto &c : conditions)
    if (c.region) c.region->prematch();
  values.resize(conditions.size());
  for (size_t n = 0; n < conditions.size(); n++) evaluate(conditions[n].value, values[n]);
  if (have_source)
    evaluate(source, extra);
  else
    extra.assign(atom->nlocal, 0.0);
}

void FixNospdHeat::move_plastic_heat()
{
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double h = pair->adiabatic_heat(i, true), d = h - aux[i][SEEN];
    if (d == 0.0) continue;
    tfield[i] += d;
    aux[i][SEEN] = h;
    plastic_in += capacity(i) * d;
  }
}

void FixNospdHeat::substep(double dt)
{
  comm->forward_comm(this);
  const int nlocal = atom->nlocal;
  if (coef_version != bonds->bond_version || coef_atoms != nlocal) build_coefficients();
  rate.resize(nlocal);
  // split over the OpenMP threads of -sf omp / package omp: each point's
  // sum is its own, so any split gives the same bits
  NOSPD::run_ranges(comm->nthreads, nlocal, [&](int from, int to, int) {
    NOSPD::Heat::exchange(bonds->bond_first, bonds->bond_j, coef.data(), tfield, from, to,
                          rate.data());
  });
  const double *vfrac = atom->vfrac;
  const int *mask = atom->mask;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double q = extra[i] * vfrac[i];    // volumetric source
    for (size_t n = 0; n < conditions.size(); n++) {
      const auto &c = conditions[n];
      if (c.kind == Condition::FIXED || !under(c, i)) continue;
      if (c.kind == Condition::CONVECTION)
        q -= c.value.number * area(i) * (tfield[i] - c.T_inf);
      else
        q += values[n][i] * area(i);
    }
    inflow += dt * q;
    tfield[i] += dt * (rate[i] + q) / capacity(i);
    if (!std::isfinite(tfield[i]))
      error->one(FLERR, "{}: atom {} reached temperature {} on step {} (its flux {:.6g} W, source "
                 "{:.6g} W): check the flux, source and convection values", CMD, atom->tag[i],
                 tfield[i], update->ntimestep, rate[i], q);
  }
  apply_fixed();
}

// held temperatures, last; what holding them puts in counts as inflow
void FixNospdHeat::apply_fixed()
{
  for (size_t n = 0; n < conditions.size(); n++) {
    const auto &c = conditions[n];
    if (c.kind != Condition::FIXED) continue;
    for (int i = 0; i < atom->nlocal; i++) {
      if (!under(c, i)) continue;
      const double T = values[n][i];
      inflow += capacity(i) * (T - tfield[i]);
      tfield[i] = T;
    }
  }
}

/* ---------------------------------------------------------------------- */

double FixNospdHeat::base_temperature(int i, int /*itype*/) const
{
  return tfield[i] - aux[i][SEEN];
}

void FixNospdHeat::prepare_flux()
{
  comm->forward_comm(this);
}

void FixNospdHeat::heat_flux(int i, double *q) const
{
  q[0] = q[1] = q[2] = 0.0;
  if (!(atom->mask[i] & groupbit) || !bonds || !bonds->bond_arrays_current()) return;
  double s[3] = {0.0, 0.0, 0.0};
  for (int b = bonds->bond_first[i]; b < bonds->bond_first[i + 1]; b++) {
    double v[3];
    bonds->bond_vector(i, b, v);
    const double d = bonds->bond_w[b] * (tfield[bonds->bond_j[b]] - tfield[i]);
    for (int a = 0; a < 3; a++) s[a] += d * v[a];
  }
  const double *K = bonds->kinv[i];
  const double k = k_type[atom->type[i]];
  NOSPD::Vec3 g;    // grad_X T; frame current: grad_x T = F^-T grad_X T
  for (int a = 0; a < 3; a++) g(a) = K[3 * a] * s[0] + K[3 * a + 1] * s[1] + K[3 * a + 2] * s[2];
  if (current_frame) {
    const NOSPD::Mat3 F = NOSPD::load(bonds->defgrad[i]);
    if (F.determinant() > 0.0) g = F.inverse().transpose() * g;
  }
  for (int a = 0; a < 3; a++) q[a] = -k * g(a);
}

/* ---------------------------------------------------------------------- */

double FixNospdHeat::compute_scalar()
{
  double e = 0.0, all = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit) e += capacity(i) * (tfield[i] + pending(i));
  MPI_Allreduce(&e, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

// 1 stable thermal step, 2 substeps, 3 energy put in by the conditions and
// the source, 4 plastic heating (cumulative; 4 and the scalar count the
// heating of the last step, which moves into the field at the next)
double FixNospdHeat::compute_vector(int n)
{
  if (n == 0) return dt_stable;
  if (n == 1) return nsub;
  double v = inflow;
  if (n == 3) {
    v = plastic_in;
    for (int i = 0; i < atom->nlocal; i++)
      if (atom->mask[i] & groupbit) v += capacity(i) * pending(i);
  }
  double all = 0.0;
  MPI_Allreduce(&v, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

// the law's heating of owned atom i not yet moved into the field
double FixNospdHeat::pending(int i) const
{
  return pair ? pair->adiabatic_heat(i, true) - aux[i][SEEN] : 0.0;
}

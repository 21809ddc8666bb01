/* ----------------------------------------------------------------------
   PERI-NOSPD: the classical style's init_style and its checks: the bonds fix, the
   stable time step's stiffness bound, hybrid styles and communication,
   barostats, the plane assumption, the restart's history law.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_base.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "input.h"
#include "lattice.h"
#include "min_nospd_newton.h"
#include "modify.h"
#include "update.h"
#include "variable.h"

#include "nospd_bond_sums.h"

#include <algorithm>
#include <cmath>
#include <vector>

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;
using NOSPD::Stab;

static constexpr double BIG = 1.0e300;

/* ---------------------------------------------------------------------- */

double PairPeriNospdBase::init_one(int i, int j)
{
  check_material(i);
  check_material(j);
  if (setflag[i][j] == 0) cut[i][j] = MAX(cut[i][i], cut[j][j]);
  cut[j][i] = cut[i][j];
  return cut[i][j];
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::init_style()
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  check_run_environment(cmd);
  // the types this style owns: under pair hybrid, only those given to it
  active.assign(atom->ntypes + 1, 0);
  for (int i = 1; i <= atom->ntypes; i++) active[i] = (setflag[i][i] && youngs[i] > 0.0);

  check_points(cmd);
  setup_type_constants();
  const int history_size = setup_laws(cmd);
  configure_bonds_fix(history_size);
}

/* ----------------------------------------------------------------------
   what the style needs of the run: atom style, map, units, 2D's periodic
   z; barostats and a minimizer that needs a potential are warned about
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_run_environment(const std::string &cmd)
{
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
  // (FIRE and the Newton minimizer's GMRES do not)
  const std::string why = update->whichflag == 2 &&
          !utils::strmatch(update->minimize_style, "^fire") &&
          !MinNospdNewton::selected(update)
      ? not_a_potential() : "";
  if (!why.empty() && !minimize_warned && comm->me == 0)
    error->warning(FLERR, "minimize with {} ({}): CG and the line searches need forces that "
                   "are the gradient of the energy; use min_style fire (or damped dynamics)",
                   cmd, why);
  if (!why.empty()) minimize_warned = true;
}

/* ----------------------------------------------------------------------
   Silling's springs on the linear fit store the curvature of a smooth
   plastic flow and hold large flows back (Taylor bars 19-27 % narrow:
   doc Howto_choose_model, "Warnings"); contained plastic zones are right
   with them.  Said once, with the alternatives.
------------------------------------------------------------------------- */

void PairPeriNospdBase::warn_plastic_flow(const std::string &cmd)
{
  if (plastic_flow_warned || family_kind() != 1 || stab != Stab::SILLING || fit_quadratic) return;
  int plastic = 0;
  // a flow law, not only history (a thermal-only type keeps history and is elastic)
  for (int i = 1; i <= atom->ntypes && !plastic; i++)
    if (active[i] && has_history(i) && (flow[i].active || drucker_prager[i].active)) plastic = i;
  if (!plastic) return;
  plastic_flow_warned = true;
  if (comm->me == 0)
    error->warning(FLERR, "{}: type {} is plastic and `stabilization silling {:g}` acts on the "
                   "linear fit, whose springs hold large plastic flow back (measured: Taylor "
                   "bar footprints 19-27 % narrow); for large flow (impacts, forming) use "
                   "stabilization silling 0.5 stabilization/fit quadratic (footprints within "
                   "3.3 %, bench/scenes/run_suite.py); plastic zones of a few per cent strain "
                   "are right as they are (doc Howto_choose_model, \"Warnings\")", cmd,
                   plastic, stab_param);
}

/* ----------------------------------------------------------------------
   every owned point of an active type has a volume and a density, and the
   horizons reach beyond the spacing of the points
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_points(const std::string &cmd)
{
  const int dim = domain->dimension;
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

}

/* ----------------------------------------------------------------------
   per-type constants of the law and of the stabilization, and what the
   forward communication carries
------------------------------------------------------------------------- */

void PairPeriNospdBase::setup_type_constants()
{
  const int dim = domain->dimension;
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

}

/* ----------------------------------------------------------------------
   the material table: user materials set up, each type's inelastic kind,
   the laws (build_materials) and the temperature source; returns the
   history size a point needs
------------------------------------------------------------------------- */

int PairPeriNospdBase::setup_laws(const std::string &cmd)
{
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
  warn_plastic_flow(cmd);
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

  return history_size;
}

/* ----------------------------------------------------------------------
   the bonds fix: made or kept, its history sized, its model (horizons,
   influence, tolerances, wave micromodulus, stiffness bound) set
------------------------------------------------------------------------- */

void PairPeriNospdBase::configure_bonds_fix(int history_size)
{
  const int dim = domain->dimension;
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
  model.carry = carries_deformation();
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

void PairPeriNospdBase::set_stiffness_bound(NospdBondModel &m)
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
    case Stab::SILLING: m.spring_kind = NOSPD::SpringKind::PER_WEIGHT; break;
    case Stab::HOURGLASS: m.spring_kind = NOSPD::SpringKind::PER_LENGTH; break;
    case Stab::WAN: m.spring_kind = NOSPD::SpringKind::WAN; break;
    default: m.spring_kind = NOSPD::SpringKind::NONE;
  }
  m.family_rows = family_row_bound();
  m.bound_margin = bound_margin();
  m.zem_control = zem_control();
}

/* the zero-energy-mode control as written in pair_style, for the bonds
   fix's warning (the classical style's: the bond-associated style has no
   zero-energy modes to control) */

std::string PairPeriNospdBase::zem_control() const
{
  if (family_kind() != 1) return "";
  switch (stab) {
    case Stab::SILLING:
      return fmt::format("silling {:g}{}", stab_param,
                         fit_quadratic ? " stabilization/fit quadratic" : "");
    case Stab::HOURGLASS: return fmt::format("hourglass {:g}", stab_param);
    case Stab::WAN: return "wan";
    default: return "none";
  }
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

void PairPeriNospdBase::raise_hybrid_comm_forward()
{
  if (force->pair && force->pair != this)
    force->pair->comm_forward = MAX(force->pair->comm_forward, comm_forward);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::warn_barostats(const std::string &cmd)
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

void PairPeriNospdBase::check_one_plane(double spacing)
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

void PairPeriNospdBase::check_history_law()
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
        return fmt::format("plasticity under strain {}", NOSPD::law_keyword(static_cast<Law>(code - 1)));
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

void PairPeriNospdBase::ensure_bonds_fix()
{
  auto *f = modify->get_fix_by_id(FixNospdBonds::ID);
  if (fix_bonds) {
    if (f == fix_bonds) return;
    error->all(FLERR, "pair_style {}: fix {} was deleted (unfix): it holds the bond families "
               "and their state, and lives as long as the pair style (a new pair_style "
               "command starts new families)", force->pair_style, FixNospdBonds::ID);
  }
  if (!f) {
    struct Making {    // the flag falls back also when add_fix throws
      Making() { FixNospdBonds::made_by_pair_style = true; }
      ~Making() { FixNospdBonds::made_by_pair_style = false; }
    } making;
    f = modify->add_fix(fmt::format("{} all PERI_NEIGH/NOSPD", FixNospdBonds::ID));
  }
  fix_bonds = dynamic_cast<FixNospdBonds *>(f);
  if (!fix_bonds)
    error->all(FLERR, "pair_style {}: fix {} exists but is not a PERI_NEIGH/NOSPD fix",
               force->pair_style, FixNospdBonds::ID);
}

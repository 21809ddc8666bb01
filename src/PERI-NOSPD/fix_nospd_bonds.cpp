/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Owner of bond families, reference state (K^-1) and deformation state (F).
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "math_const.h"
#include "memory.h"
#include "min.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "output.h"
#include "thermo.h"
#include "update.h"

#include "nospd_bond_sums.h"
#include "nospd_plasticity.h"
#include "nospd_simd.h"
#include "nospd_tensor.h"

static constexpr int NOSPD_HIST_WORK = NOSPD::Hist::WORK;

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

bool FixNospdBonds::made_by_pair_style = false;

namespace {
// the reference box of a bonds fix that a pair_style command deleted (its
// destructor runs while LAMMPS goes on), per LAMMPS instance, with the
// fingerprint of the x0 it was the box of: the next style's fix builds its
// families from the same x0 and must take the same box
struct ReplacedBox {
  double ref_h[6], last_h[6], print[7];
  double initclock;    // of the instance (another may come at the same address)
};
std::map<const LAMMPS *, ReplacedBox> replaced_boxes;
}    // namespace

/* ---------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   only the pair style makes this fix: a second instance under its ID would
   replace the one that holds the families while the pair style still
   points at it.  Checked before FixPeriNeigh's constructor runs, whose
   destructor could not undo its callbacks for a fix not yet in the list.
------------------------------------------------------------------------- */

static int made_by_pair_or_error(LAMMPS *lmp, int narg, char **arg)
{
  if (!FixNospdBonds::made_by_pair_style)
    lmp->error->all(FLERR, "Fix {} {}: this fix is internal: pair_style peri/nospd makes it, as "
                    "fix NOSPD_BONDS, and it lives as long as the pair style; do not define it "
                    "in an input script", narg > 0 ? arg[0] : "", narg > 2 ? arg[2] : "");
  return narg;
}

FixNospdBonds::FixNospdBonds(LAMMPS *lmp, int narg, char **arg) :
    FixPeriNeigh(lmp, made_by_pair_or_error(lmp, narg, arg), arg), nbond_atoms(0), bond_version(0), bond_first(nullptr), bond_j(nullptr),
    bond_slot(nullptr), bond_w(nullptr), bond_pair(nullptr), bond_ghost(nullptr), x0s(nullptr),
    kinv(nullptr), kinv2(nullptr), xi_moment(nullptr), u_moment(nullptr), family_size(nullptr),
    singular(nullptr),
    defgrad(nullptr), pk1(nullptr), energy_density(nullptr), nsingular(0), nbonds_total(0),
    nbonds_broken(0), nbonds_vanished(0), nmax_bonds(0), nmax_first(0), nmax_x0s(0), stale(nullptr),
    all_stale(true), trial_ready(0), x0s_store(nullptr), ref_box_set(0), own_tag(nullptr), family_type(nullptr)
{
  nhistory = nhist_atom = nhist_bond = hist_slots = 0;
  history = history_trial = nullptr;
  if (narg != 3) error->all(FLERR, "Illegal fix {} command: takes no arguments", style);
  vector_flag = 1;
  size_vector = 5;
  create_attribute = 1;
  global_freq = 1;
  extvector = 0;
  maxexchange_dynamic = 1;
  comm_forward = 2;    // FixPeriNeigh's 1, or the operator bound's 2
  for (int k = 0; k < 6; k++) ref_h[k] = last_h[k] = 0.0;
  for (int k = 0; k < 6; k++) created_h[k] = domain->h[k];

  FixNospdBonds::grow_arrays(atom->nmax);
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    clear_atom(i);
    own_tag[i] = atom->tag[i];
    family_type[i] = 0;
  }
}

/* ----------------------------------------------------------------------
   an atom without a family and without state: atoms present when the fix
   is made, and atoms created after the families were built (no bonds;
   K^-1 computed, and found singular, at the next rebuild)
------------------------------------------------------------------------- */

void FixNospdBonds::clear_atom(int i)
{
  npartner[i] = 0;
  vinter[i] = wvolume[i] = 0.0;
  singular[i] = 0;
  family_size[i] = 0;
  stale[i] = 1;
  for (int k = 0; k < 9; k++) kinv[i][k] = defgrad[i][k] = pk1[i][k] = 0.0;
  if (kinv2)
    for (int k = 0; k < NOSPD::QuadraticFit::RECORD; k++) kinv2[i][k] = 0.0;
  for (int k = 0; k < 3; k++) xi_moment[i][k] = u_moment[i][k] = 0.0;
  energy_density[i] = 0.0;
  own_tag[i] = 0;
  family_type[i] = 0;
  for (int k = 0; k < nhistory; k++) history[i][k] = history_trial[i][k] = 0.0;
}

/* ---------------------------------------------------------------------- */

FixNospdBonds::~FixNospdBonds()
{
  // clear and exit delete update first; a pair_style command does not: it
  // heals the damage and drops the plastic state, which a user should hear
  if (lmp->update && !first && (nbonds_broken > 0 || nhistory) && comm->me == 0)
    error->warning(FLERR, "Fix {}: a new pair_style discards the bond families{}{}: the next run "
                   "builds new, intact ones from the reference positions", style,
                   nbonds_broken > 0 ? fmt::format(" with their {} broken bonds", nbonds_broken)
                                     : std::string(),
                   nhistory ? " and the plastic state" : "");
  if (lmp->update && ref_box_set && built_periodic > 0 && x0_print_set) {
    ReplacedBox &r = replaced_boxes[lmp];
    std::copy(ref_h, ref_h + 6, r.ref_h);
    std::copy(last_h, last_h + 6, r.last_h);
    std::copy(x0_print, x0_print + 7, r.print);
    r.initclock = lmp->initclock;
  } else if (!lmp->update) {
    replaced_boxes.erase(lmp);
  }
  memory->destroy(bond_first);
  memory->destroy(bond_j);
  memory->destroy(bond_slot);
  memory->destroy(bond_w);
  memory->destroy(bond_pair);
  memory->destroy(bond_ghost);
  memory->destroy(x0s_store);
  memory->destroy(kinv);
  memory->destroy(kinv2);
  memory->destroy(xi_moment);
  memory->destroy(u_moment);
  memory->destroy(family_size);
  memory->destroy(singular);
  memory->destroy(stale);
  memory->destroy(defgrad);
  memory->destroy(pk1);
  memory->destroy(energy_density);
  memory->destroy(own_tag);
  memory->destroy(family_type);
  memory->destroy(history);
  memory->destroy(history_trial);
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::setmask()
{
  return POST_INTEGRATE | POST_NEIGHBOR | MIN_POST_NEIGHBOR | END_OF_STEP | POST_RUN;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::init()
{
  if (!model.horizon)
    error->all(FLERR, "Fix {} needs a peri/nospd pair style to define the horizons{}", style,
               strcmp(id, "NOSPD_BONDS") == 0 ? ""
               : fmt::format(" (fix {} was defined in the input: the pair style makes its own, "
                             "fix NOSPD_BONDS; remove it)", id));
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "Fix {} requires an atom map, see atom_modify", style);
  FixPeriNeigh::init();
}

/* ----------------------------------------------------------------------
   FixPeriNeigh builds families here, after the first force call; ours are
   built in setup_post_neighbor(), before it.  Nothing is left to do.
------------------------------------------------------------------------- */

void FixNospdBonds::setup(int /*vflag*/) {}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::setup_post_neighbor()
{
  const bool had_reference_box = ref_box_set;    // from a restart file
  update_x0s();
  const bool built_now = first;
  if (first) {
    choose_reference_box(had_reference_box);
    build_families();
    first = 0;
    family_horizon.clear();
  } else {
    follow_renumbered_tags();
  }
  if (!x0_print_set) {    // families from a restart file
    print_x0(x0_print);
    x0_print_set = true;
  }
  check_horizons();
  if (!built_now) check_family_types();
  // from here on the atom's history is its type's (set type between runs is
  // checked against this: horizons here, laws by the pair style's init)
  for (int i = 0; i < atom->nlocal; i++)
    if (family_type[i] > 0) family_type[i] = atom->type[i];
  check_periodicity(built_now);
  // also after a restart, where build_families() does not run
  maxexchange = maxpartner + 22 + quadratic_record() + nhistory;
  // the votes of the last init (a run with "pre no" may set up without one)
  if (pair_votes[0] + pair_votes[1] > 0) pair_order = pair_votes[1] > 0 && pair_votes[0] == 0;
  pair_votes[0] = pair_votes[1] = 0;
  build_bond_arrays();
  all_stale = true;    // after a restart or a change of settings
  update_shape_tensors();
  count_bonds();
  if (built_now) report_families();
  check_volumes();
  if (update->whichflag == 1) report_stable_timestep();
  if (update->whichflag == 2) check_min_dmax();
}

/* ----------------------------------------------------------------------
   In 2D the volumes are area x thickness t, and the micromodulus behind
   the stabilization, the stable time step estimate and the critical bond
   energy from G0 assume that a family's volume is that of its horizon's
   disk, pi delta^2 t.  Volumes of area x t without the thickness keyword
   (t = 1), or of area alone with it, break that by a factor 1/t or t,
   silently.  The fullest family (an interior point) holds its disk's
   volume to within the quadrature of the disk by the points, a factor
   below 2 for any horizon past the spacing on a square or hexagonal grid
   and for irregular points with their own volumes; a body's edges and
   damage only empty families.  So the fullest family is held to within a
   factor 5 of its disk; one warning.  (3D: check_solid_volumes.)
------------------------------------------------------------------------- */

void FixNospdBonds::check_volumes()
{
  if (volumes_warned) return;
  if (model.dim == 3) return check_solid_volumes();
  const int *type = atom->type;
  const double *vfrac = atom->vfrac;
  double fullest = 0.0, all = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const int it = type[i];
    if (model.active && !model.active[it]) continue;
    double v = vfrac[i];
    for (int b = bond_first[i]; b < bond_first[i + 1]; b++) v += vfrac[bond_j[b]];
    const double delta = model.horizon[it][it];
    fullest = std::max(fullest, v / (MathConst::MY_PI * delta * delta * model.thickness));
  }
  MPI_Allreduce(&fullest, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (all == 0.0 || (all > 0.2 && all < 5.0)) return;
  volumes_warned = true;
  if (comm->me == 0)
    error->warning(FLERR, "Fix {}: in 2D a point's volume (vfrac) is its area times the "
                   "thickness, here {:.6g}{}, but the fullest family holds {:.3g} times the "
                   "volume pi delta^2 t of its horizon's disk: the volumes imply a thickness "
                   "of about {:.3g}.  The stabilization, the stable time step estimate and G0 "
                   "assume the two agree: set the volumes to area x thickness, or give the "
                   "thickness with pair_style keyword thickness", style, model.thickness,
                   model.thickness == 1.0 ? " (the default: no thickness keyword)" : "", all,
                   all * model.thickness);
}

/* ----------------------------------------------------------------------
   In 3D a volume far below the spacing cubed (a unit slip: mm^3 given for
   a spacing in m) weakens the stabilization, the stable time step estimate
   and G0 as silently as a wrong thickness does in 2D: warn where even the
   largest V_i / d_i^3 (d_i: the nearest partner's distance, about the
   spacing) is below 0.1.  On a grid it is 1; volumes from a Voronoi
   tessellation stay within a few times of it.
------------------------------------------------------------------------- */

void FixNospdBonds::check_solid_volumes()
{
  const int *type = atom->type;
  const double *vfrac = atom->vfrac;
  double largest = 0.0, all = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (model.active && !model.active[type[i]]) continue;
    double d2 = 0.0;
    for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
      const int j = bond_j[b];
      const double dx = x0s[j][0] - x0s[i][0], dy = x0s[j][1] - x0s[i][1],
                   dz = x0s[j][2] - x0s[i][2];
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (r2 > 0.0 && (d2 == 0.0 || r2 < d2)) d2 = r2;
    }
    if (d2 > 0.0) largest = std::max(largest, vfrac[i] / (d2 * sqrt(d2)));
  }
  MPI_Allreduce(&largest, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (all == 0.0 || all >= 0.1) return;
  volumes_warned = true;
  if (comm->me == 0)
    error->warning(FLERR, "Fix {}: the point volumes (vfrac) are at most {:.3g} times the cube "
                   "of the distance to the nearest partner: a point's volume is about its "
                   "spacing cubed (a unit slip?).  The stabilization, the stable time step "
                   "estimate and G0 scale with the volumes: set them with 'set ... volume'",
                   style, all);
}

/* ----------------------------------------------------------------------
   A line search's first trial moves the atom with the largest force by
   min_modify dmax (0.1 distance units by default: 10 cm in si units).
   Moves beyond a fraction of the horizon invert families and carry
   atoms beyond the ghost cutoff or out of the box, which LAMMPS reports
   as lost atoms without a cause: warn at the setup of the minimization.
------------------------------------------------------------------------- */

namespace {
// Min keeps dmax protected and offers no accessor: a pointer to the member
// formed in a class derived from Min reads it without touching LAMMPS
struct MinDmax : LAMMPS_NS::Min {
  static double of(const LAMMPS_NS::Min *m) { return m->*(&MinDmax::dmax); }
};
}    // namespace

void FixNospdBonds::check_min_dmax()
{
  if (!update->minimize || !model.horizon) return;
  const double dmax = MinDmax::of(update->minimize);
  double delta = 0.0;    // the smallest horizon
  for (int i = 1; i <= atom->ntypes; i++)
    if ((!model.active || model.active[i]) && (delta == 0.0 || model.horizon[i][i] < delta))
      delta = model.horizon[i][i];
  if (!(delta > 0.0) || !(dmax > 0.1 * delta) || dmax == dmax_warned) return;
  dmax_warned = dmax;
  if (comm->me == 0)
    error->warning(FLERR, "Fix {}: min_modify dmax {:.6g} exceeds a tenth of the horizon "
                   "{:.6g}: a line search's trial move of that size inverts families and may "
                   "lose atoms; set min_modify dmax to a fraction of the point spacing, e.g. "
                   "min_modify dmax {:.2g}", style, dmax, delta, 0.003 * delta);
}

/* ----------------------------------------------------------------------
   families are built once, with the horizons of the first run (or those
   of the first run after a restart): a horizon changed since (pair_coeff
   between runs) would reach the weights and material constants but not
   the families, so it is an error
------------------------------------------------------------------------- */

void FixNospdBonds::check_horizons()
{
  const int n = atom->ntypes;
  const int *active = model.active;
  if (family_horizon.empty()) {
    family_horizon.assign((n + 1) * (n + 1), 0.0);
    for (int i = 1; i <= n; i++)
      for (int j = 1; j <= n; j++)
        if (!active || (active[i] && active[j])) family_horizon[i * (n + 1) + j] = model.horizon[i][j];
    return;
  }
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) {
      const double built = family_horizon[i * (n + 1) + j], now = model.horizon[i][j];
      if (built > 0.0 && (!active || (active[i] && active[j])) &&
          std::abs(now - built) > 1.0e-12 * built)
        error->all(FLERR, "pair_coeff {} {}: horizon {} differs from {}, with which the bond "
                   "families were built at the first run: families are not rebuilt; keep the "
                   "horizon, or start over with new atoms", i, j, now, built);
    }
}

/* ---------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   the reference box of the first build: the one a restart file gave (for
   families built anew under the other style); else that of the families a
   pair_style command replaced, if they were built from the same x0; else
   the box at the first pair_coeff or the current one
------------------------------------------------------------------------- */

void FixNospdBonds::choose_reference_box(bool had_reference_box)
{
  print_x0(x0_print);
  x0_print_set = true;
  if (had_reference_box) return;
  if (!take_replaced_box()) adopt_box_of_creation();
}

// bounds and sum of the x0 of all atoms: which reference body this is
void FixNospdBonds::print_x0(double *print) const
{
  double lo[3] = {1.0e300, 1.0e300, 1.0e300}, hi[3] = {-1.0e300, -1.0e300, -1.0e300}, sum = 0.0;
  double **x0 = atom->x0;
  for (int i = 0; i < atom->nlocal; i++)
    for (int d = 0; d < 3; d++) {
      lo[d] = std::min(lo[d], x0[i][d]);
      hi[d] = std::max(hi[d], x0[i][d]);
      sum += x0[i][d];
    }
  MPI_Allreduce(lo, print, 3, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(hi, print + 3, 3, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(&sum, print + 6, 1, MPI_DOUBLE, MPI_SUM, world);
}

/* ----------------------------------------------------------------------
   families built anew after a pair_style command (the old style's fix is
   gone) come from the same x0 as the old ones, whose reference box a run
   since may have deformed (fix deform, change_box ... remap): the old
   reference box stays, else the bonds across the boundary would take the
   deformed box as unstrained while those inside the body are strained
------------------------------------------------------------------------- */

bool FixNospdBonds::take_replaced_box()
{
  const auto it = replaced_boxes.find(lmp);
  if (it == replaced_boxes.end()) return false;
  const ReplacedBox saved = it->second;
  replaced_boxes.erase(it);
  if (saved.initclock != lmp->initclock) return false;
  if (!(domain->xperiodic || domain->yperiodic || domain->zperiodic)) return false;
  double scale = 0.0;
  for (int d = 0; d < 3; d++) scale = std::max(scale, domain->prd[d]);
  for (int k = 0; k < 7; k++) {
    const double tol = 1.0e-12 * (k < 6 ? scale : scale * atom->natoms);
    if (std::abs(saved.print[k] - x0_print[k]) > tol) return false;
  }
  std::copy(saved.ref_h, saved.ref_h + 6, ref_h);
  std::copy(saved.last_h, saved.last_h + 6, last_h);
  ref_box_set = 1;
  update_x0s();    // follows flips since (follow_box) and shifts the images
  bool deformed = false;
  for (int k = 0; k < 6; k++)
    if (std::abs(ref_h[k] - domain->h[k]) > 1.0e-12 * scale) deformed = true;
  if (deformed && comm->me == 0)
    utils::logmesg(lmp,
                   "  Fix {}: the families of the replaced pair style had the reference box "
                   "{} x {} x {}; the new ones keep it (the box was deformed since)\n",
                   id, ref_h[0], ref_h[1], ref_h[2]);
  return true;
}

/* ----------------------------------------------------------------------
   the reference box of bonds across periodic boundaries.  The first build
   takes the current box, unless the periodic box changed since the fix was
   made (at the first pair_coeff) and the atoms moved with it (change_box
   ... remap): their x0 then lie in the box they were placed in, which is
   the reference box, and the change is a pre-strain of the whole body.
   Taking the new box would strain the bonds inside the body and not those
   across the boundary.
------------------------------------------------------------------------- */

void FixNospdBonds::adopt_box_of_creation()
{
  const double *h = domain->h;
  const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
  // xprd yprd zprd, then yz (z), xz (z), xy (y)
  const int needs[6] = {0, 1, 2, 2, 2, 1};
  bool changed = false;
  for (int k = 0; k < 6; k++)
    if (periodic[needs[k]] &&
        std::abs(h[k] - created_h[k]) > 1.0e-12 * std::max(domain->prd[needs[k]], 1.0e-300))
      changed = true;
  if (!changed) return;
  double moved = 0.0;
  double **x = atom->x, **x0 = atom->x0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (model.active && !model.active[atom->type[i]]) continue;
    double d[3] = {x[i][0] - x0[i][0], x[i][1] - x0[i][1], x[i][2] - x0[i][2]};
    domain->minimum_image(FLERR, d);
    moved = std::max(moved, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
  }
  double moved_all = 0.0;
  MPI_Allreduce(&moved, &moved_all, 1, MPI_DOUBLE, MPI_MAX, world);
  double lmin = 1.0e300;
  for (int k = 0; k < 3; k++)
    if (periodic[k]) lmin = std::min(lmin, domain->prd[k]);
  if (moved_all <= 1.0e-9 * lmin) return;
  for (int k = 0; k < 6; k++) ref_h[k] = created_h[k];
  update_x0s();
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "  Fix {}: the periodic box changed since pair_coeff and the atoms moved "
                   "with it: the box at pair_coeff ({} x {} x {}) is the reference box, the body "
                   "is pre-strained\n",
                   id, created_h[0], created_h[1], created_h[2]);
}

/* ----------------------------------------------------------------------
   an atom whose type changed since the last setup (set type) takes the
   new type's material; its family keeps the old type's horizon (that of
   the type it was built with, checked at each change), which must then be
   the new one's
------------------------------------------------------------------------- */

void FixNospdBonds::check_family_types()
{
  const int n = atom->ntypes;
  const int *type = atom->type;
  const int *active = model.active;
  double **horizon = model.horizon;
  // the lowest such atom ID on every rank, for one message on all
  bigint first_bad = MAXBIGINT;
  int info[2] = {0, 0}, info_all[2];
  for (int i = 0; i < atom->nlocal; i++) {
    const int was = family_type[i], now = type[i];
    if (was <= 0 || was > n || was == now || atom->tag[i] >= first_bad) continue;
    for (int t = 1; t <= n; t++)
      if ((!active || (active[t] && active[was] && active[now])) &&
          std::abs(horizon[now][t] - horizon[was][t]) > 1.0e-12 * horizon[was][t]) {
        first_bad = atom->tag[i];
        info[0] = now, info[1] = was;
        break;
      }
  }
  bigint first_all;
  MPI_Allreduce(&first_bad, &first_all, 1, MPI_LMP_BIGINT, MPI_MIN, world);
  if (first_all == MAXBIGINT) return;
  if (first_bad != first_all) info[0] = info[1] = 0;
  MPI_Allreduce(info, info_all, 2, MPI_INT, MPI_MAX, world);
  error->all(FLERR, "Fix {}: atom {} has type {} but had type {} in the last run, whose "
             "horizons differ: families are not rebuilt; set the type before the first run, or "
             "give both types the same horizons", id, first_all, info_all[0], info_all[1]);
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::check_periodicity(bool built_now)
{
  const int now = domain->xperiodic | (domain->yperiodic << 1) | (domain->zperiodic << 2);
  if (built_now || built_periodic < 0) {
    built_periodic = now;
    return;
  }
  if (now == built_periodic) return;
  auto names = [](int bits) {
    std::string s;
    for (int k = 0; k < 3; k++)
      if (bits & (1 << k)) s += std::string(s.empty() ? "" : " ") + "xyz"[k];
    return s.empty() ? std::string("none") : s;
  };
  error->all(FLERR, "Fix {}: the box is periodic in {} but was periodic in {} when the bond "
             "families were built: families are not rebuilt (bonds across a boundary that is "
             "no longer periodic would span the box, faces made periodic would stay unbonded); "
             "set the boundary (change_box ... boundary) before the first run",
             id, names(now), names(built_periodic));
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::report_families()
{
  double bytes = memory_usage(), all_bytes;
  MPI_Allreduce(&bytes, &all_bytes, 1, MPI_DOUBLE, MPI_SUM, world);
  if (comm->me == 0) {
    const double natoms = (double) MAX(atom->natoms, 1);
    utils::logmesg(lmp,
                   "PERI-NOSPD bond families (fix {}):\n  bonds = {}, bonds/point = {:.6g}, "
                   "singular families = {}\n  bond and reference state = {:.0f} bytes/point\n",
                   id, nbonds_total, nbonds_total / natoms, nsingular, all_bytes / natoms);
    // accepted and trial rows
    if (nhistory)
      utils::logmesg(lmp, "  inelastic history = {} values/point ({} per point{}), "
                     "{:.0f} bytes/point of the above\n", nhistory, nhist_atom,
                     nhist_bond ? fmt::format(" and {} per partner slot", nhist_bond) : "",
                     2.0 * sizeof(double) * nhistory);
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::post_neighbor()
{
  // a fix may delete atoms and create others within one step of a run (fix
  // evaporate and fix deposit id max), the new ones taking freed IDs
  follow_renumbered_tags();
  update_x0s();
  build_bond_arrays();
  update_shape_tensors();
  if (count_bonds_pending) count_bonds();
}

static constexpr int RESTART_V2 = 10;
static constexpr int RESTART_V3 = 20;

/* ----------------------------------------------------------------------
   global restart data: FixPeriNeigh's two values, the reference box, and
   what the families were built with (periodicity, the writer's pair style,
   the horizons, the laws whose state the history holds), so that a restart
   is checked against a changed input as a continued session is
------------------------------------------------------------------------- */

void FixNospdBonds::write_restart(FILE *fp)
{
  // list[0] is `first` plus RESTART_V3 (V2 files hold seven values, older six)
  std::vector<double> list = {(double) (first + RESTART_V3), (double) maxpartner,
                              (double) ref_box_set, ref_h[0], ref_h[1], ref_h[2],
                              (double) nbonds_vanished, ref_h[3], ref_h[4], ref_h[5],
                              (double) built_periodic, (double) style_kind,
                              (double) family_horizon.size(), (double) history_law.size()};
  list.insert(list.end(), family_horizon.begin(), family_horizon.end());
  list.insert(list.end(), history_law.begin(), history_law.end());
  if (comm->me == 0) {
    int size = list.size() * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::restart(char *buf)
{
  auto *list = (double *) buf;
  const int head = static_cast<int>(list[0]);
  first = head % RESTART_V2;
  if (head >= RESTART_V2) nbonds_vanished = static_cast<bigint>(list[6]);
  maxpartner = static_cast<int>(list[1]);
  ref_box_set = static_cast<int>(list[2]);
  for (int k = 0; k < 3; k++) ref_h[k] = list[3 + k];
  // older files: the reference tilts are unknown, take the box's
  for (int k = 3; k < 6; k++) ref_h[k] = domain->h[k];
  for (int k = 0; k < 6; k++) last_h[k] = domain->h[k];
  if (head >= RESTART_V3) {
    for (int k = 3; k < 6; k++) ref_h[k] = list[4 + k];
    built_periodic = static_cast<int>(list[10]);
    restart_kind = static_cast<int>(list[11]);
    const int nh = static_cast<int>(list[12]), nl = static_cast<int>(list[13]);
    family_horizon.assign(list + 14, list + 14 + nh);
    history_law.assign(list + 14 + nh, list + 14 + nh + nl);
  }
  if (nhist_bond) layout_history(nhist_atom, nhist_bond);
  // partner arrays are 2D: size them now, before the per-atom data arrive
  grow_arrays(atom->nmax);
}

/* ---------------------------------------------------------------------- */

static const char *style_of_kind(int kind)
{
  return kind == 2 ? "peri/nospd/hs" : "peri/nospd";
}

void FixNospdBonds::adopt_style(int kind)
{
  if (restart_kind && restart_kind != kind) {
    if (comm->me == 0)
      error->warning(FLERR, "Fix {}: the restart file's bond families and state were written "
                     "under pair_style {}; pair_style {} builds new ones at the next run, as a "
                     "pair_style command between runs does (broken bonds and inelastic history "
                     "are not carried over)", id, style_of_kind(restart_kind), style_of_kind(kind));
    start_over();
  }
  restart_kind = 0;
  style_kind = kind;
}

/* ----------------------------------------------------------------------
   forget the families and the state: the next setup builds them anew
------------------------------------------------------------------------- */

void FixNospdBonds::start_over()
{
  for (int i = 0; i < atom->nlocal; i++) clear_atom(i);
  first = 1;
  nbonds_vanished = 0;
  // the x0 stay, and with them the box they are the reference of
  built_periodic = -1;
  family_horizon.clear();
  history_law.clear();
}

/* ---------------------------------------------------------------------- */

double FixNospdBonds::weight(double r, double delta) const
{
  if (model.influence == NospdBondModel::INVERSE) return delta / r;
  return 1.0;
}

/* ----------------------------------------------------------------------
   Families from reference positions: every j with |x0_j - x0_i| <= delta
   (minimum-imaged).  Partners are sorted by tag so that every rank sums a
   family in the same order.
------------------------------------------------------------------------- */

void FixNospdBonds::build_families()
{
  static bigint serial_source = 0;
  families_serial = ++serial_source;
  neighbor->build_one(list);
  const int inum = list->inum;
  int *ilist = list->ilist;
  int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  int *type = atom->type;
  tagint *tag = atom->tag;
  double *vfrac = atom->vfrac;
  const int nlocal = atom->nlocal;
  double **horizon = model.horizon;

  struct Member {
    tagint tag;
    double vol;
    bool operator<(const Member &o) const { return tag < o.tag; }
  };
  std::vector<std::vector<Member>> fam(nlocal);
  const int *active = model.active;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    if (active && !active[type[i]]) continue;
    for (int jj = 0; jj < numneigh[i]; jj++) {
      const int j = firstneigh[i][jj] & NEIGHMASK;
      if (active && !active[type[j]]) continue;
      const double dx = x0s[j][0] - x0s[i][0];
      const double dy = x0s[j][1] - x0s[i][1];
      const double dz = x0s[j][2] - x0s[i][2];
      const double rsq = dx * dx + dy * dy + dz * dz;
      const double delta = horizon[type[i]][type[j]];
      if (rsq > delta * delta) continue;
      check_coincident(i, j, sqrt(rsq));
      fam[i].push_back({tag[j], vfrac[j]});
    }
  }

  warn_unbonded_reference_pairs();

  int mymax = 0;
  for (int i = 0; i < nlocal; i++) {
    auto &f = fam[i];
    std::sort(f.begin(), f.end());
    for (size_t k = 1; k < f.size(); k++)
      if (f[k].tag == f[k - 1].tag)
        error->one(FLERR,
                   "Fix {}: atom {} is bonded to two periodic images of atom {}: the box "
                   "must be longer than twice the horizon in each periodic direction",
                   style, tag[i], f[k].tag);
    mymax = std::max(mymax, (int) f.size());
  }
  MPI_Allreduce(&mymax, &maxpartner, 1, MPI_INT, MPI_MAX, world);
  maxpartner = std::max(maxpartner, 1);
  if (nhist_bond) layout_history(nhist_atom, nhist_bond);    // one entry per partner slot

  memory->destroy(partner);
  memory->destroy(r0);
  memory->destroy(npartner);
  npartner = nullptr;
  partner = nullptr;
  r0 = nullptr;
  grow_arrays(atom->nmax);

  for (int i = 0; i < nlocal; i++) {
    npartner[i] = family_size[i] = (int) fam[i].size();
    own_tag[i] = tag[i];
    family_type[i] = type[i];
    vinter[i] = 0.0;
    wvolume[i] = 0.0;
    for (int n = 0; n < npartner[i]; n++) {
      partner[i][n] = fam[i][n].tag;
      vinter[i] += fam[i][n].vol;    // read by compute damage/atom
    }
  }
  maxexchange = maxpartner + 22 + quadratic_record() + nhistory;
}

/* ----------------------------------------------------------------------
   Families take their candidates from a neighbor list of the current
   positions (as PERI's do): two atoms within the horizon in their
   reference positions but farther apart now than the neighbor cutoff
   (horizon + skin) are not bonded.  That keeps apart bodies placed with
   displace_atoms before the first run, but also drops the bonds of a body
   deformed before it by more than the skin across a bond.  Such pairs are
   counted here (owned and ghost atoms, each pair once, by the x0 cells of
   the largest horizon) and reported, so the omission is never silent.
------------------------------------------------------------------------- */

void FixNospdBonds::warn_unbonded_reference_pairs()
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  double **x = atom->x;
  const int *active = model.active;
  double **horizon = model.horizon;
  double cell = 0.0;
  for (int a = 1; a <= atom->ntypes; a++)
    for (int b = 1; b <= atom->ntypes; b++)
      if (!active || (active[a] && active[b])) cell = std::max(cell, horizon[a][b]);
  if (!(cell > 0.0)) return;

  // a pair is left out only if its ends moved apart by more than the skin:
  // impossible when every displacement lies within skin/2 of the mean one
  // (a body at rest, moved rigidly or deformed little: no search)
  double usum[4] = {0.0, 0.0, 0.0, (double) nlocal}, uall[4];
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) usum[k] += x[i][k] - x0s[i][k];
  MPI_Allreduce(usum, uall, 4, MPI_DOUBLE, MPI_SUM, world);
  if (uall[3] == 0.0) return;
  double spread = 0.0, spread_all = 0.0;
  for (int i = 0; i < nlocal; i++) {
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
      const double d = x[i][k] - x0s[i][k] - uall[k] / uall[3];
      d2 += d * d;
    }
    spread = std::max(spread, d2);
  }
  MPI_Allreduce(&spread, &spread_all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (2.0 * sqrt(spread_all) <= neighbor->skin) return;

  using Key = std::array<long, 3>;
  std::vector<std::pair<Key, int>> cells;
  cells.reserve(nall);
  for (int k = 0; k < nall; k++)
    if (!active || active[type[k]])
      cells.push_back({{(long) std::floor(x0s[k][0] / cell), (long) std::floor(x0s[k][1] / cell),
                        (long) std::floor(x0s[k][2] / cell)}, k});
  std::sort(cells.begin(), cells.end());
  auto by_key = [](const std::pair<Key, int> &e, const Key &c) { return e.first < c; };

  bigint nfar = 0;
  tagint example[2] = {0, 0};
  for (const auto &[key, i] : cells) {
    if (i >= nlocal) continue;
    for (long d0 = -1; d0 <= 1; d0++)
      for (long d1 = -1; d1 <= 1; d1++)
        for (long d2 = -1; d2 <= 1; d2++) {
          const Key c = {key[0] + d0, key[1] + d1, key[2] + d2};
          for (auto e = std::lower_bound(cells.begin(), cells.end(), c, by_key);
               e != cells.end() && e->first == c; ++e) {
            const int j = e->second;
            if (tag[j] <= tag[i]) continue;    // each pair once, by its smaller ID
            double r0sq = 0.0, rsq = 0.0;
            for (int k = 0; k < 3; k++) {
              r0sq += (x0s[j][k] - x0s[i][k]) * (x0s[j][k] - x0s[i][k]);
              rsq += (x[j][k] - x[i][k]) * (x[j][k] - x[i][k]);
            }
            const double delta = horizon[type[i]][type[j]];
            if (r0sq > delta * delta || rsq <= neighbor->cutneighsq[type[i]][type[j]]) continue;
            if (!nfar++) example[0] = tag[i], example[1] = tag[j];
          }
        }
  }
  bigint nfar_all = 0;
  MPI_Allreduce(&nfar, &nfar_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (!nfar_all) return;
  // the example with the smallest first ID, from the rank that holds it
  const tagint mine = nfar ? example[0] : MAXTAGINT;
  tagint ex[2] = {0, 0}, second = 0;
  MPI_Allreduce(&mine, &ex[0], 1, MPI_LMP_TAGINT, MPI_MIN, world);
  if (nfar && example[0] == ex[0]) second = example[1];
  MPI_Allreduce(&second, &ex[1], 1, MPI_LMP_TAGINT, MPI_MAX, world);
  if (comm->me == 0)
    error->warning(FLERR, "Fix {}: {} pairs of atoms within the horizon in their reference "
                   "positions are farther apart now than the neighbor cutoff and are not bonded "
                   "(e.g. atoms {} and {}): atoms moved relative to each other before the first "
                   "run by more than the neighbor skin.  If they are one body, deform it after "
                   "the first run (run 0) or raise the skin (neighbor); bodies placed apart with "
                   "displace_atoms are meant to stay unbonded", style, nfar_all, ex[0], ex[1]);
}

/* ----------------------------------------------------------------------
   Two points closer than a small fraction of their spacing would make a
   bond of (nearly) zero length: K loses nothing, but the bond's stretch
   and the force state are divided by it.  Name both atoms.
------------------------------------------------------------------------- */

void FixNospdBonds::check_coincident(int i, int j, double r) const
{
  const double v = std::min(atom->vfrac[i], atom->vfrac[j]);
  const double spacing = (model.dim == 3) ? cbrt(v) : sqrt(v / model.thickness);
  if (r >= model.coincident_fraction * spacing) return;
  // r is the minimum image: name a periodic boundary when it brings them close
  double **x0 = atom->x0;
  const double direct = sqrt((x0[j][0] - x0[i][0]) * (x0[j][0] - x0[i][0]) +
                             (x0[j][1] - x0[i][1]) * (x0[j][1] - x0[i][1]) +
                             (x0[j][2] - x0[i][2]) * (x0[j][2] - x0[i][2]));
  const bool across = direct > 2.0 * r + 0.5 * spacing;
  error->one(FLERR, "Fix {}: atoms {} and {} are {:.6g} apart in the reference configuration{}, "
             "less than {} of their spacing {:.6g} (from the volume): overlapping points, {}",
             style, atom->tag[i], atom->tag[j], r,
             across ? fmt::format(" across a periodic boundary ({:.6g} apart inside the box)",
                                  direct) : "",
             model.coincident_fraction, spacing,
             across ? "e.g. atoms on both faces of a periodic box (a lattice region that ends on "
                      "the box's upper face, or a body read without its own boundary)"
                    : "e.g. two create_atoms on the same region; remove one with delete_atoms "
                      "overlap");
}

/* ----------------------------------------------------------------------
   Contiguous bond arrays for the owned atoms, refreshed once per
   reneighboring: local index of the closest image of each intact partner
   and its weight omega(|xi|) V_j.
------------------------------------------------------------------------- */

void FixNospdBonds::build_bond_arrays()
{
  const int nlocal = atom->nlocal;
  int *type = atom->type;
  double *vfrac = atom->vfrac;
  double **horizon = model.horizon;
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;

  if (nlocal + 1 > nmax_first) {
    nmax_first = atom->nmax + 1;
    memory->destroy(bond_first);
    memory->create(bond_first, nmax_first, "nospd/bonds:bond_first");
  }
  bigint ntot = 0;
  for (int i = 0; i < nlocal; i++) ntot += npartner[i];
  if (ntot > nmax_bonds) {
    nmax_bonds = (int) (1.02 * ntot) + 16;
    memory->destroy(bond_j);
    memory->destroy(bond_slot);
    memory->destroy(bond_w);
    memory->create(bond_j, nmax_bonds, "nospd/bonds:bond_j");
    memory->create(bond_slot, nmax_bonds, "nospd/bonds:bond_slot");
    memory->create(bond_w, nmax_bonds, "nospd/bonds:bond_w");
  }

  // in a periodic box, a bond's ends must sit in matching images: along a
  // periodic box vector its displacement Y - xi stays below half of it (a
  // bond is shorter than half a box, and a shear with the box of up to
  // 100 % moves its ends apart by less than the bond's length); half a box
  // or more means that the body's displacement field spans a period (a
  // shear beyond 100 %) and the reference images went wrong (2D: z is not
  // a direction of the body)
  double **x = atom->x;
  const double *hi = domain->h_inv;
  const int pdim[3] = {domain->xperiodic, domain->yperiodic,
                       domain->zperiodic && domain->dimension == 3};
  int bad_i = -1, bad_j = -1;

  std::vector<MissingPartner> missing;
  int b = 0;
  for (int i = 0; i < nlocal; i++) {
    bond_first[i] = b;
    for (int n = 0; n < npartner[i]; n++) {
      const tagint t = partner[i][n];
      if (t == 0) continue;    // broken
      int j = partner_index(t);
      if (j < 0) {
        missing.push_back({i, n, t});
        continue;
      }
      if (periodic) j = domain->closest_image(i, j);
      const double dx = x0s[j][0] - x0s[i][0];
      const double dy = x0s[j][1] - x0s[i][1];
      const double dz = x0s[j][2] - x0s[i][2];
      const double r = sqrt(dx * dx + dy * dy + dz * dz);
      if (periodic && bad_i < 0) {
        // Y - xi in fractions of the periodic box vectors
        const double ux = x[j][0] - x[i][0] - dx, uy = x[j][1] - x[i][1] - dy,
                     uz = x[j][2] - x[i][2] - dz;
        const double lam[3] = {hi[0] * ux + hi[5] * uy + hi[4] * uz, hi[1] * uy + hi[3] * uz,
                               hi[2] * uz};
        for (int k = 0; k < 3; k++)
          if (pdim[k] && std::abs(lam[k]) > 0.5) bad_i = i, bad_j = j;
      }
      bond_j[b] = j;
      bond_slot[b] = n;
      bond_w[b] = weight(r, horizon[type[i]][type[j]]) * vfrac[j];
      b++;
    }
  }
  bond_first[nlocal] = b;
  nbond_atoms = nlocal;
  bond_version++;
  if (bad_i >= 0)
    error->one(FLERR, "Fix {}: the bond of atoms {} and {} is displaced by half a box length "
               "(its ends are {:.6g} apart, {:.6g} in the reference): the body's displacement "
               "field spans a period of the box (a periodic body sheared or strained by "
               "about 100 %), beyond what its periodic reference images can follow",
               style, atom->tag[bad_i], atom->tag[bad_j],
               sqrt((x[bad_j][0] - x[bad_i][0]) * (x[bad_j][0] - x[bad_i][0]) +
                    (x[bad_j][1] - x[bad_i][1]) * (x[bad_j][1] - x[bad_i][1]) +
                    (x[bad_j][2] - x[bad_i][2]) * (x[bad_j][2] - x[bad_i][2])),
               sqrt((x0s[bad_j][0] - x0s[bad_i][0]) * (x0s[bad_j][0] - x0s[bad_i][0]) +
                    (x0s[bad_j][1] - x0s[bad_i][1]) * (x0s[bad_j][1] - x0s[bad_i][1]) +
                    (x0s[bad_j][2] - x0s[bad_i][2]) * (x0s[bad_j][2] - x0s[bad_i][2])));

  int nmissing = missing.size(), anymissing = 0;
  MPI_Allreduce(&nmissing, &anymissing, 1, MPI_INT, MPI_SUM, world);
  if (anymissing) resolve_missing(missing);
  if (pair_order) order_for_pairs();
}

/* ----------------------------------------------------------------------
   local index of a partner ID, -1 if no owned or ghost atom has it.  An
   array map is reset only up to the largest ID left (Atom::map_init): the
   entries of deleted atoms with larger IDs (fix evaporate, delete_atoms
   compress no) keep the indices they had, which other atoms now hold.
------------------------------------------------------------------------- */

int FixNospdBonds::partner_index(tagint t) const
{
  return t > atom->map_tag_max ? -1 : atom->map(t);
}

/* ----------------------------------------------------------------------
   pair order: each point's bonds to owned points j < i first, then to
   owned j > i, then to ghosts, each group in the partner order.  The pass
   that visits pairs once takes bond i-j (j > i) for both ends and skips
   it at j, so it needs every such bond in both lists: checked here by
   summing a hash of (i, j) over the first group and over the second (the
   same sums, mod 2^64, exactly when the owned pairs are symmetric; the
   damage fix breaks bonds at both ends, an asymmetric list would be a
   bug).  Without symmetry the pass falls back to visiting bonds per end.
------------------------------------------------------------------------- */

static inline uint64_t pair_hash(uint64_t lo, uint64_t hi)
{
  uint64_t z = (lo << 32 | hi) + 0x9e3779b97f4a7c15ULL;    // splitmix64
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

void FixNospdBonds::order_for_pairs()
{
  const int nlocal = atom->nlocal;
  if (nlocal > nmax_pair) {
    nmax_pair = atom->nmax;
    memory->destroy(bond_pair);
    memory->destroy(bond_ghost);
    memory->create(bond_pair, nmax_pair, "nospd/bonds:bond_pair");
    memory->create(bond_ghost, nmax_pair, "nospd/bonds:bond_ghost");
  }
  uint64_t below = 0, above = 0;
  std::vector<int> js, slots, group;
  std::vector<double> ws;
  for (int i = 0; i < nlocal; i++) {
    const int from = bond_first[i], to = bond_first[i + 1];
    js.assign(bond_j + from, bond_j + to);
    slots.assign(bond_slot + from, bond_slot + to);
    ws.assign(bond_w + from, bond_w + to);
    // 0: owned j < i; 1: owned j > i; 2: ghosts (and a bond to itself)
    group.resize(to - from);
    int count[3] = {0, 0, 0};
    for (int k = 0; k < to - from; k++) {
      const int j = js[k];
      group[k] = (j >= nlocal || j == i) ? 2 : (j < i ? 0 : 1);
      count[group[k]]++;
    }
    int next[3] = {from, from + count[0], from + count[0] + count[1]};
    bond_pair[i] = next[1];
    bond_ghost[i] = next[2];
    for (int k = 0; k < to - from; k++) {
      const int b = next[group[k]]++;
      bond_j[b] = js[k];
      bond_slot[b] = slots[k];
      bond_w[b] = ws[k];
      if (group[k] == 0) below += pair_hash(js[k], i);
      if (group[k] == 1) above += pair_hash(i, js[k]);
    }
  }
  pairs_symmetric = (below == above);
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  if (comm_mode == 0) return FixPeriNeigh::pack_forward_comm(n, list, buf, pbc_flag, pbc);
  int m = 0;
  for (int k = 0; k < n; k++) {
    buf[m++] = op_point[2 * list[k]];
    buf[m++] = op_point[2 * list[k] + 1];
  }
  return m;
}

void FixNospdBonds::unpack_forward_comm(int n, int first, double *buf)
{
  if (comm_mode == 0) return FixPeriNeigh::unpack_forward_comm(n, first, buf);
  int m = 0;
  for (int i = first; i < first + n; i++) {
    op_point[2 * i] = buf[m++];
    op_point[2 * i + 1] = buf[m++];
  }
}

/* ----------------------------------------------------------------------
   Instability caught where it starts, before LAMMPS meets its results
   (non-numeric coordinates, lost atoms, too many neighbor bins): after the
   drift, every owned point must have a finite position and velocity, and a
   point that still has bonds must not have moved half its horizon in one
   step.  Velocity Verlet's drift is v dt, so the check costs one pass over
   the atoms and none over the bonds.
------------------------------------------------------------------------- */

void FixNospdBonds::post_integrate()
{
  if (ref_box_set && domain->triclinic) follow_box();    // before a flip at this step's exchange
  const int nlocal = atom->nlocal;
  if (nbond_atoms != nlocal) return;    // the bond arrays are being rebuilt
  double **x = atom->x, **v = atom->v;
  const int *type = atom->type;
  const double dt = update->dt;
  int bad = -1;
  bool nonfinite = false;
  double moved = 0.0;
  for (int i = 0; i < nlocal; i++) {
    if (model.active && !model.active[type[i]]) continue;
    const double v2 = v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2];
    if (!std::isfinite(v2) || !std::isfinite(x[i][0] + x[i][1] + x[i][2])) {
      bad = i;
      nonfinite = true;
      break;
    }
    if (bond_first[i + 1] == bond_first[i]) continue;    // a free fragment may fly
    const double half = 0.5 * model.horizon[type[i]][type[i]];
    if (v2 * dt * dt > half * half) {
      bad = i;
      moved = sqrt(v2) * dt;
      break;
    }
  }
  int anybad = (bad >= 0), all = 0;
  MPI_Allreduce(&anybad, &all, 1, MPI_INT, MPI_MAX, world);
  if (!all) return;
  const std::string cause = unstable_cause();
  if (bad >= 0) {
    if (nonfinite)
      error->one(FLERR, "Fix {}: step {}: atom {} has a non-finite position or velocity: the "
                 "run became unstable{}", style, update->ntimestep, atom->tag[bad], cause);
    error->one(FLERR, "Fix {}: step {}: atom {}, still bonded, moved {:.4g} in one step, more "
               "than half its horizon {:.4g}: the run became unstable{}", style,
               update->ntimestep, atom->tag[bad], moved, model.horizon[type[bad]][type[bad]], cause);
  }
  error->all(FLERR, "Fix {}: step {}: the run became unstable on another rank", style,
             update->ntimestep);
}

/* ----------------------------------------------------------------------
   Atom IDs renumbered since the families were stored (delete_atoms with
   its default `compress yes`), or atoms created since: partner lists hold
   the old IDs.  Every old atom's (old, new) pair goes round the ranks
   once; each rank translates the partners it holds.  A partner whose old
   ID no old atom carries any more was deleted: its bond is broken
   (resolve_missing would not see it, since its old ID may now belong to
   another atom, a new one included).
------------------------------------------------------------------------- */

namespace {
struct Renumbering {
  std::vector<std::pair<tagint, std::pair<int, int>>> slots;    // old partner ID, (i, slot)
  std::vector<tagint> newtag;                                   // per entry of slots, 0: not found
};

void translate_ids(int n, char *buf, void *ptr)
{
  auto *r = static_cast<Renumbering *>(ptr);
  const auto *pairs = reinterpret_cast<const tagint *>(buf);    // old, new; sorted by old
  size_t k = 0;
  for (int p = 0; p < n && k < r->slots.size(); p++) {
    const tagint old = pairs[2 * p];
    while (k < r->slots.size() && r->slots[k].first < old) k++;
    for (; k < r->slots.size() && r->slots[k].first == old; k++) r->newtag[k] = pairs[2 * p + 1];
  }
}
}    // namespace

void FixNospdBonds::follow_renumbered_tags()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  int flags[2] = {0, 0}, anyflags[2] = {0, 0};    // renumbered, created
  for (int i = 0; i < nlocal; i++) {
    if (own_tag[i] == 0)
      flags[1] = 1;    // created after the families: in no family
    else if (own_tag[i] != tag[i])
      flags[0] = 1;
  }
  MPI_Allreduce(flags, anyflags, 2, MPI_INT, MPI_MAX, world);
  const bool renumbered = anyflags[0], created = anyflags[1];
  if (!renumbered && !created) return;

  Renumbering r;
  for (int i = 0; i < nlocal; i++)
    for (int n = 0; n < npartner[i]; n++)
      if (partner[i][n]) r.slots.push_back({partner[i][n], {i, n}});
  std::sort(r.slots.begin(), r.slots.end());
  r.newtag.assign(r.slots.size(), 0);
  // only atoms that were there when the partner IDs were written: a new
  // atom may carry the ID of a deleted one (LAMMPS hands out the largest ID
  // left plus one, and delete_atoms compress yes frees IDs), and must not
  // inherit its bonds
  std::vector<std::pair<tagint, tagint>> ids;
  ids.reserve(nlocal + 1);
  for (int i = 0; i < nlocal; i++)
    if (own_tag[i]) ids.push_back({own_tag[i], tag[i]});
  std::sort(ids.begin(), ids.end());
  static_assert(sizeof(std::pair<tagint, tagint>) == 2 * sizeof(tagint), "packed ID pairs");
  comm->ring((int) ids.size(), 2 * sizeof(tagint), ids.data(), 0, translate_ids, nullptr, &r);

  int ngone = 0;
  for (size_t k = 0; k < r.slots.size(); k++) {
    const int i = r.slots[k].second.first, n = r.slots[k].second.second;
    partner[i][n] = r.newtag[k];    // 0 (broken) if the partner is gone
    if (!r.newtag[k]) {
      stale[i] = 1;
      ngone++;
    }
  }
  for (int i = 0; i < nlocal; i++) own_tag[i] = tag[i];
  bigint one = ngone, all = 0;
  MPI_Allreduce(&one, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  nbonds_vanished += all;
  if (comm->me == 0) {
    if (renumbered)
      error->warning(FLERR, "Fix {}: atom IDs were renumbered since the bond families were "
                     "built (delete_atoms compress yes): the families follow the new IDs", style);
  }
  if (all) warn_vanished(all);
}

void FixNospdBonds::warn_vanished(bigint nbroken)
{
  count_bonds_pending = true;
  if (comm->me == 0)
    error->warning(FLERR, "Fix {}: {} bonds broken: their partner atoms no longer exist "
                   "(delete_atoms, fix evaporate, or atoms lost under thermo_modify lost "
                   "ignore)", style, nbroken);
}

/* ----------------------------------------------------------------------
   Partners found neither as owned atoms nor as ghosts.  Either they no
   longer exist (delete_atoms, atoms lost through a non-periodic boundary
   under thermo_modify lost ignore): their bonds are broken, alike on every
   rank count, and the families' K recomputed; or they exist on a rank
   beyond the ghost cutoff: an error with the distance.  All ranks take
   part, since which is which takes a global look-up of the tags.
------------------------------------------------------------------------- */

void FixNospdBonds::resolve_missing(const std::vector<MissingPartner> &missing)
{
  // the missing tags of all ranks, with the owner's position where one exists
  std::vector<tagint> mine;
  for (const auto &m : missing) mine.push_back(m.tag);
  std::sort(mine.begin(), mine.end());
  mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
  int nmine = mine.size();
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&nmine, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  const int nall = displs.back() + counts.back();
  std::vector<tagint> tags(nall);
  MPI_Allgatherv(mine.data(), nmine, MPI_LMP_TAGINT, tags.data(), counts.data(), displs.data(),
                 MPI_LMP_TAGINT, world);
  std::vector<double> found(4 * nall, 0.0), found_all(4 * nall);
  for (int k = 0; k < nall; k++) {
    const int j = partner_index(tags[k]);
    if (j < 0 || j >= atom->nlocal) continue;
    found[4 * k] = 1.0;
    for (int d = 0; d < 3; d++) found[4 * k + 1 + d] = atom->x[j][d];
  }
  MPI_Allreduce(found.data(), found_all.data(), 4 * nall, MPI_DOUBLE, MPI_SUM, world);
  // tags is the concatenation of sorted per-rank lists: look up within this rank's part
  const auto first_mine = tags.begin() + displs[comm->me];
  const auto last_mine = first_mine + nmine;

  int nvanished = 0, nfar = 0;
  const MissingPartner *far = nullptr;
  double far_pos[3] = {0.0, 0.0, 0.0};
  for (const auto &m : missing) {
    const int k = std::lower_bound(first_mine, last_mine, m.tag) - tags.begin();
    if (found_all[4 * k] == 0.0) {
      partner[m.i][m.slot] = 0;    // the partner is gone: so is the bond
      stale[m.i] = 1;
      nvanished++;
    } else if (!nfar++) {
      far = &m;
      for (int d = 0; d < 3; d++) far_pos[d] = found_all[4 * k + 1 + d];
    }
  }

  int anyfar = 0;
  MPI_Allreduce(&nfar, &anyfar, 1, MPI_INT, MPI_SUM, world);
  if (anyfar) {
    // a line-search minimizer moves atoms by up to min_modify dmax (0.1
    // distance units by default: 10 cm in SI) in its first trial step
    const std::string hint = (update->whichflag == 2)
        ? "; under minimize, set min_modify dmax to a fraction of the point spacing"
        : "";
    if (nfar) {
      double d[3];
      for (int k = 0; k < 3; k++) d[k] = far_pos[k] - atom->x[far->i][k];
      domain->minimum_image(FLERR, d);
      error->one(FLERR,
                 "Fix {}: bond partner {} of atom {} is {:.6g} away, beyond the ghost cutoff "
                 "{:.6g} ({} such bonds on this rank): a bond stretched beyond it; increase "
                 "it with comm_modify cutoff or break such bonds with a damage fix{}",
                 style, far->tag, atom->tag[far->i], sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]),
                 comm->get_comm_cutoff(), nfar, hint);
    }
    error->all(FLERR, "Fix {}: bond partners beyond the ghost cutoff on another rank", style);
  }

  // atoms lost (LAMMPS still counts them) rather than deleted: unless the
  // user lets atoms go (thermo_modify lost ignore|warn), LAMMPS stops at the
  // next thermo output; stop now and say why
  bigint nlocal = atom->nlocal, natoms_now = 0;
  MPI_Allreduce(&nlocal, &natoms_now, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (natoms_now < atom->natoms && output->thermo && output->thermo->lostflag == Thermo::ERROR) {
    const std::string hint = (update->whichflag == 2)
        ? ": under minimize the line search moved them up to min_modify dmax (and a fix "
          "box/relax the box by up to its vmax); set them to a fraction of the point spacing "
          "(and of the strain)"
        : ": a blown-up run or a body leaving a non-periodic box; to let atoms go, use "
          "thermo_modify lost ignore";
    error->all(FLERR, "Fix {}: {} atoms were lost, and bond partners with them{}", style,
               atom->natoms - natoms_now, hint);
  }
  bigint one = nvanished, all = 0;
  MPI_Allreduce(&one, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  nbonds_vanished += all;
  warn_vanished(all);
}

/* ----------------------------------------------------------------------
   K = sum_j w xi (x) xi and its inverse for every atom marked stale (all
   atoms after setup).  In 2D K(2,2) = 1 stands in for the missing
   out-of-plane direction so that 3x3 algebra serves both dimensions.
------------------------------------------------------------------------- */

void FixNospdBonds::set_model(const NospdBondModel &m)
{
  const bool had = model.quadratic;
  model = m;
  if (model.quadratic == had) return;
  // the fit operators come and go with the setting: computed for every
  // family at the next rebuild of the shape tensors
  if (model.quadratic) {
    memory->grow(kinv2, atom->nmax, NOSPD::QuadraticFit::RECORD, "nospd/bonds:kinv2");
    for (int i = 0; i < atom->nmax; i++)
      for (int k = 0; k < NOSPD::QuadraticFit::RECORD; k++) kinv2[i][k] = 0.0;
    all_stale = true;
  } else {
    memory->destroy(kinv2);
    kinv2 = nullptr;
  }
  maxexchange = maxpartner + 22 + quadratic_record() + nhistory;
}

/* the quadratic fit operator of owned atom i's family (bond arrays current).
   A family that has lost bonds keeps the linear fit: around a crack the
   partners left fit a quadratic poorly (a one-sided, ragged family), its
   coefficients grow large, and the springs then stiffen instead of
   stabilize (the projectile scene ran away with them). */
void FixNospdBonds::quadratic_fit_of(int i)
{
  if (bond_first[i + 1] - bond_first[i] < family_size[i]) {
    for (int k = 0; k < NOSPD::QuadraticFit::RECORD; k++) kinv2[i][k] = 0.0;
    return;
  }
  Eigen::Matrix<double, 9, 9> K2 = Eigen::Matrix<double, 9, 9>::Zero();
  double phi[9];
  for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
    const int j = bond_j[b];
    for (int d = 0; d < 3; d++) phi[d] = x0s[j][d] - x0s[i][d];
    NOSPD::quadratic_terms(phi, phi + 3);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> p(phi);
    K2.noalias() += bond_w[b] * p * p.transpose();
  }
  NOSPD::quadratic_fit_inverse(K2, kinv2[i]);
}

/* ----------------------------------------------------------------------
   the largest leverage w_b xi_b^T K^-1 xi_b over atom i's intact bonds (bond
   arrays current).  F is the least-squares fit sum w Y (x) xi K^-1 of the
   bond vectors; a bond's leverage (0..1, summing to the dimension over the
   family) is how much of that bond's own motion the fit follows.  Near 1
   the fit hinges on it: breaking it moves F by its residual times
   1/(1 - leverage), and the stored energy can jump up (sweep N's impact: a
   point with 11 bonds left, conditioning 0.39, lost one of leverage 0.51
   and its energy tripled).  An intact sc family (horizon 3 spacings) has at
   most 0.04, a half-space 0.08, a corner 0.25.
------------------------------------------------------------------------- */

double FixNospdBonds::max_bond_leverage(int i, const NOSPD::Mat3 &Kinv) const
{
  const bool plane = model.dim == 2;
  double most = 0.0;
  for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
    const int j = bond_j[b];
    const NOSPD::Vec3 xi(x0s[j][0] - x0s[i][0], x0s[j][1] - x0s[i][1],
                         plane ? 0.0 : x0s[j][2] - x0s[i][2]);
    most = std::max(most, bond_w[b] * xi.dot(Kinv * xi));
  }
  return most;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::update_shape_tensors()
{
  const int nlocal = atom->nlocal;
  const int dim = model.dim;
  int nsing_local = 0;
  const int *type = atom->type;
  for (int i = 0; i < nlocal; i++) {
    if (model.active && !model.active[type[i]]) {
      singular[i] = 2;    // not a correspondence point: no state, not counted
      stale[i] = 0;
      continue;
    }
    if (all_stale || stale[i]) {
      double k[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
      double mx = 0.0, my = 0.0, mz = 0.0;
      const double xi0 = x0s[i][0], yi0 = x0s[i][1], zi0 = x0s[i][2];
      for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
        const int j = bond_j[b];
        const double w = bond_w[b];
        const double dx = x0s[j][0] - xi0, dy = x0s[j][1] - yi0, dz = x0s[j][2] - zi0;
        k[0] += w * dx * dx;
        k[1] += w * dy * dy;
        k[2] += w * dz * dz;
        k[3] += w * dx * dy;
        k[4] += w * dx * dz;
        k[5] += w * dy * dz;
        mx += w * dx;
        my += w * dy;
        mz += w * dz;
      }
      xi_moment[i][0] = mx;
      xi_moment[i][1] = my;
      xi_moment[i][2] = mz;
      NOSPD::Mat3 K;
      K << k[0], k[3], k[4], k[3], k[1], k[5], k[4], k[5], k[2];
      if (dim == 2) {
        K(0, 2) = K(1, 2) = K(2, 0) = K(2, 1) = 0.0;
        K(2, 2) = 1.0;
      }
      NOSPD::Mat3 Ki;
      // damage is irreversible: a family found singular after losing bonds
      // stays singular (conditioning_tolerance).  Losing more bonds can raise
      // its measure (tr K falls faster than det K), and the F of the few
      // bonds left, far from their reference shape by then, would bring back
      // a stored energy that no work put in (sweep N's impact: 4e9 per atom
      // in one step).
      singular[i] = NOSPD::safe_inverse(K, dim, conditioning_tolerance(i), Ki) ? 0 : 1;
      // and a damaged family whose fit hinges on one bond (max_bond_leverage)
      if (!singular[i] && lost_bonds(i) && model.damaged_leverage < 1.0 &&
          max_bond_leverage(i, Ki) > model.damaged_leverage)
        singular[i] = 1;
      NOSPD::store(Ki, kinv[i]);
      if (kinv2) quadratic_fit_of(i);
      stale[i] = 0;
    }
    nsing_local += (singular[i] == 1);
  }
  all_stale = false;
  bigint one = nsing_local;
  MPI_Allreduce(&one, &nsingular, 1, MPI_LMP_BIGINT, MPI_SUM, world);
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::count_bonds()
{
  const int nlocal = atom->nlocal;
  // broken = original family sizes less intact bonds: migration and
  // restarts drop broken partner slots, the original size travels along
  bigint slots = 0, intact = bond_first[nlocal];
  for (int i = 0; i < nlocal; i++) slots += family_size[i];
  bigint loc[2] = {intact, slots - intact}, all[2];
  MPI_Allreduce(loc, all, 2, MPI_LMP_BIGINT, MPI_SUM, world);
  nbonds_total = all[0];
  nbonds_broken = all[1];
  count_bonds_pending = false;
}

/* ----------------------------------------------------------------------
   pass 1: F = I + N K^-1 with N = sum_j w U (x) xi, U = Y - xi.  Working on
   displacements rather than positions keeps the sum free of the
   cancellation between Y and xi, so F is exact to round-off.
------------------------------------------------------------------------- */

namespace {

// what pass 1 writes per point (flat, as the fix's 2d arrays are stored)
struct DeformationOut {
  double *F;          // 9 per atom
  double *umom;       // 3 per atom
  double *moments;    // 6 per atom, or null
};

template <bool MOMENTS>
NOSPD_KERNEL_CLONES void deformation_range(const NOSPD::Positions &p, const int *first,
                                           const int *bj, const double *bw, const double *kinv,
                                           const int *singular, int dim, int from, int to,
                                           const DeformationOut &out)
{
  for (int i = from; i < to; i++) {
    double *F = out.F + 9 * i;
    double *s = out.umom + 3 * i;
    double *m = MOMENTS ? out.moments + 6 * i : nullptr;
    if (singular[i]) {
      for (int k = 0; k < 9; k++) F[k] = (k % 4 == 0) ? 1.0 : 0.0;
      if (MOMENTS)
        for (int k = 0; k < 6; k++) m[k] = 0.0;
      s[0] = s[1] = s[2] = 0.0;
      continue;
    }
    double n[9];
    NOSPD::deformation_sums<MOMENTS>(p, {bj, bw, first[i], first[i + 1]}, i, n, s, m);
    // F = I + N K^-1
    const double *K = kinv + 9 * i;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        F[3 * r + c] = (r == c ? 1.0 : 0.0) + n[3 * r] * K[c] + n[3 * r + 1] * K[3 + c] +
            n[3 * r + 2] * K[6 + c];
    if (dim == 2) {
      F[2] = F[5] = F[6] = F[7] = 0.0;
      F[8] = 1.0;
    }
  }
}

}    // namespace

void FixNospdBonds::compute_deformation(const NOSPD::Positions &pos, double **moments, int from,
                                        int to)
{
  if (to < 0) to = atom->nlocal;
  if (to <= from) return;
  const DeformationOut out{defgrad[0], u_moment[0], moments ? moments[0] : nullptr};
  if (moments)
    deformation_range<true>(pos, bond_first, bond_j, bond_w, kinv[0], singular, model.dim, from,
                            to, out);
  else
    deformation_range<false>(pos, bond_first, bond_j, bond_w, kinv[0], singular, model.dim, from,
                             to, out);
}

/* ----------------------------------------------------------------------
   LAMMPS grows x and x0 in chunks, so nall < nmax (room for the read past
   the last atom) nearly always holds; a copy covers the other case
------------------------------------------------------------------------- */

NOSPD::Positions FixNospdBonds::padded_positions()
{
  const int nall = atom->nlocal + atom->nghost;
  auto padded = [&](double **a, bool room, std::vector<double> &copy) -> const double * {
    if (nall == 0) return nullptr;
    if (room) return a[0];
    copy.assign(3 * (size_t) nall + 1, 0.0);
    std::memcpy(copy.data(), a[0], 3 * (size_t) nall * sizeof(double));
    return copy.data();
  };
  const bool room = nall < atom->nmax;
  // x0s_store keeps a spare row of its own (update_x0s)
  const bool room0 = (x0s != atom->x0) || room;
  return {padded(atom->x, room, x_padded), padded(x0s, room0, x0_padded)};
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::break_bond(int i, int slot)
{
  partner[i][slot] = 0;
  stale[i] = 1;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::bonds_changed()
{
  // breaking only removes bonds, and local indices hold until the next
  // reneighboring: drop the broken entries in place rather than look every
  // partner up again (same arrays, same order, as a rebuild would give)
  if (nbond_atoms == atom->nlocal) compact_bond_arrays();
  else build_bond_arrays();
  update_shape_tensors();
  count_bonds();
}

/* ----------------------------------------------------------------------
   remove the entries whose partner slot has been broken since the arrays
   were built (partner tag set to 0)
------------------------------------------------------------------------- */

void FixNospdBonds::compact_bond_arrays()
{
  const int nlocal = atom->nlocal;
  // in pair order the groups keep their order: move their offsets along
  // and check the symmetry of what is left (see order_for_pairs())
  uint64_t below = 0, above = 0;
  int b = 0;
  for (int i = 0; i < nlocal; i++) {
    const int start = bond_first[i], end = bond_first[i + 1];
    const int pair_from = pair_order ? bond_pair[i] : end;
    const int ghost_from = pair_order ? bond_ghost[i] : end;
    bond_first[i] = b;
    auto keep = [&](int from, int to, int group) {
      for (int k = from; k < to; k++) {
        if (partner[i][bond_slot[k]] == 0) continue;
        const int j = bond_j[k];
        bond_j[b] = j;
        bond_slot[b] = bond_slot[k];
        bond_w[b] = bond_w[k];
        b++;
        if (group == 0) below += pair_hash(j, i);
        if (group == 1) above += pair_hash(i, j);
      }
    };
    if (!pair_order) {
      keep(start, end, 2);
      continue;
    }
    keep(start, pair_from, 0);
    bond_pair[i] = b;
    keep(pair_from, ghost_from, 1);
    bond_ghost[i] = b;
    keep(ghost_from, end, 2);
  }
  bond_first[nlocal] = b;
  bond_version++;
  if (pair_order) pairs_symmetric = (below == above);
}

/* ---------------------------------------------------------------------- */

double FixNospdBonds::compute_vector(int n)
{
  if (n == 0) return (double) nbonds_total;
  if (n == 1) return (double) nbonds_broken;
  if (n == 2) return (double) nsingular;
  if (n == 3) return nhistory ? history_sum(NOSPD_HIST_WORK) : 0.0;
  return (double) nbonds_vanished;
}

/* ---------------------------------------------------------------------- */

double FixNospdBonds::memory_usage()
{
  const double nmax = atom->nmax;
  double bytes = nmax * (sizeof(int) + 2 * sizeof(double));
  bytes += nmax * maxpartner * sizeof(tagint);
  // family_size, singular, stale, family_type; own_tag
  bytes += nmax * (3 * 9 + 2 * 3 + 1) * sizeof(double) + nmax * (4 * sizeof(int) + sizeof(tagint));
  bytes += (double) nmax_first * sizeof(int);
  bytes += (double) nmax_bonds * (2 * sizeof(int) + sizeof(double));
  bytes += (double) nmax_pair * 2 * sizeof(int);
  bytes += (double) nmax_x0s * 3 * sizeof(double);
  bytes += nmax * 2.0 * nhistory * sizeof(double);
  bytes += nmax * (double) quadratic_record() * sizeof(double);
  return bytes;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::grow_arrays(int nmax)
{
  // FixPeriNeigh's arrays less r0: bond vectors come from x0, so the
  // reference length is never stored (8 bytes per bond saved)
  memory->grow(npartner, nmax, "nospd/bonds:npartner");
  memory->grow(partner, nmax, maxpartner, "nospd/bonds:partner");
  memory->grow(vinter, nmax, "nospd/bonds:vinter");
  memory->grow(wvolume, nmax, "nospd/bonds:wvolume");
  memory->grow(kinv, nmax, 9, "nospd/bonds:kinv");
  if (model.quadratic) memory->grow(kinv2, nmax, NOSPD::QuadraticFit::RECORD, "nospd/bonds:kinv2");
  memory->grow(xi_moment, nmax, 3, "nospd/bonds:xi_moment");
  memory->grow(u_moment, nmax, 3, "nospd/bonds:u_moment");
  memory->grow(family_size, nmax, "nospd/bonds:family_size");
  memory->grow(singular, nmax, "nospd/bonds:singular");
  memory->grow(stale, nmax, "nospd/bonds:stale");
  memory->grow(defgrad, nmax, 9, "nospd/bonds:defgrad");
  memory->grow(pk1, nmax, 9, "nospd/bonds:pk1");
  memory->grow(energy_density, nmax, "nospd/bonds:energy_density");
  memory->grow(own_tag, nmax, "nospd/bonds:own_tag");
  memory->grow(family_type, nmax, "nospd/bonds:family_type");
  if (nhistory) {
    memory->grow(history, nmax, nhistory, "nospd/bonds:history");
    memory->grow(history_trial, nmax, nhistory, "nospd/bonds:history_trial");
  }
}

/* ---------------------------------------------------------------------- */

bool FixNospdBonds::bond_arrays_current() const
{
  return bond_first && nbond_atoms == atom->nlocal;
}

/* ----------------------------------------------------------------------
   an atom created after the fix: virgin material
------------------------------------------------------------------------- */

void FixNospdBonds::set_arrays(int i)
{
  nbond_atoms = -1;    // local indices have changed: the bond arrays until the next rebuild
  clear_atom(i);    // own_tag 0: IDs of new atoms are set after this call, adopted at setup
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::copy_arrays(int i, int j, int /*delflag*/)
{
  nbond_atoms = -1;    // local indices have changed: the bond arrays until the next rebuild
  npartner[j] = npartner[i];
  for (int m = 0; m < npartner[j]; m++) partner[j][m] = partner[i][m];
  vinter[j] = vinter[i];
  wvolume[j] = wvolume[i];
  for (int k = 0; k < 9; k++) {
    kinv[j][k] = kinv[i][k];
    defgrad[j][k] = defgrad[i][k];
    pk1[j][k] = pk1[i][k];
  }
  for (int k = 0; k < 3; k++) {
    xi_moment[j][k] = xi_moment[i][k];
    u_moment[j][k] = u_moment[i][k];
  }
  if (kinv2)
    for (int k = 0; k < NOSPD::QuadraticFit::RECORD; k++) kinv2[j][k] = kinv2[i][k];
  family_size[j] = family_size[i];
  singular[j] = singular[i];
  stale[j] = stale[i];
  energy_density[j] = energy_density[i];
  own_tag[j] = own_tag[i];
  family_type[j] = family_type[i];
  for (int k = 0; k < nhistory; k++) {
    history[j][k] = history[i][k];
    history_trial[j][k] = history_trial[i][k];
  }
}

/* ----------------------------------------------------------------------
   migration: FixPeriNeigh's families, then K^-1 and its flags, so that a
   migrated atom needs no recomputation
------------------------------------------------------------------------- */

int FixNospdBonds::pack_exchange(int i, double *buf)
{
  // intact partners only: broken slots are dropped in transit
  int m = 1;
  for (int n = 0; n < npartner[i]; n++)
    if (partner[i][n]) buf[m++] = partner[i][n];
  buf[0] = m - 1;
  buf[m++] = vinter[i];
  buf[m++] = family_size[i];
  buf[m++] = singular[i];
  buf[m++] = stale[i];
  for (int k = 0; k < 9; k++) buf[m++] = kinv[i][k];
  if (kinv2)
    for (int k = 0; k < NOSPD::QuadraticFit::RECORD; k++) buf[m++] = kinv2[i][k];
  for (int k = 0; k < 3; k++) buf[m++] = xi_moment[i][k];
  buf[m++] = ubuf(own_tag[i]).d;
  buf[m++] = family_type[i];
  m += pack_history(i, buf + m);
  return m;
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::unpack_exchange(int nlocal, double *buf)
{
  int m = 0;
  npartner[nlocal] = static_cast<int>(buf[m++]);
  for (int n = 0; n < npartner[nlocal]; n++) partner[nlocal][n] = static_cast<tagint>(buf[m++]);
  vinter[nlocal] = buf[m++];
  wvolume[nlocal] = 0.0;
  family_size[nlocal] = static_cast<int>(buf[m++]);
  singular[nlocal] = static_cast<int>(buf[m++]);
  stale[nlocal] = static_cast<int>(buf[m++]);
  for (int k = 0; k < 9; k++) kinv[nlocal][k] = buf[m++];
  if (kinv2)
    for (int k = 0; k < NOSPD::QuadraticFit::RECORD; k++) kinv2[nlocal][k] = buf[m++];
  for (int k = 0; k < 3; k++) xi_moment[nlocal][k] = buf[m++];
  own_tag[nlocal] = (tagint) ubuf(buf[m++]).i;
  family_type[nlocal] = static_cast<int>(buf[m++]);
  if (nhistory) m += unpack_history(nlocal, buf + m, nhist_atom, nhist_bond);
  return m;
}

/* ----------------------------------------------------------------------
   restart: the families (intact partners only), the partner volume sum and
   the singular flag (kept for a family that lost bonds);
   K^-1 and the bond arrays are rebuilt from them at setup
------------------------------------------------------------------------- */

int FixNospdBonds::pack_restart(int i, double *buf)
{
  int m = 2;
  for (int n = 0; n < npartner[i]; n++)
    if (partner[i][n]) buf[m++] = partner[i][n];
  buf[1] = m - 2;
  buf[m++] = vinter[i];
  buf[m++] = family_size[i];
  // the history's layout: its size, or (with entries per partner slot)
  // minus the atom's part and the size of a slot's entry
  if (nhist_bond) {
    buf[m++] = -nhist_atom;
    buf[m++] = nhist_bond;
  } else {
    buf[m++] = nhistory;
  }
  m += pack_history(i, buf + m);
  buf[m++] = ubuf(own_tag[i]).d;
  buf[m++] = family_type[i];
  buf[m++] = singular[i] == 1;    // a damaged family's stays (update_shape_tensors)
  buf[0] = m;    // first value: size of this fix's record, as Atom expects
  return m;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  const int end = m + static_cast<int>(extra[nlocal][m]);
  m++;
  npartner[nlocal] = static_cast<int>(extra[nlocal][m++]);
  for (int n = 0; n < npartner[nlocal]; n++)
    partner[nlocal][n] = static_cast<tagint>(extra[nlocal][m++]);
  vinter[nlocal] = extra[nlocal][m++];
  family_size[nlocal] = static_cast<int>(extra[nlocal][m++]);
  wvolume[nlocal] = 0.0;
  singular[nlocal] = 0;
  stale[nlocal] = 1;
  int n_atom = static_cast<int>(extra[nlocal][m++]), n_bond = 0;
  if (n_atom < 0) {
    n_atom = -n_atom;
    n_bond = static_cast<int>(extra[nlocal][m++]);
  }
  set_history_size(n_atom, n_bond);
  if (nhistory) m += unpack_history(nlocal, &extra[nlocal][m], n_atom, n_bond);
  // files written before IDs were tracked end here: the ID is the file's
  own_tag[nlocal] = (m < end) ? (tagint) ubuf(extra[nlocal][m++]).i : 0;
  // and before the type of the families was kept: unknown (not checked)
  family_type[nlocal] = (m < end) ? static_cast<int>(extra[nlocal][m++]) : 0;
  // and before a damaged family's singularity was kept: found anew
  if (m < end) singular[nlocal] = static_cast<int>(extra[nlocal][m++]);
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::maxsize_restart()
{
  return maxpartner + 9 + nhistory;
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::size_restart(int nlocal)
{
  int n = 0;
  for (int k = 0; k < npartner[nlocal]; k++)
    if (partner[nlocal][k]) n++;
  return n + 8 + (nhist_bond ? 1 : 0) + nhist_atom + n * nhist_bond;
}

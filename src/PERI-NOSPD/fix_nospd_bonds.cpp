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
    FixPeriNeigh(lmp, made_by_pair_or_error(lmp, narg, arg), arg), x0s(nullptr),
    kinv(nullptr), kinv2(nullptr), xi_moment(nullptr), u_moment(nullptr), family_size(nullptr),
    singular(nullptr),
    defgrad(nullptr), pk1(nullptr), fcarry(nullptr), energy_density(nullptr), nsingular(0), nbonds_total(0),
    nbonds_broken(0), nbonds_vanished(0), nmax_x0s(0), stale(nullptr),
    all_stale(true), x0s_store(nullptr), own_tag(nullptr), family_type(nullptr)
{
  if (narg != 3) error->all(FLERR, "Illegal fix {} command: takes no arguments", style);
  vector_flag = 1;
  size_vector = 5;
  create_attribute = 1;
  global_freq = 1;
  extvector = 0;
  maxexchange_dynamic = 1;
  comm_forward = 2;    // FixPeriNeigh's 1, or the operator bound's 2
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
  for (int k = 0; k < 9; k++) fcarry[i][k] = (k % 4 == 0) ? 1.0 : 0.0;
  if (kinv2)
    for (int k = 0; k < NOSPD::CarriedQuadratic::ATOM_RECORD; k++) kinv2[i][k] = 0.0;
  for (int k = 0; k < 3; k++) xi_moment[i][k] = u_moment[i][k] = 0.0;
  energy_density[i] = 0.0;
  own_tag[i] = 0;
  family_type[i] = 0;
  hist.clear(i);
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
  if (lmp->update && ref_box.set && built_periodic > 0 && x0_print_set) {
    ReplacedBox &r = replaced_boxes[lmp];
    std::copy(ref_box.ref, ref_box.ref + 6, r.ref_h);
    std::copy(ref_box.last, ref_box.last + 6, r.last_h);
    std::copy(x0_print, x0_print + 7, r.print);
    r.initclock = lmp->initclock;
  } else if (!lmp->update) {
    replaced_boxes.erase(lmp);
  }
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
  memory->destroy(fcarry);
  memory->destroy(energy_density);
  memory->destroy(own_tag);
  memory->destroy(family_type);
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
               strcmp(id, ID) == 0 ? ""
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
  const bool had_reference_box = ref_box.set;    // from a restart file
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
  maxexchange = max_exchange_size();
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
  std::copy(saved.ref_h, saved.ref_h + 6, ref_box.ref);
  std::copy(saved.last_h, saved.last_h + 6, ref_box.last);
  ref_box.set = true;
  update_x0s();    // follows flips since (follow_box) and shifts the images
  bool deformed = false;
  for (int k = 0; k < 6; k++)
    if (std::abs(ref_box.ref[k] - domain->h[k]) > 1.0e-12 * scale) deformed = true;
  if (deformed && comm->me == 0)
    utils::logmesg(lmp,
                   "  Fix {}: the families of the replaced pair style had the reference box "
                   "{} x {} x {}; the new ones keep it (the box was deformed since)\n",
                   id, ref_box.ref[0], ref_box.ref[1], ref_box.ref[2]);
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
  for (int k = 0; k < 6; k++) ref_box.ref[k] = created_h[k];
  update_x0s();
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "  Fix {}: the periodic box changed since pair_coeff and the atoms moved "
                   "with it: the box at pair_coeff ({} x {} x {}) is the reference box, the body "
                   "is pre-strained\n",
                   id, created_h[0], created_h[1], created_h[2]);
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
  maxexchange = max_exchange_size();
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

  bigint ntot = 0;
  for (int i = 0; i < nlocal; i++) ntot += npartner[i];
  fam.reserve(atom->nmax, ntot);

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

  // a partner farther than the ghost cutoff is one other ranks cannot see:
  // such bonds go the same way on any rank count (settle_far_bonds)
  const double cut = comm->get_comm_cutoff();
  std::vector<MissingPartner> missing;
  std::vector<FarBond> far;
  for (int i = 0; i < nlocal; i++) {
    fam.open(i);
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
      const double Y[3] = {x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2]};
      const double len = sqrt(Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]);
      if (len > cut) {
        far.push_back({i, n, t, len});
        continue;
      }
      if (periodic && bad_i < 0) {
        // Y - xi in fractions of the periodic box vectors
        const double ux = x[j][0] - x[i][0] - dx, uy = x[j][1] - x[i][1] - dy,
                     uz = x[j][2] - x[i][2] - dz;
        const double lam[3] = {hi[0] * ux + hi[5] * uy + hi[4] * uz, hi[1] * uy + hi[3] * uz,
                               hi[2] * uz};
        for (int k = 0; k < 3; k++)
          if (pdim[k] && std::abs(lam[k]) > 0.5) bad_i = i, bad_j = j;
      }
      fam.add(j, n, weight(r, horizon[type[i]][type[j]]) * vfrac[j]);
    }
  }
  fam.close(nlocal);
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
  if (anymissing) resolve_missing(missing, far);
  settle_far_bonds(far);
  if (pair_order) fam.order_for_pairs();
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
  std::vector<int> changed;
  std::vector<Before> before;
  const bool carry = model.carry && nbond_atoms == atom->nlocal;
  if (carry) fits_before_change(changed, before);
  if (nbond_atoms == atom->nlocal)
    fam.compact([this](int i, int slot) { return partner[i][slot] == 0; });
  else build_bond_arrays();
  update_shape_tensors(!carry);
  if (carry) {
    carry_refits(changed, before);
    count_singular();
  }
  count_bonds();
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
  bytes += nmax * (4 * 9 + 2 * 3 + 1) * sizeof(double) + nmax * (4 * sizeof(int) + sizeof(tagint));
  bytes += fam.bytes();
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
  if (model.quadratic) memory->grow(kinv2, nmax, NOSPD::CarriedQuadratic::ATOM_RECORD, "nospd/bonds:kinv2");
  memory->grow(xi_moment, nmax, 3, "nospd/bonds:xi_moment");
  memory->grow(u_moment, nmax, 3, "nospd/bonds:u_moment");
  memory->grow(family_size, nmax, "nospd/bonds:family_size");
  memory->grow(singular, nmax, "nospd/bonds:singular");
  memory->grow(stale, nmax, "nospd/bonds:stale");
  memory->grow(defgrad, nmax, 9, "nospd/bonds:defgrad");
  memory->grow(pk1, nmax, 9, "nospd/bonds:pk1");
  memory->grow(fcarry, nmax, 9, "nospd/bonds:fcarry");
  memory->grow(energy_density, nmax, "nospd/bonds:energy_density");
  memory->grow(own_tag, nmax, "nospd/bonds:own_tag");
  memory->grow(family_type, nmax, "nospd/bonds:family_type");
  hist.grow(nmax);
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
    fcarry[j][k] = fcarry[i][k];
  }
  for (int k = 0; k < 3; k++) {
    xi_moment[j][k] = xi_moment[i][k];
    u_moment[j][k] = u_moment[i][k];
  }
  if (kinv2)
    for (int k = 0; k < NOSPD::CarriedQuadratic::ATOM_RECORD; k++) kinv2[j][k] = kinv2[i][k];
  family_size[j] = family_size[i];
  singular[j] = singular[i];
  stale[j] = stale[i];
  energy_density[j] = energy_density[i];
  own_tag[j] = own_tag[i];
  family_type[j] = family_type[i];
  hist.copy(i, j);
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
  for (int k = 0; k < 9; k++) buf[m++] = fcarry[i][k];
  if (kinv2)
    for (int k = 0; k < NOSPD::CarriedQuadratic::ATOM_RECORD; k++) buf[m++] = kinv2[i][k];
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
  for (int k = 0; k < 9; k++) fcarry[nlocal][k] = buf[m++];
  if (kinv2)
    for (int k = 0; k < NOSPD::CarriedQuadratic::ATOM_RECORD; k++) kinv2[nlocal][k] = buf[m++];
  for (int k = 0; k < 3; k++) xi_moment[nlocal][k] = buf[m++];
  own_tag[nlocal] = (tagint) ubuf(buf[m++]).i;
  family_type[nlocal] = static_cast<int>(buf[m++]);
  if (nhistory) m += unpack_history(nlocal, buf + m, nhist_atom, nhist_bond);
  return m;
}

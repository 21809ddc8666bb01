/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Owner of bond families, reference state (K^-1) and deformation state (F).
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include "nospd_plasticity.h"
#include "nospd_tensor.h"

static constexpr int NOSPD_HIST_WORK = NOSPD::Hist::WORK;

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ---------------------------------------------------------------------- */

FixNospdBonds::FixNospdBonds(LAMMPS *lmp, int narg, char **arg) :
    FixPeriNeigh(lmp, narg, arg), nbond_atoms(0), bond_version(0), bond_first(nullptr), bond_j(nullptr),
    bond_slot(nullptr), bond_w(nullptr), x0s(nullptr), kinv(nullptr), xi_moment(nullptr), u_moment(nullptr), family_size(nullptr), singular(nullptr),
    defgrad(nullptr), pk1(nullptr), energy_density(nullptr), nsingular(0), nbonds_total(0),
    nbonds_broken(0), nmax_bonds(0), nmax_first(0), nmax_x0s(0), stale(nullptr),
    all_stale(true), trial_ready(0), x0s_store(nullptr), ref_box_set(0)
{
  nhistory = 0;
  history = history_trial = nullptr;
  if (narg != 3) error->all(FLERR, "Illegal fix {} command: takes no arguments", style);
  vector_flag = 1;
  size_vector = 4;
  create_attribute = 1;
  global_freq = 1;
  extvector = 0;
  maxexchange_dynamic = 1;
  ref_prd[0] = ref_prd[1] = ref_prd[2] = 0.0;

  FixNospdBonds::grow_arrays(atom->nmax);
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    singular[i] = 0;
    family_size[i] = 0;
    stale[i] = 1;
    for (int k = 0; k < 9; k++) kinv[i][k] = defgrad[i][k] = pk1[i][k] = 0.0;
    for (int k = 0; k < 3; k++) xi_moment[i][k] = u_moment[i][k] = 0.0;
    energy_density[i] = 0.0;
  }
}

/* ---------------------------------------------------------------------- */

FixNospdBonds::~FixNospdBonds()
{
  memory->destroy(bond_first);
  memory->destroy(bond_j);
  memory->destroy(bond_slot);
  memory->destroy(bond_w);
  memory->destroy(x0s_store);
  memory->destroy(kinv);
  memory->destroy(xi_moment);
  memory->destroy(u_moment);
  memory->destroy(family_size);
  memory->destroy(singular);
  memory->destroy(stale);
  memory->destroy(defgrad);
  memory->destroy(pk1);
  memory->destroy(energy_density);
  memory->destroy(history);
  memory->destroy(history_trial);
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::setmask()
{
  return POST_NEIGHBOR | MIN_POST_NEIGHBOR | END_OF_STEP | POST_RUN;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::init()
{
  if (!model.horizon)
    error->all(FLERR, "Fix {} needs a peri/nospd pair style to define the horizons", style);
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
  update_x0s();
  const bool built_now = first;
  if (first) {
    build_families();
    first = 0;
  }
  // also after a restart, where build_families() does not run
  maxexchange = maxpartner + 21 + nhistory;
  build_bond_arrays();
  all_stale = true;    // after a restart or a change of settings
  update_shape_tensors();
  count_bonds();
  if (built_now) report_families();
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
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::post_neighbor()
{
  update_x0s();
  build_bond_arrays();
  update_shape_tensors();
}

/* ----------------------------------------------------------------------
   x0 in the periodic image of x, for owned and ghost atoms.  Ghosts carry
   their owner's x0 unshifted, so x - x0 = u + (image shift); the minimum
   image of that difference is the displacement u (valid while |u| stays
   below half a box length), and the rest counts whole box lengths.  The
   image of the reference is shifted by the REFERENCE box length: a box
   deformed since the families were built (fix deform, change_box) must not
   stretch the reference bonds that cross its boundary.
------------------------------------------------------------------------- */

void FixNospdBonds::update_x0s()
{
  const int nall = atom->nlocal + atom->nghost;
  if (!(domain->xperiodic || domain->yperiodic || domain->zperiodic)) {
    x0s = atom->x0;
    return;
  }
  if (!ref_box_set) {
    for (int k = 0; k < 3; k++) ref_prd[k] = domain->prd[k];
    ref_box_set = 1;
  }
  if (nall > nmax_x0s) {
    nmax_x0s = atom->nmax;
    memory->destroy(x0s_store);
    memory->create(x0s_store, nmax_x0s, 3, "nospd/bonds:x0s");
  }
  double **x = atom->x;
  double **x0 = atom->x0;
  const double *prd = domain->prd;
  const bool ortho = !domain->triclinic;
  for (int i = 0; i < nall; i++) {
    const double d0[3] = {x[i][0] - x0[i][0], x[i][1] - x0[i][1], x[i][2] - x0[i][2]};
    double d[3] = {d0[0], d0[1], d0[2]};
    domain->minimum_image(FLERR, d);
    for (int k = 0; k < 3; k++) {
      const double shift = d0[k] - d[k];    // whole current box lengths
      // triclinic boxes: images follow the current box (see the doc page)
      x0s_store[i][k] = (ortho && prd[k] > 0.0)
          ? x0[i][k] + std::round(shift / prd[k]) * ref_prd[k]
          : x[i][k] - d[k];
    }
  }
  x0s = x0s_store;
}

/* ----------------------------------------------------------------------
   global restart data: FixPeriNeigh's two values and the reference box
------------------------------------------------------------------------- */

void FixNospdBonds::write_restart(FILE *fp)
{
  double list[6] = {(double) first, (double) maxpartner, (double) ref_box_set,
                    ref_prd[0], ref_prd[1], ref_prd[2]};
  if (comm->me == 0) {
    int size = 6 * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 6, fp);
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::restart(char *buf)
{
  auto *list = (double *) buf;
  first = static_cast<int>(list[0]);
  maxpartner = static_cast<int>(list[1]);
  ref_box_set = static_cast<int>(list[2]);
  for (int k = 0; k < 3; k++) ref_prd[k] = list[3 + k];
  // partner arrays are 2D: size them now, before the per-atom data arrive
  grow_arrays(atom->nmax);
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
      if (rsq <= delta * delta && rsq > 0.0) fam[i].push_back({tag[j], vfrac[j]});
    }
  }

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

  memory->destroy(partner);
  memory->destroy(r0);
  memory->destroy(npartner);
  npartner = nullptr;
  partner = nullptr;
  r0 = nullptr;
  grow_arrays(atom->nmax);

  for (int i = 0; i < nlocal; i++) {
    npartner[i] = family_size[i] = (int) fam[i].size();
    vinter[i] = 0.0;
    wvolume[i] = 0.0;
    for (int n = 0; n < npartner[i]; n++) {
      partner[i][n] = fam[i][n].tag;
      vinter[i] += fam[i][n].vol;    // read by compute damage/atom
    }
  }
  maxexchange = maxpartner + 21 + nhistory;
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

  int nmissing = 0;
  tagint missing_tag = 0, missing_of = 0;
  int b = 0;
  for (int i = 0; i < nlocal; i++) {
    bond_first[i] = b;
    for (int n = 0; n < npartner[i]; n++) {
      const tagint t = partner[i][n];
      if (t == 0) continue;    // broken
      int j = atom->map(t);
      if (j < 0) {
        if (!nmissing++) {
          missing_tag = t;
          missing_of = atom->tag[i];
        }
        continue;
      }
      if (periodic) j = domain->closest_image(i, j);
      const double dx = x0s[j][0] - x0s[i][0];
      const double dy = x0s[j][1] - x0s[i][1];
      const double dz = x0s[j][2] - x0s[i][2];
      const double r = sqrt(dx * dx + dy * dy + dz * dz);
      bond_j[b] = j;
      bond_slot[b] = n;
      bond_w[b] = weight(r, horizon[type[i]][type[j]]) * vfrac[j];
      b++;
    }
  }
  bond_first[nlocal] = b;
  nbond_atoms = nlocal;
  bond_version++;

  int anymissing = 0;
  MPI_Allreduce(&nmissing, &anymissing, 1, MPI_INT, MPI_SUM, world);
  if (anymissing) {
    // a line-search minimizer moves atoms by up to min_modify dmax (0.1
    // distance units by default: 10 cm in SI) in its first trial step
    const std::string hint = (update->whichflag == 2)
        ? "; under minimize, set min_modify dmax to a fraction of the point spacing"
        : "";
    if (nmissing)
      error->one(FLERR,
                 "Fix {}: bond partner {} of atom {} is not on this rank nor a ghost ({} "
                 "such bonds): a bond stretched beyond the ghost cutoff; increase it with "
                 "comm_modify cutoff or break such bonds with a damage fix{}",
                 style, missing_tag, missing_of, nmissing, hint);
    error->all(FLERR, "Fix {}: bond partners lost on another rank", style);
  }
}

/* ----------------------------------------------------------------------
   K = sum_j w xi (x) xi and its inverse for every atom marked stale (all
   atoms after setup).  In 2D K(2,2) = 1 stands in for the missing
   out-of-plane direction so that 3x3 algebra serves both dimensions.
------------------------------------------------------------------------- */

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
      singular[i] = NOSPD::safe_inverse(K, dim, model.singular_tol, Ki) ? 0 : 1;
      NOSPD::store(Ki, kinv[i]);
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
}

/* ----------------------------------------------------------------------
   pass 1: F = I + N K^-1 with N = sum_j w U (x) xi, U = Y - xi.  Working on
   displacements rather than positions keeps the sum free of the
   cancellation between Y and xi, so F is exact to round-off.
------------------------------------------------------------------------- */

void FixNospdBonds::compute_deformation(double **moments)
{
  // flat views of the per-atom arrays: one load per value in the inner loop
  const double *_noalias const xf = atom->x[0];
  const double *_noalias const x0f = x0s[0];
  const int *_noalias const bj = bond_j;
  const double *_noalias const bw = bond_w;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    double *F = defgrad[i];
    if (singular[i]) {
      for (int k = 0; k < 9; k++) F[k] = (k % 4 == 0) ? 1.0 : 0.0;
      if (moments)
        for (int k = 0; k < 6; k++) moments[i][k] = 0.0;
      u_moment[i][0] = u_moment[i][1] = u_moment[i][2] = 0.0;
      continue;
    }
    const double xi0 = x0f[3 * i], yi0 = x0f[3 * i + 1], zi0 = x0f[3 * i + 2];
    const double xi = xf[3 * i], yi = xf[3 * i + 1], zi = xf[3 * i + 2];
    double n[9] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    double m[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    double sx = 0.0, sy = 0.0, sz = 0.0;
    const int bend = bond_first[i + 1];
    for (int b = bond_first[i]; b < bend; b++) {
      const int j = bj[b];
      const double w = bw[b];
      const double *X0j = x0f + 3 * j;
      const double *Xj = xf + 3 * j;
      const double ex = X0j[0] - xi0, ey = X0j[1] - yi0, ez = X0j[2] - zi0;
      const double ux = (Xj[0] - xi) - ex, uy = (Xj[1] - yi) - ey, uz = (Xj[2] - zi) - ez;
      const double wx = w * ux, wy = w * uy, wz = w * uz;
      sx += wx;
      sy += wy;
      sz += wz;
      n[0] += wx * ex;
      n[1] += wx * ey;
      n[2] += wx * ez;
      n[3] += wy * ex;
      n[4] += wy * ey;
      n[5] += wy * ez;
      n[6] += wz * ex;
      n[7] += wz * ey;
      n[8] += wz * ez;
      if (moments) {
        m[0] += wx * ux;
        m[1] += wy * uy;
        m[2] += wz * uz;
        m[3] += wx * uy;
        m[4] += wx * uz;
        m[5] += wy * uz;
      }
    }
    u_moment[i][0] = sx;
    u_moment[i][1] = sy;
    u_moment[i][2] = sz;
    const double *K = kinv[i];
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        F[3 * r + c] = (r == c ? 1.0 : 0.0) + n[3 * r] * K[c] + n[3 * r + 1] * K[3 + c] +
            n[3 * r + 2] * K[6 + c];
    if (model.dim == 2) {
      F[2] = F[5] = F[6] = F[7] = 0.0;
      F[8] = 1.0;
    }
    if (moments)
      for (int k = 0; k < 6; k++) moments[i][k] = m[k];
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
  int b = 0;
  for (int i = 0; i < nlocal; i++) {
    const int start = bond_first[i], end = bond_first[i + 1];
    bond_first[i] = b;
    for (int k = start; k < end; k++) {
      if (partner[i][bond_slot[k]] == 0) continue;
      bond_j[b] = bond_j[k];
      bond_slot[b] = bond_slot[k];
      bond_w[b] = bond_w[k];
      b++;
    }
  }
  bond_first[nlocal] = b;
  bond_version++;
}

/* ---------------------------------------------------------------------- */

double FixNospdBonds::compute_vector(int n)
{
  if (n == 0) return (double) nbonds_total;
  if (n == 1) return (double) nbonds_broken;
  if (n == 2) return (double) nsingular;
  return nhistory ? history_sum(NOSPD_HIST_WORK) : 0.0;
}

/* ----------------------------------------------------------------------
   inelastic history
------------------------------------------------------------------------- */

void FixNospdBonds::set_history_size(int n)
{
  if (n <= nhistory) return;
  // new columns start at zero: the virgin state
  const int nmax = atom->nmax;
  double **h = nullptr, **t = nullptr;
  memory->create(h, nmax, n, "nospd/bonds:history");
  memory->create(t, nmax, n, "nospd/bonds:history_trial");
  for (int i = 0; i < nmax; i++)
    for (int k = 0; k < n; k++) {
      h[i][k] = (k < nhistory) ? history[i][k] : 0.0;
      t[i][k] = h[i][k];
    }
  memory->destroy(history);
  memory->destroy(history_trial);
  history = h;
  history_trial = t;
  nhistory = n;
  maxexchange = maxpartner + 21 + nhistory;
}

/* ----------------------------------------------------------------------
   a minimization is one load step: its converged state is accepted
   (an MD run has accepted each of its steps at their end already)
------------------------------------------------------------------------- */

void FixNospdBonds::post_run()
{
  if (update->whichflag == 2) commit_history();
  trial_ready = 0;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::commit_history()
{
  if (!nhistory || !trial_ready) return;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < nhistory; k++) history[i][k] = history_trial[i][k];
  trial_ready = 0;
}

/* ---------------------------------------------------------------------- */

double FixNospdBonds::history_sum(int k)
{
  double sum = 0.0, all = 0.0;
  if (k < nhistory) {
    const int nlocal = atom->nlocal;
    // summed like pe and ke under PERI's conventions (rmass is the density,
    // the pair energy the sum of energy densities), so that
    // ke + pe + this is the conserved total
    for (int i = 0; i < nlocal; i++) sum += history[i][k];
  }
  MPI_Allreduce(&sum, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

/* ---------------------------------------------------------------------- */

double FixNospdBonds::memory_usage()
{
  const double nmax = atom->nmax;
  double bytes = nmax * (sizeof(int) + 2 * sizeof(double));
  bytes += nmax * maxpartner * sizeof(tagint);
  bytes += nmax * (3 * 9 + 2 * 3 + 1) * sizeof(double) + 3 * nmax * sizeof(int);
  bytes += (double) nmax_first * sizeof(int);
  bytes += (double) nmax_bonds * (2 * sizeof(int) + sizeof(double));
  bytes += (double) nmax_x0s * 3 * sizeof(double);
  bytes += nmax * 2.0 * nhistory * sizeof(double);
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
  memory->grow(xi_moment, nmax, 3, "nospd/bonds:xi_moment");
  memory->grow(u_moment, nmax, 3, "nospd/bonds:u_moment");
  memory->grow(family_size, nmax, "nospd/bonds:family_size");
  memory->grow(singular, nmax, "nospd/bonds:singular");
  memory->grow(stale, nmax, "nospd/bonds:stale");
  memory->grow(defgrad, nmax, 9, "nospd/bonds:defgrad");
  memory->grow(pk1, nmax, 9, "nospd/bonds:pk1");
  memory->grow(energy_density, nmax, "nospd/bonds:energy_density");
  if (nhistory) {
    memory->grow(history, nmax, nhistory, "nospd/bonds:history");
    memory->grow(history_trial, nmax, nhistory, "nospd/bonds:history_trial");
  }
}

/* ----------------------------------------------------------------------
   an atom created after the fix: virgin material
------------------------------------------------------------------------- */

void FixNospdBonds::set_arrays(int i)
{
  for (int k = 0; k < nhistory; k++) history[i][k] = history_trial[i][k] = 0.0;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::copy_arrays(int i, int j, int /*delflag*/)
{
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
  family_size[j] = family_size[i];
  singular[j] = singular[i];
  stale[j] = stale[i];
  energy_density[j] = energy_density[i];
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
  for (int k = 0; k < 3; k++) buf[m++] = xi_moment[i][k];
  for (int k = 0; k < nhistory; k++) buf[m++] = history[i][k];
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
  for (int k = 0; k < 3; k++) xi_moment[nlocal][k] = buf[m++];
  for (int k = 0; k < nhistory; k++) history[nlocal][k] = history_trial[nlocal][k] = buf[m++];
  return m;
}

/* ----------------------------------------------------------------------
   restart: the families (intact partners only) and the partner volume sum;
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
  buf[m++] = nhistory;
  for (int k = 0; k < nhistory; k++) buf[m++] = history[i][k];
  buf[0] = m;    // first value: size of this fix's record, as Atom expects
  return m;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  npartner[nlocal] = static_cast<int>(extra[nlocal][m++]);
  for (int n = 0; n < npartner[nlocal]; n++)
    partner[nlocal][n] = static_cast<tagint>(extra[nlocal][m++]);
  vinter[nlocal] = extra[nlocal][m++];
  family_size[nlocal] = static_cast<int>(extra[nlocal][m++]);
  wvolume[nlocal] = 0.0;
  singular[nlocal] = 0;
  stale[nlocal] = 1;
  const int nh = static_cast<int>(extra[nlocal][m++]);
  set_history_size(nh);
  for (int k = 0; k < nhistory; k++)
    history[nlocal][k] = history_trial[nlocal][k] = (k < nh) ? extra[nlocal][m++] : 0.0;
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::maxsize_restart()
{
  return maxpartner + 5 + nhistory;
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::size_restart(int nlocal)
{
  int n = 0;
  for (int k = 0; k < npartner[nlocal]; k++)
    if (partner[nlocal][k]) n++;
  return n + 5 + nhistory;
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: the stencil accelerator of peri/nospd/hs.  On a regular grid
   with the linear law, the bond-associated operator of a family is the
   same for every point of one neighbourhood: it is assembled once per
   neighbourhood (a stencil), and the force pass applies it to the
   displacements.  One call from the force pass: stencil_pass.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_hs.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "neighbor.h"

#include "nospd_simd.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <numeric>

using namespace LAMMPS_NS;
using NOSPD::BondPattern;
using NOSPD::HSForm;
using NOSPD::Mat3;
using namespace HSTuning;

namespace {
// the stencil's points [from, to) of a run: forces four at a time (the
// last ones two or one at a time: the same bits), then each point's F and
// mean bond H
template <int DIM, bool ONE>
NOSPD_KERNEL_CLONES void stencil_kernel(const NOSPD::Stencil &st, const double *u,
                                        const int *cells, const int *pair_lin,
                                        const int *slot_lin, int from, int to, double (*f)[3],
                                        double (*H)[9], double (*Hbar)[9])
{
  int q = from;
  for (; q + 4 <= to; q += 4) {
    const long c[4] = {cells[q], cells[q + 1], cells[q + 2], cells[q + 3]};
    NOSPD::stencil_forces<DIM, 4, ONE>(st, u, c, pair_lin, f + (q - from));
  }
  for (; q + 2 <= to; q += 2) {
    const long c[2] = {cells[q], cells[q + 1]};
    NOSPD::stencil_forces<DIM, 2, ONE>(st, u, c, pair_lin, f + (q - from));
  }
  if (q < to) {
    const long c[1] = {cells[q]};
    NOSPD::stencil_forces<DIM, 1, ONE>(st, u, c, pair_lin, f + (q - from));
  }
  for (q = from; q < to; q++)
    NOSPD::stencil_family<DIM, ONE>(st, u, cells[q], slot_lin, H[q - from], Hbar[q - from]);
}
}    // namespace

/* what the stencils of a pattern and type are a function of, besides the
   pattern: the form, the strain law and plane, and each type's material */

std::vector<double> PairPeriNospdHS::stencil_law_signature() const
{
  std::vector<double> sig = {(double) hs_form, hs_ratio, (double) strain_law,
                             (double) plane_mode, (double) domain->dimension};
  for (int i = 1; i <= atom->ntypes; i++) {
    const NOSPD::Lame &m = lame[i];
    const NOSPD::LinearLaw &l = linear_law[i];
    sig.insert(sig.end(), {(double) active[i], m.lambda, m.mu, m.lambda_ps, (double) l.ok, l.lam,
                           l.mu, cut[i][i]});
  }
  return sig;
}

/* ----------------------------------------------------------------------
   give back the user's communication cutoff where this style raised it
   and nobody changed it since (a later run without the stencil, another
   pair style)
------------------------------------------------------------------------- */

void PairPeriNospdHS::restore_ghost_cutoff()
{
  if (cutghost_raised < 0.0) return;
  if (comm->cutghostuser == cutghost_raised) comm->cutghostuser = cutghost_replaced;
  cutghost_raised = cutghost_replaced = -1.0;
}

/* ----------------------------------------------------------------------
   The stencil reads the displacements within 2 delta of a point.  Ghosts
   reach delta plus the skin by default: the points within 2 delta of a
   subdomain's edge, or a periodic box's, would then take their families,
   about eight times the cost (on 2 ranks, half the block).  Where the
   stencil can apply, raise the communication cutoff to 2 delta plus the
   skin, as LAMMPS's styles that need far ghosts do, and say so.
------------------------------------------------------------------------- */

void PairPeriNospdHS::ghosts_for_stencil()
{
  bool linear = false;
  double delta_max = 0.0;
  for (int i = 1; i <= atom->ntypes; i++) {
    linear = linear || linear_law[i].ok;
    for (int j = i; j <= atom->ntypes; j++) delta_max = MAX(delta_max, cut[i][j]);
  }
  const bool edges =
      comm->nprocs > 1 || domain->xperiodic || domain->yperiodic || domain->zperiodic;
  restore_ghost_cutoff();    // decided anew each run: the settings may have changed
  if (!stencil_on || !linear || !edges || user_law() || fix_bonds->nhistory > 0) return;
  const double need = 2.0 * delta_max + neighbor->skin;
  if (comm->get_comm_cutoff() >= need) return;
  cutghost_replaced = comm->cutghostuser;
  cutghost_raised = need;
  comm->cutghostuser = need;
  if (comm->me == 0)
    error->warning(FLERR,
                   "pair_style {}: increasing the communication cutoff to {:.8} (2 delta plus "
                   "the skin), so that points near subdomain edges take the linear law's "
                   "stencil; 'stencil no' keeps the default cutoff",
                   force->pair_style, need);
}

/* ----------------------------------------------------------------------
   The stencil of a pattern under a type's law, built on first use; null
   where the law or the pattern has none (nospd_stencil.h)
------------------------------------------------------------------------- */

const NOSPD::Stencil *PairPeriNospdHS::stencil_for(int pattern, int type)
{
  auto &byType = pattern_stencils[pattern];
  auto it = byType.find(type);
  if (it == byType.end()) {
    const BondPattern &p = patterns[pattern];
    NOSPD::Stencil st = domain->dimension == 2
        ? NOSPD::build_stencil<2>(p, hs_form, strain_law, plane_mode, lame[type], linear_law[type])
        : NOSPD::build_stencil<3>(p, hs_form, strain_law, plane_mode, lame[type], linear_law[type]);
    it = byType.emplace(type, std::move(st)).first;
    nstencils_built++;
  }
  return it->second.ok ? &it->second : nullptr;
}

/* ----------------------------------------------------------------------
   Owned and ghost atoms on a lattice of spacings h, by their reference
   positions: cell_grid maps a cell to its atom (-1 none, -2 two atoms).
   coords receives each atom's cell (INT_MIN off the lattice).  False if
   the grid would be much larger than the atoms (bodies far apart).
------------------------------------------------------------------------- */

bool PairPeriNospdHS::build_cell_grid(const double *h, std::vector<std::array<int, 3>> &coords,
                                      long stride[3])
{
  const int nall = atom->nlocal + atom->nghost;
  double **x0s = fix_bonds->x0s;
  const int dim = domain->dimension;
  coords.assign(nall, {INT_MIN, INT_MIN, INT_MIN});
  int lo[3] = {INT_MAX, INT_MAX, INT_MAX}, hi[3] = {INT_MIN, INT_MIN, INT_MIN};
  for (int a = 0; a < nall; a++) {
    std::array<int, 3> c = {0, 0, 0};
    bool on = true;
    for (int k = 0; k < dim && on; k++) {
      const double q = (x0s[a][k] - x0s[0][k]) / h[k];
      on = std::abs(q) < 1.0e9 && std::abs(q - std::nearbyint(q)) <= 1.0e-6;
      if (on) c[k] = (int) std::nearbyint(q);
    }
    if (!on) continue;
    coords[a] = c;
    for (int k = 0; k < 3; k++) {
      lo[k] = MIN(lo[k], c[k]);
      hi[k] = MAX(hi[k], c[k]);
    }
  }
  if (lo[0] > hi[0]) return false;
  double cells = 1.0;
  for (int k = 0; k < 3; k++) cells *= (double) (hi[k] - lo[k] + 1);
  if (cells > 8.0 * nall + 4096.0) return false;
  stride[0] = 1;
  stride[1] = hi[0] - lo[0] + 1;
  stride[2] = stride[1] * (hi[1] - lo[1] + 1);
  cell_grid.assign((size_t) cells, -1);
  cell_of.assign(nall, -1);
  for (int a = 0; a < nall; a++) {
    if (coords[a][0] == INT_MIN) continue;
    for (int k = 0; k < 3; k++) coords[a][k] -= lo[k];
    cell_of[a] = coords[a][0] + stride[1] * coords[a][1] + stride[2] * coords[a][2];
    int &cell = cell_grid[cell_of[a]];
    cell = cell == -1 ? a : -2;
  }
  return true;
}

/* ----------------------------------------------------------------------
   Which owned atoms take the stencil, after the families were mapped: an
   atom whose pattern (shared by >= PROGRAM_USERS families) has a stencil,
   whose every partner has the same pattern, type and volume (a key that
   travels to ghosts), and whose cells within 2 delta are all there.  The
   families that only feed such atoms are not evaluated on stencil steps.
------------------------------------------------------------------------- */

void PairPeriNospdHS::map_stencils()
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  stencils_stale = false;
  std::vector<int> users(patterns.size(), 0);
  for (int i = 0; i < nlocal; i++) users[state_pattern[i]]++;
  stencil_runs.clear();
  stencil_blocks.clear();
  cell_grid.clear();
  cell_of.clear();
  on_stencil.assign(nall, 0);
  family_order = state_order;
  bigint nlocal_on = 0;
  const bool possible = stencil_on && fix_bonds->nhistory == 0 && !user_law();
  if (!possible) {
    nstencil_all = 0;
    pvector[1] = 0.0;
    return;
  }

  std::vector<const NOSPD::Stencil *> st_of(nlocal, nullptr);
  std::map<double, std::pair<int, int>> family_of;
  family_keys(users, st_of, family_of);
  comm_mode = 1;
  comm->forward_comm(this);

  double h[3] = {0.0, 0.0, 0.0};
  std::vector<std::array<int, 3>> coords;
  long stride[3] = {0, 0, 0};
  const bool grid = stencil_grid(users, st_of, h, coords, stride);
  std::map<const NOSPD::Stencil *, int> run_of;
  if (grid) nlocal_on += map_grid_points(st_of, coords, stride, h, run_of);
  // the points near surfaces, interfaces and broken bonds
  if (grid) nlocal_on += map_point_stencils(coords, stride, h, family_of, run_of);
  order_stencil_runs();
  // the flags go to the ghosts, whose families then leave them out
  comm_mode = 2;
  comm->forward_comm(this);
  comm_mode = 0;
  families_off_stencil();
  pvector[1] = (double) nlocal_on;
  MPI_Allreduce(&nlocal_on, &nstencil_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
}

/* ----------------------------------------------------------------------
   every owned atom's family key, and its inside stencil (st_of); the keys
   go to the ghosts.  A key hashes the pattern's shape and weights and the
   type into 52 bits, so that a double holds it exactly.  family_of: key ->
   (pattern, type) of the families owned here ((-1, -1) for two that share
   a key).  A collision of keys between ranks would go unseen; at 52 bits
   over a few thousand patterns its chance is below 1e-8.
------------------------------------------------------------------------- */

void PairPeriNospdHS::family_keys(const std::vector<int> &users,
                                  std::vector<const NOSPD::Stencil *> &st_of,
                                  std::map<double, std::pair<int, int>> &family_of)
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const int *type = atom->type;
  stencil_key.assign(nall, 0.0);
  std::map<std::pair<int, int>, double> key_of;
  for (int i = 0; i < nlocal; i++) {
    const int k = state_pattern[i];
    auto it = key_of.find({k, type[i]});
    if (it == key_of.end()) {
      BondPattern &p = patterns[k];
      if (!p.shape_hash) {
        std::vector<int64_t> key = p.key;
        for (double w : p.w) key.push_back(std::llround(std::log(w) * 1.0e9));
        // (a family kept singular for good has tol infinity)
        key.push_back(std::isfinite(p.tol) ? std::llround(std::log(p.tol) * 1.0e9) : INT64_MAX);
        p.shape_hash = key_hash(key) | 1;
      }
      const uint64_t h = key_hash({(int64_t) p.shape_hash, (int64_t) type[i]});
      it = key_of.emplace(std::make_pair(k, type[i]), (double) ((h >> 12) | 1)).first;
      auto ins = family_of.emplace(it->second, std::make_pair(k, type[i]));
      if (!ins.second) ins.first->second = {-1, -1};
    }
    stencil_key[i] = it->second;
    if (users[k] >= PROGRAM_USERS) st_of[i] = stencil_for(k, type[i]);
  }
}

/* ----------------------------------------------------------------------
   the cell grid on the lattice of the first stencil, else of the most
   common pattern (a body thinner than 4 delta has no inside); false where
   there is none
------------------------------------------------------------------------- */

bool PairPeriNospdHS::stencil_grid(const std::vector<int> &users,
                                   const std::vector<const NOSPD::Stencil *> &st_of, double *h,
                                   std::vector<std::array<int, 3>> &coords, long *stride)
{
  const int nlocal = atom->nlocal;
  const NOSPD::Stencil *first = nullptr;
  for (int i = 0; i < nlocal && !first; i++) first = st_of[i];
  bool lattice = first != nullptr;
  if (first) std::copy_n(first->h, 3, h);
  else if (!patterns.empty()) {
    const int k = (int) (std::max_element(users.begin(), users.end()) - users.begin());
    lattice = domain->dimension == 2 ? NOSPD::pattern_lattice<2>(patterns[k], h)
                                     : NOSPD::pattern_lattice<3>(patterns[k], h);
  }
  return lattice && build_cell_grid(h, coords, stride);
}

/* ----------------------------------------------------------------------
   the inside points: an owned atom whose partners all share its key, type
   and volume takes its pattern's stencil; returns how many did
------------------------------------------------------------------------- */

bigint PairPeriNospdHS::map_grid_points(const std::vector<const NOSPD::Stencil *> &st_of,
                                        const std::vector<std::array<int, 3>> &coords,
                                        const long *stride, const double *h,
                                        std::map<const NOSPD::Stencil *, int> &run_of)
{
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  const double *vfrac = atom->vfrac;
  bigint n = 0;
  bool collisions = false;
  for (int c : cell_grid) collisions = collisions || c == -2;
  for (int i = 0; i < nlocal; i++) {
    const NOSPD::Stencil *st = st_of[i];
    if (!st || coords[i][0] == INT_MIN || st->h[0] != h[0] || st->h[1] != h[1] ||
        st->h[2] != h[2])
      continue;
    bool ok = true, all_owned = true;
    for (int b = fix_bonds->bond_first[i]; ok && b < fix_bonds->bond_first[i + 1]; b++) {
      const int j = fix_bonds->bond_j[b];
      ok = stencil_key[j] == stencil_key[i] && type[j] == type[i] && vfrac[j] == vfrac[i];
      if (j < nlocal) ok = ok && state_pattern[j] == state_pattern[i];
      else all_owned = false;
    }
    // owned partners of one pattern have their partners here: their cells
    // exist, unless two atoms share one
    if (ok && (!all_owned || collisions)) ok = stencil_cells_present(*st, coords[i], stride);
    if (!ok) continue;
    join_stencil_run(i, st, stride, run_of);
    n++;
  }
  return n;
}

/* ----------------------------------------------------------------------
   each run in cell order: consecutive points share most of their
   neighbourhoods in the cache; then the runs cut into blocks of points,
   the stencil pass's work items, in the order of their first cells
------------------------------------------------------------------------- */

void PairPeriNospdHS::order_stencil_runs()
{
  for (StencilRun &run : stencil_runs) {
    std::vector<int> order(run.atoms.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return run.cells[a] < run.cells[b]; });
    std::vector<int> atoms(order.size()), cells(order.size());
    for (size_t q = 0; q < order.size(); q++) {
      atoms[q] = run.atoms[order[q]];
      cells[q] = run.cells[order[q]];
    }
    run.atoms.swap(atoms);
    run.cells.swap(cells);
  }
  // the runs cut into blocks of points, the stencil pass's work items, in
  // the order of their first cells: threads that split them in contiguous
  // ranges get slabs of the body, each with its share of the one-sided
  // stencils (which cost about twice the grid's)
  stencil_blocks.clear();
  for (int r = 0; r < (int) stencil_runs.size(); r++)
    for (int q0 = 0; q0 < (int) stencil_runs[r].atoms.size(); q0 += STENCIL_BLOCK)
      stencil_blocks.push_back(
          {r, q0, std::min((int) stencil_runs[r].atoms.size(), q0 + STENCIL_BLOCK)});
  std::sort(stencil_blocks.begin(), stencil_blocks.end(),
            [&](const std::array<int, 3> &a, const std::array<int, 3> &b) {
              return stencil_runs[a[0]].cells[a[1]] < stencil_runs[b[0]].cells[b[1]];
            });
}

/* ----------------------------------------------------------------------
   the families evaluated one by one: those with a target off the stencil
------------------------------------------------------------------------- */

void PairPeriNospdHS::families_off_stencil()
{
  family_order.clear();
  for (int i : state_order) {
    bool needed = !on_stencil[i];
    for (int b = fix_bonds->bond_first[i]; !needed && b < fix_bonds->bond_first[i + 1]; b++)
      needed = !on_stencil[fix_bonds->bond_j[b]];
    if (needed) family_order.push_back(i);
  }
}

/* ----------------------------------------------------------------------
   Whether every cell a stencil reads around a point's cell holds one atom
------------------------------------------------------------------------- */

bool PairPeriNospdHS::stencil_cells_present(const NOSPD::Stencil &st,
                                            const std::array<int, 3> &at, const long *stride) const
{
  auto there = [&](const int *off) {
    for (int sgn = st.one_sided ? 1 : -1; sgn <= 1; sgn += 2) {
      long c = 0;
      for (int k = 0; k < 3; k++) {
        const long ck = at[k] + sgn * off[k];
        const long nk = k == 2 ? (long) cell_grid.size() / stride[2] : stride[k + 1] / stride[k];
        if (ck < 0 || ck >= nk) return false;
        c += ck * stride[k];
      }
      if (cell_grid[c] < 0) return false;
    }
    return true;
  };
  // the point's own cell too (its displacement is read from there)
  const int zero[3] = {0, 0, 0};
  if (!there(zero)) return false;
  for (int q = 0; q < st.npairs(); q++)
    if (!there(&st.pair_off[3 * q])) return false;
  for (int q = 0; q < st.nslots(); q++)
    if (!there(&st.slot_off[3 * q])) return false;
  return true;
}

/* ----------------------------------------------------------------------
   Owned atom i takes stencil st: its run (one per stencil) gains it
------------------------------------------------------------------------- */

void PairPeriNospdHS::join_stencil_run(int i, const NOSPD::Stencil *st, const long *stride,
                                       std::map<const NOSPD::Stencil *, int> &run_of)
{
  auto it = run_of.find(st);
  if (it == run_of.end()) {
    it = run_of.emplace(st, (int) stencil_runs.size()).first;
    StencilRun run;
    run.st = st;
    auto lin = [&](const int *off) {
      return (int) (off[0] * stride[0] + off[1] * stride[1] + off[2] * stride[2]);
    };
    for (int q = 0; q < st->npairs(); q++) run.pair_lin.push_back(lin(&st->pair_off[3 * q]));
    for (int q = 0; q < st->nslots(); q++) run.slot_lin.push_back(lin(&st->slot_off[3 * q]));
    stencil_runs.push_back(std::move(run));
  }
  StencilRun &run = stencil_runs[it->second];
  run.atoms.push_back(i);
  run.cells.push_back(cell_of[i]);
  on_stencil[i] = 1;
}

/* ----------------------------------------------------------------------
   The neighbourhood of owned atom i: its family key and volume, then, slot
   by slot of its pattern, each partner's family key and volume (bit
   patterns).  Points with one neighbourhood have one force operator.
------------------------------------------------------------------------- */

void PairPeriNospdHS::neighbourhood_key(int i, std::vector<int64_t> &key) const
{
  auto bits = [](double v) {
    int64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  const double *vfrac = atom->vfrac;
  const int n = state_count[i];
  const uint16_t *perm = &state_perm[state_first[i]];
  const int *bj = fix_bonds->bond_j + fix_bonds->bond_first[i];
  key.resize(2 * n + 2);
  key[0] = bits(stencil_key[i]);
  key[1] = bits(vfrac[i]);
  for (int s = 0; s < n; s++) {
    const int j = bj[perm[s]];
    key[2 * s + 2] = bits(stencil_key[j]);
    key[2 * s + 3] = bits(vfrac[j]);
  }
}

/* ----------------------------------------------------------------------
   One-sided stencils (nospd_stencil.h) for the owned atoms the grid's
   stencil left out, where at least POINT_STENCIL_USERS of them share a
   neighbourhood, every family of it is known here (owned, or a ghost
   whose key an owned family has) and has a linear law, and every cell it
   reads holds an atom.  Stencils are kept by neighbourhood between
   mappings; those no atom uses any more are dropped.  Returns the number
   of atoms that joined.
------------------------------------------------------------------------- */

int PairPeriNospdHS::map_point_stencils(const std::vector<std::array<int, 3>> &coords,
                                        const long *stride, const double *h,
                                        const std::map<double, std::pair<int, int>> &family_of,
                                        std::map<const NOSPD::Stencil *, int> &run_of)
{
  const int nlocal = atom->nlocal;
  const int *type = atom->type;

  // candidates: enough points of their own family's pattern and material
  // (a cheap first cut where damage has made most families unique), then
  // grouped by neighbourhood
  std::vector<int> candidates;
  std::unordered_map<double, int> own_count;
  for (int i = 0; i < nlocal; i++) {
    if (on_stencil[i] || coords[i][0] == INT_MIN) continue;
    if (patterns[state_pattern[i]].atom_singular || !linear_law[type[i]].ok) continue;
    candidates.push_back(i);
    own_count[stencil_key[i]]++;
  }
  std::unordered_map<uint64_t, std::vector<int>> by_hash;
  std::vector<int64_t> key, other;
  for (int i : candidates) {
    if (own_count[stencil_key[i]] < POINT_STENCIL_USERS) continue;
    neighbourhood_key(i, key);
    by_hash[key_hash(key)].push_back(i);
  }
  struct Group {
    std::vector<int64_t> key;
    std::vector<int> atoms;
    NOSPD::Stencil *st = nullptr;
  };
  std::vector<Group> groups;
  for (auto &kv : by_hash) {
    if ((int) kv.second.size() < POINT_STENCIL_USERS) continue;
    Group g;
    neighbourhood_key(kv.second[0], g.key);
    for (int i : kv.second) {
      neighbourhood_key(i, other);
      if (other == g.key) g.atoms.push_back(i);
    }
    if ((int) g.atoms.size() >= POINT_STENCIL_USERS) groups.push_back(std::move(g));
  }

  // the stencils kept from earlier mappings, and those to build
  std::map<std::vector<int64_t>, NOSPD::Stencil> kept;
  // After the first mapping of a run, new neighbourhoods come from bonds
  // breaking (or atoms migrating): a crack front's are many, short-lived
  // and shared by few points, and evaluating their families' operators
  // would cost more steps than they save; only those of many points are
  // built then.
  std::vector<int> to_build;
  for (int q = 0; q < (int) groups.size(); q++) {
    auto it = point_stencils.find(groups[q].key);
    if (it != point_stencils.end()) {
      groups[q].st = &kept.emplace(it->first, std::move(it->second)).first->second;
    } else if (first_point_mapping || (int) groups[q].atoms.size() >= PROGRAM_USERS)
      to_build.push_back(q);
  }
  point_stencils.swap(kept);
  first_point_mapping = false;
  std::vector<std::pair<const std::vector<int64_t> *, int>> needs;
  for (int q : to_build) needs.emplace_back(&groups[q].key, groups[q].atoms[0]);
  build_point_stencils(needs, h, family_of);

  int joined = 0;
  for (Group &g : groups) {
    if (!g.st) {
      auto it = point_stencils.find(g.key);
      if (it == point_stencils.end()) continue;
      g.st = &it->second;
    }
    if (!g.st->ok) continue;
    for (int i : g.atoms) {
      if (!stencil_cells_present(*g.st, coords[i], stride)) continue;
      join_stencil_run(i, g.st, stride, run_of);
      joined++;
    }
  }
  return joined;
}

/* ----------------------------------------------------------------------
   Build the one-sided stencils of neighbourhoods (key, an atom that has
   it) into point_stencils (not ok where a family is unknown here, has no
   linear law or no shape tensor, or is off the lattice).  Each family
   operator (pattern and type) is evaluated once per batch and added into
   every neighbourhood that reads it.
------------------------------------------------------------------------- */

// the family operators a batch of one-sided stencils reads, and who reads
// which: per need (a neighbourhood) its own family's operator and whether
// every family it reads has one
struct PairPeriNospdHS::PointPlan {
  using Offset = NOSPD::detail::Offset;
  struct Operator {
    int pattern, type;
    bool ok;
    std::vector<Offset> e;
    std::map<Offset, int> slot_at;
  };
  struct Ref {
    int need, slot;    // slot -1: the need's own family
    Offset at;         // the family's centre relative to the point
    double ws;         // (V_centre / V_point) w_slot
  };
  std::vector<Operator> ops;
  std::vector<std::vector<Ref>> refs;    // by operator
  std::map<std::pair<int, int>, int> op_of;
  int emax = 0;
  std::vector<char> ok;
  std::vector<int> own;
};

void PairPeriNospdHS::build_point_stencils(
    const std::vector<std::pair<const std::vector<int64_t> *, int>> &needs, const double *h,
    const std::map<double, std::pair<int, int>> &family_of)
{
  if (needs.empty()) return;
  PointPlan P;
  plan_point_stencils(needs, h, family_of, P);
  assemble_point_stencils(needs, h, P);
}

/* ----------------------------------------------------------------------
   the operators each neighbourhood reads: its own family's and, for every
   partner, that partner's family's (whose slot points back at it)
------------------------------------------------------------------------- */

void PairPeriNospdHS::plan_point_stencils(
    const std::vector<std::pair<const std::vector<int64_t> *, int>> &needs, const double *h,
    const std::map<double, std::pair<int, int>> &family_of, PointPlan &P)
{
  using NOSPD::detail::Offset;
  const int nlocal = atom->nlocal, dim = domain->dimension;
  const int *type = atom->type;
  const double *vfrac = atom->vfrac;
  auto op_index = [&](int k, int t) {
    auto it = P.op_of.find({k, t});
    if (it != P.op_of.end()) return it->second;
    PointPlan::Operator op{k, t, false, {}, {}};
    const BondPattern &p = patterns[k];
    op.ok = !p.atom_singular && linear_law[t].ok &&
        (dim == 2 ? NOSPD::lattice_offsets<2>(p, h, op.e) : NOSPD::lattice_offsets<3>(p, h, op.e));
    for (int s = 0; op.ok && s < p.n; s++) {
      op.slot_at[op.e[s]] = s;
      for (int c = 0; c < 3; c++) P.emax = MAX(P.emax, std::abs(op.e[s][c]));
    }
    P.ops.push_back(std::move(op));
    P.refs.emplace_back();
    P.op_of.emplace(std::make_pair(k, t), (int) P.ops.size() - 1);
    return (int) P.ops.size() - 1;
  };

  const int nneed = (int) needs.size();
  P.ok.assign(nneed, 1);
  P.own.assign(nneed, 0);
  for (int q = 0; q < nneed; q++) {
    const int i = needs[q].second;
    const int oi = op_index(state_pattern[i], type[i]);
    P.own[q] = oi;
    if (!P.ops[oi].ok) {
      P.ok[q] = 0;
      continue;
    }
    P.refs[oi].push_back({q, -1, {0, 0, 0}, 1.0});
    const int n = state_count[i];
    const uint16_t *perm = &state_perm[state_first[i]];
    const int *bj = fix_bonds->bond_j + fix_bonds->bond_first[i];
    for (int s = 0; P.ok[q] && s < n; s++) {
      const int j = bj[perm[s]];
      int pj = -1;
      if (j < nlocal) pj = state_pattern[j];
      else {
        auto f = family_of.find(stencil_key[j]);
        if (f != family_of.end() && f->second.second == type[j]) pj = f->second.first;
      }
      if (pj < 0) {
        P.ok[q] = 0;
        break;
      }
      const int oj = op_index(pj, type[j]);
      const Offset a = P.ops[oi].e[s];
      auto slot = P.ops[oj].slot_at.find(NOSPD::detail::neg(a));
      if (!P.ops[oj].ok || slot == P.ops[oj].slot_at.end()) {
        P.ok[q] = 0;
        break;
      }
      const double ws = vfrac[j] / vfrac[i] * patterns[pj].w[slot->second];
      P.refs[oj].push_back({q, slot->second, a, ws});
    }
  }

}

/* ----------------------------------------------------------------------
   batches of neighbourhoods, each assembled on a dense cube of blocks
------------------------------------------------------------------------- */

void PairPeriNospdHS::assemble_point_stencils(
    const std::vector<std::pair<const std::vector<int64_t> *, int>> &needs, const double *h,
    PointPlan &P)
{
  const int dim = domain->dimension;
  const int R = 2 * P.emax, nneed = (int) needs.size();
  const double cube = 72.0 * (2 * R + 1) * (2 * R + 1) * (dim == 3 ? 2 * R + 1 : 1);
  const int batch = MAX(1, (int) (POINT_STENCIL_BATCH_BYTES / cube));
  std::vector<double> A;
  for (int q0 = 0; q0 < nneed; q0 += batch) {
    const int q1 = MIN(nneed, q0 + batch);
    std::vector<NOSPD::PointStencilBuilder> builders(q1 - q0, NOSPD::PointStencilBuilder(dim, R));
    for (size_t o = 0; o < P.ops.size(); o++) {
      bool used = false;
      for (const PointPlan::Ref &r : P.refs[o]) used = used || (r.need >= q0 && r.need < q1 && P.ok[r.need]);
      if (!used) continue;
      const PointPlan::Operator &op = P.ops[o];
      const BondPattern &p = patterns[op.pattern];
      const bool have = dim == 2
          ? NOSPD::family_operator<2>(p, hs_form, strain_law, plane_mode, lame[op.type],
                                      linear_law[op.type], h[0], A)
          : NOSPD::family_operator<3>(p, hs_form, strain_law, plane_mode, lame[op.type],
                                      linear_law[op.type], h[0], A);
      for (const PointPlan::Ref &r : P.refs[o]) {
        if (r.need < q0 || r.need >= q1 || !P.ok[r.need]) continue;
        NOSPD::PointStencilBuilder &b = builders[r.need - q0];
        const bool added = have &&
            (r.slot < 0 ? b.add_own(op.e, p.w, A) : b.add_member(r.at, op.e, A, r.slot, r.ws));
        if (!added) P.ok[r.need] = 0;
      }
    }
    for (int q = q0; q < q1; q++) {
      NOSPD::Stencil &st = point_stencils[*needs[q].first];
      if (!P.ok[q]) continue;
      const PointPlan::Operator &op = P.ops[P.own[q]];
      st = dim == 2 ? builders[q - q0].finish<2>(patterns[op.pattern], op.e, h)
                    : builders[q - q0].finish<3>(patterns[op.pattern], op.e, h);
      nstencils_built++;
    }
  }
}

/* ----------------------------------------------------------------------
   Forces, F and stress of the points on the stencil
------------------------------------------------------------------------- */

void PairPeriNospdHS::stencil_pass()
{
  // displacements by lattice cell: a point's neighbours without lookups
  // (cells that hold no atom, or two, are never read)
  const int nall = atom->nlocal + atom->nghost;
  double **x = atom->x;
  double **x0s = fix_bonds->x0s;
  ustencil.resize(4 * cell_grid.size() + 4);
  double *u = ustencil.data();
  for (int a = 0; a < nall; a++) {
    const long c = cell_of[a];
    if (c < 0) continue;
    for (int k = 0; k < 3; k++) u[4 * c + k] = x[a][k] - x0s[a][k];
    u[4 * c + 3] = 0.0;
  }
  double **f = atom->f;
  const bool two = domain->dimension == 2;
  // one range over the blocks of every run: threads share the many short
  // runs of one-sided stencils as well as the long one of the grid's
  for_ranges((int) stencil_blocks.size(), true, [&](int from, int to, int, Tally &) {
    double fb[STENCIL_BLOCK][3], Hb[STENCIL_BLOCK][9], Hbarb[STENCIL_BLOCK][9];
    for (int b = from; b < to; b++) {
      const StencilRun &run = stencil_runs[stencil_blocks[b][0]];
      const int q0 = stencil_blocks[b][1], q1 = stencil_blocks[b][2];
      const int *cells = run.cells.data(), *pl = run.pair_lin.data(), *sl = run.slot_lin.data();
      const bool one = run.st->one_sided;
      if (two && one) stencil_kernel<2, true>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      else if (two) stencil_kernel<2, false>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      else if (one) stencil_kernel<3, true>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      else stencil_kernel<3, false>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      for (int q = q0; q < q1; q++) {
        const int i = run.atoms[q];
        for (int k = 0; k < 3; k++) f[i][k] += fb[q - q0][k];
        store_stencil_state(i, *run.st, Hb[q - q0], Hbarb[q - q0]);
      }
    }
  });
}

/* ----------------------------------------------------------------------
   F and stress of a point on the stencil, as the family path stores them:
   P of the bonds' mean H (the law is linear), the family's F through the
   law where singular bond families use it (plane stress solves F_zz)
------------------------------------------------------------------------- */

void PairPeriNospdHS::store_stencil_state(int i, const NOSPD::Stencil &st, const double *H,
                                          const double *Hbar)
{
  const int itype = atom->type[i];
  Mat3 F = NOSPD::load(H) + Mat3::Identity(), Fbar = NOSPD::load(Hbar) + Mat3::Identity();
  Mat3 P, Pf;
  double W;
  NOSPD::first_piola(strain_law, plane_mode, lame[itype], Fbar, P, W);
  if (st.family_fallback) NOSPD::first_piola(strain_law, plane_mode, lame[itype], F, Pf, W);
  // plane stress: the bonds' mean out-of-plane stretch, as the family path
  if (plane_mode == NOSPD::Plane::STRESS) F(2, 2) = Fbar(2, 2);
  NOSPD::store(F, fix_bonds->defgrad[i]);
  NOSPD::store(P, fix_bonds->pk1[i]);
}

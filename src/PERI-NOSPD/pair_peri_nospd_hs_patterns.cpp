/* ----------------------------------------------------------------------
   PERI-NOSPD: pattern sharing in peri/nospd/hs.  Families whose bonds have
   the same offsets and weights share one pattern (the bond-associated
   sub-families and their sum program), found by a hash of the offsets.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_hs.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"

#include <algorithm>
#include <cstdint>
#include <cmath>

using namespace LAMMPS_NS;
using NOSPD::BondPattern;
using NOSPD::HSForm;
using NOSPD::Mat3;
using namespace HSTuning;

/* ----------------------------------------------------------------------
   Assign every owned atom's family to a pattern, after the bonds fix
   rebuilt its arrays (reneighboring, broken bonds).  The order of an
   atom's bonds in those arrays is fixed while no bond of it breaks, so
   an atom found at the same index with as many bonds as before keeps its
   pattern and slot order, once the weights still match; the others are
   matched afresh.  Patterns nobody uses any more are dropped.
------------------------------------------------------------------------- */

void PairPeriNospdHS::map_families()
{
  const int nlocal = atom->nlocal;
  const int *bfirst = fix_bonds->bond_first;
  std::vector<int> npat(nlocal), nfirst(nlocal + 1), ncount(nlocal);
  std::vector<tagint> ntag(nlocal);
  std::vector<uint16_t> nperm;
  nperm.reserve(bfirst[nlocal]);
  match_families(npat, nfirst, ncount, ntag, nperm);
  std::vector<int> users, renum;
  drop_unused_patterns(npat, users, renum);

  state_pattern.swap(npat);
  state_first.swap(nfirst);
  state_count.swap(ncount);
  state_tag.swap(ntag);
  state_perm.swap(nperm);
  mapped_version = fix_bonds->bond_version;

  // 1/V of owned and ghost atoms, for the partners' share of each force
  const int nall = nlocal + atom->nghost;
  inv_vfrac.resize(nall);
  for (int i = 0; i < nall; i++) inv_vfrac[i] = 1.0 / atom->vfrac[i];

  // evaluation order: atoms grouped by pattern, so that neighbours in the
  // order can share an evaluation
  std::vector<int> start(patterns.size() + 1, 0);
  for (int i = 0; i < nlocal; i++) start[state_pattern[i] + 1]++;
  for (size_t k = 0; k < patterns.size(); k++) start[k + 1] += start[k];
  state_order.assign(nlocal, 0);
  for (int i = 0; i < nlocal; i++) state_order[start[state_pattern[i]]++] = i;

  // scratch for the largest family (prepare_work sizes each thread's)
  nbig = 0;
  for (auto &p : patterns) nbig = std::max(nbig, p.n);
  prepare_work(1, 0);
  // sum programs for the patterns many families share
  for (size_t k = 0; k < users.size(); k++) {
    if (users[k] < PROGRAM_USERS) continue;
    BondPattern &p = patterns[renum[k]];
    if (!p.program.ready()) p.program = NOSPD::build_sum_program(NOSPD::member_sets(p), p.n);
  }

  count_fallbacks();

  // the stencils: now on a run's first mapping (its log line counts
  // them), else before the next step that can use them (damage remaps
  // often, and some decks want energy or virial on every step)
  if (!reported) map_stencils();
  else {
    stencils_stale = true;
    nstencil_all = 0;
  }

  if (!reported) {
    report_patterns();
    reported = true;
  }
}

/* ----------------------------------------------------------------------
   every owned atom's pattern and slot permutation: kept where its family
   is unchanged since the last mapping, else matched anew
------------------------------------------------------------------------- */

void PairPeriNospdHS::match_families(std::vector<int> &npat, std::vector<int> &nfirst,
                                     std::vector<int> &ncount, std::vector<tagint> &ntag,
                                     std::vector<uint16_t> &nperm)
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  const int *bfirst = fix_bonds->bond_first;
  const double *bw = fix_bonds->bond_w;
  const int *type = atom->type;
  std::vector<uint16_t> perm;
  const int nold = (int) state_pattern.size();
  for (int i = 0; i < nlocal; i++) {
    const int cnt = bfirst[i + 1] - bfirst[i];
    nfirst[i] = (int) nperm.size();
    ncount[i] = cnt;
    ntag[i] = tag[i];
    bool keep = mapped_version >= 0 && i < nold && state_tag[i] == tag[i] &&
        state_count[i] == cnt && state_pattern[i] >= 0;
    if (keep) {
      const BondPattern &p = patterns[state_pattern[i]];
      keep = p.radius == hs_ratio * cut[type[i]][type[i]];
      const uint16_t *op = &state_perm[state_first[i]];
      for (int s = 0; keep && s < cnt; s++)
        keep = std::abs(bw[bfirst[i] + op[s]] - p.w[s]) <= WEIGHT_TOL * p.w[s];
      if (keep) {
        npat[i] = state_pattern[i];
        nperm.insert(nperm.end(), op, op + cnt);
        continue;
      }
    }
    npat[i] = match_pattern(i, perm);
    nperm.insert(nperm.end(), perm.begin(), perm.end());
  }
  nfirst[nlocal] = (int) nperm.size();

}

/* ----------------------------------------------------------------------
   drop the patterns no family uses and renumber the rest (npat follows);
   users and renum by old pattern number
------------------------------------------------------------------------- */

void PairPeriNospdHS::drop_unused_patterns(std::vector<int> &npat, std::vector<int> &users,
                                           std::vector<int> &renum)
{
  const int nlocal = atom->nlocal;
  users.assign(patterns.size(), 0);
  renum.assign(patterns.size(), -1);
  for (int i = 0; i < nlocal; i++) users[npat[i]]++;
  std::vector<BondPattern> kept;
  std::vector<std::map<int, NOSPD::Stencil>> kept_stencils;
  pattern_stencils.resize(patterns.size());
  pattern_lookup.clear();
  for (size_t k = 0; k < patterns.size(); k++) {
    if (!users[k]) continue;
    renum[k] = (int) kept.size();
    kept.push_back(std::move(patterns[k]));
    kept_stencils.push_back(std::move(pattern_stencils[k]));
  }
  patterns.swap(kept);
  pattern_stencils.swap(kept_stencils);
  for (size_t k = 0; k < patterns.size(); k++)
    pattern_lookup.emplace(key_hash(patterns[k].key), (int) k);
  for (int i = 0; i < nlocal; i++) npat[i] = renum[npat[i]];
}

/* ----------------------------------------------------------------------
   the bond families that fall back to the family's F, counted
------------------------------------------------------------------------- */

void PairPeriNospdHS::count_fallbacks()
{
  const int nlocal = atom->nlocal;
  bigint nsing = 0, nfall = 0;
  for (int i = 0; i < nlocal; i++) {
    const BondPattern &p = patterns[state_pattern[i]];
    if (p.atom_singular) continue;
    nsing += p.nsingular;
    nfall += p.nsingular ? 1 : 0;
  }
  pvector[0] = (double) nsing;
  MPI_Allreduce(&nsing, &nsingular_bonds, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Allreduce(&nfall, &nfallback_states, 1, MPI_LMP_BIGINT, MPI_SUM, world);
}

/* ----------------------------------------------------------------------
   Find (or build) the pattern of atom i's family; perm receives, for each
   slot of the pattern, the bond's offset within i's part of the fix's
   arrays.  The key is the family's offsets rounded to KEY_QUANTUM*delta,
   in lexicographic (z, y, x) order.
------------------------------------------------------------------------- */

int PairPeriNospdHS::match_pattern(int i, std::vector<uint16_t> &perm)
{
  const int bf = fix_bonds->bond_first[i];
  const int n = fix_bonds->bond_first[i + 1] - bf;
  if (n > 65535)
    error->one(FLERR, "pair_style {}: atom {} has {} bonds; at most 65535 are supported",
               force->pair_style, atom->tag[i], n);
  const int *bj = fix_bonds->bond_j + bf;
  const double *bw = fix_bonds->bond_w + bf;
  double **x0s = fix_bonds->x0s;
  const double delta = cut[atom->type[i]][atom->type[i]];
  const double radius = hs_ratio * delta;
  const double q = KEY_QUANTUM * delta;
  const double tol = fix_bonds->conditioning_tolerance(i);    // stricter once damaged

  struct Item {
    int64_t k[3];    // z, y, x
    int off;
  };
  std::vector<Item> items(n);
  for (int s = 0; s < n; s++) {
    const int j = bj[s];
    for (int c = 0; c < 3; c++)
      items[s].k[2 - c] = (int64_t) std::llround((x0s[j][c] - x0s[i][c]) / q);
    items[s].off = s;
  }
  std::sort(items.begin(), items.end(), [](const Item &a, const Item &b) {
    return std::lexicographical_compare(a.k, a.k + 3, b.k, b.k + 3);
  });
  std::vector<int64_t> key(3 * n);
  for (int l = 0; l < n; l++)
    for (int c = 0; c < 3; c++) key[3 * l + c] = items[l].k[2 - c];    // x, y, z
  const uint64_t h = key_hash(key);

  int found = -1;
  auto range = pattern_lookup.equal_range(h);
  for (auto it = range.first; it != range.second && found < 0; ++it) {
    const BondPattern &p = patterns[it->second];
    if (p.n != n || p.radius != radius || p.tol != tol || p.key != key) continue;
    bool same = true;
    for (int l = 0; same && l < n; l++) {
      const double wp = p.w[p.lex_to_slot[l]];
      same = std::abs(bw[items[l].off] - wp) <= WEIGHT_TOL * wp;
    }
    if (same) found = it->second;
  }

  if (found < 0) {
    std::vector<double> b(3 * n), w(n), vol(n);
    const double *vfrac = atom->vfrac;
    for (int l = 0; l < n; l++) {
      const int j = bj[items[l].off];
      for (int c = 0; c < 3; c++) b[3 * l + c] = x0s[j][c] - x0s[i][c];
      w[l] = bw[items[l].off];
      vol[l] = vfrac[j];
    }
    patterns.emplace_back();
    NOSPD::build_pattern(patterns.back(), domain->dimension, n, b.data(), w.data(), vol.data(),
                         key, radius, hs_form, tol);
    found = (int) patterns.size() - 1;
    pattern_lookup.emplace(h, found);
  }

  const BondPattern &p = patterns[found];
  perm.assign(n, 0);
  for (int l = 0; l < n; l++) perm[p.lex_to_slot[l]] = (uint16_t) items[l].off;
  return found;
}

/* ----------------------------------------------------------------------
   Once per run: the bond-associated families in numbers.  A ratio that
   leaves most bond-associated families degenerate is an input error.
------------------------------------------------------------------------- */

void PairPeriNospdHS::report_patterns()
{
  double loc[5] = {0.0, 0.0, 0.0, (double) patterns.size(), 0.0}, all[5];
  for (int i = 0; i < atom->nlocal; i++) {
    const BondPattern &p = patterns[state_pattern[i]];
    loc[0] += p.n;
    loc[1] += (double) p.members;
    loc[2] += (double) p.runs.size() / 2.0;
  }
  for (auto &p : patterns) loc[4] += p.bytes();
  for (auto &byType : pattern_stencils)
    for (auto &kv : byType) loc[4] += kv.second.bytes();
  for (auto &kv : point_stencils) loc[4] += kv.second.bytes() + 8.0 * kv.first.size();
  loc[4] += (double) (cell_grid.size() + cell_of.size() + family_order.size()) * sizeof(int) +
      (double) on_stencil.size() + 8.0 * stencil_key.size();
  for (auto &run : stencil_runs)
    loc[4] += (double) (run.pair_lin.size() + run.slot_lin.size() + 2 * run.atoms.size()) *
        sizeof(int);
  loc[4] += (double) state_perm.size() * sizeof(uint16_t) +
      (double) state_pattern.size() * (3 * sizeof(int) + sizeof(tagint));
  // the one-sided stencils and their points
  double one[2] = {0.0, 0.0}, one_all[2];
  for (auto &kv : point_stencils) one[0] += kv.second.ok ? 1.0 : 0.0;
  for (auto &run : stencil_runs)
    if (run.st->one_sided) one[1] += (double) run.atoms.size();
  MPI_Allreduce(loc, all, 5, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(one, one_all, 2, MPI_DOUBLE, MPI_SUM, world);
  const double natoms = (double) MAX(atom->natoms, 1);
  const double nbonds = MAX(all[0], 1.0);
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "PERI-NOSPD bond-associated families (pair {}, form {}, ratio {}):\n"
                   "  bond families = {:.0f}, mean members = {:.4g}, mean runs = {:.4g}\n"
                   "  singular bond families (family F used) = {}, in {} atoms\n"
                   "  patterns = {:.0f} (summed over ranks), pattern and mapping state = "
                   "{:.0f} bytes/point\n"
                   "  points on the linear law's stencil = {} of {} ({:.0f} of them on "
                   "{:.0f} one-sided stencils, summed over ranks)\n",
                   force->pair_style, hs_form == HSForm::I ? "I" : "II", hs_ratio, all[0],
                   all[1] / nbonds, all[2] / nbonds, nsingular_bonds, nfallback_states, all[3],
                   all[4] / natoms, nstencil_all, atom->natoms, one_all[1], one_all[0]);
  if (fix_bonds->nbonds_broken == 0 && all[0] > 0.0 && nsingular_bonds > 0.5 * all[0])
    error->all(FLERR, "pair_style {}: ratio {} is too small for singular_tol {:.4g}: {} of "
               "{:.0f} bond-associated families are degenerate (fewer than {} non-coplanar "
               "members, or shape tensors below singular_tol); use a larger ratio{}",
               force->pair_style, hs_ratio, singular_tol, nsingular_bonds, all[0],
               domain->dimension, singular_tol > 1.0e-4 ? " or a smaller singular_tol" : "");
}

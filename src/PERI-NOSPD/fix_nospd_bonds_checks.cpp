/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's input checks: volumes, horizons, the minimizer's dmax,
   family types, periodicity, reference pairs left unbonded, coincident
   points; each a warning or error printed once, naming what to change.
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "math_const.h"
#include "min.h"
#include "min_nospd_newton.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;

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
  // the Newton minimizer's first trial is its Newton step, not dmax
  if (MinNospdNewton::selected(update)) return;
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
   zero-energy-mode indicator of owned point i (NOSPD::ZemSum), from the F
   of the last force evaluation and the reference bonds
------------------------------------------------------------------------- */

// each bond of point i into `sum`: its weight, reference bond and U
template <class Sum> void FixNospdBonds::add_bond_motion(int i, Sum &sum) const
{
  double **x = atom->x;
  for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
    const int j = bond_j[b];
    NOSPD::Vec3 xi;
    bond_vector(i, b, xi.data());
    const NOSPD::Vec3 U(x[j][0] - x[i][0] - xi[0], x[j][1] - x[i][1] - xi[1],
                        x[j][2] - x[i][2] - xi[2]);
    sum.add(bond_w[b], xi, U);
  }
}

double FixNospdBonds::zem_indicator(int i) const
{
  if (singular[i]) return 0.0;
  NOSPD::ZemSum sum(NOSPD::load(defgrad[i]) - NOSPD::Mat3::Identity(), domain->dimension == 2);
  add_bond_motion(i, sum);
  return sum.value();
}

double FixNospdBonds::zem_quadratic(int i) const
{
  if (singular[i]) return -1.0;
  NOSPD::QuadraticZemSum sum;
  add_bond_motion(i, sum);
  return sum.value();
}

/* ----------------------------------------------------------------------
   A zero-energy mode that the stabilization does not hold shows as bond
   motion that no smooth field describes, of the order of the strain:
   the quadratic fit's indicator over the strain (zem_ratio).  Checked
   every ZEM_CHECK_EVERY steps of a run and at the end of each
   minimization, on the points with whole families (a surface's or a cut
   family's fit is not a mode) of a body with no broken bond; warned
   once, with the worst point and what to do.  The limit lies between the worst of runs
   whose fields are right (thick cylinder with silling 0.5: 0.07; plate
   with a hole: 0.16) and of runs with anisotropic plastic zones (the
   cylinder with silling 0.05: 0.32, on the quadratic fit 0.44): doc
   Howto_choose_model, "Warnings".
------------------------------------------------------------------------- */

void FixNospdBonds::check_zero_energy_modes()
{
  if (zem_warned || model.zem_control.empty() || !bond_arrays_current()) return;
  // bonds that break release waves at the spacing's scale, which the
  // indicator cannot tell from modes: bodies with broken bonds are not checked
  if (nbonds_broken > 0) return;
  const int nlocal = atom->nlocal, ntypes = atom->ntypes;
  const int *type = atom->type;
  const bool plane = (domain->dimension == 2);
  // whole families: at least 95 % of the largest family of the type
  std::vector<int> fmax(ntypes + 1, 0), fall(ntypes + 1, 0);
  for (int i = 0; i < nlocal; i++) fmax[type[i]] = std::max(fmax[type[i]], family_size[i]);
  MPI_Allreduce(fmax.data(), fall.data(), ntypes + 1, MPI_INT, MPI_MAX, world);
  auto counted = [&](int i) {
    return !singular[i] && !lost_bonds(i) && !(model.active && !model.active[type[i]]) &&
        family_size[i] >= 0.95 * fall[type[i]];
  };
  std::vector<double> e(nlocal, 0.0);
  double emax = 0.0, body = 0.0;
  for (int i = 0; i < nlocal; i++)
    if (counted(i))
      emax = std::max(emax, e[i] = NOSPD::green_strain_norm(NOSPD::load(defgrad[i]), plane));
  MPI_Allreduce(&emax, &body, 1, MPI_DOUBLE, MPI_MAX, world);
  if (!std::isfinite(body)) return;    // the instability checks say so
  // the worst ratio with its atom ID, and the count above the limit
  struct {
    double ratio;
    int rank;
  } mine = {0.0, comm->me}, worst;
  double info[3] = {0.0, 0.0, 0.0};    // ID, indicator, strain of the worst
  bigint nabove = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!counted(i)) continue;
    const double z = zem_quadratic(i);
    if (z < 0.0) continue;
    const double r = NOSPD::zem_ratio(z, e[i], body);
    if (r > ZEM_RATIO_LIMIT) nabove++;
    if (r > mine.ratio) {
      mine.ratio = r;
      info[0] = (double) atom->tag[i], info[1] = z, info[2] = e[i];
    }
  }
  MPI_Allreduce(&mine, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  if (!(worst.ratio > ZEM_RATIO_LIMIT)) return;
  bigint nall = 0;
  MPI_Allreduce(&nabove, &nall, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Bcast(info, 3, MPI_DOUBLE, worst.rank, world);
  zem_warned = true;
  if (comm->me == 0)
    error->warning(FLERR, "Fix {}: step {}: zero-energy modes: at {} point(s) the bond motion "
                   "that no smooth field describes exceeds {} of the strain (worst: atom {}, "
                   "{:.3g} at strain {:.3g}); `stabilization {}` does not hold them here and "
                   "the stress field is unreliable (a patchy or anisotropic plastic zone, a "
                   "wavy field): raise the stabilization (silling 0.5) or use pair_style "
                   "peri/nospd/hs; compute nospd/atom zem shows where (doc Howto_choose_model, "
                   "\"Warnings\")", style, update->ntimestep, nall, ZEM_RATIO_LIMIT,
                   (tagint) info[0], info[1], info[2], model.zem_control);
}

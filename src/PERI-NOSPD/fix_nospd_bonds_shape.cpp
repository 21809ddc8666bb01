/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's shape tensors (K^-1, the quadratic fit's
   operator, the stabilization scalar) and the deformation gradient F.
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "memory.h"

#include "nospd_bond_sums.h"
#include "nospd_carry.h"
#include "nospd_simd.h"
#include "nospd_tensor.h"

#include <algorithm>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

/* ----------------------------------------------------------------------
   K = sum_j w xi (x) xi and its inverse for every atom marked stale (all
   atoms after setup).  In 2D K(2,2) = 1 stands in for the missing
   out-of-plane direction so that 3x3 algebra serves both dimensions.
------------------------------------------------------------------------- */

void FixNospdBonds::set_model(const NospdBondModel &m)
{
  const bool had = kinv2 != nullptr;    // (a restart's curvatures may be there already)
  model = m;
  if (model.quadratic == had) return;
  // the fit operators come and go with the setting: computed for every
  // family at the next rebuild of the shape tensors
  if (model.quadratic) {
    memory->grow(kinv2, atom->nmax, NOSPD::CarriedQuadratic::ATOM_RECORD, "nospd/bonds:kinv2");
    for (int i = 0; i < atom->nmax; i++)
      for (int k = 0; k < NOSPD::CarriedQuadratic::ATOM_RECORD; k++) kinv2[i][k] = 0.0;
    all_stale = true;
  } else {
    memory->destroy(kinv2);
    kinv2 = nullptr;
  }
  maxexchange = max_exchange_size();
}

/* the quadratic fit operator of owned atom i's family (bond arrays current).
   A family that has lost bonds fits no quadratic: around a crack the
   partners left fit one poorly (a one-sided, ragged family), its
   coefficients grow large, and the springs then stiffen instead of
   stabilize (the projectile scene ran away with them).  With the carried
   deformation it keeps the curvature of its last intact fit
   (nospd_quadratic_carry.h, G set by carry_refits); without, the linear
   fit's springs. */
void FixNospdBonds::quadratic_fit_of(int i)
{
  const bool damaged = bond_first[i + 1] - bond_first[i] < family_size[i];
  if (damaged && !model.carry) {
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
  if (damaged) NOSPD::carried_quadratic_record(K2, NOSPD::load(kinv[i]), kinv2[i]);
  else NOSPD::quadratic_fit_inverse(K2, kinv2[i]);
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

void FixNospdBonds::update_shape_tensors(bool count)
{
  const int nlocal = atom->nlocal;
  const int dim = model.dim;
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
  }
  all_stale = false;
  if (count) count_singular();
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::count_singular()
{
  bigint one = 0;
  for (int i = 0; i < atom->nlocal; i++) one += (singular[i] == 1);
  MPI_Allreduce(&one, &nsingular, 1, MPI_LMP_BIGINT, MPI_SUM, world);
}

/* ----------------------------------------------------------------------
   the families about to change (broken slots marked, K^-1 stale) and
   their F at the current positions, from the bonds they still list
------------------------------------------------------------------------- */

void FixNospdBonds::fits_before_change(std::vector<int> &changed, std::vector<Before> &before)
{
  if (all_stale) return;    // no K^-1 yet (pre-cracks at the first setup): nothing to carry
  NOSPD::Positions pos;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!stale[i] || singular[i]) continue;
    if (changed.empty()) pos = padded_positions();
    compute_deformation(pos, nullptr, i, i + 1);
    changed.push_back(i);
    Before b;
    b.F = NOSPD::load(defgrad[i]);
    b.FFc = b.F * NOSPD::load(fcarry[i]);
    b.curved = kinv2 && kinv2[i][NOSPD::QuadraticFit::PACKED] == 1.0;
    if (b.curved) {
      double sums[NOSPD::QSUMS];
      NOSPD::quadratic_sums(pos, {bond_j, bond_w, bond_first[i], bond_first[i + 1]}, i, sums);
      const Eigen::Map<const Eigen::Matrix<double, 3, 9>> N2(sums);
      b.Qs = NOSPD::quadratic_fit(N2, kinv2[i]).rightCols<6>();
    }
    before.push_back(b);
  }
}

/* ----------------------------------------------------------------------
   after the change: each family's refit at the same positions, carried in
   F_c, or the point made singular (nospd_carry.h); a family that loses its
   first bonds under the quadratic fit starts carrying its curvature
   (nospd_quadratic_carry.h)
------------------------------------------------------------------------- */

void FixNospdBonds::carry_refits(const std::vector<int> &changed, const std::vector<Before> &before)
{
  if (changed.empty()) return;
  const NOSPD::Positions pos = padded_positions();
  for (size_t c = 0; c < changed.size(); c++) {
    const int i = changed[c];
    if (singular[i]) continue;
    compute_deformation(pos, nullptr, i, i + 1);
    NOSPD::Mat3 Fc = NOSPD::load(fcarry[i]);
    if (!NOSPD::carry_deformation(before[c].F, NOSPD::load(defgrad[i]), Fc)) {
      singular[i] = 1;    // kept by conditioning_tolerance, as a damaged family's
      continue;
    }
    NOSPD::store(Fc, fcarry[i]);
    if (before[c].curved) {
      const NOSPD::Mat36 G = NOSPD::carried_quadratic_start(before[c].Qs, before[c].FFc);
      for (int k = 0; k < NOSPD::CarriedQuadratic::G_SIZE; k++)
        kinv2[i][NOSPD::CarriedQuadratic::G_AT + k] = G.data()[k];
    }
  }
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

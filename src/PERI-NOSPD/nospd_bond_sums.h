/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The bond sums of the classical style's two passes, over one point's
   contiguous bond list: the deformation moments of pass 1 and the force
   sum of pass 2.  Knows nothing of LAMMPS.

   Why a header of its own: these loops are where a classical step spends
   its time.  Each bond's 3-vectors (xi, U, B_j xi) are handled as one
   4-lane vector, the partner's position and its B loaded whole rather
   than element by element, and 3x3 products are columns times broadcast
   components.  With NOSPD_KERNEL_CLONES (nospd_simd.h) the callers are
   built for AVX2 and AVX-512 as well, where a 4-lane vector is one
   register; elsewhere the compiler splits it.  A point's sums are the
   same bits run after run and on any rank or thread count on one machine
   (the hourglass pass over pairs: run after run on the same partition).

   Layout the loads rely on (the fourth lane of a load is unused unless
   said otherwise, but must be readable memory):
   - positions: flat, 3 per atom, with at least one double after the last
     atom that is read;
   - the pass-2 record of each atom, BREC = 10 doubles: B^T row-major (B's
     columns one after the other) and the stabilization scalar, which the
     load of the third column brings in its fourth lane;
   - T: 9 per atom, T^T likewise, with one double after the last atom
     (Wan: S; hourglass: c H, the scalar already applied, which saves the
     pass three products per bond).
------------------------------------------------------------------------- */

#ifndef NOSPD_BOND_SUMS_H
#define NOSPD_BOND_SUMS_H

#include "nospd_simd.h"

#include <cmath>

namespace NOSPD {

// doubles per atom of the pass-2 record: B^T (9), stabilization scalar
constexpr int BREC = 10;

// a point's bonds: partner local index and weight omega(|xi|) V_j, entries
// [from, to) of the per-atom bond arrays
struct BondList {
  const int *__restrict j;
  const double *__restrict w;
  int from, to;
};

// flat (3 per atom, padded: see above) current and reference positions
struct Positions {
  const double *__restrict x;
  const double *__restrict x0;
};

/* ----------------------------------------------------------------------
   pass 1 at point i: N = sum_j w U (x) xi (row-major), s = sum_j w U and,
   with MOMENTS, m = sum_j w U (x) U (xx yy zz xy xz yz); U = Y - xi
------------------------------------------------------------------------- */

template <bool MOMENTS>
inline void deformation_sums(const Positions &p, const BondList &bl, int i, double *N, double *s,
                             double *m)
{
  using namespace simd;
  const v4 x0i = load4(p.x0 + 3 * i), xi = load4(p.x + 3 * i);
  // columns of N (N e_k = sum w U xi_k), s, and the columns of sum w U (x) U
  v4 c0{}, c1{}, c2{}, cs{}, m0{}, m1{}, m2{};
  for (int b = bl.from; b < bl.to; b++) {
    const int j3 = 3 * bl.j[b];
    const v4 e = load4(p.x0 + j3) - x0i;
    const v4 u = (load4(p.x + j3) - xi) - e;
    const v4 wu = bl.w[b] * u;
    cs += wu;
    c0 += wu * e[0];
    c1 += wu * e[1];
    c2 += wu * e[2];
    if (MOMENTS) {
      m0 += wu * u[0];
      m1 += wu * u[1];
      m2 += wu * u[2];
    }
  }
  for (int r = 0; r < 3; r++) {
    N[3 * r] = c0[r];
    N[3 * r + 1] = c1[r];
    N[3 * r + 2] = c2[r];
    s[r] = cs[r];
  }
  if (MOMENTS) m[0] = m0[0], m[1] = m1[1], m[2] = m2[2], m[3] = m1[0], m[4] = m2[0], m[5] = m2[1];
}

/* ----------------------------------------------------------------------
   the quadratic fit's sums at point i (nospd_stabilization.h): N2 =
   sum_j w U phi(xi)^T column by column (N2[3 k + r], 9 columns) and
   q = sum_j w phi_q(xi), the six quadratic entries
------------------------------------------------------------------------- */

constexpr int QSUMS = 33;    // doubles per point: N2 (27), then q (6)

inline void quadratic_sums(const Positions &p, const BondList &bl, int i, double *out)
{
  using namespace simd;
  const v4 x0i = load4(p.x0 + 3 * i), xi = load4(p.x + 3 * i);
  v4 c[9] = {}, qa{}, qb{};
  for (int b = bl.from; b < bl.to; b++) {
    const int j3 = 3 * bl.j[b];
    const v4 e = load4(p.x0 + j3) - x0i;
    const v4 u = (load4(p.x + j3) - xi) - e;
    const double w = bl.w[b];
    const v4 wu = w * u;
    const v4 ee = e * e;
    const v4 ex{e[0] * e[1], e[0] * e[2], e[1] * e[2], 0.0};
    c[0] += wu * e[0];
    c[1] += wu * e[1];
    c[2] += wu * e[2];
    c[3] += wu * ee[0];
    c[4] += wu * ee[1];
    c[5] += wu * ee[2];
    c[6] += wu * ex[0];
    c[7] += wu * ex[1];
    c[8] += wu * ex[2];
    qa += w * ee;
    qb += w * ex;
  }
  for (int k = 0; k < 9; k++)
    for (int r = 0; r < 3; r++) out[3 * k + r] = c[k][r];
  for (int r = 0; r < 3; r++) out[27 + r] = qa[r], out[30 + r] = qb[r];
}

/* ----------------------------------------------------------------------
   pass 2 at point i under the stabilization STAB:
     g = w ((B_j [+ B_i]) xi + stabilization term),  f = sum_j g
   B: the BREC records (B^T and the stabilization scalar c); T: T^T per
   atom (Wan's S, or the hourglass c H, H = F - I); Q: the quadratic fit's
   alpha Q per atom, 6 columns of 3 (with SILLING_QUADRATIC, which adds
   (alpha_j Q_j [- alpha_i Q_i]) phi_q(xi) per bond).  Without VIRIAL the i-terms are
   left out (the caller adds B_i sum_j w xi and S_i sum_j w U); with it they
   are in g and v collects the bond virial 1/2 (x_i - x_j) (x) g
   (xx yy zz xy xz yz).
------------------------------------------------------------------------- */

/* The stabilization a force pass is compiled for: the pair style's Stab,
   with Silling's springs on the quadratic fit as a pass of its own. */
enum class StabPass { NONE, SILLING, HOURGLASS, WAN, SILLING_QUADRATIC };
constexpr bool has_springs(StabPass s)
{
  return s == StabPass::SILLING || s == StabPass::SILLING_QUADRATIC;
}

struct ForceTerms {
  const double *__restrict B;
  const double *__restrict T;
  const double *__restrict Q = nullptr;    // 18 per atom, one readable double after
};

constexpr int QREC = 18;    // doubles per atom of Q

namespace detail {
  // what pass 2 needs of bond (i, j) before any stabilization: xi, Y,
  // U = Y - xi, g = (B_j [+ B_i]) xi and the stabilization scalar c_j
  struct StressBond {
    simd::v4 e, y, u, g;
    double sj;
  };

  template <int VIRIAL>
  inline __attribute__((always_inline)) StressBond
  stress_bond(const Positions &p, const ForceTerms &ft, int j, simd::v4 x0i, simd::v4 xi,
              const double *Bi)
  {
    using namespace simd;
    const v4 e = load4(p.x0 + 3 * j) - x0i;
    const v4 y = load4(p.x + 3 * j) - xi;
    const double *Bj = ft.B + BREC * j;
    const v4 col2 = load4(Bj + 6);    // B's third column and c_j
    v4 g = load4(Bj) * e[0] + load4(Bj + 3) * e[1] + col2 * e[2];
    if (VIRIAL) g += matvec(Bi, e);
    return {e, y, y - e, g, col2[3]};
  }

  // accumulate a bond's force w g and, with VIRIAL, its virial 1/2 r (x) F
  // with r = x_i - x_j = -Y and F = w g, the force on i: columns h g_k of
  // the full tensor, h = -w Y / 2
  template <int VIRIAL>
  inline __attribute__((always_inline)) void add_bond_force(double w, simd::v4 g, simd::v4 y,
                                                            simd::v4 &acc, simd::v4 *vc)
  {
    acc += w * g;
    if (VIRIAL) {
      const simd::v4 h = (-0.5 * w) * y;
      vc[0] += h * g[0];
      vc[1] += h * g[1];
      vc[2] += h * g[2];
    }
  }

  inline void store_virial(const simd::v4 *vc, double *v)
  {
    v[0] = vc[0][0], v[1] = vc[1][1], v[2] = vc[2][2];
    v[3] = vc[1][0], v[4] = vc[2][0], v[5] = vc[2][1];
  }
}    // namespace detail

template <int VIRIAL>
inline void hourglass_force_sums(const Positions &p, const BondList &bl, const ForceTerms &ft,
                                 int i, double *f, double *v);

template <StabPass STAB, int VIRIAL>
inline void force_sums(const Positions &p, const BondList &bl, const ForceTerms &ft, int i,
                       double *f, double *v)
{
  if (STAB == StabPass::HOURGLASS) return hourglass_force_sums<VIRIAL>(p, bl, ft, i, f, v);
  using namespace simd;
  const v4 x0i = load4(p.x0 + 3 * i), xi = load4(p.x + 3 * i);
  const double *Bi = ft.B + BREC * i;
  const double *Ti = ft.T + 9 * i;
  const double si = Bi[9];
  v4 acc{}, vc[3] = {};
  for (int b = bl.from; b < bl.to; b++) {
    const int j = bl.j[b];
    detail::StressBond t = detail::stress_bond<VIRIAL>(p, ft, j, x0i, xi, Bi);
    if (has_springs(STAB)) {
      t.g += (VIRIAL ? si + t.sj : t.sj) * t.u;
    }
    if (STAB == StabPass::SILLING_QUADRATIC) {
      const v4 ee = t.e * t.e;
      const double q3 = t.e[0] * t.e[1], q4 = t.e[0] * t.e[2], q5 = t.e[1] * t.e[2];
      const double *Qj = ft.Q + QREC * j;
      t.g += load4(Qj) * ee[0] + load4(Qj + 3) * ee[1] + load4(Qj + 6) * ee[2] +
          load4(Qj + 9) * q3 + load4(Qj + 12) * q4 + load4(Qj + 15) * q5;
      if (VIRIAL) {
        const double *Qi = ft.Q + QREC * i;
        t.g -= load4(Qi) * ee[0] + load4(Qi + 3) * ee[1] + load4(Qi + 6) * ee[2] +
            load4(Qi + 9) * q3 + load4(Qi + 12) * q4 + load4(Qi + 15) * q5;
      }
    } else if (STAB == StabPass::WAN) {
      t.g += matvec(ft.T + 9 * j, t.u);
      if (VIRIAL) t.g += matvec(Ti, t.u);
    }
    detail::add_bond_force<VIRIAL>(bl.w[b], t.g, t.y, acc, vc);
  }
  f[0] = acc[0], f[1] = acc[1], f[2] = acc[2];
  if (VIRIAL) detail::store_virial(vc, v);
}

/* ----------------------------------------------------------------------
   pass 2 with the hourglass term, g = w ((B_j [+ B_i]) xi + h Y), where
     h = (c_i z_i + c_j z_j) . Y / (|Y|^2 |xi|),  z = U - H xi,
   written (c_i + c_j) U - (T_i + T_j) xi with T = c H as stored,
   and h = 0 for a collapsed bond (Y = 0: no direction).  Bonds go four at
   a time so that their three dot products are one shuffle-and-add each and
   the square root and the division one vector operation for the four
   (built with -fno-math-errno, the four roots are one instruction): 5.7
   rather than 7.1 ns per bond in a standalone loop over a 3D grid.  The
   same operations in the same order as one bond at a time, so the same
   bits; the last bonds of a point (fewer than four) go one by one.
------------------------------------------------------------------------- */

namespace detail {
  // a bond's terms before the hourglass scalar: g without it, Y, and the
  // products z * Y, Y * Y, xi * xi whose first three lanes make the dots
  struct HourglassBond {
    simd::v4 g, y, zy, yy, ee;
  };

  template <int VIRIAL>
  inline __attribute__((always_inline)) HourglassBond
  hourglass_bond(const Positions &p, const ForceTerms &ft, int j, simd::v4 x0i, simd::v4 xi,
                 const double *Bi, const double *Ti, double si)
  {
    using namespace simd;
    const StressBond t = stress_bond<VIRIAL>(p, ft, j, x0i, xi, Bi);
    const v4 z = (si + t.sj) * t.u - (matvec(Ti, t.e) + matvec(ft.T + 9 * j, t.e));
    return {t.g, t.y, z * t.y, t.y * t.y, t.e * t.e};
  }

  // the hourglass scalars of four bonds from their dots z.Y, Y.Y, xi.xi;
  // zero for a collapsed bond
  inline __attribute__((always_inline)) simd::v4 hourglass_scalars(simd::v4 zy, simd::v4 yy,
                                                                   simd::v4 ee)
  {
    using namespace simd;
    const v4 rxi{std::sqrt(ee[0]), std::sqrt(ee[1]), std::sqrt(ee[2]), std::sqrt(ee[3])};
    const auto live = yy > splat(0.0);
    return live ? zy / (live ? yy * rxi : splat(1.0)) : splat(0.0);
  }
}    // namespace detail

template <int VIRIAL>
inline void hourglass_force_sums(const Positions &p, const BondList &bl, const ForceTerms &ft,
                                 int i, double *f, double *v)
{
  using namespace simd;
  using detail::HourglassBond;
  const v4 x0i = load4(p.x0 + 3 * i), xi = load4(p.x + 3 * i);
  const double *Bi = ft.B + BREC * i;
  const double *Ti = ft.T + 9 * i;
  const double si = Bi[9];
  v4 acc{}, vc[3] = {};
  int b = bl.from;
  for (; b + 4 <= bl.to; b += 4) {
    HourglassBond t[4];
#pragma GCC unroll 4
    for (int k = 0; k < 4; k++)
      t[k] = detail::hourglass_bond<VIRIAL>(p, ft, bl.j[b + k], x0i, xi, Bi, Ti, si);
    const v4 zy = sum3x4(t[0].zy, t[1].zy, t[2].zy, t[3].zy);
    const v4 yy = sum3x4(t[0].yy, t[1].yy, t[2].yy, t[3].yy);
    const v4 ee = sum3x4(t[0].ee, t[1].ee, t[2].ee, t[3].ee);
    const v4 h = detail::hourglass_scalars(zy, yy, ee);
#pragma GCC unroll 4
    for (int k = 0; k < 4; k++)
      detail::add_bond_force<VIRIAL>(bl.w[b + k], t[k].g + h[k] * t[k].y, t[k].y, acc, vc);
  }
  for (; b < bl.to; b++) {
    const HourglassBond t = detail::hourglass_bond<VIRIAL>(p, ft, bl.j[b], x0i, xi, Bi, Ti, si);
    const double yy = sum3(t.yy);
    // a collapsed bond (Y = 0) has no direction and takes no term
    const double h = yy > 0.0 ? sum3(t.zy) / (yy * std::sqrt(sum3(t.ee))) : 0.0;
    detail::add_bond_force<VIRIAL>(bl.w[b], t.g + h * t.y, t.y, acc, vc);
  }
  f[0] = acc[0], f[1] = acc[1], f[2] = acc[2];
  if (VIRIAL) detail::store_virial(vc, v);
}

/* ----------------------------------------------------------------------
   pass 2 with the hourglass term over each pair of owned points once, for
   lists in the bonds fix's pair order (bonds to owned j < i, to owned
   j > i, to ghosts).  The bond force density g is odd in the bond: seen
   from j, xi, Y and U change sign, so do z_i and z_j, and h keeps its
   value; so bond i-j with j > i adds w_ij g to f_i and -w_ji g to f_j,
   w_ji = omega V_i = w_ij V_i / V_j, and is skipped at j.  Bonds to ghosts
   are taken from this end only (their owner takes the other).  Per bond
   the arithmetic of hourglass_force_sums with VIRIAL (g holds both B
   terms), arranged as g = (B_i + B_j) xi + h Y and
   c_i z_i + c_j z_j = (c_i + c_j) U - ((T_i + T_j) xi): the same up to
   rounding, for half the bonds' loads, products and roots.
   f: 3 per atom; inv_vol: 1 / V of owned atoms (0 where V is); with VIRIAL, v (6 per
   atom, zeroed by the caller) collects each end's half of the bond virial
   as hourglass_force_sums does.
------------------------------------------------------------------------- */

struct PairOrder {
  const int *first, *pair, *ghost;    // the bonds fix's offsets
};

namespace detail {
  // what every bond of point i shares: its positions, the columns of B_i
  // and of T_i = c_i H_i, c_i
  struct PairPoint {
    simd::v4 x0, x, b[3], t[3];
    double s;
  };

  // bond i-j up to the hourglass scalar: g = (B_i + B_j) xi, Y, and the
  // products for z . Y, Y . Y, xi . xi (z = c_i z_i + c_j z_j)
  inline __attribute__((always_inline)) HourglassBond
  hourglass_pair_bond(const Positions &p, const ForceTerms &ft, int j, const PairPoint &pt)
  {
    using namespace simd;
    const v4 e = load4(p.x0 + 3 * j) - pt.x0;
    const v4 y = load4(p.x + 3 * j) - pt.x;
    const double *Bj = ft.B + BREC * j;
    const double *Tj = ft.T + 9 * j;
    const v4 col2 = load4(Bj + 6);    // B_j's third column and c_j
    const double sj = col2[3];
    const v4 g = (pt.b[0] + load4(Bj)) * e[0] + (pt.b[1] + load4(Bj + 3)) * e[1] +
        (pt.b[2] + col2) * e[2];
    const v4 hx = (pt.t[0] + load4(Tj)) * e[0] + (pt.t[1] + load4(Tj + 3)) * e[1] +
        (pt.t[2] + load4(Tj + 6)) * e[2];
    const v4 z = (pt.s + sj) * (y - e) - hx;
    return {g, y, z * y, y * y, e * e};
  }

  // the bonds [from, to) of point i; with BOTH, also the partner's force
  // and, with VIRIAL, its virial (v: 6 per atom)
  template <bool BOTH, int VIRIAL>
  inline __attribute__((always_inline)) void
  hourglass_pair_run(const Positions &p, const int *bj, const double *bw, const ForceTerms &ft,
                     const PairPoint &pt, double vol_i, const double *inv_vol, int from, int to,
                     simd::v4 &acc, simd::v4 *vc, double *f, double *v)
  {
    using namespace simd;
    auto add = [&](int j, double w, v4 P, v4 y) {
      // forces, not densities: w_ij V_i g on i, its opposite on j
      const double a = w * vol_i;
      acc += a * P;
      if (VIRIAL) {
        const v4 h = (-0.5 * w) * y;
        vc[0] += h * P[0];
        vc[1] += h * P[1];
        vc[2] += h * P[2];
      }
      if (BOTH) {
        double *fj = f + 3 * j;
        fj[0] -= a * P[0];
        fj[1] -= a * P[1];
        fj[2] -= a * P[2];
        if (VIRIAL) {
          // 1/2 (x_j - x_i) (x) (-w_ji g) = -w_ji/2 Y (x) g
          const v4 c = (-0.5 * a * inv_vol[j]) * y;
          double *vj = v + 6 * j;
          vj[0] += c[0] * P[0], vj[1] += c[1] * P[1], vj[2] += c[2] * P[2];
          vj[3] += c[0] * P[1], vj[4] += c[0] * P[2], vj[5] += c[1] * P[2];
        }
      }
    };
    int b = from;
    for (; b + 4 <= to; b += 4) {
      HourglassBond t[4];
#pragma GCC unroll 4
      for (int k = 0; k < 4; k++) t[k] = hourglass_pair_bond(p, ft, bj[b + k], pt);
      const v4 zy = sum3x4(t[0].zy, t[1].zy, t[2].zy, t[3].zy);
      const v4 yy = sum3x4(t[0].yy, t[1].yy, t[2].yy, t[3].yy);
      const v4 ee = sum3x4(t[0].ee, t[1].ee, t[2].ee, t[3].ee);
      const v4 h = hourglass_scalars(zy, yy, ee);
#pragma GCC unroll 4
      for (int k = 0; k < 4; k++) add(bj[b + k], bw[b + k], t[k].g + h[k] * t[k].y, t[k].y);
    }
    for (; b < to; b++) {
      const HourglassBond t = hourglass_pair_bond(p, ft, bj[b], pt);
      const double yy = sum3(t.yy);
      // a collapsed bond (Y = 0) has no direction and takes no term
      const double h = yy > 0.0 ? sum3(t.zy) / (yy * std::sqrt(sum3(t.ee))) : 0.0;
      add(bj[b], bw[b], t.g + h * t.y, t.y);
    }
  }
}    // namespace detail

template <int VIRIAL>
inline void hourglass_pair_sums(const Positions &p, const PairOrder &po, const int *bj,
                                const double *bw, const ForceTerms &ft, const double *vol,
                                const double *inv_vol, int from, int to, double *f, double *v)
{
  using namespace simd;
  // f holds forces (density times volume) while the pass adds to it: each
  // row is final once its point has been visited (its partners j > i add
  // to it no more) and goes back to a density then.  Rows of points
  // without bonds (another pair style's atoms) are left alone.
  auto scaled = [&](int i) { return po.first[i + 1] > po.first[i] && vol[i] > 0.0; };
  for (int i = from; i < to; i++)
    if (scaled(i))
      for (int d = 0; d < 3; d++) f[3 * i + d] *= vol[i];
  for (int i = from; i < to; i++) {
    const double *Bi = ft.B + BREC * i;
    const double *Ti = ft.T + 9 * i;
    detail::PairPoint pt;
    pt.x0 = load4(p.x0 + 3 * i);
    pt.x = load4(p.x + 3 * i);
    pt.s = Bi[9];
    for (int k = 0; k < 3; k++) {
      pt.b[k] = load4(Bi + 3 * k);
      pt.t[k] = load4(Ti + 3 * k);
    }
    v4 acc{}, vc[3] = {};
    detail::hourglass_pair_run<true, VIRIAL>(p, bj, bw, ft, pt, vol[i], inv_vol, po.pair[i],
                                             po.ghost[i], acc, vc, f, v);
    detail::hourglass_pair_run<false, VIRIAL>(p, bj, bw, ft, pt, vol[i], inv_vol, po.ghost[i],
                                              po.first[i + 1], acc, vc, f, v);
    if (scaled(i))
      for (int d = 0; d < 3; d++) f[3 * i + d] = (f[3 * i + d] + acc[d]) * inv_vol[i];
    if (VIRIAL) {
      double vi[6];
      detail::store_virial(vc, vi);
      for (int k = 0; k < 6; k++) v[6 * i + k] += vi[k];
    }
  }
}

}    // namespace NOSPD

#endif

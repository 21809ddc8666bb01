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
   same bits run after run and on any rank or thread count on one machine.

   Layout the loads rely on (the fourth lane of a load is unused unless
   said otherwise, but must be readable memory):
   - positions: flat, 3 per atom, with at least one double after the last
     atom that is read;
   - the pass-2 record of each atom, BREC = 10 doubles: B^T row-major (B's
     columns one after the other) and the stabilization scalar, which the
     load of the third column brings in its fourth lane;
   - T: 9 per atom, T^T likewise, with one double after the last atom.
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
   pass 2 at point i, the stabilization STAB as the style numbers it
   (0 none, 1 Silling, 2 hourglass, 3 Wan):
     g = w ((B_j [+ B_i]) xi + stabilization term),  f = sum_j g
   B: the BREC records (B^T and the stabilization scalar c); T: T^T per
   atom (Wan's S, or the hourglass H = F - I).  Without VIRIAL the i-terms are
   left out (the caller adds B_i sum_j w xi and S_i sum_j w U); with it they
   are in g and v collects the bond virial 1/2 (x_i - x_j) (x) g
   (xx yy zz xy xz yz).
------------------------------------------------------------------------- */

struct ForceTerms {
  const double *__restrict B;
  const double *__restrict T;
};

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

template <int STAB, int VIRIAL>
inline void force_sums(const Positions &p, const BondList &bl, const ForceTerms &ft, int i,
                       double *f, double *v)
{
  if (STAB == 2) return hourglass_force_sums<VIRIAL>(p, bl, ft, i, f, v);
  using namespace simd;
  const v4 x0i = load4(p.x0 + 3 * i), xi = load4(p.x + 3 * i);
  const double *Bi = ft.B + BREC * i;
  const double *Ti = ft.T + 9 * i;
  const double si = Bi[9];
  v4 acc{}, vc[3] = {};
  for (int b = bl.from; b < bl.to; b++) {
    const int j = bl.j[b];
    detail::StressBond t = detail::stress_bond<VIRIAL>(p, ft, j, x0i, xi, Bi);
    if (STAB == 1) {
      t.g += (VIRIAL ? si + t.sj : t.sj) * t.u;
    } else if (STAB == 3) {
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
    const v4 z = si * (t.u - matvec(Ti, t.e)) + t.sj * (t.u - matvec(ft.T + 9 * j, t.e));
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

}    // namespace NOSPD

#endif

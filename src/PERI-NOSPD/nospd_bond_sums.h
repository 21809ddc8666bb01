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

template <int STAB, int VIRIAL>
inline void force_sums(const Positions &p, const BondList &bl, const ForceTerms &ft, int i,
                       double *f, double *v)
{
  using namespace simd;
  const v4 x0i = load4(p.x0 + 3 * i), xi = load4(p.x + 3 * i);
  const double *Bi = ft.B + BREC * i;
  const double *Ti = ft.T + 9 * i;
  const double si = Bi[9];
  v4 acc{}, v0{}, v1{}, v2{};
  for (int b = bl.from; b < bl.to; b++) {
    const int j = bl.j[b];
    const double w = bl.w[b];
    const v4 e = load4(p.x0 + 3 * j) - x0i;
    const v4 y = load4(p.x + 3 * j) - xi;
    const v4 u = y - e;
    const double *Bj = ft.B + BREC * j;
    const v4 col2 = load4(Bj + 6);    // B's third column and c_j
    v4 g = load4(Bj) * e[0] + load4(Bj + 3) * e[1] + col2 * e[2];
    const double sj = col2[3];
    if (VIRIAL) g += matvec(Bi, e);
    if (STAB == 1) {
      g += (VIRIAL ? si + sj : sj) * u;
    } else if (STAB == 3) {
      g += matvec(ft.T + 9 * j, u);
      if (VIRIAL) g += matvec(Ti, u);
    } else if (STAB == 2) {
      // hourglass: (c_i z_i + c_j z_j).Y / (|Y|^2 |xi|) Y, z = U - H xi
      const v4 z = si * (u - matvec(Ti, e)) + sj * (u - matvec(ft.T + 9 * j, e));
      const double ry2 = dot3(y, y);
      // a collapsed bond (Y = 0) has no direction and takes no term
      if (ry2 > 0.0) g += (dot3(z, y) / (ry2 * std::sqrt(dot3(e, e)))) * y;
    }
    acc += w * g;
    if (VIRIAL) {
      // 1/2 r (x) F with r = x_i - x_j = -Y and F = w g, the force on i:
      // columns h g_k of the full tensor, h = -w Y / 2
      const v4 h = (-0.5 * w) * y;
      v0 += h * g[0];
      v1 += h * g[1];
      v2 += h * g[2];
    }
  }
  f[0] = acc[0], f[1] = acc[1], f[2] = acc[2];
  if (VIRIAL) v[0] = v0[0], v[1] = v1[1], v[2] = v2[2], v[3] = v1[0], v[4] = v2[0], v[5] = v2[1];
}

}    // namespace NOSPD

#endif

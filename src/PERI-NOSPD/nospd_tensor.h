/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   3x3 tensor helpers on Eigen fixed-size types.  Knows nothing of LAMMPS.
------------------------------------------------------------------------- */

#ifndef NOSPD_TENSOR_H
#define NOSPD_TENSOR_H

#include <Eigen/Dense>
#include <cmath>

namespace NOSPD {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

// Tensors travel between LAMMPS arrays and Eigen as 9 doubles, row-major.
inline Mat3 load(const double *p)
{
  Mat3 m;
  m << p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8];
  return m;
}

inline void store(const Mat3 &m, double *p)
{
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) p[3 * r + c] = m(r, c);
}

// Symmetric tensors as 6 doubles: xx yy zz xy xz yz (LAMMPS's order).
inline Mat3 load_sym(const double *v)
{
  Mat3 m;
  m << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
  return m;
}

inline void store_sym(const Mat3 &m, double *v)
{
  v[0] = m(0, 0);
  v[1] = m(1, 1);
  v[2] = m(2, 2);
  v[3] = 0.5 * (m(0, 1) + m(1, 0));
  v[4] = 0.5 * (m(0, 2) + m(2, 0));
  v[5] = 0.5 * (m(1, 2) + m(2, 1));
}

/* Conditioning of a shape tensor: det(K) / (tr(K)/dim)^dim, which is 1 for
   an isotropic family and 0 for a family whose bonds are (nearly) coplanar
   (3D) or collinear (2D).  In 2D the out-of-plane entry K(2,2) is 1 and is
   left out of the measure. */
inline double shape_conditioning(const Mat3 &K, int dim)
{
  if (dim == 2) {
    const double tr = 0.5 * (K(0, 0) + K(1, 1));
    if (!(tr > 0.0)) return 0.0;
    const double det = K(0, 0) * K(1, 1) - K(0, 1) * K(1, 0);
    return det / (tr * tr);
  }
  const double tr = K.trace() / 3.0;
  if (!(tr > 0.0)) return 0.0;
  return K.determinant() / (tr * tr * tr);
}

/* Inverse of a shape tensor with a conditioning test.  Returns false and
   leaves Kinv = 0 when the tensor is singular to within `tol`: such a
   family cannot define a deformation gradient and must not be divided by. */
inline bool safe_inverse(const Mat3 &K, int dim, double tol, Mat3 &Kinv)
{
  if (!(shape_conditioning(K, dim) > tol) || !K.allFinite()) {
    Kinv.setZero();
    return false;
  }
  Kinv = K.inverse();
  return Kinv.allFinite();
}

/* Right polar decomposition F = R U by Higham's scaled Newton iteration
   R <- (zeta R + R^-T / zeta)/2.  Converges quadratically; near a rotation
   it takes 2-4 steps, far cheaper than an eigen-solve.  Requires det F > 0. */
inline bool polar_decomposition(const Mat3 &F, Mat3 &R, Mat3 &U)
{
  R = F;
  for (int it = 0; it < 50; ++it) {
    const Mat3 Rinvt = R.inverse().transpose();
    // determinant scaling accelerates the first steps of a stretched F
    const double d = std::abs(R.determinant());
    const double zeta = (it < 6 && d > 0.0) ? std::pow(d, -1.0 / 3.0) : 1.0;
    const Mat3 next = 0.5 * (zeta * R + Rinvt / zeta);
    const double change = (next - R).cwiseAbs().maxCoeff();
    R = next;
    if (change < 1e-15) break;
  }
  U = R.transpose() * F;
  U = 0.5 * (U + U.transpose()).eval();
  return R.allFinite();
}

/* Symmetric 3x3 tensors in the kernels below: six values, no Eigen
   temporaries.  The series of ln and exp only ever multiply polynomials in
   one tensor, which commute, so every product is symmetric and only its
   six distinct entries are formed: 18 multiply-adds instead of 27. */
struct Sym3 {
  double xx, yy, zz, xy, xz, yz;
};

inline Sym3 sym_of(const Mat3 &m)
{
  return {m(0, 0), m(1, 1), m(2, 2), 0.5 * (m(0, 1) + m(1, 0)), 0.5 * (m(0, 2) + m(2, 0)),
          0.5 * (m(1, 2) + m(2, 1))};
}

inline Mat3 mat_of(const Sym3 &s)
{
  Mat3 m;
  m << s.xx, s.xy, s.xz, s.xy, s.yy, s.yz, s.xz, s.yz, s.zz;
  return m;
}

inline Sym3 load_sym3(const double *v)
{
  return {v[0], v[1], v[2], v[3], v[4], v[5]};
}

inline void store_sym(const Sym3 &s, double *v)
{
  v[0] = s.xx, v[1] = s.yy, v[2] = s.zz, v[3] = s.xy, v[4] = s.xz, v[5] = s.yz;
}

// A B for symmetric A and B that commute (then A B is symmetric)
inline Sym3 mul_commuting(const Sym3 &a, const Sym3 &b)
{
  return {a.xx * b.xx + a.xy * b.xy + a.xz * b.xz, a.xy * b.xy + a.yy * b.yy + a.yz * b.yz,
          a.xz * b.xz + a.yz * b.yz + a.zz * b.zz, a.xx * b.xy + a.xy * b.yy + a.xz * b.yz,
          a.xx * b.xz + a.xy * b.yz + a.xz * b.zz, a.xy * b.xz + a.yy * b.yz + a.yz * b.zz};
}

inline Sym3 plus_identity(const Sym3 &a, double d)
{
  return {a.xx + d, a.yy + d, a.zz + d, a.xy, a.xz, a.yz};
}

inline Sym3 scaled(const Sym3 &a, double s)
{
  return {s * a.xx, s * a.yy, s * a.zz, s * a.xy, s * a.xz, s * a.yz};
}

// squared Frobenius norm
inline double norm2(const Sym3 &a)
{
  return a.xx * a.xx + a.yy * a.yy + a.zz * a.zz +
      2.0 * (a.xy * a.xy + a.xz * a.xz + a.yz * a.yz);
}

// A S A^T (symmetric for any A)
inline Sym3 congruence(const Mat3 &A, const Sym3 &S)
{
  const Mat3 G = A * mat_of(S);
  auto dot = [&](int r, int c) { return G(r, 0) * A(c, 0) + G(r, 1) * A(c, 1) + G(r, 2) * A(c, 2); };
  return {dot(0, 0), dot(1, 1), dot(2, 2), dot(0, 1), dot(0, 2), dot(1, 2)};
}

// 1/k for the series' coefficients: a table lookup, not a division per term
struct Reciprocals {
  double v[32];
  constexpr Reciprocals() : v()
  {
    for (int k = 1; k < 32; ++k) v[k] = 1.0 / k;
  }
};
inline constexpr Reciprocals reciprocal{};

/* ln b of a symmetric positive definite b near a multiple of the
   identity, without its eigenvectors: with s = tr b / 3, B = b / s and
   Y = (B - I)(B + I)^-1 (a function of b, so symmetric and coaxial),
     ln b = ln s I + 2 atanh Y = ln s I + 2 (Y + Y^3/3 + Y^5/5 + ...),
   to the power whose successor is below 2e-17 |Y| (Y^11 at |Y| = 0.05,
   Frobenius, the bound: B's eigenvalues within 0.905 and 1.105; Y^5 at
   |Y| = 1e-3: an elastic distortion of a metal is a few 1e-3).  At most
   seven products of commuting symmetric tensors and one adjugate: a few
   times cheaper than an iterative eigen-solve, and as accurate where the
   eigenvalues are close (where the closed-form cubic solve is not).
   Returns false, L untouched, for b farther from isotropic (or not
   positive definite): the caller then takes the eigen-decomposition. */
inline bool log_spd_near_isotropic(const Sym3 &b, Sym3 &L)
{
  const double s = (b.xx + b.yy + b.zz) / 3.0;
  if (!(s > 0.0)) return false;
  const Sym3 B = scaled(b, 1.0 / s);
  const Sym3 Bp = plus_identity(B, 1.0);
  // (B + I)^-1 = adj(B + I) / det(B + I)
  const Sym3 adj = {Bp.yy * Bp.zz - Bp.yz * Bp.yz, Bp.xx * Bp.zz - Bp.xz * Bp.xz,
                    Bp.xx * Bp.yy - Bp.xy * Bp.xy, Bp.xz * Bp.yz - Bp.xy * Bp.zz,
                    Bp.xy * Bp.yz - Bp.xz * Bp.yy, Bp.xy * Bp.xz - Bp.xx * Bp.yz};
  const double det = Bp.xx * adj.xx + Bp.xy * adj.xy + Bp.xz * adj.xz;
  if (!(det > 0.0)) return false;
  const Sym3 Y = scaled(mul_commuting(plus_identity(B, -1.0), adj), 1.0 / det);
  const double y2 = norm2(Y);
  if (!(y2 <= 0.05 * 0.05)) return false;
  // highest power 2K+1 with |Y|^(2K+2) / (2K+3) <= 2e-17
  const int K = y2 <= 1e-6 ? 2 : (y2 <= 1e-4 ? 3 : (y2 <= 6.25e-4 ? 4 : 5));
  const Sym3 Z = mul_commuting(Y, Y);
  const double top = reciprocal.v[2 * K + 1];
  Sym3 q = {top, top, top, 0.0, 0.0, 0.0};
  for (int k = K - 1; k >= 0; --k) q = plus_identity(mul_commuting(Z, q), reciprocal.v[2 * k + 1]);
  const Sym3 out = plus_identity(scaled(mul_commuting(Y, q), 2.0), std::log(s));
  if (!std::isfinite(norm2(out))) return false;
  L = out;
  return true;
}

inline bool log_spd_near_isotropic(const Mat3 &b, Mat3 &L)
{
  Sym3 l;
  if (!log_spd_near_isotropic(sym_of(b), l)) return false;
  L = mat_of(l);
  return true;
}

/* exp D of a symmetric D with |D| <= 0.2 (Frobenius) by its Taylor
   series, in Horner form, to the power N whose successor's bound
   |D|^(N+1) / (N+1)! is below 1e-18 (N = 12 at |D| = 0.2, 7 at 0.01).
   Returns false, E untouched, for a larger D. */
inline bool exp_sym_small(const Sym3 &D, Sym3 &E)
{
  const double nd = std::sqrt(norm2(D));
  if (!(nd <= 0.2)) return false;
  int N = 1;    // at most 12 (at |D| = 0.2)
  for (double t = nd; (t *= nd * reciprocal.v[N + 1]) > 1e-18;) ++N;
  Sym3 q = plus_identity(scaled(D, reciprocal.v[N]), 1.0);
  for (int k = N - 1; k >= 1; --k)
    q = plus_identity(scaled(mul_commuting(D, q), reciprocal.v[k]), 1.0);
  if (!std::isfinite(norm2(q))) return false;
  E = q;
  return true;
}

inline bool exp_sym_small(const Mat3 &D, Mat3 &E)
{
  Sym3 e;
  if (!exp_sym_small(sym_of(D), e)) return false;
  E = mat_of(e);
  return true;
}

// a tangent dA/dB of 3x3 tensors as a 9x9 matrix over row-major indices (ij, kl)
using Tangent9 = Eigen::Matrix<double, 9, 9>;

inline Tangent9 outer(const Mat3 &a, const Mat3 &b)
{
  Tangent9 t;
  for (int i = 0; i < 9; ++i)
    for (int k = 0; k < 9; ++k) t(i, k) = a(i / 3, i % 3) * b(k / 3, k % 3);
  return t;
}

// D : dB, the change of A that a tangent D gives for a change dB
inline Mat3 linear_step(const Tangent9 &D, const Mat3 &dB)
{
  Eigen::Matrix<double, 9, 1> b, a;
  for (int k = 0; k < 9; ++k) b(k) = dB(k / 3, k % 3);
  a = D * b;
  Mat3 dA;
  for (int k = 0; k < 9; ++k) dA(k / 3, k % 3) = a(k);
  return dA;
}

// d sym(e)/d e
inline Tangent9 sym_identity()
{
  Tangent9 t = Tangent9::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      t(3 * i + j, 3 * i + j) += 0.5;
      t(3 * i + j, 3 * j + i) += 0.5;
    }
  return t;
}

}    // namespace NOSPD

#endif

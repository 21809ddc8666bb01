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

/* ln b of a symmetric positive definite b near a multiple of the
   identity, without its eigenvectors: with s = tr b / 3, B = b / s and
   Y = (B - I)(B + I)^-1 (a function of b, so symmetric and coaxial),
     ln b = ln s I + 2 atanh Y = ln s I + 2 (Y + Y^3/3 + Y^5/5 + ...),
   to the power whose successor is below 2e-17 |Y| (Y^11 at |Y| = 0.05,
   Frobenius, the bound: B's eigenvalues within 0.905 and 1.105; Y^5 at
   |Y| = 1e-3: an elastic distortion of a metal is a few 1e-3).  At most
   six 3x3 products: a few times cheaper than an iterative eigen-solve, and
   as accurate where the eigenvalues are close (where the closed-form
   cubic solve is not).
   Returns false, L untouched, for b farther from isotropic (or not
   positive definite): the caller then takes the eigen-decomposition. */
inline bool log_spd_near_isotropic(const Mat3 &b, Mat3 &L)
{
  const double s = b.trace() / 3.0;
  if (!(s > 0.0)) return false;
  const Mat3 I = Mat3::Identity();
  const Mat3 B = b / s;
  Mat3 Y = (B - I) * (B + I).inverse();
  Y = 0.5 * (Y + Y.transpose()).eval();
  const double y2 = Y.squaredNorm();
  if (!(y2 <= 0.05 * 0.05)) return false;
  // highest power 2K+1 with |Y|^(2K+2) / (2K+3) <= 2e-17
  const int K = y2 <= 1e-6 ? 2 : (y2 <= 1e-4 ? 3 : (y2 <= 6.25e-4 ? 4 : 5));
  const Mat3 Z = Y * Y;
  Mat3 q = I / double(2 * K + 1);
  for (int k = K - 1; k >= 0; --k) q = I / double(2 * k + 1) + Z * q;
  L = 2.0 * Y * q + std::log(s) * I;
  L = 0.5 * (L + L.transpose()).eval();
  return L.allFinite();
}

/* exp D of a symmetric D with |D| <= 0.2 (Frobenius) by its Taylor
   series, in Horner form, to the power N whose successor's bound
   |D|^(N+1) / (N+1)! is below 1e-18 (N = 15 at |D| = 0.2, 7 at 0.01).
   Returns false, E untouched, for a larger D. */
inline bool exp_sym_small(const Mat3 &D, Mat3 &E)
{
  const double nd = D.norm();
  if (!(nd <= 0.2)) return false;
  int N = 1;
  for (double t = nd; (t *= nd / (N + 1)) > 1e-18;) ++N;
  const Mat3 I = Mat3::Identity();
  Mat3 q = I + D / double(N);
  for (int k = N - 1; k >= 1; --k) q = I + (D * q) / double(k);
  E = 0.5 * (q + q.transpose());
  return E.allFinite();
}

}    // namespace NOSPD

#endif

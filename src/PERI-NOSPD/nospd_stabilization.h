/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Zero-energy-mode control.  Knows nothing of LAMMPS.

   All terms act on the nonuniform part of the deformation state
   z<xi> = Y - F xi, which is exactly zero under any homogeneous
   deformation, so none of them changes the response to one.

   Linear terms (Silling 2017, Wan et al. 2019) add S z to the force state:
       T<xi> = omega (P K^-1 xi + S z)
   with S = alpha I (Silling, alpha = G c / delta) or S = C : K^-1
   (Wan, C the elasticity tensor).  Writing U = Y - xi and H = F - I,
       T_i<xi> - T_j<-xi> = omega ((B_i + B_j) xi + (S_i + S_j) U),
       B = P K^-1 - S H,
   so pass 2 needs only B and S of the partner.  Both derive from the
   energy  E_s = sum_i V_i 1/2 sum_j omega z.S z V_j  (a potential).

   The hourglass force (Littlewood 2011) is the bond-aligned projection
       T<xi> += c_hg omega (z . yhat / |xi|) yhat ,  c_hg = C c,
   objective but not derived from an energy.
------------------------------------------------------------------------- */

#ifndef NOSPD_STABILIZATION_H
#define NOSPD_STABILIZATION_H

#include "nospd_constitutive.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace NOSPD {

enum class Stab { NONE, SILLING, HOURGLASS, WAN };

constexpr double PI = 3.14159265358979323846;

/* Bond-based micromodulus c for the material: 3D 18 K/(pi delta^4);
   2D plane stress 9 E/(pi t delta^3); 2D plane strain 48 E/(5 pi t delta^3)
   (E the 3D Young's modulus, t the thickness carried by the volumes). */
inline double micromodulus(int dim, Plane plane, double E, double nu, double delta,
                           double thickness)
{
  if (dim == 3) {
    const double K = E / (3.0 * (1.0 - 2.0 * nu));
    return 18.0 * K / (PI * delta * delta * delta * delta);
  }
  const double d3 = delta * delta * delta;
  if (plane == Plane::STRESS) return 9.0 * E / (PI * thickness * d3);
  return 48.0 * E / (5.0 * PI * thickness * d3);
}

/* Micromodulus of the bond-based body with the same P-wave modulus M
   (the stiffness of the fastest wave): PMB's c with its fixed Poisson ratio
   (1/4 in 3D and plane strain, 1/3 in plane stress) and K or E chosen so
   that its M equals ours.  3D 10 M/(pi delta^4), 2D 8 M/(pi t delta^3).
   Used for the stable time step estimate. */
inline double pwave_micromodulus(int dim, Plane plane, const Lame &m, double delta,
                                 double thickness)
{
  if (dim == 3) return 10.0 * (m.lambda + 2.0 * m.mu) / (PI * delta * delta * delta * delta);
  const double M = (plane == Plane::STRESS ? m.lambda_ps : m.lambda) + 2.0 * m.mu;
  return 8.0 * M / (PI * thickness * delta * delta * delta);
}

/* Wan et al.'s stabilization tensor S = C : K^-1 for isotropic C:
   lambda tr(K^-1) I + 2 mu K^-1.  In 2D only the in-plane block counts
   (K^-1's out-of-plane entry is a placeholder) and plane stress uses the
   reduced lambda* = 2 lambda mu/(lambda + 2 mu). */
inline Mat3 wan_tensor(const Lame &m, int dim, Plane plane, const Mat3 &Kinv)
{
  Mat3 S;
  if (dim == 3) {
    S = m.lambda * Kinv.trace() * Mat3::Identity() + 2.0 * m.mu * Kinv;
    return S;
  }
  const double lam = (plane == Plane::STRESS) ? m.lambda_ps : m.lambda;
  S.setZero();
  const double tr = Kinv(0, 0) + Kinv(1, 1);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) S(a, b) = (a == b ? lam * tr : 0.0) + 2.0 * m.mu * Kinv(a, b);
  return S;
}

/* Hourglass pair force (T_i<xi> - T_j<-xi>) / omega for one bond:
   (c_i z_i + c_j z_j) . yhat / |xi| yhat, where T_j<-xi> is written on the
   bond seen from i (z_j<-xi> = -z_j<xi>, yhat<-xi> = -yhat).  z = U - H xi
   keeps the cancellation at the scale of displacements. */
inline Vec3 hourglass_pair(double c_i, const Mat3 &H_i, double c_j, const Mat3 &H_j,
                           const Vec3 &xi, const Vec3 &U)
{
  const Vec3 Y = xi + U;
  const double ry = Y.norm();
  if (ry == 0.0) return Vec3::Zero();
  const Vec3 yhat = Y / ry;
  const Vec3 zw = c_i * (U - H_i * xi) + c_j * (U - H_j * xi);
  return (zw.dot(yhat) / xi.norm()) * yhat;
}

/* ----------------------------------------------------------------------
   Silling's springs on the residual of a quadratic fit
   (stabilization/fit quadratic).

   Silling's springs resist z = U - H xi, the part of the bond motion that
   the linear fit F does not describe.  Under a curved but smooth motion
   (a bending beam, the bulging face of a Taylor bar) z is the curvature's
   share, 1/2 G:xi xi, and the springs store energy that no real material
   stores: they act as a strain-gradient stiffness of the size of the
   horizon, which holds a flowing metal back where its deformation bends.
   With the quadratic fit the springs see only what the best fit
       U ~ A phi(xi),  phi = (xi, xi_x^2, xi_y^2, xi_z^2, xi_x xi_y, xi_x xi_z, xi_y xi_z)
   (least squares with the family's weights w = omega V) leaves:
       z2 = U - A phi(xi),  A = N2 K2^-1,  N2 = sum w U phi^T,  K2 = sum w phi phi^T.
   A zero-energy mode varies from point to point and is no quadratic, so
   the springs still hold it.  E = 1/2 alpha sum w |z2|^2 is the squared
   norm of a w-orthogonal projection of U, so its force state is
   T<xi> = omega alpha z2 (no further term) and, with A = [H2 | Q],
       T_i<xi> - T_j<-xi> = omega ((B_i + B_j) xi + (alpha_i + alpha_j) U
                                   - (alpha_i Q_i - alpha_j Q_j) phi_q(xi)),
   B = P K^-1 - alpha H2, phi_q the six quadratic entries (even in xi).
   The stress still comes from the linear F: the patch test, the material
   and every output are the linear fit's; only the springs change.
------------------------------------------------------------------------- */

namespace QuadraticFit {
  constexpr int N = 9;        // basis functions
  constexpr int PACKED = 45;  // K2^-1, upper triangle row by row
  constexpr int RECORD = PACKED + 1;    // and a flag: 1 if the fit exists
  constexpr double TOLERANCE = 1.0e-8;  // smallest / largest eigenvalue, scaled
}    // namespace QuadraticFit

// the six quadratic entries of phi(xi)
inline void quadratic_terms(const double *e, double *q)
{
  q[0] = e[0] * e[0], q[1] = e[1] * e[1], q[2] = e[2] * e[2];
  q[3] = e[0] * e[1], q[4] = e[0] * e[2], q[5] = e[1] * e[2];
}

inline int packed_index(int r, int c)
{
  if (r > c) std::swap(r, c);
  return r * QuadraticFit::N - r * (r - 1) / 2 + (c - r);
}

/* K2^-1 from K2 (9 x 9, symmetric) into rec (QuadraticFit::RECORD).
   Basis functions no bond spans (in 2D the out-of-plane ones) are left
   out; the rest is scaled to unit diagonal and inverted from its
   eigenvalues.  Where the smallest is below TOLERANCE times the largest
   (too few or too regular partners, e.g. one layer of points) the fit
   does not exist: flag 0, and the springs fall back to the linear fit. */
inline bool quadratic_fit_inverse(const Eigen::Matrix<double, 9, 9> &K2, double *rec)
{
  using namespace QuadraticFit;
  for (int k = 0; k < RECORD; k++) rec[k] = 0.0;
  int idx[N], n = 0;
  double scale[N];
  for (int k = 0; k < N; k++)
    if (K2(k, k) > 0.0) {
      idx[n] = k;
      scale[n++] = 1.0 / std::sqrt(K2(k, k));
    }
  if (n == 0) return false;
  Eigen::MatrixXd S(n, n);
  for (int a = 0; a < n; a++)
    for (int b = 0; b < n; b++) S(a, b) = scale[a] * K2(idx[a], idx[b]) * scale[b];
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  if (eig.info() != Eigen::Success) return false;
  const Eigen::VectorXd lam = eig.eigenvalues();
  if (!(lam(0) > TOLERANCE * lam(n - 1))) return false;
  const Eigen::MatrixXd V = eig.eigenvectors();
  const Eigen::MatrixXd Si = V * lam.cwiseInverse().asDiagonal() * V.transpose();
  for (int a = 0; a < n; a++)
    for (int b = a; b < n; b++) rec[packed_index(idx[a], idx[b])] = scale[a] * Si(a, b) * scale[b];
  rec[PACKED] = 1.0;
  return true;
}

/* A = N2 K2^-1 (3 x 9) from N2 (3 x 9) and a fit record */
inline Eigen::Matrix<double, 3, 9> quadratic_fit(const Eigen::Matrix<double, 3, 9> &N2,
                                                 const double *rec)
{
  Eigen::Matrix<double, 9, 9> K2i;
  for (int r = 0; r < QuadraticFit::N; r++)
    for (int c = 0; c < QuadraticFit::N; c++) K2i(r, c) = rec[packed_index(r, c)];
  return N2.lazyProduct(K2i);
}

/* The zero-energy-mode indicator of a point,
     |z| = sqrt( sum_j w |U_j - H xi_j|^2 / sum_j w |xi_j|^2 ),
   the part of the bond motion that F = I + H does not describe, relative
   to the bond lengths: zero for any homogeneous deformation, of the order
   of the strain in an hourglass mode.  In 2D the out-of-plane component of
   H xi (plane stress F33) is not a bond quantity and is left out. */
class ZemSum {
 public:
  ZemSum(const Mat3 &H, bool plane) : H(H), plane(plane) {}
  void add(double w, const Vec3 &xi, const Vec3 &U)
  {
    Vec3 Hxi = H * xi;
    if (plane) Hxi[2] = 0.0;
    zz += w * (U - Hxi).squaredNorm();
    xx += w * xi.squaredNorm();
  }
  double value() const { return xx > 0.0 ? std::sqrt(zz / xx) : 0.0; }

 private:
  Mat3 H;
  bool plane;
  double zz = 0.0, xx = 0.0;
};

/* The same measure after a quadratic fit: the bond motion that neither a
   linear nor a quadratic field describes.  A smooth field's curvature
   (a stress concentration, a bending plate) leaves the linear indicator
   of the order of delta |grad H| but this one of delta^2 |grad grad H|,
   while a mode at the spacing's scale shows in both.  One pass: the
   residual is sum w |U|^2 - tr(N2 K2^-1 N2^T).  Negative where the family
   spans no quadratic fit. */
class QuadraticZemSum {
 public:
  void add(double w, const Vec3 &xi, const Vec3 &U)
  {
    double phi[9] = {xi[0], xi[1], xi[2]};
    quadratic_terms(xi.data(), phi + 3);
    const double wu[3] = {w * U[0], w * U[1], w * U[2]};
    for (int c = 0; c < 9; c++) {
      const double wc = w * phi[c];
      for (int r = 0; r <= c; r++) K2(r, c) += wc * phi[r];    // upper triangle
      for (int a = 0; a < 3; a++) N2(a, c) += wu[a] * phi[c];
    }
    uu += w * U.squaredNorm();
    xx += w * xi.squaredNorm();
  }
  // a check, not a force: the scaled K2 by LDLT (basis functions no bond
  // spans, in 2D the out-of-plane ones, left out as identity rows), its
  // pivots' spread standing in for the conditioning of quadratic_fit_inverse
  double value() const
  {
    if (!(xx > 0.0)) return -1.0;
    Eigen::Matrix<double, 9, 9> S = K2.selfadjointView<Eigen::Upper>();
    Eigen::Matrix<double, 9, 1> scale;
    for (int k = 0; k < 9; k++) scale[k] = S(k, k) > 0.0 ? 1.0 / std::sqrt(S(k, k)) : 0.0;
    S = scale.asDiagonal() * S * scale.asDiagonal();
    for (int k = 0; k < 9; k++)
      if (scale[k] == 0.0) S(k, k) = 1.0;
    const Eigen::LDLT<Eigen::Matrix<double, 9, 9>> ldlt(S);
    const auto d = ldlt.vectorD();
    if (!(d.minCoeff() > QuadraticFit::TOLERANCE * d.maxCoeff())) return -1.0;
    const Eigen::Matrix<double, 3, 9> Ns = N2 * scale.asDiagonal();
    const Eigen::Matrix<double, 9, 3> A = ldlt.solve(Ns.transpose());
    return std::sqrt(std::max(uu - Ns.cwiseProduct(A.transpose()).sum(), 0.0) / xx);
  }

 private:
  Eigen::Matrix<double, 9, 9> K2 = Eigen::Matrix<double, 9, 9>::Zero();
  Eigen::Matrix<double, 3, 9> N2 = Eigen::Matrix<double, 3, 9>::Zero();
  double uu = 0.0, xx = 0.0;
};

/* The strain the indicator is measured against: |F^T F - I| / 2 (the Green
   strain's norm, blind to rotations; in 2D of the in-plane block). */
inline double green_strain_norm(const Mat3 &F, bool plane)
{
  Mat3 C = F.transpose() * F - Mat3::Identity();
  if (plane) C.row(2).setZero(), C.col(2).setZero();
  return 0.5 * C.norm();
}

/* An indicator over the strain, the strain floored at `floor_fraction` of
   the body's largest (a point at rest in a strained body is measured
   against the body's strain, not its own). */
inline double zem_ratio(double z, double strain, double body_strain, double floor_fraction = 0.1)
{
  // below 1e-6 the strain is no scale (a body at rest or turning rigidly,
  // whose indicator is rounding): a pure mode (F = I) still shows
  return z / std::max({strain, floor_fraction * body_strain, 1.0e-6});
}

}    // namespace NOSPD

#endif

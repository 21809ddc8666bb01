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

}    // namespace NOSPD

#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Constitutive laws P(F) and W(F), and their plane reductions.
   Knows nothing of LAMMPS.
------------------------------------------------------------------------- */

#ifndef NOSPD_CONSTITUTIVE_H
#define NOSPD_CONSTITUTIVE_H

#include "nospd_tensor.h"

#include <Eigen/Eigenvalues>

namespace NOSPD {

// Strain measure / law.  SMALL: P = sigma = C:eps, eps = sym(F) - I.
// COROTATIONAL: P = J sigma F^-T with sigma = R (C:(U-I)) U R^T / J, the
//   exact integral of a Green-Naghdi (polar) rotated linear law; it equals
//   P = R C:(U-I), hyperelastic in U, objective.
// SVK: Saint Venant-Kirchhoff, P = F S, S = lambda tr(E) I + 2 mu E.
// NEOHOOKE: compressible Neo-Hooke, S = mu (I - C^-1) + lambda ln(J) C^-1.
// HENCKY: logarithmic strain, W = lambda/2 (tr ln V)^2 + mu |ln V|^2,
//   Kirchhoff stress tau = lambda tr(ln V) I + 2 mu ln V, P = tau F^-T;
//   the elastic part of the finite-strain plasticity (nospd_plasticity.h).
// USER: a law supplied at run time through the PointLaw interface below
//   (a strain-energy formula, nospd_formula.h); the material's Lame
//   constants still set the stabilization and the time step estimate.
// UMAT_SMALL, UMAT_FINITE: an Abaqus UMAT (nospd_umat.h) with small-strain
//   (P = sigma) or logarithmic-strain (P = J sigma F^-T) kinematics; it has
//   history, so it has no point form here.
enum class Law { SMALL, COROTATIONAL, SVK, NEOHOOKE, HENCKY, USER, UMAT_SMALL, UMAT_FINITE };

// a law's name as the strain keyword gives it, for messages
inline const char *law_keyword(Law law)
{
  static const char *names[] = {"small", "finite", "svk", "neohookean", "hencky", "formula",
                                "umat", "umat/finite"};
  return names[static_cast<int>(law)];
}

// laws whose stress is sigma of the small strain, P = sigma
inline bool small_kinematics(Law law) { return law == Law::SMALL || law == Law::UMAT_SMALL; }

/* A hyperelastic point law P(F), W(F) defined outside this header.
   first_piola returns false where the law is undefined (e.g. det F <= 0).
   Implementations keep scratch space, so one object serves one thread. */
class PointLaw {
 public:
  virtual ~PointLaw() = default;
  virtual bool first_piola(const Mat3 &F, Mat3 &P, double &W) const = 0;
};

// Out-of-plane assumption: 3D, or 2D plane strain (F33 = 1) or plane
// stress (F33 chosen so that P33 = 0).
enum class Plane { NONE, STRAIN, STRESS };

struct Lame {
  double lambda, mu;
  double lambda_ps;    // plane-stress lambda* = E nu / (1 - nu^2) = 2 lambda mu/(lambda + 2 mu)
  const PointLaw *user = nullptr;    // Law::USER: the law itself
  static Lame from_young(double E, double nu)
  {
    return {E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu)),
            E * nu / (1.0 - nu * nu), nullptr};
  }
  double bulk() const { return lambda + 2.0 * mu / 3.0; }
};

// P(F) of the 3D law and its energy density W.  Returns false where the law
// is undefined (det F <= 0 for the finite-strain laws that need J).
inline bool first_piola_3d(Law law, const Lame &m, const Mat3 &F, Mat3 &P, double &W)
{
  const Mat3 I = Mat3::Identity();
  switch (law) {
    case Law::SMALL: {
      const Mat3 eps = 0.5 * (F + F.transpose()) - I;
      const double tr = eps.trace();
      P = m.lambda * tr * I + 2.0 * m.mu * eps;
      W = 0.5 * m.lambda * tr * tr + m.mu * eps.squaredNorm();
      return true;
    }
    case Law::COROTATIONAL: {
      if (!(F.determinant() > 0.0)) return false;
      Mat3 R, U;
      if (!polar_decomposition(F, R, U)) return false;
      const Mat3 Eb = U - I;
      const double tr = Eb.trace();
      const Mat3 T = m.lambda * tr * I + 2.0 * m.mu * Eb;
      P = R * T;
      W = 0.5 * m.lambda * tr * tr + m.mu * Eb.squaredNorm();
      return true;
    }
    case Law::SVK: {
      const Mat3 E = 0.5 * (F.transpose() * F - I);
      const double tr = E.trace();
      const Mat3 S = m.lambda * tr * I + 2.0 * m.mu * E;
      P = F * S;
      W = 0.5 * m.lambda * tr * tr + m.mu * E.squaredNorm();
      return true;
    }
    case Law::NEOHOOKE: {
      const double J = F.determinant();
      if (!(J > 0.0)) return false;
      const Mat3 C = F.transpose() * F;
      const Mat3 Cinv = C.inverse();
      const double lnJ = std::log(J);
      const Mat3 S = m.mu * (I - Cinv) + m.lambda * lnJ * Cinv;
      P = F * S;
      W = 0.5 * m.mu * (C.trace() - 3.0) - m.mu * lnJ + 0.5 * m.lambda * lnJ * lnJ;
      return true;
    }
    case Law::HENCKY: {
      if (!(F.determinant() > 0.0)) return false;
      // ln V = ln b / 2, b = F F^T; tau is coaxial with V.  Near isotropic b
      // by its series, else from b's eigenpairs (nospd_tensor.h)
      Mat3 b = F * F.transpose();
      b = 0.5 * (b + b.transpose()).eval();
      Mat3 lnb;
      if (log_spd_near_isotropic(b, lnb)) {
        const Mat3 e = 0.5 * lnb;
        const double tr = e.trace();
        P = (m.lambda * tr * I + 2.0 * m.mu * e) * F.inverse().transpose();
        W = 0.5 * m.lambda * tr * tr + m.mu * e.squaredNorm();
        return true;
      }
      Eigen::SelfAdjointEigenSolver<Mat3> eig(b);
      if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 0.0)) return false;
      Vec3 e;
      for (int a = 0; a < 3; ++a) e(a) = 0.5 * std::log(eig.eigenvalues()(a));
      const double tr = e.sum();
      const Vec3 tau = (m.lambda * tr) * Vec3::Ones() + 2.0 * m.mu * e;
      const Mat3 &N = eig.eigenvectors();
      P = N * tau.asDiagonal() * N.transpose() * F.inverse().transpose();
      W = 0.5 * m.lambda * tr * tr + m.mu * e.squaredNorm();
      return true;
    }
    case Law::USER:
      return m.user && m.user->first_piola(F, P, W);
    case Law::UMAT_SMALL:
    case Law::UMAT_FINITE:
      return false;
  }
  return false;
}

/* Plane stress for any 3D point law eval(F, P, W) -> bool: F(2,2) is solved
   for so that P33 = 0 by a secant iteration started from the small-strain
   answer eps33 = -lambda/(lambda+2mu) (eps11+eps22), and written back into
   F so that stress output sees it. */
template <class Eval>
inline bool solve_plane_stress(const Lame &m, Mat3 &F, Mat3 &P, double &W, Eval eval)
{
  const double r = m.lambda / (m.lambda + 2.0 * m.mu);
  F(2, 2) = 1.0 - r * (F(0, 0) + F(1, 1) - 2.0);
  if (!eval(F, P, W)) return false;

  const double scale = m.lambda + 2.0 * m.mu;
  double s0 = F(2, 2), p0 = P(2, 2);
  double s1 = s0 * (1.0 - 1e-6), p1;
  F(2, 2) = s1;
  if (!eval(F, P, W)) return false;
  p1 = P(2, 2);
  for (int it = 0; it < 60 && std::abs(p1) > 1e-13 * scale; ++it) {
    if (p1 == p0) break;
    const double s2 = s1 - p1 * (s1 - s0) / (p1 - p0);
    s0 = s1;
    p0 = p1;
    s1 = s2;
    F(2, 2) = s1;
    if (!eval(F, P, W)) return false;
    p1 = P(2, 2);
  }
  return true;
}

/* P(F) under the plane assumption.  F arrives with its in-plane block set
   and F(2,2) = 1; for plane stress F(2,2) is solved for so that P33 = 0
   (closed form for small strain, secant iteration otherwise) and written
   back into F so that stress output sees it. */
inline bool first_piola(Law law, Plane plane, const Lame &m, Mat3 &F, Mat3 &P, double &W)
{
  if (plane != Plane::STRESS) return first_piola_3d(law, m, F, P, W);

  if (law == Law::SMALL) {
    // 2D law with lambda*, valid for -1 < nu < 1; eps33 follows from sigma33 = 0
    Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
    eps(2, 2) = 0.0;
    const double tr = eps(0, 0) + eps(1, 1);
    P = 2.0 * m.mu * eps;
    P(0, 0) += m.lambda_ps * tr;
    P(1, 1) += m.lambda_ps * tr;
    W = 0.5 * (P(0, 0) * eps(0, 0) + P(1, 1) * eps(1, 1) + 2.0 * P(0, 1) * eps(0, 1));
    F(2, 2) = 1.0 - m.lambda_ps / (2.0 * m.mu) * tr;
    return true;
  }

  return solve_plane_stress(m, F, P, W, [&](const Mat3 &Ft, Mat3 &Pt, double &Wt) {
    return first_piola_3d(law, m, Ft, Pt, Wt);
  });
}

// Cauchy stress from P: sigma = P F^T / J (small strain: sigma = P).
inline Mat3 cauchy_stress(Law law, const Mat3 &F, const Mat3 &P)
{
  if (small_kinematics(law)) return 0.5 * (P + P.transpose());
  const Mat3 s = P * F.transpose() / F.determinant();
  return 0.5 * (s + s.transpose());
}

inline double von_mises(const Mat3 &s)
{
  const Mat3 dev = s - (s.trace() / 3.0) * Mat3::Identity();
  return std::sqrt(1.5 * dev.squaredNorm());
}

}    // namespace NOSPD

#endif

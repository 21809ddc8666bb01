/* ----------------------------------------------------------------------
   PERI-NOSPD: Drucker-Prager plasticity of one material point (no LAMMPS
   headers): pressure-dependent yield for rock, concrete and soils.

       f = sqrt(J2(s)) + eta p - xi c(a),     p = tr(sigma)/3 (tension > 0)
       g = sqrt(J2(s)) + eta_bar p            (flow potential)
       da = xi dgamma,  c(a) = c0 + H a       (linear cohesion hardening)

   eta_bar = eta is associative flow; eta_bar < eta a smaller dilatancy.
   From Mohr-Coulomb's friction angle phi, dilatancy angle psi and cohesion
   c0, the cone through the compression meridian (outer edges):
       eta = 6 sin(phi) / (sqrt(3) (3 - sin(phi))),
       xi  = 6 cos(phi) / (sqrt(3) (3 - sin(phi))),
       eta_bar = 6 sin(psi) / (sqrt(3) (3 - sin(psi))).
   The return is backward Euler in closed form (linear hardening): onto the
   smooth cone, or onto its apex where the cone return would overshoot it
   (E. A. de Souza Neto, D. Peric, D. R. J. Owen, Computational Methods for
   Plasticity, Wiley 2008, section 8.3.3), with its consistent tangent.

   Energy: with associative flow the stress is the gradient of the step's
   incremental potential W_e + int_{a_n}^{a_n+da} c(a) da, as for J2
   (nospd_plasticity.h); a non-associative step also dissipates the work of
   its dilatancy mismatch, (eta_bar - eta) p dgamma, so that the plastic
   work booked is sigma : d eps_p less the hardening's stored part.

   Kinematics as the J2 law's: small strain (eps_e = sym(F) - I - eps_p,
   P = sigma) or Hencky (log strain of b_e = F C_p^-1 F^T in its principal
   frame, Kirchhoff stress, b_e's new value exp(2 e_e)).
------------------------------------------------------------------------- */

#ifndef NOSPD_DRUCKER_PRAGER_H
#define NOSPD_DRUCKER_PRAGER_H

#include "nospd_plasticity.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace NOSPD {

struct DruckerPrager {
  bool active = false;    // a type's law: Drucker-Prager instead of J2
  double eta = 0.0, eta_bar = 0.0, xi = 0.0;
  double c0 = 0.0, H = 0.0;

  // from the friction and dilatancy angles (radians), compression meridian
  static DruckerPrager from_angles(double phi, double psi, double c0, double H)
  {
    DruckerPrager dp;
    const double r3 = std::sqrt(3.0);
    dp.eta = 6.0 * std::sin(phi) / (r3 * (3.0 - std::sin(phi)));
    dp.xi = 6.0 * std::cos(phi) / (r3 * (3.0 - std::sin(phi)));
    dp.eta_bar = 6.0 * std::sin(psi) / (r3 * (3.0 - std::sin(psi)));
    dp.c0 = c0;
    dp.H = H;
    dp.active = true;
    return dp;
  }
  double cohesion(double a) const { return c0 + H * a; }
  // int_{a}^{a+d} c(s) ds
  double cohesion_work(double a, double d) const { return c0 * d + H * (a * d + 0.5 * d * d); }
};

enum class DPMode { ELASTIC = 0, CONE = 1, APEX = 2 };

namespace detail {

  /* The return on the trial elastic strain e (small strain, or the log
     strain of b_e): e becomes the elastic strain, stress the stress
     (Cauchy or Kirchhoff), dep the plastic strain increment, da the
     increment of a; dD the dissipation booked; D (if given) the consistent
     tangent dstress/de.  False where no admissible state exists: a trial
     beyond the apex with no dilatancy (eta_bar = 0) cannot return. */
  inline bool dp_return(const Lame &m, const DruckerPrager &dp, double a_n, Mat3 &e, Mat3 &stress,
                        Mat3 &dep, double &da, double &dD, DPMode &mode, Tangent9 *D)
  {
    const Mat3 I = Mat3::Identity();
    const double G = m.mu, K = m.lambda + 2.0 * m.mu / 3.0;
    const double ev = e.trace();
    const Mat3 ed = e - (ev / 3.0) * I;
    const double ned = ed.norm();
    const double p_tr = K * ev, q_tr = std::sqrt(2.0) * G * ned;
    const double c_n = dp.cohesion(a_n);
    const double phi = q_tr + dp.eta * p_tr - dp.xi * c_n;
    dep.setZero();
    da = dD = 0.0;
    const Tangent9 Isym = sym_identity(), II = outer(I, I);
    if (!(phi > 1.0e-14 * (std::abs(q_tr) + std::abs(dp.eta * p_tr) + dp.xi * std::abs(c_n)))) {
      mode = DPMode::ELASTIC;
      stress = m.lambda * ev * I + 2.0 * m.mu * e;
      if (D) *D = m.lambda * II + 2.0 * m.mu * Isym;
      return std::isfinite(phi);
    }
    const double A = 1.0 / (G + K * dp.eta * dp.eta_bar + dp.xi * dp.xi * dp.H);
    const double dgamma = phi * A;
    if (q_tr - G * dgamma >= 0.0 && ned > 0.0) {
      // the smooth cone: the deviator shrinks along n, p by K eta_bar dgamma
      mode = DPMode::CONE;
      const Mat3 n = ed / ned;
      dep = dgamma * (n / std::sqrt(2.0) + (dp.eta_bar / 3.0) * I);
      da = dp.xi * dgamma;
      e -= dep;
      const double p = p_tr - K * dp.eta_bar * dgamma;
      stress = 2.0 * G * (e - (e.trace() / 3.0) * I) + p * I;
      dD = dp.cohesion_work(a_n, da) + (dp.eta_bar - dp.eta) * p * dgamma;
      if (D) {
        const double r2 = std::sqrt(2.0);
        const Tangent9 Idev = Isym - II / 3.0;
        *D = 2.0 * G * (1.0 - dgamma / (r2 * ned)) * Idev +
             (r2 * G * dgamma / ned - 2.0 * G * G * A) * outer(n, n) -
             r2 * G * A * dp.eta * K * outer(n, I) - r2 * G * K * dp.eta_bar * A * outer(I, n) +
             K * (1.0 - K * dp.eta * dp.eta_bar * A) * II;
      }
      return std::isfinite(dD);
    }
    // the apex: s = 0, p = beta c(a), a = a_n + alpha d eps_v
    if (!(dp.eta > 0.0 && dp.eta_bar > 0.0)) return false;
    mode = DPMode::APEX;
    const double alpha = dp.xi / dp.eta_bar, beta = dp.xi / dp.eta;
    const double dev_p = (p_tr - beta * c_n) / (alpha * beta * dp.H + K);
    const double p = p_tr - K * dev_p;
    da = alpha * dev_p;
    const Mat3 e1 = (p / (3.0 * K)) * I;
    dep = e - e1;
    e = e1;
    stress = p * I;
    // sigma : dep = p dev_p = c(a_n + da) da for both flows; the potential's part
    dD = dp.cohesion_work(a_n, da) + (p * dev_p - dp.cohesion(a_n + da) * da);
    if (D) *D = K * (1.0 - K / (K + alpha * beta * dp.H)) * II;
    return std::isfinite(dD);
  }

  inline double elastic_energy(const Lame &m, const Mat3 &e)
  {
    const double tr = e.trace();
    return 0.5 * m.lambda * tr * tr + m.mu * e.squaredNorm();
  }
}    // namespace detail

/* One Drucker-Prager point under small strain: P = sigma from F and the
   history hn (Hist layout: PLASTIC eps_p, EQPS a, WORK, YIELDING the mode
   of the increment); h1 the history at its end, D (if given) dP/dF. */
inline ReturnStatus drucker_prager_small(const Lame &m, const DruckerPrager &dp, const Mat3 &F,
                                         const double *hn, double *h1, Mat3 &P, double &W,
                                         Tangent9 *D = nullptr)
{
  for (int k = 0; k < Hist::SIZE; ++k) h1[k] = hn[k];
  const Mat3 ep_n = load_sym(hn + Hist::PLASTIC);
  Mat3 e = 0.5 * (F + F.transpose()) - Mat3::Identity() - ep_n, dep;
  double da, dD;
  DPMode mode;
  Tangent9 Ds;
  if (!detail::dp_return(m, dp, hn[Hist::EQPS], e, P, dep, da, dD, mode, D ? &Ds : nullptr))
    return ReturnStatus::NO_CONVERGENCE;
  store_sym(ep_n + dep, h1 + Hist::PLASTIC);
  h1[Hist::EQPS] = hn[Hist::EQPS] + da;
  h1[Hist::WORK] = hn[Hist::WORK] + dD;
  h1[Hist::YIELDING] = static_cast<double>(mode);
  W = detail::elastic_energy(m, e);
  if (D) *D = Ds * sym_identity();    // sigma depends on F through sym(F)
  return P.allFinite() ? ReturnStatus::OK : ReturnStatus::BAD_DEFORMATION;
}

/* The same with Hencky kinematics: the trial b_e = F C_p^-1 F^T (PLASTIC
   holds C_p^-1 - I), its log strain returned in b_e's principal frame
   (isotropic: e, the Kirchhoff stress tau and the flow share it), the new
   b_e = exp(2 e), P = tau F^-T. */
inline ReturnStatus drucker_prager_hencky(const Lame &m, const DruckerPrager &dp, const Mat3 &F,
                                          const double *hn, double *h1, Mat3 &P, double &W)
{
  for (int k = 0; k < Hist::SIZE; ++k) h1[k] = hn[k];
  const double J = F.determinant();
  if (!(J > 0.0) || !F.allFinite()) return ReturnStatus::BAD_DEFORMATION;
  const Mat3 Cpinv = Mat3::Identity() + load_sym(hn + Hist::PLASTIC);
  Eigen::SelfAdjointEigenSolver<Mat3> eig(F * Cpinv * F.transpose());
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 0.0))
    return ReturnStatus::BAD_DEFORMATION;
  Mat3 e = Mat3::Zero(), tau, dep;
  for (int a = 0; a < 3; ++a) e(a, a) = 0.5 * std::log(eig.eigenvalues()(a));
  double da, dD;
  DPMode mode;
  if (!detail::dp_return(m, dp, hn[Hist::EQPS], e, tau, dep, da, dD, mode, nullptr))
    return ReturnStatus::NO_CONVERGENCE;
  const Mat3 &N = eig.eigenvectors();
  Mat3 be1 = Mat3::Zero();
  for (int a = 0; a < 3; ++a) be1(a, a) = std::exp(2.0 * e(a, a));
  const Mat3 Finv = F.inverse();
  P = (N * tau * N.transpose()) * Finv.transpose();
  store_sym(Finv * (N * be1 * N.transpose()) * Finv.transpose() - Mat3::Identity(),
            h1 + Hist::PLASTIC);
  h1[Hist::EQPS] = hn[Hist::EQPS] + da;
  h1[Hist::WORK] = hn[Hist::WORK] + dD;
  h1[Hist::YIELDING] = static_cast<double>(mode);
  W = detail::elastic_energy(m, e);
  return P.allFinite() ? ReturnStatus::OK : ReturnStatus::BAD_DEFORMATION;
}

}    // namespace NOSPD

#endif

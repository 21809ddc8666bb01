/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Consistent tangents dP/dF of the J2 / Johnson-Cook point of
   nospd_plasticity.h (inelastic_point_3d) for a Newton solver: the
   derivative of the P it returns as a function of F, with the history h_n
   and the environment fixed.  Knows nothing of LAMMPS.

   What P depends on through F: only the radial return of the step.  The
   flow stress is sigma_y = f k(a) with the factor f = thermal(T_n) *
   rate(rate_n) of the start history's temperature (user T + h_n's HEAT)
   and strain rate (h_n's RATE, lagged by one step; 0 if dt = 0): the rate
   strain_rate(F) of the step itself and the step's adiabatic heat go to
   h_n+1 only, so dP/dF has no term through them, and rate and temperature
   enter only through f, which scales the hardening slope h = f k'(a).  A
   Johnson-Cook step starts from h_n relaxed onto the moved surface at the
   accepted F (detail::relaxed_start), a function of h_n alone: the tangent
   starts from the same history.

   Radial return (de Souza Neto, Peric & Owen 2008, section 7.4): with eta
   the trial deviatoric stress less the back stress, q = sqrt(3/2)|eta|,
   n = eta/|eta|, d the root of q - (3 mu + Hkin) d - sigma_y(a_n + d) = 0
   and h = d sigma_y/da at a_n + d,
       dsigma/de = C - 6 mu^2/(3 mu + Hkin + h) n(x)n - 6 mu^2 d/q (I_dev - n(x)n).
   SMALL: e = sym(F) - I - eps_p - eth I, P = sigma: D = dsigma/de : dsym(F)/dF.
   HENCKY (ibid. ch. 14): e = ln(b_e)/2 - ln(1 + eth) I with b_e = F C_p^-1 F^T,
   tau the same return of e, P = tau F^-T:
       dP = [dtau/de : (1/2) dln(b_e)/db_e : db_e/dF](dF) F^-T - P dF^T F^-T,
   the derivative of ln by the Daleckii-Krein formula over b_e's eigenpairs
   (divided differences of ln, which stay exact where eigenvalues meet).

   None (false): plane stress (F33 comes from a secant solve of P33 = 0 to
   1e-13 (lambda + 2 mu), noise a difference check could not tell from the
   condensed tangent), hencky with kinematic hardening (not a model the
   point has), and a point whose return fails.  At the accepted F itself
   (inelastic_point's 1e-12 box, which returns the stored P) this is the
   tangent of the return around it.
------------------------------------------------------------------------- */

#ifndef NOSPD_PLASTIC_TANGENT_H
#define NOSPD_PLASTIC_TANGENT_H

#include "nospd_plasticity.h"

namespace NOSPD {

namespace detail {

  /* dsigma/de of the return of the trial elastic strain e (SMALL: Cauchy;
     HENCKY: Kirchhoff and e the log strain) from the history s at the rate
     and temperature factor f, as a 9x9 on symmetric e; stress: the
     returned stress.  The yield test and the root are return_map's. */
  inline bool return_tangent(const Lame &m, const FlowLaw &fl, double f, const double *s,
                             const Mat3 &e, Tangent9 &De, Mat3 &stress)
  {
    const Mat3 I = Mat3::Identity();
    const Tangent9 Isym = sym_identity(), II = outer(I, I);
    De = m.lambda * II + 2.0 * m.mu * Isym;
    stress = m.lambda * e.trace() * I + 2.0 * m.mu * e;
    if (!fl.active) return true;
    const Mat3 eta = stress - (stress.trace() / 3.0) * I - load_sym(s + Hist::BACK);
    const double norm = eta.norm(), q = std::sqrt(1.5) * norm, a_n = s[Hist::EQPS];
    double s0;
    const double sy = fl.flow_at(a_n, f, s0);
    if (!(q > sy && norm > 0.0)) return true;    // elastic
    double d = 0.0, h;
    if (!solve_return(fl, m.mu, q, a_n, f, sy, s0, d) || !(d >= 0.0)) return false;
    // the slope where the increment ends, with the step's rate and temperature factor
    fl.flow_at(a_n + d, f, h);
    const Mat3 n = eta / norm;
    const double mu2 = 6.0 * m.mu * m.mu;
    const Tangent9 nn = outer(n, n);
    De -= mu2 / (3.0 * m.mu + fl.Hkin + h) * nn + mu2 * d / q * (Isym - II / 3.0 - nn);
    stress -= (3.0 * m.mu * d / q) * eta;    // 2 mu d N, N = (3/2) eta / q
    return De.allFinite();
  }

  // (ln x - ln y) / (x - y), and 1/y where x meets y
  inline double log_divided(double x, double y)
  {
    const double u = (x - y) / y;
    if (std::abs(u) < 1.0e-8) return (1.0 - 0.5 * u) / y;
    return std::log1p(u) / (x - y);
  }

  /* ln b of a symmetric positive definite b and its derivative as a 9x9 on
     symmetric db (Daleckii-Krein): with b = sum_a l_a N_a N_a^T,
       dln(b)[db] = sum_ac g(l_a, l_c) N_a (N_a . db N_c) N_c^T,
     g the divided difference of ln. */
  inline bool log_tangent(const Mat3 &b, Mat3 &lnb, Tangent9 &L)
  {
    Eigen::SelfAdjointEigenSolver<Mat3> eig(b);
    if (eig.info() != Eigen::Success) return false;
    const Vec3 l = eig.eigenvalues();
    if (!(l.minCoeff() > 0.0)) return false;
    const Mat3 &N = eig.eigenvectors();
    lnb.setZero();
    L.setZero();
    for (int a = 0; a < 3; ++a) {
      lnb += std::log(l(a)) * N.col(a) * N.col(a).transpose();
      for (int c = 0; c < 3; ++c) {
        const Mat3 Nac = N.col(a) * N.col(c).transpose();
        L += log_divided(l(a), l(c)) * outer(Nac, Nac);
      }
    }
    return L.allFinite();
  }

  // SMALL: D = dsigma/de : dsym(F)/dF, e the trial strain from the history s
  inline bool small_tangent_from(const Lame &m, const FlowLaw &fl, double f, double eth,
                                 const Mat3 &F, const double *s, Tangent9 &D)
  {
    const Mat3 I = Mat3::Identity();
    const Mat3 e = 0.5 * (F + F.transpose()) - I - load_sym(s + Hist::PLASTIC) - eth * I;
    Mat3 sigma;
    if (!return_tangent(m, fl, f, s, e, D, sigma)) return false;
    D = D * sym_identity();
    return D.allFinite();
  }

  /* HENCKY: chain rule through b_e = F A F^T (A = C_p^-1 of the history s),
     e = ln(b_e)/2 - lth I, tau(e) and P = tau F^-T (lth = ln(1 + eth)). */
  inline bool hencky_tangent_from(const Lame &m, const FlowLaw &fl, double f, double lth,
                                  const Mat3 &F, const double *s, Tangent9 &D)
  {
    // kinematic hardening is small strain only (the pair style refuses it)
    if (fl.Hkin != 0.0 || !F.allFinite() || !(F.determinant() > 0.0)) return false;
    const Sym3 A3 = plus_identity(load_sym3(s + Hist::PLASTIC), 1.0);
    const Mat3 A = mat_of(A3), be = mat_of(congruence(F, A3));
    Mat3 lnb, tau;
    Tangent9 L, De;
    if (!log_tangent(be, lnb, L)) return false;
    if (!return_tangent(m, fl, f, s, 0.5 * lnb - lth * Mat3::Identity(), De, tau)) return false;
    const Mat3 Finv = F.inverse(), P = tau * Finv.transpose();
    const Mat3 FA = F * A, AFt = A * F.transpose();
    // B = db_e/dF, R: dtau -> dtau F^-T, G: d(F^-T)/dF at fixed tau
    Tangent9 B, R, G;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l) {
            B(3 * i + j, 3 * k + l) = (i == k ? AFt(l, j) : 0.0) + (j == k ? FA(i, l) : 0.0);
            R(3 * i + j, 3 * k + l) = i == k ? Finv(j, l) : 0.0;
            G(3 * i + j, 3 * k + l) = -P(i, l) * Finv(j, k);
          }
    D = R * (De * (0.5 * L) * B) + G;
    return D.allFinite();
  }

}    // namespace detail

/* dP/dF of detail::point_core (law SMALL or HENCKY; 3D, and plane strain,
   whose point is the 3D one) at F from the history s, as point_core
   returns it: the flow stress's factor env1's (FlowLaw::factor of s's rate
   and temperature where env1 has none).  A bond-associated bond's return
   is this one (nospd_bond_history.h).  False where there is none. */
inline bool core_tangent(Law law, const Lame &m, const FlowLaw &fl, const ThermalLaw &th,
                         const PointEnv &env1, const Mat3 &F, const double *s, Tangent9 &D)
{
  if (law != Law::SMALL && law != Law::HENCKY) return false;
  const double T = env1.T_base + s[Hist::HEAT];
  const double f = env1.has_factor ? env1.factor
                                   : fl.factor(env1.dt > 0.0 ? s[Hist::RATE] : 0.0, T);
  // point_core's thermal strain and its limits
  const double eth = th.alpha * (T - th.T_ref);
  if (law == Law::SMALL) {
    if (!(std::abs(eth) < 1.0)) return false;
    return detail::small_tangent_from(m, fl, f, eth, F, s, D);
  }
  if (!(eth > -1.0) || !std::isfinite(eth)) return false;
  return detail::hencky_tangent_from(m, fl, f, std::log1p(eth), F, s, D);
}

/* dP/dF of inelastic_point_3d at F from hn: the return from the history
   the step starts from (relaxed onto a moved Johnson-Cook surface) at the
   factor of hn's rate and temperature.  False where there is none. */
inline bool j2_tangent(Law law, const Lame &m, const FlowLaw &fl, const ThermalLaw &th,
                       const PointEnv &env, const Mat3 &F, const double *hn, Tangent9 &D)
{
  if (law != Law::SMALL && law != Law::HENCKY) return false;
  const PointEnv env1 = detail::frozen_env(fl, env, hn);
  double hr[Hist::SIZE], released;
  const double *s = detail::relaxed_start(law, m, fl, th, env1, hn, hr, released);
  return core_tangent(law, m, fl, th, env1, F, s, D);
}

}    // namespace NOSPD

#endif

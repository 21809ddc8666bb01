/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Inelastic material points: J2 (von Mises) plasticity with isotropic
   (linear, power-law, Johnson-Cook) and linear kinematic hardening,
   thermal eigenstrain, adiabatic heating and Johnson-Cook failure.
   Knows nothing of LAMMPS.

   Two kinematic settings share one radial return:
   - SMALL: additive split eps = eps_e + eps_p + eps_th, eps = sym(F) - I,
     P = sigma (the package's small-strain convention);
   - HENCKY: multiplicative F = F_e F_th F_p with a logarithmic elastic
     strain (Simo 1992; de Souza Neto, Peric & Owen 2008, ch. 14).  The
     return acts on e = ln V_e of the trial elastic left Cauchy-Green
     tensor b_e = F C_p^-1 F^T, coaxial with it, so the model is objective
     by construction and reduces to the Hencky hyperelastic law while
     elastic.  ln b_e and exp come from their series where b_e is near
     isotropic (log_spd_near_isotropic: a metal's elastic distortion; a
     third of the cost of an eigen-solve), else from b_e's eigenpairs.

   The return is backward Euler; the flow stress of the increment is
   sigma_y(a_n + da, rate_n, T_n): temperature and history of the last
   accepted step (isothermal split), and the equivalent deviatoric strain
   rate of that step, sqrt(2/3 dev D : dev D) with D from the change of F
   over the step (lagged by one step; the total rate, as explicit codes
   take for the Johnson-Cook rate term, because it is continuous where the
   plastic rate jumps between yielding and elastic steps).  With the rate
   and temperature frozen over the step the return is an exact
   minimization (closed form for linear hardening), and the surface a step
   starts from moves only as much as the strain rate changes between two
   steps: the explicit step then nearly conserves energy as it does for
   rate-independent flow.

   Energy: the stored energy W_e(eps_e) goes to pe.  The plastic work of the
   increment is the increment of the incremental potential,
       dD = int_{a_n}^{a_n+da} sigma_y da' + dpsi_kin,
   whose derivative with respect to the strain is the returned stress: the
   force on a body is then minus the gradient of sum V (W_e + dD) with the
   history of the step frozen, so velocity Verlet conserves ke + pe + D to
   the same order as it conserves an elastic body's energy, and minimize
   sees a consistent energy (the closest-point return is the minimizer).
------------------------------------------------------------------------- */

#ifndef NOSPD_PLASTICITY_H
#define NOSPD_PLASTICITY_H

#include "nospd_constitutive.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace NOSPD {

// Per-point history: all zero is the virgin state.
namespace Hist {
  constexpr int PLASTIC = 0;    // 6: eps_p (SMALL) or C_p^-1 - I (HENCKY): xx yy zz xy xz yz
  constexpr int EQPS = 6;       // equivalent plastic strain
  constexpr int BACK = 7;       // 6: back stress (SMALL, kinematic hardening)
  constexpr int WORK = 13;      // plastic work per unit reference volume
  constexpr int HEAT = 14;      // temperature rise from adiabatic heating
  constexpr int DAMAGE = 15;    // Johnson-Cook damage sum(d eps_p / eps_f)
  constexpr int YIELDING = 16;  // 1 if the last accepted increment yielded
  constexpr int FPREV = 17;     // 9: F - I of the accepted step (row-major)
  constexpr int PACC = 26;      // 9: P of the accepted step
  constexpr int WACC = 35;      // W_e of the accepted step
  constexpr int TACC = 36;      // user temperature of the accepted step
  constexpr int VALID = 37;     // 1 once PACC, WACC, TACC hold an accepted state
  constexpr int RATE = 38;      // equivalent deviatoric strain rate of the step
  constexpr int SIZE = 39;
}    // namespace Hist

enum class Hardening { LINEAR, POWER, JOHNSON_COOK };

// Flow stress sigma_y(a, rate, T) and its derivatives.
struct FlowLaw {
  bool active = false;
  Hardening kind = Hardening::LINEAR;
  double sigma_y0 = 0.0;    // initial yield (LINEAR, POWER); A (JOHNSON_COOK)
  double H = 0.0;           // LINEAR: sigma_y0 + H a
  double K = 0.0, n = 1.0;  // POWER: sigma_y0 + K a^n;  JOHNSON_COOK: B = K, n
  double Hkin = 0.0;        // linear kinematic (Prager) modulus, SMALL only
  double C = 0.0, rate0 = 1.0, m = 1.0, T_ref = 293.0, T_melt = 1.0e300;    // Johnson-Cook

  // Johnson-Cook homologous temperature, clamped to [0, 1]
  double homologous(double T) const
  {
    if (kind != Hardening::JOHNSON_COOK) return 0.0;
    return std::min(1.0, std::max(0.0, (T - T_ref) / (T_melt - T_ref)));
  }

  // strain part of the flow stress and its slope d/da
  double hardening(double a, double &slope) const
  {
    switch (kind) {
      case Hardening::LINEAR:
        slope = H;
        return sigma_y0 + H * a;
      case Hardening::POWER:
      case Hardening::JOHNSON_COOK:
        if (a <= 0.0) {
          slope = (n < 1.0) ? 1.0e300 : (n == 1.0 ? K : 0.0);
          return sigma_y0;
        }
        const double an = std::pow(a, n);
        slope = K * n * an / a;
        return sigma_y0 + K * an;
    }
    slope = 0.0;
    return sigma_y0;
  }

  // rate factor 1 + C ln(rate/rate0), 1 below the reference rate
  double rate_factor(double rate, double &slope) const
  {
    slope = 0.0;
    if (kind != Hardening::JOHNSON_COOK || C == 0.0 || !(rate > rate0)) return 1.0;
    slope = C / rate;
    return 1.0 + C * std::log(rate / rate0);
  }

  double thermal_factor(double T) const
  {
    if (kind != Hardening::JOHNSON_COOK) return 1.0;
    const double Ts = homologous(T);
    return Ts > 0.0 ? 1.0 - std::pow(Ts, m) : 1.0;
  }

  // the factor of rate and temperature, sigma_y = factor * hardening: one
  // power and one logarithm, which a return takes once (a bond-associated
  // family once for all its bonds, which share its rate and temperature)
  double factor(double rate, double T) const
  {
    double sr;
    return thermal_factor(T) * rate_factor(rate, sr);
  }

  // sigma_y(a) at a given factor, and its slope d/da
  double flow_at(double a, double f, double &slope) const
  {
    double sh;
    const double h = hardening(a, sh);
    slope = f * sh;
    return f * h;
  }

  // int_0^d sigma_y(a_n + s, rate, T) ds, in closed form
  double work(double a_n, double d, double rate, double T) const
  {
    return work_at(a_n, d, factor(rate, T));
  }

  // the same at a given factor
  double work_at(double a_n, double d, double f) const
  {
    if (d <= 0.0) return 0.0;
    if (kind == Hardening::LINEAR) return f * (sigma_y0 * d + H * (a_n * d + 0.5 * d * d));
    // (a_n + d)^(n+1) - a_n^(n+1) without the cancellation of a small d
    const double rise = a_n > 0.0
        ? std::pow(a_n, n + 1.0) * std::expm1((n + 1.0) * std::log1p(d / a_n))
        : std::pow(d, n + 1.0);
    return f * (sigma_y0 * d + K / (n + 1.0) * rise);
  }
};

// Thermal expansion, adiabatic heating and Johnson-Cook failure of a type.
struct ThermalLaw {
  double alpha = 0.0;      // linear expansion coefficient
  double T_ref = 293.0;    // temperature of zero thermal strain
  double cp = 0.0;         // specific heat; 0: no adiabatic heating
  double chi = 0.9;        // Taylor-Quinney fraction
  bool failure = false;    // Johnson-Cook failure model
  double D[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
  // last (restarts before layout 5 end here): conduction for fix nospd/heat
  double k = 0.0;          // conductivity; 0: none
  double c = 0.0;          // its specific heat capacity
};

// What the point needs from its surroundings.
struct PointEnv {
  // time step of the increment, for the strain rate; 0: quasi-static (a
  // minimize step), where the Johnson-Cook rate term is off
  double dt = 0.0;
  double T_base = 0.0;    // temperature set by the user (adiabatic rise is added)
  double rho = 0.0;       // mass density (heating)
  // FlowLaw::factor of the history's rate and temperature, if the caller
  // has it (has_factor); else the return computes it
  bool has_factor = false;
  double factor = 1.0;
};

// BAD_TEMPERATURE: the thermal stretch 1 + alpha (T - T_ref) is not
// positive (Hencky) or the thermal strain not below 1 (small strain)
enum class ReturnStatus { OK, NO_CONVERGENCE, BAD_DEFORMATION, BAD_TEMPERATURE };

namespace detail {

  /* Radial return of the deviatoric trial stress eta = s_trial - beta_n:
     solves q - (3 mu + Hkin) d - sigma_y(a_n + d) = 0 for d >= 0 by
     Newton's method kept inside a shrinking bracket [lo, hi].  Returns
     false if it does not converge. */
  inline bool solve_return(const FlowLaw &fl, double mu, double q, double a_n, double f,
                           double sy0, double slope0, double &d)
  {
    const double g3 = 3.0 * mu + fl.Hkin;
    double lo = 0.0, hi = q / g3;    // r(lo) > 0 >= r(hi) since sigma_y >= 0
    if (fl.kind == Hardening::LINEAR) {
      d = (q - sy0) / (g3 + f * fl.H);
      return std::isfinite(d);
    }
    const double scale = std::max(q, 1.0e-300);
    // rate and temperature are frozen (their factor f): one power a step
    auto flow = [&](double dd, double &slope) { return fl.flow_at(a_n + dd, f, slope); };
    // after the first yield, start from the linearization at d = 0 (one
    // Newton step; sy0 and slope0 are the flow stress and slope there):
    // the increments of a time step are small, and it lands close to the
    // root (at a_n = 0 the slope may be infinite: mid-bracket)
    d = 0.5 * hi;
    if (a_n > 0.0) {
      const double r0 = q - sy0;
      const double d0 = r0 / (g3 + slope0);
      if (d0 > lo && d0 < hi) d = d0;
    }
    for (int it = 0; it < 200; ++it) {
      double slope;
      const double r = q - g3 * d - flow(d, slope);
      if (std::abs(r) <= 1.0e-14 * scale || (hi - lo) <= 1.0e-16 * hi) return true;
      if (r > 0.0) lo = d;
      else hi = d;
      const double dr = -g3 - slope;
      double next = (std::isfinite(dr) && dr < 0.0) ? d - r / dr : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      d = next;
    }
    return false;
  }

  // Johnson-Cook failure strain at triaxiality sstar, rate and temperature
  inline double failure_strain(const ThermalLaw &th, const FlowLaw &fl, double sstar,
                               double rate, double T)
  {
    const double *D = th.D;
    double ef = D[0] + D[1] * std::exp(D[2] * sstar);
    const double rs = (fl.rate0 > 0.0) ? rate / fl.rate0 : 0.0;
    if (rs > 1.0) ef *= 1.0 + D[3] * std::log(rs);
    if (fl.kind == Hardening::JOHNSON_COOK) ef *= 1.0 + D[4] * fl.homologous(T);
    return std::max(ef, 1.0e-12);
  }

  /* The common part of both kinematic settings: given the trial elastic
     strain e (tensor; for HENCKY a diagonal tensor of principal log
     strains), return the elastic strain, stress (Cauchy for SMALL,
     Kirchhoff for HENCKY), the plastic increment and the history. */
  inline bool return_map(const Lame &m, const FlowLaw &fl, const ThermalLaw &th,
                         const PointEnv &env, const double *hn, double *h1, Mat3 &e,
                         Mat3 &stress, Mat3 &dep, double &W, double &W_trial)
  {
    const Mat3 I = Mat3::Identity();
    const double T = env.T_base + hn[Hist::HEAT];
    double tr = e.trace();
    W_trial = 0.5 * m.lambda * tr * tr + m.mu * e.squaredNorm();
    stress = m.lambda * tr * I + 2.0 * m.mu * e;
    dep.setZero();
    h1[Hist::YIELDING] = 0.0;
    if (fl.active) {
      const Mat3 beta = load_sym(hn + Hist::BACK);
      const Mat3 eta = stress - (stress.trace() / 3.0) * I - beta;
      const double norm = eta.norm();
      const double q = std::sqrt(1.5) * norm;
      const double a_n = hn[Hist::EQPS];
      const double rate_n = env.dt > 0.0 ? hn[Hist::RATE] : 0.0;
      const double f = env.has_factor ? env.factor : fl.factor(rate_n, T);
      double s0;
      const double sy = fl.flow_at(a_n, f, s0);
      if (q > sy && norm > 0.0) {
        double d = 0.0;
        if (!solve_return(fl, m.mu, q, a_n, f, sy, s0, d) || !(d >= 0.0)) return false;
        const Mat3 N = (1.5 / q) * eta;    // flow direction, dep = d N, |N| = sqrt(3/2)
        dep = d * N;
        e -= dep;
        stress -= 2.0 * m.mu * dep;
        const Mat3 beta1 = beta + (2.0 / 3.0) * fl.Hkin * dep;
        store_sym(beta1, h1 + Hist::BACK);
        h1[Hist::EQPS] = a_n + d;
        h1[Hist::YIELDING] = 1.0;
        // plastic work: flow-stress integral plus the change of the
        // kinematic stored energy (3/4) |beta|^2 / Hkin
        double dD = fl.work_at(a_n, d, f);
        if (fl.Hkin > 0.0)
          dD += 0.75 * (beta1.squaredNorm() - beta.squaredNorm()) / fl.Hkin;
        h1[Hist::WORK] = hn[Hist::WORK] + dD;
        if (th.cp > 0.0 && env.rho > 0.0)
          h1[Hist::HEAT] = hn[Hist::HEAT] + th.chi * dD / (env.rho * th.cp);
        if (th.failure) {
          const double seq = von_mises(stress);
          const double sstar = seq > 0.0 ? stress.trace() / (3.0 * seq) : 0.0;
          h1[Hist::DAMAGE] = hn[Hist::DAMAGE] + d / failure_strain(th, fl, sstar, rate_n, T);
        }
      }
    }
    tr = e.trace();
    W = 0.5 * m.lambda * tr * tr + m.mu * e.squaredNorm();
    return std::isfinite(W);
  }

}    // namespace detail

namespace detail {
inline ReturnStatus point_core(Law law, const Lame &m, const FlowLaw &fl, const ThermalLaw &th,
                               const PointEnv &env, const Mat3 &F, const double *hn, double *h1,
                               Mat3 &P, double &W, double &W_trial)
{
  const Mat3 I = Mat3::Identity();
  for (int k = 0; k < Hist::SIZE; ++k) h1[k] = hn[k];
  const double T = env.T_base + hn[Hist::HEAT];
  const double eth = th.alpha * (T - th.T_ref);
  // (the log of a non-positive stretch; a "small" strain of 100 % or more)
  if (!(std::abs(eth) < 1.0) && (law == Law::SMALL || !(eth > -1.0) || !std::isfinite(eth)))
    return ReturnStatus::BAD_TEMPERATURE;

  if (law == Law::SMALL) {
    const Mat3 eps = 0.5 * (F + F.transpose()) - I;
    const Mat3 ep_n = load_sym(hn + Hist::PLASTIC);
    Mat3 e = eps - ep_n - eth * I;
    Mat3 sigma, dep;
    if (!return_map(m, fl, th, env, hn, h1, e, sigma, dep, W, W_trial))
      return ReturnStatus::NO_CONVERGENCE;
    store_sym(ep_n + dep, h1 + Hist::PLASTIC);
    P = sigma;
    return ReturnStatus::OK;
  }

  // HENCKY: trial b_e = F C_p^-1 F^T; e = ln V_e - ln(1 + alpha dT) I
  const double J = F.determinant();
  if (!(J > 0.0) || !F.allFinite()) return ReturnStatus::BAD_DEFORMATION;
  const Sym3 be = congruence(F, plus_identity(load_sym3(hn + Hist::PLASTIC), 1.0));
  const double lth = std::log1p(eth);    // log of the thermal stretch 1 + alpha dT
  const Mat3 Finv = F.inverse();
  Mat3 tau, dep;
  Sym3 lnb;
  if (log_spd_near_isotropic(be, lnb)) {
    // near-isotropic b_e (any metal's elastic distortion): e, tau and the
    // new b_e as tensors, coaxial with b_e, no eigenvectors needed
    Mat3 e = 0.5 * mat_of(lnb) - lth * I;
    if (!return_map(m, fl, th, env, hn, h1, e, tau, dep, W, W_trial))
      return ReturnStatus::NO_CONVERGENCE;
    P = tau * Finv.transpose();
    if (fl.active && h1[Hist::YIELDING] > 0.0) {
      // the new b_e = exp(2 (e - dep + ln(1 + alpha dT) I)) = b_e exp(-2 dep),
      // dep coaxial with the trial b_e (isotropic hardening: dep is along
      // dev e); |2 dep| <= 2 |dev e| <= 0.11 where b_e is within the
      // series' bound, inside exp_sym_small's
      Sym3 X;
      if (!exp_sym_small(scaled(sym_of(dep), -2.0), X)) return ReturnStatus::BAD_DEFORMATION;
      store_sym(plus_identity(congruence(Finv, mul_commuting(be, X)), -1.0), h1 + Hist::PLASTIC);
    }
    return P.allFinite() ? ReturnStatus::OK : ReturnStatus::BAD_DEFORMATION;
  }
  // otherwise in b_e's principal frame, where e and tau stay diagonal
  Eigen::SelfAdjointEigenSolver<Mat3> eig(mat_of(be));
  if (eig.info() != Eigen::Success) return ReturnStatus::BAD_DEFORMATION;
  const Vec3 lam2 = eig.eigenvalues();
  if (!(lam2.minCoeff() > 0.0)) return ReturnStatus::BAD_DEFORMATION;
  const Mat3 &Nv = eig.eigenvectors();
  Mat3 e = Mat3::Zero();
  for (int a = 0; a < 3; ++a) e(a, a) = 0.5 * std::log(lam2(a)) - lth;
  if (!return_map(m, fl, th, env, hn, h1, e, tau, dep, W, W_trial))
    return ReturnStatus::NO_CONVERGENCE;
  Mat3 tau_s = Mat3::Zero(), be1 = Mat3::Zero();
  for (int a = 0; a < 3; ++a) {
    tau_s(a, a) = tau(a, a);
    be1(a, a) = std::exp(2.0 * (e(a, a) + lth));
  }
  P = (Nv * tau_s * Nv.transpose()) * Finv.transpose();
  if (fl.active && h1[Hist::YIELDING] > 0.0) {
    const Mat3 be1_g = Nv * be1 * Nv.transpose();
    store_sym(Finv * be1_g * Finv.transpose() - I, h1 + Hist::PLASTIC);
  }
  return P.allFinite() ? ReturnStatus::OK : ReturnStatus::BAD_DEFORMATION;
}
}    // namespace detail

/* Equivalent deviatoric strain rate sqrt(2/3) |dev D| of the step from the
   accepted F (hn's FPREV) to F over dt (0 if dt is 0). */
inline double strain_rate(Law law, const Mat3 &F, const double *hn, double dt)
{
  if (!(dt > 0.0)) return 0.0;
  const Mat3 dF = F - Mat3::Identity() - load(hn + Hist::FPREV);
  const Mat3 L = (law == Law::SMALL) ? dF : Mat3(dF * F.inverse());
  Mat3 D = 0.5 * (L + L.transpose());
  D -= (D.trace() / 3.0) * Mat3::Identity();
  return std::sqrt(2.0 / 3.0) * D.norm() / dt;
}

namespace detail {
  // both returns of a step start from hn's rate and temperature: their
  // FlowLaw::factor, once (the step's own rate goes to the new history only)
  inline PointEnv frozen_env(const FlowLaw &fl, const PointEnv &env, const double *hn)
  {
    PointEnv env1 = env;
    if (fl.active && !env1.has_factor) {
      env1.has_factor = true;
      env1.factor = fl.factor(env.dt > 0.0 ? hn[Hist::RATE] : 0.0, env.T_base + hn[Hist::HEAT]);
    }
    return env1;
  }

  /* The history a step starts from: hn, or (Johnson-Cook) hn returned onto
     the surface of env1's factor at its own accepted F, written to hr, with
     the elastic energy that relaxation releases.  A function of hn and env
     alone, not of the step's F. */
  inline const double *relaxed_start(Law law, const Lame &m, const FlowLaw &fl,
                                     const ThermalLaw &th, const PointEnv &env1, const double *hn,
                                     double *hr, double &released)
  {
    released = 0.0;
    if (!fl.active || fl.kind != Hardening::JOHNSON_COOK) return hn;
    Mat3 Pr;
    double Wr, Wtr;
    const Mat3 Fa = Mat3::Identity() + load(hn + Hist::FPREV);
    if (point_core(law, m, fl, th, env1, Fa, hn, hr, Pr, Wr, Wtr) != ReturnStatus::OK ||
        !(hr[Hist::YIELDING] > 0.0))
      return hn;
    released = Wtr - Wr;
    // booked after the step, so that the step's thermal strain and flow
    // stress take the lagged heat as every other step does
    hr[Hist::WORK] = hn[Hist::WORK];
    hr[Hist::HEAT] = hn[Hist::HEAT];
    return hr;
  }
}    // namespace detail

/* One material point in 3D: P and the stored energy W_e from F and the
   history of the start of the step hn; writes the history of the end of
   the step to h1 (hn is never modified, so trial evaluations repeat
   exactly).  law is SMALL or HENCKY.

   A Johnson-Cook yield surface moves between steps (rate and temperature):
   the accepted state of the last step may lie outside the surface the new
   increment starts from.  It is first returned onto that surface at its own
   configuration (the accepted F): at fixed F no work is done, so all the
   elastic energy the relaxation releases, W_trial - W, is dissipated (and
   heats the point), and the step's increment starts from the relaxed
   history.  A step that then unloads is elastic from the relaxed state, so
   ke + pe + plastic work books no dissipation the stress did not undergo. */
inline ReturnStatus inelastic_point_3d(Law law, const Lame &m, const FlowLaw &fl,
                                       const ThermalLaw &th, const PointEnv &env, const Mat3 &F,
                                       const double *hn, double *h1, Mat3 &P, double &W)
{
  const PointEnv env1 = detail::frozen_env(fl, env, hn);
  double hr[Hist::SIZE];
  double released;
  const double *start = detail::relaxed_start(law, m, fl, th, env1, hn, hr, released);
  double W_trial;
  const ReturnStatus st = detail::point_core(law, m, fl, th, env1, F, start, h1, P, W, W_trial);
  if (st != ReturnStatus::OK) return st;
  h1[Hist::RATE] = strain_rate(law, F, hn, env.dt);
  if (released > 0.0) {
    h1[Hist::WORK] += released;
    if (th.cp > 0.0 && env.rho > 0.0) h1[Hist::HEAT] += th.chi * released / (env.rho * th.cp);
    h1[Hist::YIELDING] = 1.0;
  }
  store(F - Mat3::Identity(), h1 + Hist::FPREV);
  return ReturnStatus::OK;
}

/* The same under the plane assumption (plane stress solves F33 for P33 = 0
   with the history of the step start, as the elastic laws do).

   At the configuration and temperature of the accepted step itself (to
   1e-12 in F) the point returns the accepted state: the force evaluation
   that starts a run, or a run 0 after one, then gives the forces of the
   step that was accepted there.  Re-running the return from the accepted
   history would not, for a rate-dependent flow stress (the zero increment
   has no rate), and a run continued from a restart would leave the path
   of the uninterrupted run. */
inline ReturnStatus inelastic_point(Law law, Plane plane, const Lame &m, const FlowLaw &fl,
                                    const ThermalLaw &th, const PointEnv &env, Mat3 &F,
                                    const double *hn, double *h1, Mat3 &P, double &W)
{
  if (hn[Hist::VALID] > 0.0 && hn[Hist::TACC] == env.T_base) {
    const Mat3 Fa = Mat3::Identity() + load(hn + Hist::FPREV);
    Mat3 d = F - Fa;
    if (plane == Plane::STRESS) d(2, 2) = 0.0;
    if (d.cwiseAbs().maxCoeff() <= 1.0e-12) {
      for (int k = 0; k < Hist::SIZE; ++k) h1[k] = hn[k];
      if (plane == Plane::STRESS) F(2, 2) = Fa(2, 2);
      P = load(hn + Hist::PACC);
      W = hn[Hist::WACC];
      return ReturnStatus::OK;
    }
  }
  ReturnStatus st = ReturnStatus::OK;
  if (plane != Plane::STRESS) {
    st = inelastic_point_3d(law, m, fl, th, env, F, hn, h1, P, W);
  } else {
    auto eval = [&](const Mat3 &Ft, Mat3 &Pt, double &Wt) {
      st = inelastic_point_3d(law, m, fl, th, env, Ft, hn, h1, Pt, Wt);
      return st == ReturnStatus::OK;
    };
    if (!solve_plane_stress(m, F, P, W, eval) && st == ReturnStatus::OK)
      st = ReturnStatus::NO_CONVERGENCE;
  }
  if (st != ReturnStatus::OK) return st;
  store(P, h1 + Hist::PACC);
  h1[Hist::WACC] = W;
  h1[Hist::TACC] = env.T_base;
  h1[Hist::VALID] = 1.0;
  return ReturnStatus::OK;
}

}    // namespace NOSPD

#endif

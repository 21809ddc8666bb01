/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the Drucker-Prager material point
   (nospd_drucker_prager.h), without LAMMPS.

   References derived here from the equations, not from the return: the
   triaxial compression response in closed form (a fixed flow direction
   and linear hardening make it linear in the plastic multiplier), elastic
   unloading, the apex state from the yield condition and elasticity, the
   consistent tangent against central differences, the incremental
   potential's gradient (associative flow), frame indifference (Hencky).
------------------------------------------------------------------------- */

#include "nospd_drucker_prager.h"
#include "secant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace NOSPD;

namespace {

// a concrete-like material
constexpr double E = 30.0e9, NU = 0.2, C0 = 5.0e6, HC = 2.0e9;
const double PHI = 30.0 * M_PI / 180.0;

struct DPPoint {
  Lame m = Lame::from_young(E, NU);
  DruckerPrager dp;
  bool hencky = false;
  std::vector<double> h = std::vector<double>(Hist::SIZE, 0.0);
  Mat3 step(const Mat3 &F, double &W, bool commit = true, Tangent9 *D = nullptr)
  {
    std::vector<double> h1(Hist::SIZE);
    Mat3 P;
    const ReturnStatus st = hencky ? drucker_prager_hencky(m, dp, F, h.data(), h1.data(), P, W)
                                   : drucker_prager_small(m, dp, F, h.data(), h1.data(), P, W, D);
    EXPECT_EQ(st, ReturnStatus::OK);
    if (commit) h = h1;
    return P;
  }
};

Mat3 diag(double a, double b, double c)
{
  Mat3 F = Mat3::Zero();
  F(0, 0) = 1.0 + a;
  F(1, 1) = 1.0 + b;
  F(2, 2) = 1.0 + c;
  return F;
}

/* Axial strain e1 with the lateral stress held at sl (secant on the
   lateral strain: the lateral stress is piecewise linear in it, so the
   iteration ends exact); the step is committed.  Returns the axial stress. */
double triaxial(DPPoint &pt, double e1, double sl, double &e2)
{
  auto lateral = [&](double x) {
    double W;
    return pt.step(diag(e1, x, x), W, false)(1, 1) - sl;
  };
  e2 = secant_root(lateral, e2, e2 + 1e-7, 1e-12 * std::abs(sl), 60);
  double W;
  return pt.step(diag(e1, e2, e2), W)(0, 0);
}

/* Triaxial compression (sigma2 = sigma3 = -pc, sigma1 < sigma3) in closed
   form.  On the surface, with q = (sigma3 - sigma1)/sqrt(3) and
   p = (sigma1 + 2 sigma3)/3:
       sigma1(g) = (xi c(xi g) - sigma3 (1/sqrt3 + 2 eta/3)) / (eta/3 - 1/sqrt3)
   and the flow direction s/(2q) + eta_bar/3 I has the axial component
   a1 = -1/sqrt3 + eta_bar/3, so
       eps1(g) = (sigma1(g) - 2 nu sigma3)/E + a1 g,
   linear in g: solved for g at a given eps1. */
double triaxial_exact(const DruckerPrager &dp, double pc, double e1)
{
  const double r3 = std::sqrt(3.0), s3 = -pc;
  const double den = dp.eta / 3.0 - 1.0 / r3;
  const double S0 = (dp.xi * dp.c0 - s3 * (1.0 / r3 + 2.0 * dp.eta / 3.0)) / den;
  const double S1 = dp.xi * dp.xi * dp.H / den;
  const double a1 = -1.0 / r3 + dp.eta_bar / 3.0;
  const double elastic = s3 + E * (e1 - s3 * (1.0 - 2.0 * NU) / E);    // sigma1 while elastic
  if (elastic >= S0) return elastic;
  const double g = (e1 - (S0 - 2.0 * NU * s3) / E) / (S1 / E + a1);
  return S0 + S1 * g;
}

void check_triaxial(double psi_deg, double pc)
{
  DPPoint pt;
  pt.dp = DruckerPrager::from_angles(PHI, psi_deg * M_PI / 180.0, C0, HC);
  const double e0 = -pc * (1.0 - 2.0 * NU) / E;    // the confined state
  double e2 = e0;
  double peak = 0.0, e_peak = 0.0;
  int plastic = 0;
  for (int k = 0; k <= 40; ++k) {
    const double e1 = e0 - 1.0e-4 * k;
    const double s1 = triaxial(pt, e1, -pc, e2);
    const double exact = triaxial_exact(pt.dp, pc, e1);
    EXPECT_NEAR(s1, exact, 1e-10 * std::abs(exact)) << "step " << k;
    if (pt.h[Hist::YIELDING] > 0.0) plastic++;
    peak = s1;
    e_peak = e1;
  }
  EXPECT_GT(plastic, 10) << "the path must yield";
  EXPECT_GT(pt.h[Hist::EQPS], 0.0);
  // unloading: elastic at Young's slope from the peak
  for (int k = 1; k <= 5; ++k) {
    const double e1 = e_peak + 2.0e-5 * k;
    const double s1 = triaxial(pt, e1, -pc, e2);
    EXPECT_NEAR(s1, peak + E * (e1 - e_peak), 1e-10 * std::abs(peak)) << "unloading " << k;
    EXPECT_EQ(pt.h[Hist::YIELDING], 0.0);
  }
}

TEST(DruckerPrager, TriaxialCompressionAssociative)
{
  for (double pc : {1.0e6, 20.0e6}) check_triaxial(30.0, pc);
}

TEST(DruckerPrager, TriaxialCompressionNonAssociative)
{
  for (double pc : {1.0e6, 20.0e6}) check_triaxial(10.0, pc);
}

// The closed form itself: a higher confinement raises the strength, and
// without hardening the cone through the compression meridian gives
// Mohr-Coulomb's triaxial strength there.
TEST(DruckerPrager, ConfinementRaisesStrength)
{
  const DruckerPrager dp = DruckerPrager::from_angles(PHI, PHI, C0, 0.0);
  const double low = triaxial_exact(dp, 1e6, -0.01), high = triaxial_exact(dp, 20e6, -0.01);
  EXPECT_LT(high, low);
  // Mohr-Coulomb on the compression meridian (the cone's match):
  // sigma1 = -(2 c cos(phi) + pc (1 + sin(phi))) / (1 - sin(phi))
  for (double pc : {1e6, 20e6}) {
    const double mc = -(2.0 * C0 * std::cos(PHI) + pc * (1.0 + std::sin(PHI))) / (1.0 - std::sin(PHI));
    EXPECT_NEAR(triaxial_exact(dp, pc, -0.01), mc, 1e-9 * std::abs(mc)) << pc;
  }
}

/* Hydrostatic tension beyond the apex: the state returns to s = 0 and
   p = beta c(a), a = a_n + alpha d eps_v^p, p = K (eps_v - d eps_v^p):
   two linear equations, solved here. */
TEST(DruckerPrager, ApexReturn)
{
  for (double psi_deg : {30.0, 15.0}) {
    DPPoint pt;
    pt.dp = DruckerPrager::from_angles(PHI, psi_deg * M_PI / 180.0, C0, HC);
    const double K = pt.m.lambda + 2.0 * pt.m.mu / 3.0;
    const double ev = 3.0 * 4e-3;
    double W;
    const Mat3 P = pt.step(diag(4e-3, 4e-3, 4e-3), W);
    const double alpha = pt.dp.xi / pt.dp.eta_bar, beta = pt.dp.xi / pt.dp.eta;
    // p = K (ev - x) = beta (c0 + H alpha x)
    const double x = (K * ev - beta * C0) / (K + beta * HC * alpha);
    const double p = K * (ev - x);
    EXPECT_EQ(pt.h[Hist::YIELDING], static_cast<double>(DPMode::APEX));
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(P(a, a), p, 1e-12 * p);
    EXPECT_NEAR(P(0, 1), 0.0, 1e-12 * p);
    EXPECT_NEAR(pt.h[Hist::EQPS], alpha * x, 1e-12 * alpha * x);
    // a deviatoric trial beyond the apex returns there as well
    DPPoint q = pt;
    q.h.assign(Hist::SIZE, 0.0);
    Mat3 F = diag(4e-3, 4e-3, 4e-3);
    F(0, 1) = F(1, 0) = 1e-5;
    const Mat3 Pq = q.step(F, W);
    EXPECT_EQ(q.h[Hist::YIELDING], static_cast<double>(DPMode::APEX));
    EXPECT_NEAR((Pq - Pq.trace() / 3.0 * Mat3::Identity()).norm(), 0.0, 1e-12 * p);
  }
  // no dilatancy: no plastic volume change can bring the trial back
  DPPoint none;
  none.dp = DruckerPrager::from_angles(PHI, 0.0, C0, HC);
  std::vector<double> h1(Hist::SIZE);
  Mat3 P;
  double W;
  EXPECT_EQ(drucker_prager_small(none.m, none.dp, diag(4e-3, 4e-3, 4e-3), none.h.data(),
                                 h1.data(), P, W),
            ReturnStatus::NO_CONVERGENCE);
}

/* The consistent tangent dP/dF against central differences of the
   return from the same history, in each mode (elastic, cone, apex). */
TEST(DruckerPrager, ConsistentTangent)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  struct Case {
    Mat3 F;
    DPMode mode;
  };
  Mat3 shear = diag(-1e-3, 2e-4, 3e-4);
  shear(0, 1) = 8e-4;
  shear(1, 0) = 2e-4;
  const std::vector<Case> cases = {{diag(-1e-5, 2e-6, 0.0), DPMode::ELASTIC},
                                   {shear, DPMode::CONE},
                                   {diag(4e-3, 4.2e-3, 3.9e-3), DPMode::APEX}};
  for (double psi_deg : {30.0, 10.0})
    for (const auto &c : cases) {
      DPPoint pt;
      pt.dp = DruckerPrager::from_angles(PHI, psi_deg * M_PI / 180.0, C0, HC);
      // a history with plastic strain: one committed plastic step first
      double W;
      Mat3 pre = diag(-6e-4, 1e-4, 1e-4);
      pre(0, 2) = pre(2, 0) = 1e-4;
      pt.step(pre, W);
      Tangent9 D;
      pt.step(c.F, W, false, &D);
      std::vector<double> h1(Hist::SIZE);
      Mat3 P;
      drucker_prager_small(pt.m, pt.dp, c.F, pt.h.data(), h1.data(), P, W);
      EXPECT_EQ(h1[Hist::YIELDING], static_cast<double>(c.mode));
      const double h = 1e-9;
      double worst = 0.0;
      for (int k = 0; k < 9; ++k) {
        Mat3 Fp = c.F, Fm = c.F;
        Fp(k / 3, k % 3) += h;
        Fm(k / 3, k % 3) -= h;
        const Mat3 Pp = pt.step(Fp, W, false), Pm = pt.step(Fm, W, false);
        for (int i = 0; i < 9; ++i) {
          const double fd = (Pp(i / 3, i % 3) - Pm(i / 3, i % 3)) / (2.0 * h);
          worst = std::max(worst, std::abs(fd - D(i, k)));
        }
      }
      EXPECT_LT(worst, 1e-6 * D.cwiseAbs().maxCoeff())
          << "mode " << static_cast<int>(c.mode) << " psi " << psi_deg;
    }
}

/* Associative flow: P is the gradient of W_e + dD (the step's incremental
   potential) at fixed history, as for J2. */
TEST(DruckerPrager, StressIsIncrementalPotentialGradient)
{
  for (const Mat3 &F : {diag(-2e-3, 4e-4, 4e-4), diag(4e-3, 4.1e-3, 3.8e-3)}) {
    DPPoint pt;
    pt.dp = DruckerPrager::from_angles(PHI, PHI, C0, HC);
    auto potential = [&](const Mat3 &Ft) {
      std::vector<double> h1(Hist::SIZE);
      Mat3 P;
      double W;
      drucker_prager_small(pt.m, pt.dp, Ft, pt.h.data(), h1.data(), P, W);
      return W + h1[Hist::WORK] - pt.h[Hist::WORK];
    };
    double W;
    const Mat3 P = pt.step(F, W, false);
    const double h = 1e-9;
    for (int k = 0; k < 9; ++k) {
      Mat3 Fp = F, Fm = F;
      Fp(k / 3, k % 3) += h;
      Fm(k / 3, k % 3) -= h;
      const double fd = (potential(Fp) - potential(Fm)) / (2.0 * h);
      EXPECT_NEAR(fd, P(k / 3, k % 3), 1e-6 * P.cwiseAbs().maxCoeff()) << k;
    }
  }
}

/* Hencky: the small-strain response in the small-strain limit, and frame
   indifference after plastic flow (P(QF) = Q P(F), same history). */
TEST(DruckerPrager, HenckyLimitAndObjectivity)
{
  DPPoint small, hencky;
  small.dp = hencky.dp = DruckerPrager::from_angles(PHI, 10.0 * M_PI / 180.0, C0, HC);
  hencky.hencky = true;
  double W;
  // a plastic step of 2e-3 axial strain: the two agree to O(strain)
  const Mat3 Fs = diag(-2e-3, 4e-4, 4e-4);
  const Mat3 Ps = small.step(Fs, W), Ph = hencky.step(Fs, W);
  EXPECT_LT((Ps - Ph).norm(), 1e-2 * Ps.norm());
  EXPECT_GT(small.h[Hist::EQPS], 0.0);
  // objectivity after flow
  Mat3 F2 = diag(-0.03, 0.01, 0.008);
  F2(0, 1) = 0.01;
  hencky.step(F2, W);
  const Mat3 F3 = diag(-0.04, 0.012, 0.01);
  const double ang = 0.7;
  Mat3 Q;
  Q << std::cos(ang), -std::sin(ang), 0.0, std::sin(ang), std::cos(ang), 0.0, 0.0, 0.0, 1.0;
  const Mat3 P3 = hencky.step(F3, W, false), PQ = hencky.step(Q * F3, W, false);
  EXPECT_LT((PQ - Q * P3).norm(), 1e-10 * P3.norm());
}

}    // namespace

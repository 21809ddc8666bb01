/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the inelastic material point
   (nospd_plasticity.h) on one point, without LAMMPS.

   Expectations come from closed forms of J2 plasticity under uniaxial
   stress (elastic slope E, plastic slope E H/(E + H), reverse yield after
   isotropic or kinematic hardening), from the definition of the
   incremental potential (P = d(W_e + dD)/dF by central differences), from
   frame indifference and from free and clamped thermal expansion.
------------------------------------------------------------------------- */

#include "nospd_plasticity.h"
#include "secant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace NOSPD;

namespace {

constexpr double E = 200.0e9, NU = 0.3, SY = 250.0e6;

struct Point {
  explicit Point(Law l) : law(l) {}
  Law law;
  Lame m = Lame::from_young(E, NU);
  FlowLaw fl;
  ThermalLaw th;
  PointEnv env;
  std::vector<double> h = std::vector<double>(Hist::SIZE, 0.0);
  double eth = 0.0;    // the thermal strain uniaxial() adds to its path

  // one increment to F; the history is committed when commit is set
  Mat3 step(const Mat3 &F, double &W, bool commit = true)
  {
    std::vector<double> h1(Hist::SIZE);
    Mat3 P;
    EXPECT_EQ(inelastic_point_3d(law, m, fl, th, env, F, h.data(), h1.data(), P, W),
              ReturnStatus::OK);
    if (commit) h = h1;
    return P;
  }
};

// axial stress measure: Cauchy (SMALL) or Kirchhoff (HENCKY) and its strain
Mat3 axial_F(Law law, double e1, double e2)
{
  Mat3 F = Mat3::Identity();
  if (law == Law::SMALL) {
    F(0, 0) += e1;
    F(1, 1) += e2;
    F(2, 2) += e2;
  } else {
    F(0, 0) = std::exp(e1);
    F(1, 1) = F(2, 2) = std::exp(e2);
  }
  return F;
}

Mat3 stress_measure(Law law, const Mat3 &F, const Mat3 &P)
{
  return law == Law::SMALL ? P : Mat3(P * F.transpose());
}

// a point with linear isotropic hardening H from the yield stress SY
Point linear_hardening_point(Law law, double H)
{
  Point pt(law);
  pt.fl.active = true;
  pt.fl.kind = Hardening::LINEAR;
  pt.fl.sigma_y0 = SY;
  pt.fl.H = H;
  return pt;
}

// F of the mechanical strains of F0 plus the point's thermal strain eth:
// eps + eth I (SMALL), a stretch 1 + eth, ln(1 + eth) in log strain (HENCKY)
Mat3 heated(const Point &pt, const Mat3 &F0)
{
  return pt.law == Law::SMALL ? Mat3(F0 + pt.eth * Mat3::Identity()) : Mat3((1.0 + pt.eth) * F0);
}

/* Uniaxial stress at axial strain e1: the lateral strain is solved so that
   the lateral stress vanishes (secant; the lateral stress is piecewise
   linear in it, so a few steps are exact), then the step is committed. */
double uniaxial(Point &pt, double e1, double &e2)
{
  auto lateral = [&](double x) {
    double W;
    const Mat3 F = heated(pt, axial_F(pt.law, e1, x));
    return stress_measure(pt.law, F, pt.step(F, W, false))(1, 1);
  };
  e2 = secant_root(lateral, e2, e2 - 1e-4 * (std::abs(e1) + 1e-6), 1e-6);
  double W;
  const Mat3 F = heated(pt, axial_F(pt.law, e1, e2));
  return stress_measure(pt.law, F, pt.step(F, W))(0, 0);
}

// a Johnson-Cook flow law (reference rate 1/s)
void set_johnson_cook(FlowLaw &fl, double A, double B, double n, double C, double m,
                      double T_ref, double T_melt)
{
  fl.active = true;
  fl.kind = Hardening::JOHNSON_COOK;
  fl.sigma_y0 = A;
  fl.K = B;
  fl.n = n;
  fl.C = C;
  fl.rate0 = 1.0;
  fl.m = m;
  fl.T_ref = T_ref;
  fl.T_melt = T_melt;
}

// The closed-form uniaxial J2 curve for linear isotropic (H) and kinematic
// (Hk) hardening along a strain path, as a small state machine.
struct UniaxialCurve {
  double H, Hk, sy;
  double eps_p = 0.0, alpha = 0.0, back = 0.0;    // axial plastic strain, eqps, axial back stress
  double stress(double eps)
  {
    const double trial = E * (eps - eps_p);
    const double xi = trial - back;
    const double f = std::abs(xi) - (sy + H * alpha);
    if (f <= 0.0) return trial;
    const double d = f / (E + H + Hk);
    const double sgn = xi > 0.0 ? 1.0 : -1.0;
    eps_p += sgn * d;
    alpha += d;
    back += sgn * Hk * d;
    return E * (eps - eps_p);
  }
};

void check_uniaxial_curve(Law law, double H, double Hk, double sy = SY, double dT = 0.0)
{
  Point pt(law);
  if (dT != 0.0) {
    // heated by dT: the mechanical strain follows the same curve
    pt.th.alpha = 1.2e-5;
    pt.th.T_ref = 293.0;
    pt.env.T_base = 293.0 + dT;
    pt.eth = 1.2e-5 * dT;
  }
  pt.fl.active = true;
  pt.fl.kind = Hardening::LINEAR;
  pt.fl.sigma_y0 = sy;
  pt.fl.H = H;
  pt.fl.Hkin = Hk;
  UniaxialCurve ref{H, Hk, sy};
  const double ey = sy / E;
  // load to 4 ey, unload and reverse to -4 ey, reload to 6 ey
  std::vector<double> path;
  for (int k = 1; k <= 40; ++k) path.push_back(0.1 * k * ey);
  for (int k = 1; k <= 80; ++k) path.push_back(4.0 * ey - 0.1 * k * ey);
  for (int k = 1; k <= 100; ++k) path.push_back(-4.0 * ey + 0.1 * k * ey);
  double e2 = 0.0, worst = 0.0;
  bool yielded_back = false;
  for (double e1 : path) {
    const double s = uniaxial(pt, e1, e2);
    const double r = ref.stress(e1);
    worst = std::max(worst, std::abs(s - r) / sy);
    if (e1 < 0.0 && pt.h[Hist::YIELDING] > 0.0) yielded_back = true;
  }
  EXPECT_LT(worst, 1e-10) << "uniaxial curve, H = " << H << ", Hk = " << Hk;
  EXPECT_TRUE(yielded_back) << "the reverse path must yield";
  EXPECT_NEAR(pt.h[Hist::EQPS], ref.alpha, 1e-10 * ref.alpha);
}

TEST(Plasticity, UniaxialLinearIsotropicSmall) { check_uniaxial_curve(Law::SMALL, 2.0e9, 0.0); }
TEST(Plasticity, UniaxialKinematicSmall) { check_uniaxial_curve(Law::SMALL, 0.0, 5.0e9); }
TEST(Plasticity, UniaxialMixedSmall) { check_uniaxial_curve(Law::SMALL, 1.0e9, 3.0e9); }
TEST(Plasticity, UniaxialPerfectlyPlasticSmall) { check_uniaxial_curve(Law::SMALL, 0.0, 0.0); }
// in log strain and Kirchhoff stress the finite-strain return is the same curve
TEST(Plasticity, UniaxialLinearIsotropicHencky) { check_uniaxial_curve(Law::HENCKY, 2.0e9, 0.0); }
// the same with elastic log strains of 0.06 (yield at E/16): b_e is then too
// far from isotropic for the series of ln b_e, and the return runs in b_e's
// principal frame once the load passes about half the yield strain
TEST(Plasticity, UniaxialLinearIsotropicHenckyLargeElasticStrain)
{
  check_uniaxial_curve(Law::HENCKY, 2.0e9, 0.0, E / 16.0);
}

// one step to 80 times the yield strain (a plastic increment of 0.1; the
// trial b_e far from isotropic, the return in its principal frame), then
// elastic unloading and reloading: all on the closed-form curve
TEST(Plasticity, UniaxialHenckyOneLargeStep)
{
  Point pt = linear_hardening_point(Law::HENCKY, 2.0e9);
  UniaxialCurve ref{2.0e9, 0.0, SY};
  const double ey = SY / E;
  double e2 = 0.0;
  for (double e1 : {80.0 * ey, 78.0 * ey, 79.5 * ey}) {
    const double s = uniaxial(pt, e1, e2);
    EXPECT_NEAR(s, ref.stress(e1), 1e-10 * SY) << "e1 = " << e1 / ey << " ey";
  }
  EXPECT_NEAR(pt.h[Hist::EQPS], ref.alpha, 1e-10 * ref.alpha);
  EXPECT_GT(ref.alpha, 0.09);
}

// at 200 K above the reference temperature, the path shifted by the thermal
// strain: the same curve (linear hardening has no thermal softening), so
// the plastic state a yielding step stores holds no thermal part
TEST(Plasticity, UniaxialCurveHeated)
{
  for (Law law : {Law::SMALL, Law::HENCKY}) check_uniaxial_curve(law, 2.0e9, 0.0, SY, 200.0);
}

// ln b and exp D by their series against the eigen-decomposition, on
// near-isotropic tensors of every scale of distortion (exact multiples of
// the identity and double eigenvalues included); beyond their range
// (|Y| > 0.05, |D| > 0.2) or for b not positive definite they decline
// The six-value products the series use: A B of commuting symmetric
// tensors (polynomials in one tensor) and the congruence A S A^T, against
// Eigen's full products.
TEST(Plasticity, SymmetricProducts)
{
  std::mt19937 gen(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int t = 0; t < 200; ++t) {
    Mat3 G;
    for (int k = 0; k < 9; ++k) G(k / 3, k % 3) = u(gen);
    const Mat3 S = 0.5 * (G + G.transpose());
    // A and B commute: both are polynomials in S
    const Mat3 A = 0.3 * Mat3::Identity() + S - 0.2 * S * S;
    const Mat3 B = -1.1 * Mat3::Identity() + 0.7 * S + 0.4 * S * S;
    const Mat3 AB = mat_of(mul_commuting(sym_of(A), sym_of(B)));
    EXPECT_LT((AB - A * B).cwiseAbs().maxCoeff(), 1e-14);
    Mat3 F;
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = u(gen);
    const Mat3 C = mat_of(congruence(F, sym_of(S)));
    EXPECT_LT((C - F * S * F.transpose()).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_EQ(C, C.transpose());
    const Sym3 s = sym_of(S);
    EXPECT_NEAR(norm2(s), S.squaredNorm(), 1e-14);
    EXPECT_EQ(mat_of(plus_identity(s, 2.5)), S + 2.5 * Mat3::Identity());
    double v[6];
    store_sym(s, v);
    EXPECT_EQ(mat_of(load_sym3(v)), S);
  }
}

TEST(Plasticity, LogAndExpSeriesMatchEigen)
{
  std::mt19937 gen(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto eigen_fn = [](const Mat3 &A, double (*f)(double)) {
    Eigen::SelfAdjointEigenSolver<Mat3> d(A);
    Vec3 x = d.eigenvalues();
    for (int a = 0; a < 3; ++a) x(a) = f(x(a));
    return Mat3(d.eigenvectors() * x.asDiagonal() * d.eigenvectors().transpose());
  };
  auto ln = [](double x) { return std::log(x); };
  auto ex = [](double x) { return std::exp(x); };
  int used = 0;
  for (double amp : {0.0, 1e-9, 1e-5, 1e-3, 1e-2, 0.03}) {
    for (int t = 0; t < 300; ++t) {
      Eigen::Quaterniond q(u(gen), u(gen), u(gen), u(gen));
      q.normalize();
      const Mat3 R = q.toRotationMatrix();
      const double s = 1.0 + 0.1 * u(gen);
      Vec3 lam(1.0 + amp * u(gen), 1.0 + amp * u(gen), 1.0 + amp * u(gen));
      if (t % 3 == 0) lam(1) = lam(0);    // a double eigenvalue
      Mat3 b = s * R * lam.asDiagonal() * R.transpose();
      b = 0.5 * (b + b.transpose()).eval();
      Mat3 L;
      ASSERT_TRUE(log_spd_near_isotropic(b, L)) << "amp " << amp;
      EXPECT_LT((L - eigen_fn(b, ln)).cwiseAbs().maxCoeff(), 1e-14) << "amp " << amp;
      const Mat3 D = 2.0 * (L - (L.trace() / 3.0) * Mat3::Identity());
      Mat3 Ed;
      ASSERT_TRUE(exp_sym_small(D, Ed)) << "amp " << amp;
      EXPECT_LT((Ed - eigen_fn(D, ex)).cwiseAbs().maxCoeff(), 1e-14) << "amp " << amp;
      used++;
    }
  }
  EXPECT_EQ(used, 1800);
  // near the series' bound |Y| = 0.05, where its high powers count
  int near_bound = 0;
  for (int t = 0; t < 2000; ++t) {
    Eigen::Quaterniond q(u(gen), u(gen), u(gen), u(gen));
    q.normalize();
    const Mat3 R = q.toRotationMatrix();
    const Vec3 lam(1.0 + 0.09 * u(gen), 1.0 + 0.09 * u(gen), 1.0 + 0.09 * u(gen));
    Mat3 b = R * lam.asDiagonal() * R.transpose();
    b = 0.5 * (b + b.transpose()).eval();
    Mat3 L;
    if (!log_spd_near_isotropic(b, L)) continue;
    const Mat3 B = b / (b.trace() / 3.0), I = Mat3::Identity();
    if (((B - I) * (B + I).inverse()).norm() > 0.04) near_bound++;
    EXPECT_LT((L - eigen_fn(b, ln)).cwiseAbs().maxCoeff(), 1e-14);
  }
  EXPECT_GT(near_bound, 50);
  Mat3 L, Ed;
  Mat3 far = Mat3::Identity();
  far(0, 0) = 1.3;
  EXPECT_FALSE(log_spd_near_isotropic(far, L));
  Mat3 indefinite = Mat3::Identity();
  indefinite(2, 2) = -1.0;
  EXPECT_FALSE(log_spd_near_isotropic(indefinite, L));
  EXPECT_FALSE(log_spd_near_isotropic(-Mat3::Identity(), L));
  Mat3 big = Mat3::Zero();
  big(0, 1) = big(1, 0) = 0.15;
  EXPECT_FALSE(exp_sym_small(big, Ed));
  // its bound, |D| = 0.2, where the Hencky return may take it
  big(0, 1) = big(1, 0) = 0.14;
  ASSERT_TRUE(exp_sym_small(big, Ed));
  EXPECT_LT((Ed - eigen_fn(big, ex)).cwiseAbs().maxCoeff(), 1e-15);
}

// Power-law hardening: on the monotonic curve sigma = sigma_y(eqps) and the
// axial strain splits into sigma/E + eqps.
TEST(Plasticity, UniaxialPowerLaw)
{
  for (Law law : {Law::SMALL, Law::HENCKY}) {
    Point pt(law);
    pt.fl.active = true;
    pt.fl.kind = Hardening::POWER;
    pt.fl.sigma_y0 = SY;
    pt.fl.K = 500e6;
    pt.fl.n = 0.3;
    double e2 = 0.0;
    int plastic = 0;
    for (int k = 1; k <= 60; ++k) {
      const double e1 = 0.001 * k;
      const double s = uniaxial(pt, e1, e2);
      const double a = pt.h[Hist::EQPS];
      if (a > 0.0) {
        plastic++;
        EXPECT_NEAR(s, SY + 500e6 * std::pow(a, 0.3), 1e-10 * s);
        EXPECT_NEAR(e1, s / E + a, 1e-10 * e1);
      }
    }
    EXPECT_GT(plastic, 50);
  }
}

// Johnson-Cook at a constant strain rate: the stress is the flow stress at
// the equivalent deviatoric strain rate of the previous increment (lagged
// by one step), with temperature softening.
TEST(Plasticity, JohnsonCookRateAndTemperature)
{
  Point pt(Law::SMALL);
  set_johnson_cook(pt.fl, 90e6, 292e6, 0.31, 0.025, 1.09, 298.0, 1356.0);
  pt.env.dt = 1e-6;    // 1e-3 strain per step: rate 1e3 /s
  pt.env.T_base = 500.0;
  // the equivalent deviatoric rate of an increment of the small strain
  auto eq_rate = [&](const Mat3 &dF) {
    Mat3 D = 0.5 * (dF + dF.transpose());
    D -= (D.trace() / 3.0) * Mat3::Identity();
    return std::sqrt(2.0 / 3.0) * D.norm() / pt.env.dt;
  };
  double e2 = 0.0, rate_prev = 0.0;
  Mat3 F_prev = Mat3::Identity();
  int plastic = 0;
  for (int k = 1; k <= 50; ++k) {
    const double s = uniaxial(pt, 0.001 * k, e2);
    const double a = pt.h[Hist::EQPS];
    const Mat3 F = Mat3::Identity() + load(pt.h.data() + Hist::FPREV);
    const double rate = eq_rate(F - F_prev);
    EXPECT_NEAR(pt.h[Hist::RATE], rate, 1e-9 * rate);
    if (a > 0.0 && k > 2) {
      plastic++;
      const double Ts = (500.0 - 298.0) / (1356.0 - 298.0);
      const double sy = (90e6 + 292e6 * std::pow(a, 0.31)) * (1.0 + 0.025 * std::log(rate_prev)) *
          (1.0 - std::pow(Ts, 1.09));
      EXPECT_NEAR(s, sy, 1e-10 * sy);
    }
    rate_prev = rate;
    F_prev = F;
  }
  EXPECT_GT(plastic, 40);
}

/* The plastic work of an increment, int_0^d sigma_y(a_n + s, rate, T) ds,
   against a fine composite Simpson rule in s (graded towards s = 0, where
   a power law with a_n = 0 has its kink), for the power law and
   Johnson-Cook, from increments a millionth of the accumulated strain
   (where a difference of powers loses its digits) to large ones. */
TEST(Plasticity, WorkIsFlowStressIntegral)
{
  for (int kind = 0; kind < 2; ++kind) {
    FlowLaw fl;
    const double rate = 3e4, T = 600.0;
    double factor = 1.0;
    if (kind == 0) {
      fl.active = true;
      fl.kind = Hardening::POWER;
      fl.sigma_y0 = 90e6;
      fl.K = 292e6;
      fl.n = 0.31;
    } else {
      set_johnson_cook(fl, 90e6, 292e6, 0.31, 0.025, 1.09, 298.0, 1356.0);
      // (1 + C ln(rate/rate0)) (1 - T*^m) written out
      factor = (1.0 + 0.025 * std::log(rate)) *
          (1.0 - std::pow((T - 298.0) / (1356.0 - 298.0), 1.09));
    }
    for (double a_n : {0.0, 0.05, 1.3})
      for (double d : {5e-9, 2e-8, 1e-6, 3e-4, 0.02, 5.0}) {
        auto sigma = [&](double s) { return factor * (90e6 + 292e6 * std::pow(a_n + s, 0.31)); };
        const int N = 20000;
        double sum = 0.0;
        for (int k = 0; k <= N; ++k) {
          const double t = (double) k / N;    // s = d t^4
          const double wk = (k == 0 || k == N) ? 1.0 : (k % 2 ? 4.0 : 2.0);
          sum += wk * sigma(d * std::pow(t, 4)) * 4.0 * d * std::pow(t, 3);
        }
        const double ref = sum / (3.0 * N);
        EXPECT_NEAR(fl.work(a_n, d, rate, T), ref, 1e-10 * ref)
            << "kind " << kind << " a_n " << a_n << " d " << d;
      }
  }
}

/* The returned P is the gradient of the incremental potential
   W_e(F) + dD(F) at frozen start-of-step history: central differences on
   a general (non-uniaxial) plastic increment, for every flow law. */
TEST(Plasticity, StressIsIncrementalPotentialGradient)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (Law law : {Law::SMALL, Law::HENCKY}) {
    for (int kind = 0; kind < 4; ++kind) {
      Point pt(law);
      pt.fl.active = true;
      pt.fl.sigma_y0 = SY;
      if (kind == 0) { pt.fl.kind = Hardening::LINEAR; pt.fl.H = 2e9; }
      if (kind == 1) { pt.fl.kind = Hardening::POWER; pt.fl.K = 400e6; pt.fl.n = 0.4; }
      if (kind == 2) {
        set_johnson_cook(pt.fl, SY, 400e6, 0.4, 0.03, 1.0, 293.0, 1500.0);
        pt.env.T_base = 400.0;
        pt.env.dt = 1e-7;
      }
      if (kind == 3) {
        if (law == Law::HENCKY) continue;
        pt.fl.kind = Hardening::LINEAR; pt.fl.H = 1e9; pt.fl.Hkin = 4e9;
      }
      // a plastic pre-strain, committed
      Mat3 G;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) G(r, c) = 0.004 * U(rng);
      double W;
      pt.step(Mat3::Identity() + G, W);
      ASSERT_GT(pt.h[Hist::EQPS], 0.0);
      // a further plastic increment: compare P with -d/dF of W_e + dD
      Mat3 F = Mat3::Identity() + 2.0 * G;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) F(r, c) += 0.001 * U(rng);
      const Mat3 P = pt.step(F, W, false);
      auto potential = [&](const Mat3 &Ft) {
        std::vector<double> h1(Hist::SIZE);
        Mat3 Pt;
        double Wt;
        inelastic_point_3d(law, pt.m, pt.fl, pt.th, pt.env, Ft, pt.h.data(), h1.data(), Pt, Wt);
        return Wt + h1[Hist::WORK] - pt.h[Hist::WORK];
      };
      const double h = 1e-7;
      double worst = 0.0;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          Mat3 Fp = F, Fm = F;
          Fp(r, c) += h;
          Fm(r, c) -= h;
          const double d = (potential(Fp) - potential(Fm)) / (2.0 * h);
          // small strain: W depends on sym(F) only, P = sigma is symmetric
          worst = std::max(worst, std::abs(d - P(r, c)));
        }
      EXPECT_LT(worst, 1e-5 * P.cwiseAbs().maxCoeff())
          << "law " << static_cast<int>(law) << " hardening " << kind;
    }
  }
}

// Objectivity of the finite-strain return: Q F gives Q P, the same stored
// energy and the same history, after plastic flow.
TEST(Plasticity, HenckyObjectivity)
{
  Point pt(Law::HENCKY);
  pt.fl.active = true;
  pt.fl.sigma_y0 = SY;
  pt.fl.H = 1e9;
  Mat3 F;
  F << 1.02, 0.03, -0.01, 0.005, 0.985, 0.02, -0.01, 0.01, 1.004;
  double W;
  pt.step(F, W);
  ASSERT_GT(pt.h[Hist::EQPS], 0.0);
  Mat3 F2 = F;
  F2(0, 1) += 0.01;
  F2(1, 1) -= 0.005;
  std::vector<double> h1(Hist::SIZE), h2(Hist::SIZE);
  Mat3 P1, P2;
  double W1, W2;
  ASSERT_EQ(inelastic_point_3d(Law::HENCKY, pt.m, pt.fl, pt.th, pt.env, F2, pt.h.data(),
                               h1.data(), P1, W1), ReturnStatus::OK);
  const Mat3 Q = Eigen::AngleAxisd(1.1, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  ASSERT_EQ(inelastic_point_3d(Law::HENCKY, pt.m, pt.fl, pt.th, pt.env, Q * F2, pt.h.data(),
                               h2.data(), P2, W2), ReturnStatus::OK);
  EXPECT_LT((P2 - Q * P1).cwiseAbs().maxCoeff(), 1e-9 * P1.cwiseAbs().maxCoeff());
  EXPECT_NEAR(W1, W2, 1e-12 * W1);
  // all but the stored F of the step, which rotates
  for (int k = 0; k < Hist::FPREV; ++k) EXPECT_NEAR(h1[k], h2[k], 1e-12 * (1.0 + std::abs(h1[k])));
  // the elastic Hencky law is the same point without a flow law
  pt.fl.active = false;
  Mat3 Pe;
  double We;
  ASSERT_TRUE(first_piola_3d(Law::HENCKY, pt.m, F2, Pe, We));
  std::vector<double> h0(Hist::SIZE, 0.0), h3(Hist::SIZE);
  inelastic_point_3d(Law::HENCKY, pt.m, pt.fl, pt.th, pt.env, F2, h0.data(), h3.data(), P1, W1);
  EXPECT_LT((P1 - Pe).cwiseAbs().maxCoeff(), 1e-12 * Pe.cwiseAbs().maxCoeff());
}

// A free heated point is stress free; a clamped one carries
// -3 K alpha dT on the diagonal.
TEST(Plasticity, ThermalStrain)
{
  for (Law law : {Law::SMALL, Law::HENCKY}) {
    Point pt(law);
    pt.th.alpha = 1.2e-5;
    pt.th.T_ref = 293.0;
    pt.env.T_base = 493.0;
    const double eth = 1.2e-5 * 200.0;
    double W;
    const Mat3 Pfree = pt.step((1.0 + eth) * Mat3::Identity(), W);
    EXPECT_LT(Pfree.cwiseAbs().maxCoeff(), 1e-12 * E * eth);
    EXPECT_LT(std::abs(W), 1e-20 * E);
    const Mat3 Pc = pt.step(Mat3::Identity(), W);
    const double expect = -E * eth / (1.0 - 2.0 * NU);
    // small strain: exact; Hencky: log(1 + eth) instead of eth
    const double exact = law == Law::SMALL ? expect : -E * std::log1p(eth) / (1.0 - 2.0 * NU);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(Pc(a, a), exact, 1e-12 * std::abs(expect));
    EXPECT_NEAR(Pc(0, 0), expect, 0.005 * std::abs(expect));
  }
}

// Adiabatic heating: dT = chi dD / (rho cp), fed back into the thermal
// softening of the next step.
TEST(Plasticity, AdiabaticHeating)
{
  Point pt(Law::SMALL);
  set_johnson_cook(pt.fl, SY, 300e6, 0.3, 0.0, 1.0, 293.0, 1700.0);
  pt.th.cp = 450.0;
  pt.th.chi = 0.9;
  pt.env.T_base = 293.0;
  pt.env.rho = 7850.0;
  double e2 = 0.0;
  for (int k = 1; k <= 100; ++k) uniaxial(pt, 0.002 * k, e2);
  EXPECT_GT(pt.h[Hist::WORK], 0.0);
  EXPECT_NEAR(pt.h[Hist::HEAT], 0.9 * pt.h[Hist::WORK] / (7850.0 * 450.0), 1e-12 * pt.h[Hist::HEAT]);
  EXPECT_GT(pt.h[Hist::HEAT], 10.0);    // 0.2 strain at ~0.5 GPa heats steel by tens of K
}

// Johnson-Cook failure: under uniaxial tension (triaxiality 1/3) at the
// reference rate and temperature the damage is eqps / (D1 + D2 exp(D3/3)).
TEST(Plasticity, JohnsonCookDamage)
{
  Point pt = linear_hardening_point(Law::SMALL, 1e9);
  pt.th.failure = true;
  const double D[5] = {0.05, 3.44, -2.12, 0.002, 0.61};
  for (int k = 0; k < 5; ++k) pt.th.D[k] = D[k];
  double e2 = 0.0;
  for (int k = 1; k <= 30; ++k) uniaxial(pt, 0.002 * k, e2);
  const double ef = D[0] + D[1] * std::exp(D[2] / 3.0);
  EXPECT_NEAR(pt.h[Hist::DAMAGE], pt.h[Hist::EQPS] / ef, 1e-6 * pt.h[Hist::DAMAGE]);
}

// Johnson-Cook energy balance when the surface shrinks under a step that
// unloads: heated (T rises, the flow stress falls) and unloaded in the same
// step, or heated at a fixed F, or unloaded alone, in turn.  Under small
// strain the stress is linear in the elastic strain, so the work of a step
// is exact: the relaxation of the accepted state at its own F does none,
// the elastic path from the relaxed stress P_r to P_1 does
// (P_r + P_1) : dF / 2.  W + plastic work must change by exactly that (to
// rounding); booking the relaxation without relaxing the stress broke it
// by the energy the relaxation would release.
TEST(Plasticity, JohnsonCookHeatedUnloadingStepsCloseTheBalance)
{
  Point pt(Law::SMALL);
  set_johnson_cook(pt.fl, SY, 300e6, 0.3, 0.0, 1.0, 293.0, 1700.0);
  pt.env.T_base = 293.0;
  pt.env.dt = 1e-7;
  double e2 = 0.0;
  for (int k = 1; k <= 10; ++k) uniaxial(pt, 0.001 * k, e2);
  ASSERT_GT(pt.h[Hist::EQPS], 1e-3);
  Mat3 F = axial_F(Law::SMALL, 0.01, e2);
  double W0;
  pt.step(F, W0, false);
  int relaxed = 0;
  for (int k = 0; k < 30; ++k) {
    const bool heat = (k % 3) != 2, unload = (k % 3) != 1;
    if (heat) pt.env.T_base += 40.0;
    Mat3 F1 = F;
    if (unload) F1 -= 2e-5 * Mat3(Eigen::Vector3d(1.0, -0.3, -0.3).asDiagonal());
    double Wr, W1;
    const Mat3 Pr = pt.step(F, Wr, false);    // the accepted state under this step's surface
    const double D0 = pt.h[Hist::WORK];
    const Mat3 P1 = pt.step(F1, W1);
    const double work = 0.5 * (Pr + P1).cwiseProduct(F1 - F).sum();
    const double change = (W1 - W0) + (pt.h[Hist::WORK] - D0);
    EXPECT_NEAR(change, work, 1e-12 * W0) << "step " << k << (heat ? " heated" : "")
                                          << (unload ? " unloaded" : "");
    if (pt.h[Hist::WORK] > D0) relaxed++;
    F = F1;
    W0 = W1;
  }
  EXPECT_GT(relaxed, 10) << "the heated steps must relax the state";
}

}    // namespace

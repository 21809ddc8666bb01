/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the material-point interface
   (nospd_material.h), without LAMMPS: each law behind it gives what its
   kernel gives, and the tangents it offers are the derivatives of its
   stress (central differences of the return from the same history).
------------------------------------------------------------------------- */

#include "nospd_material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

using namespace NOSPD;

namespace {

constexpr double E = 200.0e9, NU = 0.3;

// the largest |analytic - central difference| of dP/dF over D's largest entry
// (step h: its rounding noise is about 1e-16 / h relative, more where F is far from I)
double tangent_error(const Material &law, const Mat3 &F, const double *hn,
                     const MaterialEnv &env, double h = 1e-9)
{
  Tangent9 D;
  EXPECT_TRUE(law.tangent(F, hn, env, D));
  std::vector<double> h1(std::max(1, law.history_size()));
  double worst = 0.0;
  for (int k = 0; k < 9; ++k) {
    Mat3 Fp = F, Fm = F, Pp, Pm;
    Fp(k / 3, k % 3) += h;
    Fm(k / 3, k % 3) -= h;
    double W;
    EXPECT_TRUE(law.stress(Fp, hn, h1.data(), env, Pp, W).ok());
    EXPECT_TRUE(law.stress(Fm, hn, h1.data(), env, Pm, W).ok());
    for (int i = 0; i < 9; ++i)
      worst = std::max(worst, std::abs((Pp(i / 3, i % 3) - Pm(i / 3, i % 3)) / (2.0 * h) - D(i, k)));
  }
  return worst / D.cwiseAbs().maxCoeff();
}

// the worst relative error of a test, in its XML output (--gtest_output=xml)
void record_worst(double worst)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", worst);
  ::testing::Test::RecordProperty("worst_relative_error", buf);
}

Mat3 strained(double a, double b, double c, double shear)
{
  Mat3 F = Mat3::Identity();
  F(0, 0) += a;
  F(1, 1) += b;
  F(2, 2) += c;
  F(0, 1) += shear;
  F(1, 2) += 0.3 * shear;
  return F;
}

/* J2's consistent tangent (small strain) with linear isotropic, power-law
   and kinematic hardening, from a virgin and from a plastically deformed
   history, in an elastic and in a yielding step. */
TEST(Material, J2ConsistentTangent)
{
  const Lame m = Lame::from_young(E, NU);
  struct Case {
    const char *name;
    Hardening kind;
    double H, K, n, Hk;
  };
  const Case cases[] = {{"linear", Hardening::LINEAR, 2e9, 0, 1, 0},
                        {"perfect", Hardening::LINEAR, 0, 0, 1, 0},
                        {"power", Hardening::POWER, 0, 8e8, 0.4, 0},
                        {"kinematic", Hardening::LINEAR, 1e9, 0, 1, 3e9}};
  for (const auto &c : cases) {
    FlowLaw fl;
    fl.active = true;
    fl.kind = c.kind;
    fl.sigma_y0 = 250e6;
    fl.H = c.H;
    fl.K = c.K;
    fl.n = c.n;
    fl.Hkin = c.Hk;
    ThermalLaw th;
    th.alpha = 1.2e-5;
    const J2Material law(Law::SMALL, Plane::NONE, m, fl, th);
    MaterialEnv env;
    env.T = 350.0;    // a thermal strain in the trial
    std::vector<double> hn(Hist::SIZE, 0.0), h1(Hist::SIZE);
    // a plastic history: one committed step
    Mat3 F0 = strained(3e-3, -1e-3, -1e-3, 1e-3), P;
    double W;
    ASSERT_TRUE(law.stress(F0, hn.data(), h1.data(), env, P, W).ok());
    ASSERT_GT(h1[Hist::EQPS], 0.0) << c.name;
    for (const bool virgin : {true, false}) {
      const std::vector<double> &h = virgin ? hn : h1;
      // yielding further along, and an elastic unloading from there
      for (const Mat3 &F : {strained(4e-3, -1.5e-3, -1e-3, 1.4e-3), strained(2e-3, -0.5e-3, -0.6e-3, 0.5e-3)}) {
        std::vector<double> probe(Hist::SIZE);
        Mat3 Ft = F;
        ASSERT_TRUE(law.stress(Ft, h.data(), probe.data(), env, P, W).ok());
        EXPECT_LT(tangent_error(law, F, h.data(), env), 1e-6)
            << c.name << (virgin ? " virgin" : " deformed") << " yielding " << probe[Hist::YIELDING];
      }
    }
  }
  // plane stress offers none (its F33 is a secant solve's)
  Tangent9 D;
  std::vector<double> hn(Hist::SIZE, 0.0);
  for (Law lw : {Law::SMALL, Law::HENCKY})
    EXPECT_FALSE(J2Material(lw, Plane::STRESS, m, FlowLaw(), ThermalLaw()).tangent(Mat3::Identity(), hn.data(), MaterialEnv(), D));
}

// a Johnson-Cook steel, rate term on, heating (Taylor-Quinney) on
FlowLaw johnson_cook(double Hkin)
{
  FlowLaw fl;
  fl.active = true;
  fl.kind = Hardening::JOHNSON_COOK;
  fl.sigma_y0 = 350e6;
  fl.K = 275e6;
  fl.n = 0.36;
  fl.C = 0.05;
  fl.rate0 = 1.0;
  fl.m = 1.0;
  fl.T_ref = 293.0;
  fl.T_melt = 1800.0;
  fl.Hkin = Hkin;
  return fl;
}

// plane strain: the in-plane block, F33 = 1
Mat3 planar(Mat3 F)
{
  F(0, 2) = F(2, 0) = F(1, 2) = F(2, 1) = 0.0;
  F(2, 2) = 1.0;
  return F;
}

/* The histories a Johnson-Cook tangent is checked from (all from hn = 0
   by the interface's own steps, dt as given): virgin; deformed (two
   yielding steps, the second slower, so that at dt > 0 the surface the
   next step starts from has moved in and the start is relaxed); heated
   (the deformed one 150 K hotter: a softer, relaxed start and a thermal
   strain). */
std::vector<std::vector<double>> jc_histories(const Material &law, const MaterialEnv &env, bool plane)
{
  std::vector<double> h0(Hist::SIZE, 0.0), h1(Hist::SIZE), h2(Hist::SIZE);
  Mat3 F0 = strained(3e-3, -1e-3, -1e-3, 1e-3), F1 = strained(4.5e-3, -1.7e-3, -1.5e-3, 1.8e-3), P;
  if (plane) {
    F0 = planar(F0);
    F1 = planar(F1);
  }
  double W;
  EXPECT_TRUE(law.stress(F0, h0.data(), h1.data(), env, P, W).ok());
  EXPECT_TRUE(law.stress(F1, h1.data(), h2.data(), env, P, W).ok());
  EXPECT_EQ(h2[Hist::YIELDING], 1.0);
  std::vector<double> hot = h2;
  hot[Hist::HEAT] += 150.0;
  return {h0, h2, hot};
}

/* Johnson-Cook's consistent tangent (small strain and hencky; 3D and plane
   strain; with and without kinematic hardening): against central
   differences of the interface's stress from virgin, deformed (relaxed
   start) and heated histories, in yielding and elastic (unloading) steps,
   quasi-static (dt = 0) and with the rate term on (dt > 0, the history's
   rate above rate0; the step's own rate, a function of F, must not enter). */
TEST(Material, JohnsonCookConsistentTangent)
{
  const Lame m = Lame::from_young(E, NU);
  ThermalLaw th;
  th.alpha = 1.2e-5;
  th.cp = 460.0;
  MaterialEnv env;
  env.T = 320.0;
  env.rho = 7850.0;
  int yielding = 0, elastic = 0, relaxed = 0;
  double worst = 0.0;
  for (Law lw : {Law::SMALL, Law::HENCKY})
    for (Plane pl : {Plane::NONE, Plane::STRAIN})
      for (double Hk : {0.0, 2e9}) {
        if (lw == Law::HENCKY && Hk > 0.0) continue;    // small strain only
        const FlowLaw fl = johnson_cook(Hk);
        const J2Material law(lw, pl, m, fl, th);
        for (double dt : {0.0, 1e-6}) {
          env.dt = dt;
          const auto hs = jc_histories(law, env, pl == Plane::STRAIN);
          for (size_t k = 0; k < hs.size(); ++k) {
            const double *h = hs[k].data();
            if (k > 0 && dt > 0.0) {
              EXPECT_GT(h[Hist::RATE], 10.0 * fl.rate0);    // the rate term is on
            }
            // relaxed start: the accepted state lies outside the surface of this step
            PointEnv pe;
            pe.dt = dt, pe.T_base = env.T, pe.rho = env.rho;
            double hr[Hist::SIZE], rel;
            const PointEnv pe1 = detail::frozen_env(fl, pe, h);
            const double *start = detail::relaxed_start(lw, m, fl, th, pe1, h, hr, rel);
            if (start != h) ++relaxed;
            for (Mat3 F : {strained(6e-3, -2.4e-3, -2e-3, 2.4e-3), strained(2e-3, -0.5e-3, -0.6e-3, 0.5e-3),
                           strained(3.2e-3, -1.4e-3, -0.8e-3, 1.6e-3)}) {
              if (pl == Plane::STRAIN) F = planar(F);
              std::vector<double> probe(Hist::SIZE);
              Mat3 Ft = F, P;
              double W;
              ASSERT_TRUE(law.stress(Ft, h, probe.data(), env, P, W).ok());
              const bool yields = probe[Hist::EQPS] > start[Hist::EQPS];
              (yields ? yielding : elastic)++;
              const double err = tangent_error(law, F, h, env);
              worst = std::max(worst, err);
              EXPECT_LT(err, 1e-6) << (lw == Law::SMALL ? "small" : "hencky")
                                   << (pl == Plane::STRAIN ? " plane strain" : " 3D") << " Hkin " << Hk
                                   << " dt " << dt << " history " << k << " yielding " << yields;
            }
          }
        }
      }
  // every regime was met
  EXPECT_GT(yielding, 10);
  EXPECT_GT(elastic, 10);
  EXPECT_GT(relaxed, 4);
  record_worst(worst);
}

// a rotation by angle t about the axis (1, 2, 3)
Mat3 rotation(double t)
{
  return Eigen::AngleAxisd(t, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
}

/* J2 with strain hencky at finite strain (linear, perfect, power-law and
   Johnson-Cook hardening; 3D and plane strain): the tangent against
   central differences from a virgin history and from two large committed
   plastic steps, in large yielding steps (trial b_e far from isotropic: the
   point takes b_e's eigenpairs), rotated ones, and elastic unloading
   (b_e near isotropic: the point takes ln's series). */
TEST(Material, HenckyConsistentTangent)
{
  const Lame m = Lame::from_young(E, NU);
  struct Case {
    const char *name;
    Hardening kind;
    double H, K, n;
  };
  const Case cases[] = {{"linear", Hardening::LINEAR, 2e9, 0, 1},
                        {"perfect", Hardening::LINEAR, 0, 0, 1},
                        {"power", Hardening::POWER, 0, 8e8, 0.4},
                        {"johnson-cook", Hardening::JOHNSON_COOK, 0, 0, 0}};
  ThermalLaw th;
  th.alpha = 1.2e-5;
  th.cp = 460.0;
  MaterialEnv env;
  env.T = 400.0;
  env.rho = 7850.0;
  env.dt = 1e-6;
  int yielding = 0, elastic = 0, series = 0, eigen = 0;
  double worst = 0.0;
  for (const auto &c : cases)
    for (Plane pl : {Plane::NONE, Plane::STRAIN}) {
      FlowLaw fl = johnson_cook(0.0);
      if (c.kind != Hardening::JOHNSON_COOK) {
        fl = FlowLaw();
        fl.active = true;
        fl.kind = c.kind;
        fl.sigma_y0 = 250e6;
        fl.H = c.H;
        fl.K = c.K;
        fl.n = c.n;
      }
      const J2Material law(Law::HENCKY, pl, m, fl, th);
      auto in_plane = [&](Mat3 F) { return pl == Plane::STRAIN ? planar(F) : F; };
      const Mat3 R = pl == Plane::STRAIN ? Mat3(Eigen::AngleAxisd(0.4, Vec3::UnitZ())) : rotation(0.4);
      std::vector<double> h0(Hist::SIZE, 0.0), h1(Hist::SIZE), h2(Hist::SIZE);
      Mat3 F0 = in_plane(strained(0.05, -0.02, -0.025, 0.03)), F1 = R * in_plane(strained(0.09, -0.03, -0.04, 0.06)), P;
      double W;
      ASSERT_TRUE(law.stress(F0, h0.data(), h1.data(), env, P, W).ok());
      ASSERT_TRUE(law.stress(F1, h1.data(), h2.data(), env, P, W).ok());
      ASSERT_EQ(h2[Hist::YIELDING], 1.0) << c.name;
      for (const auto *hv : {&h0, &h2}) {
        const double *h = hv->data();
        const Mat3 Fs[] = {in_plane(strained(0.12, -0.04, -0.05, 0.08)), R * in_plane(strained(0.12, -0.04, -0.05, 0.08)),
                           R * in_plane(strained(0.0891, -0.0297, -0.0396, 0.0594)), in_plane(strained(2e-3, -1e-3, 0.0, 1e-3))};
        for (const Mat3 &F : Fs) {
          std::vector<double> probe(Hist::SIZE);
          Mat3 Ft = F;
          ASSERT_TRUE(law.stress(Ft, h, probe.data(), env, P, W).ok());
          const bool yields = probe[Hist::EQPS] > h[Hist::EQPS];
          (yields ? yielding : elastic)++;
          // which ln the point took for the trial b_e
          Mat3 lnb;
          const Mat3 Ai = load_sym(h + Hist::PLASTIC) + Mat3::Identity();
          (log_spd_near_isotropic(Mat3(F * Ai * F.transpose()), lnb) ? series : eigen)++;
          // a step of 1e-7: at 1e-9 the noise of F ~ 1.1 is up to 5e-7 here
          const double err = tangent_error(law, F, h, env, 1e-7);
          worst = std::max(worst, err);
          EXPECT_LT(err, 1e-6) << c.name << (pl == Plane::STRAIN ? " plane strain" : " 3D")
                               << (h == h0.data() ? " virgin" : " deformed") << " yielding " << yields;
        }
      }
    }
  EXPECT_GT(yielding, 8);
  EXPECT_GT(elastic, 4);
  EXPECT_GT(series, 4);
  EXPECT_GT(eigen, 4);
  record_worst(worst);
}

// Drucker-Prager through the interface: its tangent, and the same stress
// as the kernel (plane stress solves F33)
TEST(Material, DruckerPragerThroughTheInterface)
{
  const Lame m = Lame::from_young(30e9, 0.2);
  const DruckerPrager dp = DruckerPrager::from_angles(30.0 * M_PI / 180.0, 10.0 * M_PI / 180.0, 5e6, 2e9);
  const DruckerPragerMaterial law(Law::SMALL, Plane::NONE, m, dp);
  std::vector<double> hn(Hist::SIZE, 0.0), h1(Hist::SIZE), h2(Hist::SIZE);
  Mat3 F = strained(-2e-3, 4e-4, 3e-4, 5e-4), P, Pk;
  double W, Wk;
  ASSERT_TRUE(law.stress(F, hn.data(), h1.data(), MaterialEnv(), P, W).ok());
  ASSERT_EQ(drucker_prager_small(m, dp, F, hn.data(), h2.data(), Pk, Wk), ReturnStatus::OK);
  EXPECT_EQ((P - Pk).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(h1[Hist::YIELDING], 1.0);
  EXPECT_LT(tangent_error(law, strained(-2.5e-3, 5e-4, 3e-4, 6e-4), h1.data(), MaterialEnv()), 1e-6);
  // plane stress: P33 = 0 at the solved F33
  const DruckerPragerMaterial ps(Law::SMALL, Plane::STRESS, m, dp);
  Mat3 F2 = strained(-2e-3, 4e-4, 0.0, 5e-4);
  F2(1, 2) = F2(2, 1) = F2(0, 2) = F2(2, 0) = 0.0;
  ASSERT_TRUE(ps.stress(F2, hn.data(), h1.data(), MaterialEnv(), P, W).ok());
  EXPECT_LT(std::abs(P(2, 2)), 1e-6 * P.cwiseAbs().maxCoeff());
  EXPECT_NE(F2(2, 2), 1.0);
}

// the elastic laws through the interface are the laws themselves
TEST(Material, ElasticThroughTheInterface)
{
  const Lame m = Lame::from_young(E, NU);
  for (Law lw : {Law::SMALL, Law::COROTATIONAL, Law::SVK, Law::NEOHOOKE, Law::HENCKY}) {
    const ElasticMaterial law(lw, Plane::NONE, m);
    Mat3 F = strained(2e-2, -5e-3, 1e-3, 1e-2), Fk = F, P, Pk;
    double W, Wk;
    ASSERT_TRUE(law.stress(F, nullptr, nullptr, MaterialEnv(), P, W).ok());
    ASSERT_TRUE(first_piola(lw, Plane::NONE, m, Fk, Pk, Wk));
    EXPECT_EQ((P - Pk).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(W, Wk);
    EXPECT_EQ(law.history_size(), 0);
  }
  // an inverted F is a failure the interface reports, not a NaN
  const ElasticMaterial svk(Law::NEOHOOKE, Plane::NONE, m);
  Mat3 F = -Mat3::Identity(), P;
  double W;
  EXPECT_EQ(svk.stress(F, nullptr, nullptr, MaterialEnv(), P, W).family, PointStatus::ELASTIC);
}

}    // namespace

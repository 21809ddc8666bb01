/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the material-point interface
   (nospd_material.h), without LAMMPS: each law behind it gives what its
   kernel gives, and the tangents it offers are the derivatives of its
   stress (central differences of the return from the same history).
------------------------------------------------------------------------- */

#include "nospd_material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

using namespace NOSPD;

namespace {

constexpr double E = 200.0e9, NU = 0.3;

// the largest |analytic - central difference| of dP/dF over D's largest entry
double tangent_error(const Material &law, const Mat3 &F, const double *hn,
                     const MaterialEnv &env)
{
  Tangent9 D;
  EXPECT_TRUE(law.tangent(F, hn, env, D));
  std::vector<double> h1(std::max(1, law.history_size()));
  const double h = 1e-9;
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
  // Johnson-Cook and hencky offer none (directional differences instead)
  FlowLaw jc;
  jc.active = true;
  jc.kind = Hardening::JOHNSON_COOK;
  jc.sigma_y0 = 250e6;
  Tangent9 D;
  std::vector<double> hn(Hist::SIZE, 0.0);
  EXPECT_FALSE(J2Material(Law::SMALL, Plane::NONE, m, jc, ThermalLaw()).tangent(Mat3::Identity(), hn.data(), MaterialEnv(), D));
  EXPECT_FALSE(J2Material(Law::HENCKY, Plane::NONE, m, FlowLaw(), ThermalLaw()).tangent(Mat3::Identity(), hn.data(), MaterialEnv(), D));
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

/* Kernel tests of the strain-energy formula law (nospd_formula.h):
   the Neo-Hooke and SVK energies typed as formulas give the built-in
   laws' P and W; P = dW/dF against central differences of W for three
   nontrivial formulas (invariant and stretch based); objectivity;
   plane stress through the shared F33 solve; parse errors. */

#include "nospd_formula.h"

#include "gtest/gtest.h"

#include <random>

using NOSPD::FormulaLaw;
using NOSPD::Lame;
using NOSPD::Law;
using NOSPD::Mat3;

namespace {

const double E = 2.0e6, NU = 0.3;

std::string neohooke_w()
{
  return "0.5*mu*(I1-3) - mu*log(J) + 0.5*lambda*log(J)^2";
}
std::string svk_w()
{
  // tr E = (I1 - 3)/2, |E|^2 = (I1^2 - 2 I2 - 2 I1 + 3)/4
  return "lambda/8*(I1-3)^2 + mu/4*(I1^2 - 2*I2 - 2*I1 + 3)";
}
std::vector<std::pair<std::string, double>> lame_params()
{
  const Lame m = Lame::from_young(E, NU);
  return {{"lambda", m.lambda}, {"mu", m.mu}};
}

Mat3 random_F(std::mt19937 &rng, double amp)
{
  std::uniform_real_distribution<double> U(-amp, amp);
  Mat3 F = Mat3::Identity();
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) F(r, c) += U(rng);
  return F;
}

Mat3 random_rotation(std::mt19937 &rng)
{
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Eigen::Vector3d a(U(rng), U(rng), U(rng));
  const double ang = 2.0 * a.norm();
  return Eigen::AngleAxisd(ang, a.normalized()).toRotationMatrix();
}

double rel(const Mat3 &a, const Mat3 &b) { return (a - b).norm() / std::max(b.norm(), 1e-300); }

void expect_matches_builtin(const std::string &w, Law law)
{
  FormulaLaw f(w, lame_params());
  Lame m = Lame::from_young(E, NU);
  std::mt19937 rng(11);
  for (int t = 0; t < 50; t++) {
    const Mat3 F = random_F(rng, 0.25);
    ASSERT_GT(F.determinant(), 0.0);
    Mat3 P1, P2;
    double W1, W2;
    ASSERT_TRUE(f.first_piola(F, P1, W1));
    ASSERT_TRUE(NOSPD::first_piola_3d(law, m, F, P2, W2));
    EXPECT_LT(rel(P1, P2), 1e-12) << "F =\n" << F;
    EXPECT_NEAR(W1, W2, 1e-12 * std::abs(W2) + 1e-12 * m.mu);
  }
}

}    // namespace

TEST(Formula, NeoHookeMatchesBuiltin) { expect_matches_builtin(neohooke_w(), Law::NEOHOOKE); }

TEST(Formula, SvkMatchesBuiltin) { expect_matches_builtin(svk_w(), Law::SVK); }

// the same energies through the Law::USER path of first_piola, in 3D and
// in both plane modes (the plane stress solve is the shared one)
TEST(Formula, UserLawInPlaneModes)
{
  FormulaLaw f(neohooke_w(), lame_params());
  Lame mu = Lame::from_young(E, NU);
  mu.user = &f;
  const Lame mb = Lame::from_young(E, NU);
  std::mt19937 rng(3);
  for (auto plane : {NOSPD::Plane::NONE, NOSPD::Plane::STRAIN, NOSPD::Plane::STRESS}) {
    for (int t = 0; t < 20; t++) {
      Mat3 F = random_F(rng, 0.2);
      if (plane != NOSPD::Plane::NONE) {
        F(0, 2) = F(1, 2) = F(2, 0) = F(2, 1) = 0.0;
        F(2, 2) = 1.0;
      }
      Mat3 Fu = F, Fb = F, Pu, Pb;
      double Wu, Wb;
      ASSERT_TRUE(NOSPD::first_piola(Law::USER, plane, mu, Fu, Pu, Wu));
      ASSERT_TRUE(NOSPD::first_piola(Law::NEOHOOKE, plane, mb, Fb, Pb, Wb));
      EXPECT_LT(rel(Pu, Pb), 1e-11);
      EXPECT_NEAR(Fu(2, 2), Fb(2, 2), 1e-12);
      if (plane == NOSPD::Plane::STRESS) {
        EXPECT_LT(std::abs(Pu(2, 2)), 1e-9 * E);
      }
    }
  }
}

// P = dW/dF by central differences of W (fourth-order stencil)
TEST(Formula, StressIsEnergyDerivative)
{
  const std::vector<std::string> formulas = {
      // Mooney-Rivlin, isochoric split
      "C10*(I1b-3) + C01*(I2b-3) + 0.5*K*(J-1)^2; C10=3e5; C01=8e4; K=5e6",
      // Gent
      "-0.5*mu*Jm*log(1-(I1b-3)/Jm) + 0.5*K*log(J)^2; mu=6e5; Jm=40; K=4e6",
      // Ogden (one term) in the principal stretches, with a volumetric part
      "mu/a*((l1^a + l2^a + l3^a)*J^(-a/3) - 3) + 0.5*K*(J-1)^2; mu=5e5; a=3.3; K=3e6"};
  std::mt19937 rng(7);
  for (const auto &w : formulas) {
    FormulaLaw f(w);
    for (int t = 0; t < 10; t++) {
      const Mat3 F = random_F(rng, 0.2);
      Mat3 P, Pd;
      double W;
      ASSERT_TRUE(f.first_piola(F, P, W)) << w;
      const double h = 1e-4;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
          double Wk[4];
          const double steps[4] = {-2, -1, 1, 2};
          for (int s = 0; s < 4; s++) {
            Mat3 Fh = F, Ph;
            Fh(r, c) += steps[s] * h;
            ASSERT_TRUE(f.first_piola(Fh, Ph, Wk[s]));
          }
          Pd(r, c) = (Wk[0] - 8 * Wk[1] + 8 * Wk[2] - Wk[3]) / (12 * h);
        }
      EXPECT_LT(rel(P, Pd), 1e-8) << w << "\nF =\n" << F << "\nP =\n" << P << "\nFD =\n" << Pd;
    }
  }
}

// W(QF) = W(F), P(QF) = Q P(F); equal stretches (the spectral form's
// degenerate case) give the same as slightly split ones
TEST(Formula, ObjectiveAndDegenerateStretches)
{
  const std::vector<std::string> formulas = {
      neohooke_w() + "; mu=1e6; lambda=2e6",
      "C10*(I1b-3) + C01*(I2b-3) + 0.5*K*(J-1)^2; C10=3e5; C01=8e4; K=5e6",
      "mu/a*((l1^a + l2^a + l3^a)*J^(-a/3) - 3) + 0.5*K*(J-1)^2; mu=5e5; a=3.3; K=3e6"};
  std::mt19937 rng(5);
  for (const auto &w : formulas) {
    FormulaLaw f(w);
    for (int t = 0; t < 10; t++) {
      const Mat3 F = random_F(rng, 0.2), Q = random_rotation(rng);
      Mat3 P, PQ;
      double W, WQ;
      ASSERT_TRUE(f.first_piola(F, P, W));
      ASSERT_TRUE(f.first_piola(Q * F, PQ, WQ));
      EXPECT_NEAR(WQ, W, 1e-12 * std::abs(W));
      EXPECT_LT(rel(PQ, Q * P), 1e-12) << w;
    }
    // uniaxial stretch: two equal stretches
    Mat3 F = Mat3::Identity(), Fs, P, Ps;
    F(0, 0) = 1.1;
    Fs = F;
    Fs(1, 1) += 1e-7;
    double W;
    ASSERT_TRUE(f.first_piola(F, P, W));
    ASSERT_TRUE(f.first_piola(Fs, Ps, W));
    EXPECT_LT(rel(P, Ps), 1e-5) << w;
    EXPECT_NEAR(P(1, 1), P(2, 2), 1e-9 * P.norm()) << w;
  }
}

TEST(Formula, ParseErrors)
{
  auto message = [](const std::string &w) {
    try {
      FormulaLaw f(w);
    } catch (std::invalid_argument &e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("0.5*mu*(I1-3").find("cannot parse"), std::string::npos);
  EXPECT_NE(message("0.5*mu*(I1-3)").find("unknown variable 'mu'"), std::string::npos);
  EXPECT_NE(message("l1^2 + 2*l2^2 + l3^2").find("not symmetric"), std::string::npos);
  EXPECT_EQ(message("0.5*(I1-3) - log(J) + 0.5*log(J)^2"), "");
  // named constants given separately
  FormulaLaw f("c*(I1-3)", {{"c", 2.0}});
  Mat3 P;
  double W;
  ASSERT_TRUE(f.first_piola(1.1 * Mat3::Identity(), P, W));
  EXPECT_NEAR(W, 2.0 * (3 * 1.21 - 3), 1e-14);
  EXPECT_NEAR(P(0, 0), 2.0 * 2 * 1.1, 1e-14);
}

// an undefined point (det F <= 0) is reported, not computed
TEST(Formula, InvertedPointIsUndefined)
{
  FormulaLaw f(neohooke_w() + "; mu=1; lambda=1");
  Mat3 F = Mat3::Identity(), P;
  F(0, 0) = -1.0;
  double W;
  EXPECT_FALSE(f.first_piola(F, P, W));
}

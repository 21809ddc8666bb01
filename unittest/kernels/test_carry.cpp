/* The deformation a point carries across a change of its family
   (nospd_carry.h).  A family of bonds on a grid is deformed non-affinely;
   bonds are cut; the fit of the bonds left differs from the old one, and
   the carried F_c makes the law's deformation F F_c the same as before (so
   W, the stress and a plastic law's trial state are continuous).  F_c acts
   on the reference side: a rigid rotation afterwards leaves the carried
   strain unchanged.  The force state with P F_c^T is the gradient of
   W(F F_c), checked by central differences with an independent
   Saint Venant-Kirchhoff law.  Inverting refits and large ones refuse. */

#include "nospd_carry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using NOSPD::Mat3;
using NOSPD::Vec3;

namespace {

struct Family {
  std::vector<Vec3> xi;    // reference bonds
  std::vector<Vec3> Y;     // current bonds
  std::vector<bool> cut;
};

// an sc grid of spacing 1 within horizon 3.015, displaced by an affine part,
// a quadratic part and noise (the non-affine content a refit sees)
Family make_family(unsigned seed)
{
  Family f;
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3 A = Mat3::Identity();
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) A(r, c) += 0.05 * u(gen);
  for (int a = -3; a <= 3; a++)
    for (int b = -3; b <= 3; b++)
      for (int c = -3; c <= 3; c++) {
        const Vec3 x(a, b, c);
        if (x.norm() == 0.0 || x.norm() > 3.015) continue;
        Vec3 y = A * x;
        y(0) += 0.01 * x(1) * x(2);
        y(2) += 0.008 * x(0) * x(0);
        for (int d = 0; d < 3; d++) y(d) += 0.01 * u(gen);
        f.xi.push_back(x);
        f.Y.push_back(y);
        f.cut.push_back(false);
      }
  return f;
}

Mat3 shape(const Family &f)
{
  Mat3 K = Mat3::Zero();
  for (size_t b = 0; b < f.xi.size(); b++)
    if (!f.cut[b]) K += f.xi[b] * f.xi[b].transpose();
  return K;
}

Mat3 fit(const Family &f)
{
  Mat3 N = Mat3::Zero();
  for (size_t b = 0; b < f.xi.size(); b++)
    if (!f.cut[b]) N += f.Y[b] * f.xi[b].transpose();
  return N * shape(f).inverse();
}

// Saint Venant-Kirchhoff, written here: W and P = F S
double svk(const Mat3 &F, Mat3 &P)
{
  const double lam = 1.3, mu = 0.8;
  const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
  const Mat3 S = lam * E.trace() * Mat3::Identity() + 2.0 * mu * E;
  P = F * S;
  return 0.5 * lam * E.trace() * E.trace() + mu * (E.cwiseProduct(E)).sum();
}

// cut the bonds on one side of a plane through the point (a crack face)
void cut_half(Family &f, const Vec3 &normal)
{
  for (size_t b = 0; b < f.xi.size(); b++)
    if (f.xi[b].dot(normal) > 0.5) f.cut[b] = true;
}

}    // namespace

TEST(Carry, AffineFamilyCarriesNothing)
{
  Family f = make_family(1);
  Mat3 A;
  A << 1.02, 0.01, 0.0, -0.01, 0.99, 0.02, 0.0, 0.01, 1.01;
  for (size_t b = 0; b < f.xi.size(); b++) f.Y[b] = A * f.xi[b];
  const Mat3 Fold = fit(f);
  cut_half(f, Vec3(0.3, 0.9, 0.1));
  Mat3 Fc = Mat3::Identity();
  ASSERT_TRUE(NOSPD::carry_deformation(Fold, fit(f), Fc));
  EXPECT_LT((Fc - Mat3::Identity()).norm(), 1e-13);
}

TEST(Carry, RefitKeepsTheLawsDeformationAndEnergy)
{
  for (unsigned seed : {2u, 3u, 4u}) {
    Family f = make_family(seed);
    Mat3 Fc = Mat3::Identity();
    Mat3 P;
    // two successive changes: a crack face, then more bonds on another side
    for (const Vec3 &n : {Vec3(0.0, 0.0, 1.0), Vec3(1.0, 0.2, 0.0)}) {
      const Mat3 Fold = fit(f);
      const Mat3 Feff = Fold * Fc;
      cut_half(f, n);
      const Mat3 Fnew = fit(f);
      EXPECT_GT((Fnew - Fold).norm(), 1e-3) << "the refit must differ for the test to mean anything";
      ASSERT_TRUE(NOSPD::carry_deformation(Fold, Fnew, Fc));
      EXPECT_LT((Fnew * Fc - Feff).norm(), 1e-13 * Feff.norm());
      Mat3 P1;
      EXPECT_NEAR(svk(Fnew * Fc, P1), svk(Feff, P), 1e-13);
      // without the carry the energy would jump
      EXPECT_GT(std::abs(svk(Fnew, P1) - svk(Feff, P)), 1e-6);
    }
  }
}

TEST(Carry, RotationAfterwardsLeavesTheCarriedStrain)
{
  Family f = make_family(5);
  const Mat3 Fold = fit(f);
  cut_half(f, Vec3(0.0, 1.0, 0.0));
  const Mat3 Fnew = fit(f);
  Mat3 Fc = Mat3::Identity();
  ASSERT_TRUE(NOSPD::carry_deformation(Fold, Fnew, Fc));
  const Mat3 Q = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 0.5).normalized()).toRotationMatrix();
  const Mat3 Ce = (Fnew * Fc).transpose() * (Fnew * Fc);
  const Mat3 Cq = (Q * Fnew * Fc).transpose() * (Q * Fnew * Fc);
  EXPECT_LT((Cq - Ce).norm(), 1e-13);
  // carried on the other side, the rotation would strain the point
  const Mat3 Fl = Fold * Fnew.inverse();
  const Mat3 Cl = (Fl * Q * Fnew).transpose() * (Fl * Q * Fnew);
  EXPECT_GT((Cl - Ce).norm(), 1e-4);
}

TEST(Carry, ForcesAreTheGradientOfTheCarriedEnergy)
{
  Family f = make_family(6);
  const Mat3 Fold = fit(f);
  cut_half(f, Vec3(0.2, 0.1, 1.0));
  Mat3 Fc = Mat3::Identity();
  ASSERT_TRUE(NOSPD::carry_deformation(Fold, fit(f), Fc));
  const Mat3 Kinv = shape(f).inverse();
  Mat3 P;
  svk(fit(f) * Fc, P);
  const Mat3 A = P * Fc.transpose() * Kinv;    // T_b = A xi_b
  double worst = 0.0, scale = 0.0;
  for (size_t b = 0; b < f.xi.size(); b++) {
    if (f.cut[b]) continue;
    const Vec3 T = A * f.xi[b];
    for (int d = 0; d < 3; d++) {
      const double h = 1e-6, y0 = f.Y[b](d);
      Mat3 dummy;
      f.Y[b](d) = y0 + h;
      const double ep = svk(fit(f) * Fc, dummy);
      f.Y[b](d) = y0 - h;
      const double em = svk(fit(f) * Fc, dummy);
      f.Y[b](d) = y0;
      worst = std::max(worst, std::abs((ep - em) / (2.0 * h) - T(d)));
      scale = std::max(scale, std::abs(T(d)));
    }
  }
  EXPECT_LT(worst, 1e-7 * scale);
}

TEST(Carry, InvertingOrLargeRefitsRefuse)
{
  Mat3 Fc = Mat3::Identity();
  const Mat3 Fold = Mat3::Identity();
  Mat3 Finv = Mat3::Identity();
  Finv(2, 2) = -0.5;
  EXPECT_FALSE(NOSPD::carry_deformation(Fold, Finv, Fc));
  Mat3 Fbig = Mat3::Identity();
  Fbig(0, 0) = 3.0;    // F_c(0,0) = 1/3: |F_c - I| = 0.67 > 0.5
  EXPECT_FALSE(NOSPD::carry_deformation(Fold, Fbig, Fc));
  EXPECT_EQ(Fc, Mat3::Identity());    // untouched
  Mat3 Fok = Mat3::Identity();
  Fok(0, 0) = 1.25;    // |F_c - I| = 0.2
  EXPECT_TRUE(NOSPD::carry_deformation(Fold, Fok, Fc));
  EXPECT_NEAR(Fc(0, 0), 0.8, 1e-15);
  EXPECT_TRUE(NOSPD::carried_deformation_valid(Fc));
  Mat3 bad = Mat3::Identity();
  bad(1, 1) = std::nan("");
  EXPECT_FALSE(NOSPD::carried_deformation_valid(bad));
}

/* The zero-energy-mode indicators (nospd_stabilization.h): the linear one
   vanishes for any affine field and the quadratic one for any quadratic
   field, while a mode at the spacing's scale (the checkerboard) shows in
   both; the ratio's strain floor keeps a rigidly turning body quiet. */

#include "nospd_stabilization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace NOSPD;

namespace {
// the family of radius 3.01 spacings on a unit grid
std::vector<Vec3> family()
{
  std::vector<Vec3> b;
  for (int x = -3; x <= 3; x++)
    for (int y = -3; y <= 3; y++)
      for (int z = -3; z <= 3; z++) {
        const int r2 = x * x + y * y + z * z;
        if (r2 > 0 && r2 <= 9) b.emplace_back(x, y, z);
      }
  return b;
}

// both indicators of a displacement field u(x) about the point at 0 (F fitted)
void indicators(Vec3 (*u)(const Vec3 &), double &zl, double &zq)
{
  const auto fam = family();
  Mat3 K = Mat3::Zero(), N = Mat3::Zero();
  for (const auto &xi : fam) {
    K += xi * xi.transpose();
    N += (u(xi) - u(Vec3::Zero())) * xi.transpose();
  }
  ZemSum lin(N * K.inverse(), false);
  QuadraticZemSum quad;
  for (const auto &xi : fam) {
    const Vec3 U = u(xi) - u(Vec3::Zero());
    lin.add(1.0, xi, U);
    quad.add(1.0, xi, U);
  }
  zl = lin.value();
  zq = quad.value();
}
}    // namespace

TEST(Zem, AffineFieldIsNoMode)
{
  double zl, zq;
  indicators([](const Vec3 &x) -> Vec3 { return Vec3(1e-3 * x[0] + 2e-4 * x[1], -3e-4 * x[2], 5e-4 * x[0]); }, zl, zq);
  EXPECT_LT(zl, 1e-15);
  EXPECT_LT(zq, 1e-12);
}

TEST(Zem, QuadraticFieldShowsOnlyInTheLinearIndicator)
{
  double zl, zq;
  indicators([](const Vec3 &x) -> Vec3 { return 1e-4 * Vec3(x[0] * x[1], -0.5 * x[0] * x[0], x[2] * x[2]); }, zl, zq);
  EXPECT_GT(zl, 1e-5);
  EXPECT_LT(zq, 1e-9 * zl);
}

TEST(Zem, CheckerboardShowsInBoth)
{
  double zl, zq;
  indicators([](const Vec3 &x) -> Vec3 {
    const double s = std::cos(M_PI * (std::lround(x[0]) + std::lround(x[1]) + std::lround(x[2])));
    return Vec3(1e-4 * s, 0.0, 0.0);
  }, zl, zq);
  EXPECT_GT(zl, 1e-5);
  EXPECT_GT(zq, 0.5 * zl);
}

TEST(Zem, RatioFloorsTheStrain)
{
  EXPECT_DOUBLE_EQ(zem_ratio(1e-4, 1e-3, 2e-3), 0.1);
  EXPECT_DOUBLE_EQ(zem_ratio(1e-4, 1e-5, 2e-3), 0.5);      // floored at 0.1 of the body's
  EXPECT_DOUBLE_EQ(zem_ratio(1e-9, 0.0, 1e-15), 1e-3);     // rounding of a rigid turn: quiet
  EXPECT_GT(zem_ratio(1e-4, 0.0, 0.0), 0.22);              // a pure mode at F = I shows
  // the Green strain ignores rotations
  Mat3 R;
  R << std::cos(0.7), -std::sin(0.7), 0, std::sin(0.7), std::cos(0.7), 0, 0, 0, 1;
  EXPECT_LT(green_strain_norm(R, false), 1e-15);
  EXPECT_NEAR(green_strain_norm(R * Mat3(Vec3(1.01, 1.0, 1.0).asDiagonal()), false), 0.5 * (1.01 * 1.01 - 1.0), 1e-14);
}

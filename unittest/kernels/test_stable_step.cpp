/* The stable time step kernel (nospd_stable_step.h): the step from a row
   bound is velocity Verlet's limit for an oscillator of that stiffness
   (below it the motion stays bounded, above it grows), and the estimate of
   a type is the smaller of its bond-based part and the margin times its
   bound; K^-1's norm in 2D ignores the out-of-plane placeholder. */

#include "nospd_stable_step.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace NOSPD;

namespace {
// largest |x| of velocity Verlet on m x'' = -k x over n steps from x = 1
double verlet_amplitude(double m, double k, double dt, int n)
{
  double x = 1.0, v = 0.0, a = -k * x / m, big = 1.0;
  for (int s = 0; s < n; s++) {
    v += 0.5 * dt * a;
    x += dt * v;
    a = -k * x / m;
    v += 0.5 * dt * a;
    big = std::max(big, std::abs(x));
  }
  return big;
}
}    // namespace

TEST(StableStep, RowBoundIsVelocityVerletsLimit)
{
  const double rho = 7800.0, R = 3.7e15;
  const double dt = StableStep::from_row_bound(rho, R);
  EXPECT_LT(verlet_amplitude(rho, R, 0.99 * dt, 2000), 10.0);
  EXPECT_GT(verlet_amplitude(rho, R, 1.01 * dt, 2000), 1.0e6);
  EXPECT_EQ(StableStep::from_row_bound(rho, 0.0), StableStep::NONE);
}

TEST(StableStep, EstimateIsTheSmallerPart)
{
  StableStep st;
  const double N = StableStep::NONE;
  // type 1: the bound decides; type 2: the bond-based value; type 3: no bound
  EXPECT_TRUE(st.take({N, 4.0, 1.0, 3.0}, {N, 1.0, 2.0, N}, 2.0));
  EXPECT_EQ(st.of(1), 2.0);
  EXPECT_EQ(st.of(2), 1.0);
  EXPECT_EQ(st.of(3), 3.0);
  EXPECT_EQ(st.bound_part(3), 0.0);
  EXPECT_EQ(st.smallest(), 1.0);
  EXPECT_EQ(st.smallest_type(), 2);
  EXPECT_FALSE(st.take({N, 4.0, 1.0, 3.0}, {N, 1.0, 2.0, N}, 2.0));
  EXPECT_EQ(st.of(7), 0.0);    // a type with no points
}

TEST(StableStep, PlaneNormIgnoresThePlaceholder)
{
  Mat3 K;
  K << 2.0, 0.5, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 100.0;
  const double in_plane = 1.5 + std::sqrt(0.25 + 0.25);    // eigenvalues of the 2x2 block
  EXPECT_NEAR(spectral_norm(K, true), in_plane, 1e-14);
  EXPECT_NEAR(spectral_norm(K, false), 100.0, 1e-12);
}

/* The reference box (nospd_reference_box.h): the reference bond is the
   minimum image in the reference box, antisymmetric bit for bit, and differs
   from the raw difference by a whole lattice vector of that box; a flip of
   the current box (h' = h M, M integer) carries the reference box along
   (ref' = ref M) so that every reference bond stays the same vector, while a
   deformation, however large, leaves it. */

#include "nospd_reference_box.h"

#include <gtest/gtest.h>

#include <random>

using namespace NOSPD;

namespace {
const int ALL[3] = {1, 1, 1};

// components of v in the basis of the box h (upper triangular)
Vec3 fractions(const double *h, const double *v)
{
  return ReferenceBox::matrix(h).inverse() * Vec3(v[0], v[1], v[2]);
}
}    // namespace

TEST(ReferenceBox, BondIsTheAntisymmetricMinimumImage)
{
  ReferenceBox rb;
  const double h[6] = {2.0, 1.5, 1.2, 0.3, -0.2, 0.4};    // triclinic
  rb.follow(h);
  ASSERT_TRUE(rb.set);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int n = 0; n < 2000; n++) {
    const double a[3] = {u(gen), u(gen), u(gen)}, b[3] = {u(gen), u(gen), u(gen)};
    double xi[3], back[3];
    rb.bond(a, b, ALL, h, xi);
    rb.bond(b, a, ALL, h, back);
    for (int k = 0; k < 3; k++) ASSERT_EQ(xi[k], -back[k]);
    // within half a box along each reduction direction (z, then y, then x)
    ASSERT_LE(std::abs(xi[2]), 0.5 * h[2]);
    ASSERT_LE(std::abs(xi[1]), 0.5 * h[1]);
    ASSERT_LE(std::abs(xi[0]), 0.5 * h[0]);
    // and a whole lattice vector away from the raw difference
    const double d[3] = {b[0] - a[0] - xi[0], b[1] - a[1] - xi[1], b[2] - a[2] - xi[2]};
    const Vec3 f = fractions(h, d);
    for (int k = 0; k < 3; k++) ASSERT_NEAR(f[k], std::round(f[k]), 1e-9);
  }
  // a non-periodic dimension is left alone
  const int xonly[3] = {1, 0, 0};
  const double a[3] = {0, 0, 0}, b[3] = {1.9, 1.4, 1.1};
  double xi[3];
  rb.bond(a, b, xonly, h, xi);
  EXPECT_DOUBLE_EQ(xi[0], 1.9 - 2.0);
  EXPECT_EQ(xi[1], 1.4);
  EXPECT_EQ(xi[2], 1.1);
}

TEST(ReferenceBox, FlipCarriesTheReferenceAlongAndKeepsEveryBond)
{
  ReferenceBox rb;
  const double h0[6] = {2.0, 1.0, 1.0, 0.0, 0.0, 0.0};
  rb.follow(h0);
  // the body shears: the current box tilts to xy = 0.49 lx; the reference stays
  const double h1[6] = {2.0, 1.0, 1.0, 0.0, 0.0, 0.98};
  rb.follow(h1);
  for (int k = 0; k < 6; k++) EXPECT_EQ(rb.ref[k], h0[k]);
  // it shears on to 0.505 lx and fix deform flips it: xy -> xy - lx, the
  // same lattice (h' = h M)
  const double h2[6] = {2.0, 1.0, 1.0, 0.0, 0.0, 1.01 - 2.0};
  const double x0i[3] = {0.1, 0.05, 0.2}, x0j[3] = {1.95, 0.9, 0.25};
  double before[3], after[3];
  rb.follow(h1);
  rb.bond(x0i, x0j, ALL, h1, before);
  rb.follow(h2);
  // M = [[1, -1, 0], [0, 1, 0], [0, 0, 1]]: ref' = ref M, xy_ref -> -lx_ref
  EXPECT_DOUBLE_EQ(rb.ref[5], -2.0);
  EXPECT_DOUBLE_EQ(rb.ref[0], 2.0);
  rb.bond(x0i, x0j, ALL, h2, after);
  for (int k = 0; k < 3; k++) EXPECT_NEAR(after[k], before[k], 1e-15);
  // a one-shot change_box to xy = 0.6 lx (no flip: the tilt passes half a
  // box length) is a deformation: the reference stays
  ReferenceBox big;
  big.follow(h0);
  const double h3[6] = {2.0, 1.0, 1.0, 0.0, 0.0, 1.2};
  big.follow(h3);
  for (int k = 0; k < 6; k++) EXPECT_EQ(big.ref[k], h0[k]);
}

TEST(ReferenceBox, ImageShiftsByWholeReferenceVectors)
{
  ReferenceBox rb;
  const double h[6] = {2.0, 1.5, 1.2, 0.3, -0.2, 0.4};
  rb.follow(h);
  double s[3];
  rb.image(1.0, -2.0, 3.0, s);
  const Vec3 f = fractions(rb.ref, s);
  EXPECT_NEAR(f[0], 1.0, 1e-14);
  EXPECT_NEAR(f[1], -2.0, 1e-14);
  EXPECT_NEAR(f[2], 3.0, 1e-14);
}

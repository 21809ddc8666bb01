/* Kernel tests of the damage fix's criteria (nospd_damage_criteria.h): each
   functor against the closed form of its quantity on bonds whose answer is
   known: the normal stress of a uniaxial state along, across and at 45
   degrees to the bond, von Mises of uniaxial stress and pure shear, the
   bond energy of a hand-computed force state, the tension-only rules, and
   the mechanical part of a bond with a thermal strain. */

#include "nospd_damage_criteria.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace NOSPD;

namespace {
// a bond of reference xi stretched to Y, with state rows sa, sc
BondView bond(const double *xi, const double *Y, double *U, const double *sa, const double *sc,
              double horizon = 1.0)
{
  for (int k = 0; k < 3; ++k) U[k] = Y[k] - xi[k];
  BondView v{xi, U, Y, 0.0, 0.0, 0.0, sa, sc, horizon};
  v.rxi = std::sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
  v.ry = std::sqrt(Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]);
  v.s = (v.ry - v.rxi) / v.rxi;
  return v;
}
}    // namespace

TEST(DamageCriteria, PrincipalIsTheNormalComponentAlongTheBond)
{
  const double sigma = 3.0e8;
  const double S[6] = {sigma, 0, 0, 0, 0, 0};    // uniaxial along x at both ends
  double U[3], val, limit = 1.0;
  const double r = std::sqrt(0.5);
  const double along[3] = {2.0, 0, 0}, across[3] = {0, 2.0, 0}, diag[3] = {r, r, 0};
  PrincipalCriterion stress{true}, strain{false};
  ASSERT_TRUE(stress(bond(along, along, U, S, S), val, limit));
  EXPECT_NEAR(val, sigma, 1e-6);
  ASSERT_TRUE(stress(bond(along, across, U, S, S), val, limit));
  EXPECT_NEAR(val, 0.0, 1e-6);    // stress reads the current bond
  ASSERT_TRUE(strain(bond(along, across, U, S, S), val, limit));
  EXPECT_NEAR(val, sigma, 1e-6);  // strain the reference one
  ASSERT_TRUE(stress(bond(diag, diag, U, S, S), val, limit));
  EXPECT_NEAR(val, 0.5 * sigma, 1e-6);
  // the ends' mean: a stress at one end only counts half
  const double Z[6] = {0, 0, 0, 0, 0, 0};
  ASSERT_TRUE(stress(bond(along, along, U, S, Z), val, limit));
  EXPECT_NEAR(val, 0.5 * sigma, 1e-6);
  EXPECT_EQ(limit, 1.0);
}

TEST(DamageCriteria, VonMisesInTensionOnly)
{
  const double tau = 1.0e8, sigma = 2.0e8;
  const double shear[6] = {0, 0, 0, tau, 0, 0}, uni[6] = {sigma, 0, 0, 0, 0, 0};
  const double xi[3] = {1, 0, 0}, longer[3] = {1.001, 0, 0}, shorter[3] = {0.999, 0, 0};
  double U[3], val = -1.0, limit = 1.0;
  VonMisesCriterion vm;
  ASSERT_TRUE(vm(bond(xi, longer, U, shear, shear), val, limit));
  EXPECT_NEAR(val, std::sqrt(3.0) * tau, 1e-6);
  ASSERT_TRUE(vm(bond(xi, longer, U, uni, uni), val, limit));
  EXPECT_NEAR(val, sigma, 1e-6);
  EXPECT_FALSE(vm(bond(xi, shorter, U, uni, uni), val, limit));
  EXPECT_FALSE(vm(bond(xi, xi, U, uni, uni), val, limit));
}

TEST(DamageCriteria, EnergyIsHalfTheForceStateDotU)
{
  // A = P K^-1 at the two ends (row-major); the bond's force density
  // omega (A_a + A_c) xi dotted with U, halved
  const double Aa[9] = {1, 2, 0, 0, 3, 0, 0, 0, 4}, Ac[9] = {2, 0, 0, 1, 1, 0, 0, 0, 1};
  const double xi[3] = {0.5, 0.25, 0.0}, Y[3] = {0.52, 0.26, 0.01};
  double U[3], val, limit = 1.0;
  const BondView v = bond(xi, Y, U, Aa, Ac, 3.0);
  // (A_a + A_c) = [[3,2,0],[1,4,0],[0,0,5]]: T = (1.5+0.5, 0.5+1.0, 0)
  const double T[3] = {2.0, 1.5, 0.0};
  const double expect = 0.5 * (T[0] * U[0] + T[1] * U[1] + T[2] * U[2]);
  EnergyCriterion constant{false}, inverse{true};
  ASSERT_TRUE(constant(v, val, limit));
  EXPECT_NEAR(val, expect, 1e-15);
  ASSERT_TRUE(inverse(v, val, limit));
  EXPECT_NEAR(val, 3.0 / v.rxi * expect, 1e-14);    // omega = delta/|xi|
  const double shorter[3] = {0.49, 0.245, 0.0};
  EXPECT_FALSE(constant(bond(xi, shorter, U, Aa, Ac), val, limit));
}

TEST(DamageCriteria, AlphaLowersTheLimitByTheEndsSmallestStretch)
{
  // Silling & Askari: s_0 = s_00 - alpha s_min, the larger s_min of the ends
  const double smin_a[1] = {-0.002}, smin_c[1] = {0.001};
  const double xi[3] = {1, 0, 0}, Y[3] = {1.004, 0, 0};
  double U[3], val, limit = 0.005;
  AlphaStretchCriterion crit{0.25};
  ASSERT_TRUE(crit(bond(xi, Y, U, smin_a, smin_c), val, limit));
  EXPECT_NEAR(val, 0.004, 1e-15);
  EXPECT_DOUBLE_EQ(limit, 0.005 - 0.25 * 0.001);
  EXPECT_TRUE(AlphaStretchCriterion::TRACKS_SMIN);
  EXPECT_FALSE(EnergyCriterion::TRACKS_SMIN);
}

TEST(DamageCriteria, PointFailureTakesTheFailedEnd)
{
  const double a[1] = {0.3}, c[1] = {1.2};
  const double xi[3] = {1, 0, 0};
  double U[3], val, limit = 1.0;
  PointFailureCriterion crit;
  ASSERT_TRUE(crit(bond(xi, xi, U, a, c), val, limit));
  EXPECT_EQ(val, 1.2);
  ASSERT_TRUE(crit(bond(xi, xi, U, c, a), val, limit));
  EXPECT_EQ(val, 1.2);
}

// a bond of a body expanding freely by its thermal strain e has no
// mechanical stretch nor displacement, small strain and Hencky alike; a bond
// held at its length while cooled by e < 0 is stretched by -e (small) and
// 1/(1+e) - 1 (Hencky), the two agreeing to first order
TEST(DamageCriteria, ThermalStrainLeavesTheMechanicalPart)
{
  const double e = 2.0e-3;
  const double xi[3] = {1.0, 2.0, -0.5};
  const double Y[3] = {(1 + e) * xi[0], (1 + e) * xi[1], (1 + e) * xi[2]};
  const double s = std::sqrt((Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]) /
                             (xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2])) - 1.0;
  double Um[3];
  for (bool small : {true, false}) {
    EXPECT_NEAR(mechanical_stretch(small, e, s), 0.0, 1e-15);
    mechanical_displacement(small, e, xi, Y, Um);
    for (int k = 0; k < 3; k++) EXPECT_NEAR(Um[k], 0.0, 1e-15);
    // held at xi while cooled: stretched by the thermal contraction
    mechanical_displacement(small, -e, xi, xi, Um);
    for (int k = 0; k < 3; k++) EXPECT_NEAR(Um[k], (small ? e : e / (1 - e)) * xi[k], 1e-15);
  }
  EXPECT_DOUBLE_EQ(mechanical_stretch(true, -e, 0.0), e);
  EXPECT_NEAR(mechanical_stretch(false, -e, 0.0), e / (1 - e), 1e-15);
  EXPECT_NEAR(mechanical_stretch(false, -e, 0.0), mechanical_stretch(true, -e, 0.0), 2 * e * e);
}

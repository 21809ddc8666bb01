/* The contact memory (nospd_contact_memory.h): a bond that breaks while its
   ends are closer than the contact rest distance must not switch on a
   loaded contact spring.  The rules are checked one by one, then on two
   points in 1D: a bonded pair squeezed together, its bond cut at the
   closest approach, then left to fly, bounce and separate: with the memory
   the energy never rises above its value before the cut (and the pair
   still repels when pushed closer), without it the cut creates the loaded
   spring's energy. */

#include "nospd_contact_memory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using NOSPD::ContactMemory;

TEST(ContactMemory, RemembersOnlyPairsBelowTheRestDistance)
{
  double rec[ContactMemory::RECORD];
  ContactMemory::clear(rec);
  EXPECT_TRUE(ContactMemory::remember(rec, 7.0, 1.0, 0.9));    // open: nothing to keep
  EXPECT_EQ(ContactMemory::count(rec), 0);
  EXPECT_TRUE(ContactMemory::remember(rec, 7.0, 0.8, 0.9));
  EXPECT_TRUE(ContactMemory::remember(rec, 9.0, 0.7, 0.9));
  EXPECT_TRUE(ContactMemory::remember(rec, 7.0, 0.85, 0.9));    // the smaller stays
  ASSERT_EQ(ContactMemory::count(rec), 2);
  EXPECT_EQ(ContactMemory::find(rec, 7.0), 0);
  EXPECT_EQ(ContactMemory::find(rec, 9.0), 1);
  EXPECT_EQ(ContactMemory::find(rec, 8.0), -1);
  EXPECT_EQ(rec[2], 0.8);
  EXPECT_EQ(ContactMemory::used(rec), 5);
}

TEST(ContactMemory, RestRisesWithTheOpeningUpToNominalThenIsForgotten)
{
  double rec[ContactMemory::RECORD];
  ContactMemory::clear(rec);
  ContactMemory::remember(rec, 3.0, 0.5, 0.9);
  ContactMemory::remember(rec, 4.0, 0.6, 0.9);
  bool keep[ContactMemory::CAPACITY] = {};
  EXPECT_EQ(ContactMemory::rest(rec, 0, 0.45, 0.9, keep), 0.5);    // closer: stays
  EXPECT_EQ(ContactMemory::rest(rec, 0, 0.7, 0.9, keep), 0.7);     // opened: follows
  EXPECT_TRUE(keep[0]);
  EXPECT_EQ(ContactMemory::rest(rec, 0, 0.6, 0.9, keep), 0.7);     // never back down
  EXPECT_EQ(ContactMemory::rest(rec, 0, 1.2, 0.9, keep), 0.9);     // at most nominal
  EXPECT_FALSE(keep[0]);
  EXPECT_EQ(ContactMemory::rest(rec, -1, 0.3, 0.9, keep), 0.9);    // unknown pair: nominal
  // slot 1 not seen (out of range), slot 0 back at nominal: both dropped
  ContactMemory::prune(rec, keep);
  EXPECT_EQ(ContactMemory::count(rec), 0);

  ContactMemory::remember(rec, 3.0, 0.5, 0.9);
  ContactMemory::remember(rec, 4.0, 0.6, 0.9);
  bool keep2[ContactMemory::CAPACITY] = {};
  ContactMemory::rest(rec, 1, 0.65, 0.9, keep2);
  ContactMemory::prune(rec, keep2);
  ASSERT_EQ(ContactMemory::count(rec), 1);
  EXPECT_EQ(rec[1], 4.0);
  EXPECT_EQ(rec[2], 0.65);
}

TEST(ContactMemory, FullRecordSaysSo)
{
  double rec[ContactMemory::RECORD];
  ContactMemory::clear(rec);
  for (int k = 0; k < ContactMemory::CAPACITY; k++)
    EXPECT_TRUE(ContactMemory::remember(rec, 10.0 + k, 0.5, 0.9));
  EXPECT_FALSE(ContactMemory::remember(rec, 99.0, 0.5, 0.9));
  EXPECT_TRUE(ContactMemory::remember(rec, 10.0, 0.4, 0.9));    // known pair: still fine
  EXPECT_EQ(ContactMemory::count(rec), ContactMemory::CAPACITY);
}

namespace {
// Two unit masses on a line at distance r, a bond spring kb (rest length
// L) until step ncut, then the contact spring kc below the rest distance
// d0 = 0.9 L (both ends keep their own memory, as in the fix).  Returns the
// largest energy after the cut minus the kinetic energy at the cut (the
// cut bond's energy is released: a remembered contact starts unloaded),
// and the smallest distance reached after the cut.
struct Outcome {
  double rise, rmin;
};
Outcome squeeze_and_cut(bool memory, double v0, int ncut)
{
  const double kb = 1.0, kc = 15.0, L = 1.0, d0 = 0.9 * L, dt = 0.01;
  double x1 = 0.0, x2 = L, v1 = v0, v2 = -v0;
  double rec1[ContactMemory::RECORD], rec2[ContactMemory::RECORD];
  ContactMemory::clear(rec1);
  ContactMemory::clear(rec2);
  bool bonded = true;
  auto force = [&](double &e) {    // force on 1 along +x; e the energy
    const double r = x2 - x1;
    if (bonded) {
      e = 0.5 * kb * (r - L) * (r - L);
      return kb * (r - L);
    }
    bool keep1[ContactMemory::CAPACITY] = {}, keep2[ContactMemory::CAPACITY] = {};
    const double d = ContactMemory::rest(rec1, ContactMemory::find(rec1, 2.0), r, d0, keep1);
    const double d2 = ContactMemory::rest(rec2, ContactMemory::find(rec2, 1.0), r, d0, keep2);
    EXPECT_EQ(d, d2);    // both ends agree
    ContactMemory::prune(rec1, keep1);
    ContactMemory::prune(rec2, keep2);
    e = (r < d) ? 0.5 * kc * (r - d) * (r - d) : 0.0;
    return (r < d) ? kc * (r - d) : 0.0;
  };
  double e = 0.0, f = force(e), before = 0.0, rise = -1e300, rmin = 1e300;
  for (int s = 0; s < 4000; s++) {
    v1 += 0.5 * dt * f;
    v2 -= 0.5 * dt * f;
    x1 += dt * v1;
    x2 += dt * v2;
    if (s == ncut) {
      before = 0.5 * (v1 * v1 + v2 * v2);    // the bond's energy goes with it
      if (memory) {
        ContactMemory::remember(rec1, 2.0, x2 - x1, d0);
        ContactMemory::remember(rec2, 1.0, x2 - x1, d0);
      }
      bonded = false;
    }
    f = force(e);
    v1 += 0.5 * dt * f;
    v2 -= 0.5 * dt * f;
    if (s >= ncut) {
      rise = std::max(rise, e + 0.5 * (v1 * v1 + v2 * v2) - before);
      rmin = std::min(rmin, x2 - x1);
    }
  }
  return {rise, rmin};
}
}    // namespace

TEST(ContactMemory, BreakingACompressedBondCreatesNoEnergy)
{
  // squeezed to r = 0.5 (v0 = 0.5, bond period 2 pi / sqrt(2)): cut near
  // the closest approach, still moving together, and after it, at rest
  for (int ncut : {100, 111}) {
    const Outcome with = squeeze_and_cut(true, 0.5, ncut);
    const Outcome without = squeeze_and_cut(false, 0.5, ncut);
    // Verlet's energy error on the contact spring is O(dt^2): 1e-4 here
    EXPECT_LT(with.rise, 1e-4) << "cut at step " << ncut;
    // without the memory the cut loads the contact spring: 1/2 kc (d0 - r)^2
    EXPECT_GT(without.rise, 0.5) << "cut at step " << ncut;
    // the remembered contact still repels: the pair does not pass through
    EXPECT_GT(with.rmin, 0.0);
  }
}

/* The energy audit (nospd_energy_audit.h) on a mass between two springs,
   integrated by velocity Verlet with the work taken as fix nospd/damage
   takes it (-1/2 dt f . v at the half step, with the force of either end
   of the step).  Elastic: the audit's wander stays below its noise floor.
   A spring that breaks takes its energy away: released grows, nothing is
   created.  A spring that comes back loaded (what a contact switched on
   inside its rest distance would do) creates its energy: flagged. */

#include "nospd_energy_audit.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

struct Oscillator {
  double k1 = 4.0, k2 = 9.0;    // two springs from the mass to the wall
  double rest2 = 0.0;           // spring 2's rest position
  bool spring2 = true;
  double x = 0.3, v = 0.0, m = 1.0, dt = 0.01, W = 0.0;
  double force() const { return -k1 * x - (spring2 ? k2 * (x - rest2) : 0.0); }
  double energy() const
  {
    return 0.5 * k1 * x * x + (spring2 ? 0.5 * k2 * (x - rest2) * (x - rest2) : 0.0);
  }
  // one step; `change` alters the springs between the move and the new
  // force, as the damage fix breaks bonds in pre_force
  template <class Change> void step(Change change)
  {
    const double f0 = force();
    v += 0.5 * dt * f0 / m;
    x += dt * v;
    W -= 0.5 * dt * f0 * v;    // post_integrate: the old force
    change();
    const double f1 = force();
    W -= 0.5 * dt * f1 * v;    // post_force: the new one
    v += 0.5 * dt * f1 / m;
  }
};

}    // namespace

TEST(EnergyAudit, ElasticMotionStaysBelowTheFloor)
{
  Oscillator o;
  NOSPD::EnergyAudit a;
  a.observe(o.W, o.energy(), 0.0);
  for (int n = 0; n < 2000; n++) {
    o.step([] {});
    a.observe(o.W, o.energy(), 0.0);
  }
  EXPECT_GT(a.work_scale(), 0.3);
  EXPECT_LT(a.created(), 1.0e-3 * a.work_scale()) << a.created();
  EXPECT_FALSE(a.creates(0.01, 1.0e-3));
}

TEST(EnergyAudit, ABreakReleasesAndCreatesNothing)
{
  Oscillator o;
  NOSPD::EnergyAudit a;
  a.observe(o.W, o.energy(), 0.0);
  double held = 0.0;
  for (int n = 0; n < 400; n++) {
    const bool cut = n == 100;
    if (cut) held = 0.5 * o.k2 * o.x * o.x;    // about what spring 2 holds
    o.step([&] {
      if (cut) o.spring2 = false;
    });
    a.observe(o.W, o.energy(), 0.0);
  }
  EXPECT_GT(held, 0.01);
  EXPECT_NEAR(a.released(), held, 0.1 * held);
  EXPECT_GT(a.dissipated(), 0.5 * held);
  EXPECT_FALSE(a.creates(0.01, 1.0e-3)) << a.created() << " of " << a.dissipated();
}

TEST(EnergyAudit, ASpringComingBackLoadedIsCreatedEnergy)
{
  Oscillator o;
  NOSPD::EnergyAudit a;
  a.observe(o.W, o.energy(), 0.0);
  for (int n = 0; n < 400; n++) {
    o.step([&] {
      if (n == 100) o.spring2 = false;    // released
      if (n == 250) {                     // back, stretched: energy from nothing
        o.spring2 = true;
        o.rest2 = o.x + 0.2;
      }
    });
    a.observe(o.W, o.energy(), 0.0);
  }
  EXPECT_NEAR(a.created(), 0.5 * o.k2 * 0.04, 0.05 * 0.5 * o.k2 * 0.04);
  EXPECT_TRUE(a.creates(0.01, 1.0e-3));
}

TEST(EnergyAudit, DissipationCountsAndTheFirstObservationIsTheReference)
{
  NOSPD::EnergyAudit a;
  EXPECT_FALSE(a.creates(0.01, 1.0e-3));
  a.observe(5.0, 2.0, 1.0);      // reference: W0 5, E0 2, D0 1
  a.observe(15.0, 4.0, 4.0);     // work 10: 2 stored, 3 plastic, 5 released
  EXPECT_DOUBLE_EQ(a.released(), 5.0);
  EXPECT_DOUBLE_EQ(a.dissipated(), 8.0);
  a.observe(15.0, 4.5, 4.0);     // 0.5 stored from nothing
  EXPECT_DOUBLE_EQ(a.created(), 0.5);
  EXPECT_TRUE(a.creates(0.01, 1.0e-3));
  EXPECT_FALSE(a.creates(0.1, 1.0e-3));    // 0.5 of 7.5 dissipated: 6.7 %
}

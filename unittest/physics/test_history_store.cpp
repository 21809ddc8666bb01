/* The bonds fix's history store (nospd_history_store.h) on its own: a
   record packed on one rank and unpacked on another keeps every value of
   the atom and of its intact partner slots, in slot order, broken slots
   dropped; a layout that grows keeps the values and zeroes the new columns
   (the virgin state); commit makes the trial rows the accepted ones, and a
   minimization reports its trial rows until then. */

#include "nospd_history_store.h"
#include "nospd_test_util.h"

#include "memory.h"

#include <gtest/gtest.h>

using namespace nospdtest;
using LAMMPS_NS::LAMMPS;
using LAMMPS_NS::NospdHistoryStore;

namespace {
// a value no other (atom, column) of the test shares
double value(int i, int k)
{
  return 1000.0 * (i + 1) + k + 0.5;
}
}    // namespace

TEST(HistoryStore, MigrationKeepsIntactSlotsInOrder)
{
  LAMMPS *lmp = open_lammps();
  NospdHistoryStore a(lmp->memory), b(lmp->memory);
  const int na = 3, nb = 2, slots = 4, nmax = 5;
  a.layout(na, nb, slots, nmax);
  b.layout(na, nb, slots, nmax);
  ASSERT_EQ(a.n, na + nb * slots);
  for (int i = 0; i < nmax; i++)
    for (int k = 0; k < a.n; k++) a.accepted[i][k] = value(i, k);
  // slot 1 broken: its entry stays behind, slots 0, 2, 3 arrive as 0, 1, 2
  const LAMMPS_NS::tagint partner[4] = {7, 0, 9, 11};
  std::vector<double> buf(a.n);
  const int m = a.pack(2, buf.data(), 4, partner);
  EXPECT_EQ(m, na + 3 * nb);
  EXPECT_EQ(b.unpack(4, buf.data(), na, nb, 3), m);
  for (int k = 0; k < na; k++) EXPECT_EQ(b.accepted[4][k], value(2, k));
  const int from[3] = {0, 2, 3};
  for (int s = 0; s < 3; s++)
    for (int k = 0; k < nb; k++)
      EXPECT_EQ(b.bond(b.accepted[4], s)[k], a.bond(a.accepted[2], from[s])[k]) << s;
  for (int k = 0; k < nb; k++) EXPECT_EQ(b.bond(b.accepted[4], 3)[k], 0.0);
  for (int k = 0; k < b.n; k++) EXPECT_EQ(b.trial[4][k], b.accepted[4][k]);
  delete lmp;
}

TEST(HistoryStore, GrowingLayoutKeepsValuesAndZeroesNewColumns)
{
  LAMMPS *lmp = open_lammps();
  NospdHistoryStore h(lmp->memory);
  h.layout(2, 1, 2, 3);
  for (int i = 0; i < 3; i++)
    for (int k = 0; k < h.n; k++) h.accepted[i][k] = value(i, k);
  h.layout(4, 3, 5, 3);    // more atom values, more per slot, more slots
  ASSERT_EQ(h.n, 4 + 3 * 5);
  for (int i = 0; i < 3; i++) {
    for (int k = 0; k < 4; k++) EXPECT_EQ(h.accepted[i][k], k < 2 ? value(i, k) : 0.0);
    for (int s = 0; s < 5; s++)
      for (int k = 0; k < 3; k++)
        EXPECT_EQ(h.bond(h.accepted[i], s)[k], (s < 2 && k < 1) ? value(i, 2 + s) : 0.0);
    for (int k = 0; k < h.n; k++) EXPECT_EQ(h.trial[i][k], h.accepted[i][k]);
  }
  h.layout(0, 0, 0, 3);
  EXPECT_EQ(h.n, 0);
  EXPECT_EQ(h.accepted, nullptr);
  delete lmp;
}

TEST(HistoryStore, CommitAcceptsTheTrialRows)
{
  LAMMPS *lmp = open_lammps();
  NospdHistoryStore h(lmp->memory);
  h.layout(2, 0, 0, 2);
  for (int i = 0; i < 2; i++) {
    h.accepted[i][0] = 1.0;
    h.trial[i][0] = 2.0 + i;
  }
  h.commit();    // no force evaluation since: nothing to accept
  EXPECT_EQ(h.accepted[0][0], 1.0);
  h.trial_ready = true;
  EXPECT_EQ(h.current(true)[1][0], 3.0);     // a minimization shows its latest
  EXPECT_EQ(h.current(false)[1][0], 1.0);    // a run its accepted state
  EXPECT_EQ(h.local_sum(0, 2, true), 5.0);
  h.commit();
  EXPECT_EQ(h.accepted[0][0], 2.0);
  EXPECT_EQ(h.accepted[1][0], 3.0);
  EXPECT_FALSE(h.trial_ready);
  delete lmp;
}

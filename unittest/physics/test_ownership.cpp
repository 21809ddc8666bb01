/* Two late core rules of the bonds fix:
   - under pair hybrid, peri/nospd owns only the types pair_coeff gives it:
     other atoms get no family, no checks and are not singular families;
   - the broken-bond count survives a restart (broken slots are not
     written, the original family size is). */

#include "nospd_test_util.h"

#include <cstdio>

#include "fix_nospd_bonds.h"

using namespace nospdtest;
using LAMMPS_NS::FixNospdBonds;

namespace {

FixNospdBonds *bonds(LAMMPS *lmp)
{
  return static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
}

TEST(Ownership, HybridOtherTypeHasNoFamily)
{
  LAMMPS *lmp = open_lammps();
  cmd(lmp, "units si");
  cmd(lmp, "atom_style peri");
  cmd(lmp, "atom_modify map array");
  cmd(lmp, "lattice sc 0.001");
  cmd(lmp, "region box block -0.25 7.75 -0.25 7.75 -0.25 7.75");
  cmd(lmp, "create_box 2 box");
  cmd(lmp, "create_atoms 1 box");
  // type 2: a few particles far from each other, not part of the body
  cmd(lmp, "region top block -0.25 7.75 -0.25 7.75 6.5 7.75");
  cmd(lmp, "set region top type 2");
  cmd(lmp, "set group all density 7850");
  cmd(lmp, "set group all volume 1e-9");
  cmd(lmp, "pair_style hybrid/overlay peri/nospd soft 0.001");
  cmd(lmp, "pair_coeff 1 1 peri/nospd 200e9 0.3 0.00301");
  cmd(lmp, "pair_coeff * 2 soft 1.0e6");
  EXPECT_EQ(error_of(lmp, "run 0"), "");
  auto *fb = bonds(lmp);
  ASSERT_NE(fb, nullptr);
  EXPECT_EQ(fb->nsingular, 0);
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const int nb = fb->bond_first[i + 1] - fb->bond_first[i];
    if (lmp->atom->type[i] == 2) {
      EXPECT_EQ(nb, 0);
      EXPECT_EQ(fb->singular[i], 2);
    } else {
      EXPECT_GT(nb, 0);
    }
  }
  delete lmp;
}

TEST(Ownership, BrokenCountSurvivesRestart)
{
  LAMMPS *lmp = open_lammps();
  Block blk;
  blk.n = 8;
  make_block(lmp, blk);
  cmd(lmp, "run 0");
  auto *fb = bonds(lmp);
  // break the bonds of atom 1 on both ends
  const int i = lmp->atom->map(1);
  int nbroken = 0;
  for (int s = 0; s < fb->npartner[i]; s++) {
    const int j = lmp->atom->map(fb->partner[i][s]);
    for (int t = 0; t < fb->npartner[j]; t++)
      if (fb->partner[j][t] == 1) fb->partner[j][t] = 0;
    fb->partner[i][s] = 0;
    nbroken++;
  }
  cmd(lmp, "run 0");
  const double before = fb->compute_vector(1);
  EXPECT_EQ(before, 2.0 * nbroken);
  cmd(lmp, "write_restart ownership.restart");
  cmd(lmp, "clear");
  cmd(lmp, "read_restart ownership.restart");
  std::remove("ownership.restart");    // ctest runs in the build folder; leave nothing behind
  cmd(lmp, "run 0");
  EXPECT_EQ(bonds(lmp)->compute_vector(1), before);
  delete lmp;
}

}    // namespace

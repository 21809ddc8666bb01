/* compute nospd/bond/local: under a homogeneous deformation y = F0 X every
   bond-associated deformation gradient is F0 (the HS patch test seen
   through the output), and the stretch column is |F0 xi|/|xi| - 1. */

#include "nospd_test_util.h"

#include "nospd_tensor.h"

using namespace nospdtest;

namespace {

class BondLocal : public ::testing::TestWithParam<std::string> {};

TEST_P(BondLocal, PatchTestThroughOutput)
{
  LAMMPS *lmp = open_lammps();
  Block blk;
  blk.n = 9;
  blk.style = GetParam();
  blk.settings = GetParam() == "peri/nospd/hs" ? "form II" : "";
  make_block(lmp, blk);
  cmd(lmp, "compute b all nospd/bond/local id stretch F own");
  cmd(lmp, "run 0");
  NOSPD::Mat3 F0;
  F0 << 1.01, 0.02, -0.01, 0.005, 0.99, 0.015, -0.02, 0.01, 1.012;
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const NOSPD::Vec3 X(x0[i][0], x0[i][1], x0[i][2]);
    const NOSPD::Vec3 y = F0 * X;
    for (int k = 0; k < 3; k++) x[i][k] = y[k];
  }
  cmd(lmp, "run 0");
  auto *c = lmp->modify->get_compute_by_id("b");
  c->compute_local();
  ASSERT_GT(c->size_local_rows, 1000);
  int nown = 0;
  for (int r = 0; r < c->size_local_rows; r++) {
    const double *row = c->array_local[r];
    const int i = lmp->atom->map((int) row[0]), j = lmp->atom->map((int) row[1]);
    ASSERT_GE(i, 0);
    ASSERT_GE(j, 0);
    NOSPD::Vec3 xi(x0[j][0] - x0[i][0], x0[j][1] - x0[i][1], x0[j][2] - x0[i][2]);
    EXPECT_NEAR(row[2], (F0 * xi).norm() / xi.norm() - 1.0, 1e-12);
    for (int k = 0; k < 9; k++) EXPECT_NEAR(row[3 + k], F0(k / 3, k % 3), 1e-12);
    nown += (int) row[12];
  }
  if (GetParam() == "peri/nospd/hs") EXPECT_EQ(nown, c->size_local_rows);
  else EXPECT_EQ(nown, 0);
  delete lmp;
}

INSTANTIATE_TEST_SUITE_P(Styles, BondLocal, ::testing::Values("peri/nospd", "peri/nospd/hs"),
                         [](const ::testing::TestParamInfo<std::string> &p) {
                           return p.param == "peri/nospd" ? std::string("classical")
                                                          : std::string("hs");
                         });

}    // namespace

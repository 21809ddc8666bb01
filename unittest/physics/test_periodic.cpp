/* Periodic boxes: the patch test everywhere (no surface), also after the
   box itself is deformed (change_box ... remap, as fix deform does): bonds
   that cross the boundary keep their reference length, so F is the box's
   stretch at every atom and the forces vanish. */

#include "nospd_test_util.h"

#include "fix_nospd_bonds.h"
#include "nospd_tensor.h"

using namespace nospdtest;

namespace {

class Periodic : public ::testing::TestWithParam<int> {};

TEST_P(Periodic, StretchedBoxPatchTest)
{
  LAMMPS *lmp = open_lammps();
  Block blk;
  blk.dim = GetParam();
  blk.n = blk.dim == 3 ? 8 : 12;
  blk.periodic = true;
  blk.settings = "strain svk stabilization silling 0.5";
  make_block(lmp, blk);
  cmd(lmp, "run 0");
  // stretch x by 1 %, shrink y by 0.5 %, atoms remapped with the box
  cmd(lmp, "change_box all x scale 1.01 y scale 0.995 remap");
  cmd(lmp, "run 0");
  auto *fb = static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  NOSPD::Mat3 F0 = NOSPD::Mat3::Identity();
  F0(0, 0) = 1.01;
  F0(1, 1) = 0.995;
  double dF = 0.0, fmax = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    dF = std::max(dF, (NOSPD::load(fb->defgrad[i]) - F0).cwiseAbs().maxCoeff());
    for (int k = 0; k < 3; k++) fmax = std::max(fmax, std::abs(lmp->atom->f[i][k]));
  }
  EXPECT_LT(dF, 1e-12);
  EXPECT_LT(fmax, 1e-9 * blk.E / blk.dx);
  // the energy is N W(F0) with W of the law: nonzero and uniform
  EXPECT_GT(lmp->force->pair->eng_vdwl, 0.0);
  delete lmp;
}

INSTANTIATE_TEST_SUITE_P(Box, Periodic, ::testing::Values(3, 2),
                         [](const ::testing::TestParamInfo<int> &p) {
                           return std::to_string(p.param) + "D";
                         });

}    // namespace

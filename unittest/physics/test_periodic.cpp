/* Periodic boxes: the patch test everywhere (no surface), also after the
   box itself is deformed (change_box ... remap, as fix deform does): bonds
   that cross the boundary keep their reference length, so F is the box's
   stretch at every atom and the forces vanish. */

#include "nospd_test_util.h"

#include "domain.h"
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

// the same for a sheared triclinic box: bonds across the boundary take the
// reference box's tilts (not the current ones) at every setup and
// reneighboring, so F is the box's deformation at every atom
TEST_P(Periodic, ShearedBoxPatchTest)
{
  LAMMPS *lmp = open_lammps();
  Block blk;
  blk.dim = GetParam();
  blk.n = blk.dim == 3 ? 8 : 12;
  blk.periodic = true;
  blk.settings = "strain svk stabilization silling 0.5";
  make_block(lmp, blk);
  cmd(lmp, "change_box all triclinic");
  cmd(lmp, "run 0");
  auto box = [&] {
    const double *h = lmp->domain->h;
    NOSPD::Mat3 m;
    m << h[0], h[5], h[4], 0.0, h[1], h[3], 0.0, 0.0, h[2];
    return m;
  };
  const NOSPD::Mat3 H0 = box();
  const double L = blk.n * blk.dx;
  cmd(lmp, "change_box all xy final " + num(0.02 * L) + " x scale 1.01 remap units box");
  if (blk.dim == 3)
    cmd(lmp, "change_box all xz final " + num(-0.01 * L) + " yz final " + num(0.015 * L) +
             " remap units box");
  cmd(lmp, "run 0");
  // twice: the second setup takes the box from the first one's state
  cmd(lmp, "run 0");
  const NOSPD::Mat3 F0 = box() * H0.inverse();
  auto *fb = static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  double dF = 0.0, fmax = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    dF = std::max(dF, (NOSPD::load(fb->defgrad[i]) - F0).cwiseAbs().maxCoeff());
    for (int k = 0; k < 3; k++) fmax = std::max(fmax, std::abs(lmp->atom->f[i][k]));
  }
  EXPECT_GT(std::abs(F0(0, 1)), 0.01);
  EXPECT_LT(dF, 1e-12);
  EXPECT_LT(fmax, 1e-9 * blk.E / blk.dx);
  delete lmp;
}

INSTANTIATE_TEST_SUITE_P(Box, Periodic, ::testing::Values(3, 2),
                         [](const ::testing::TestParamInfo<int> &p) {
                           return std::to_string(p.param) + "D";
                         });

}    // namespace

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

class Periodic : public ::testing::TestWithParam<int> {
 protected:
  Block blk;
  // an 8^3 (3D) or 12^2 (2D) periodic block
  LAMMPS *periodic_block()
  {
    LAMMPS *lmp = open_lammps();
    blk.dim = GetParam();
    blk.n = blk.dim == 3 ? 8 : 12;
    blk.periodic = true;
    blk.settings = "strain svk stabilization silling 0.5";
    make_block(lmp, blk);
    return lmp;
  }
  static NOSPD::Mat3 box(LAMMPS *lmp)
  {
    const double *h = lmp->domain->h;
    NOSPD::Mat3 m;
    m << h[0], h[5], h[4], 0.0, h[1], h[3], 0.0, 0.0, h[2];
    return m;
  }
  // families built in the triclinic box, then sheared and stretched with
  // the atoms (in 3D in all three tilts); returns the box of the families
  NOSPD::Mat3 shear_after_first_run(LAMMPS *lmp)
  {
    cmd(lmp, "change_box all triclinic");
    cmd(lmp, "run 0");
    const NOSPD::Mat3 H0 = box(lmp);
    const double L = blk.n * blk.dx;
    cmd(lmp, "change_box all xy final " + num(0.02 * L) + " x scale 1.01 remap units box");
    if (blk.dim == 3)
      cmd(lmp, "change_box all xz final " + num(-0.01 * L) + " yz final " + num(0.015 * L) +
               " remap units box");
    cmd(lmp, "run 0");
    return H0;
  }
  std::string coeff() const
  {
    return "pair_coeff * * " + num(blk.E) + " " + num(blk.nu) + " " + num(blk.delta());
  }
  // F is F0 at every atom and the forces vanish
  void expect_uniform(LAMMPS *lmp, const NOSPD::Mat3 &F0)
  {
    auto *fb =
        static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
    double dF = 0.0, fmax = 0.0;
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      dF = std::max(dF, (NOSPD::load(fb->defgrad[i]) - F0).cwiseAbs().maxCoeff());
      for (int k = 0; k < 3; k++) fmax = std::max(fmax, std::abs(lmp->atom->f[i][k]));
    }
    EXPECT_LT(dF, 1e-12);
    EXPECT_LT(fmax, 1e-9 * blk.E / blk.dx);
  }
};

TEST_P(Periodic, StretchedBoxPatchTest)
{
  LAMMPS *lmp = periodic_block();
  cmd(lmp, "run 0");
  // stretch x by 1 %, shrink y by 0.5 %, atoms remapped with the box
  cmd(lmp, "change_box all x scale 1.01 y scale 0.995 remap");
  cmd(lmp, "run 0");
  NOSPD::Mat3 F0 = NOSPD::Mat3::Identity();
  F0(0, 0) = 1.01;
  F0(1, 1) = 0.995;
  expect_uniform(lmp, F0);
  // the energy is N W(F0) with W of the law: nonzero and uniform
  EXPECT_GT(lmp->force->pair->eng_vdwl, 0.0);
  delete lmp;
}

// the same for a sheared triclinic box: bonds across the boundary take the
// reference box's tilts (not the current ones) at every setup and
// reneighboring, so F is the box's deformation at every atom
TEST_P(Periodic, ShearedBoxPatchTest)
{
  LAMMPS *lmp = periodic_block();
  const NOSPD::Mat3 H0 = shear_after_first_run(lmp);
  // twice: the second setup takes the box from the first one's state
  cmd(lmp, "run 0");
  const NOSPD::Mat3 F0 = box(lmp) * H0.inverse();
  EXPECT_GT(std::abs(F0(0, 1)), 0.01);
  expect_uniform(lmp, F0);
  delete lmp;
}

// the box changed before the first run: with the atoms (change_box ...
// remap) it is a pre-strain, and the box at pair_coeff, where x0 were
// placed, is the reference box; without them it is a new box for the same
// reference body, and F is the identity
TEST_P(Periodic, BoxChangedBeforeFirstRun)
{
  for (const bool remap : {true, false}) {
    SCOPED_TRACE(remap ? "remap" : "no remap");
    LAMMPS *lmp = periodic_block();
    cmd(lmp, "change_box all triclinic");
    const NOSPD::Mat3 H0 = box(lmp);
    const double L = blk.n * blk.dx;
    const std::string how = remap ? " remap units box" : " units box";
    cmd(lmp, "change_box all xy final " + num(0.02 * L) + " x scale 1.01 y scale 0.995" + how);
    cmd(lmp, "run 0");
    expect_uniform(lmp, remap ? NOSPD::Mat3(box(lmp) * H0.inverse()) : NOSPD::Mat3::Identity());
    if (remap)
      EXPECT_GT(lmp->force->pair->eng_vdwl, 0.0);
    else
      EXPECT_LT(std::abs(lmp->force->pair->eng_vdwl), 1e-20 * blk.E);
    delete lmp;
  }
}

// a pair_style command in a box deformed since the families were built:
// the new style's families come from the same x0 and keep the reference
// box of the old ones, so F is still the box's deformation everywhere
TEST_P(Periodic, PairStyleChangedInDeformedBox)
{
  LAMMPS *lmp = periodic_block();
  const NOSPD::Mat3 H0 = shear_after_first_run(lmp);
  cmd(lmp, "pair_style peri/nospd/hs strain svk");
  cmd(lmp, coeff());
  cmd(lmp, "run 0");
  cmd(lmp, "pair_style peri/nospd " + blk.settings);
  cmd(lmp, coeff());
  cmd(lmp, "run 0");
  expect_uniform(lmp, box(lmp) * H0.inverse());
  delete lmp;
}

// the same through a restart file: read under the other style (families
// built anew in the reference box the file holds), then switched back; or
// read under the same style (the file's families) and then switched
TEST_P(Periodic, RestartInDeformedBoxThenOtherStyle)
{
  const std::string rfile = "nospd_periodic_" + std::to_string(GetParam()) + "d.restart";
  LAMMPS *lmp = periodic_block();
  cmd(lmp, "run 0");
  NOSPD::Mat3 F0 = NOSPD::Mat3::Identity();
  F0(0, 0) = 1.01;
  F0(1, 1) = 0.995;
  cmd(lmp, "change_box all x scale 1.01 y scale 0.995 remap");
  cmd(lmp, "run 0");
  cmd(lmp, "write_restart " + rfile);
  delete lmp;
  for (const bool same_style_first : {false, true}) {
    SCOPED_TRACE(same_style_first ? "read under peri/nospd" : "read under peri/nospd/hs");
    lmp = open_lammps();
    cmd(lmp, "read_restart " + rfile);
    const std::string classical = "pair_style peri/nospd " + blk.settings;
    const std::string hs = "pair_style peri/nospd/hs strain svk";
    for (const std::string &style : same_style_first ? std::vector<std::string>{classical, hs}
                                                     : std::vector<std::string>{hs, classical}) {
      cmd(lmp, style);
      cmd(lmp, coeff());
      cmd(lmp, "run 0");
      // a uniform F: no force under either style
      double fmax = 0.0;
      for (int i = 0; i < lmp->atom->nlocal; i++)
        for (int k = 0; k < 3; k++) fmax = std::max(fmax, std::abs(lmp->atom->f[i][k]));
      EXPECT_LT(fmax, 1e-9 * blk.E / blk.dx) << style;
      EXPECT_GT(lmp->force->pair->eng_vdwl, 0.0);
      if (style == classical) expect_uniform(lmp, F0);
    }
    delete lmp;
  }
  std::remove(rfile.c_str());
}

/* A uniform deformation of a periodic body (the box deformed after the
   families were built: stretched along x, or sheared through its tilt)
   breaks the same bonds at every point: the damage fix measures each bond
   against the reference bond the forces use.  It once imaged x0
   differences in the current box, so the bonds across the boundary looked
   shorter than they are, and the points next to it lost fewer (damage
   0.16-0.20 there, 0.31 inside, under a uniform stretch). */
TEST_P(Periodic, UniformDeformationBreaksBondsUniformly)
{
  for (const std::string style : {"peri/nospd", "peri/nospd/hs"})
    for (const bool tilt : {false, true}) {
      SCOPED_TRACE(style + (tilt ? ", sheared through the tilt" : ", stretched"));
      LAMMPS *lmp = open_lammps();
      blk.dim = GetParam();
      blk.n = blk.dim == 3 ? 8 : 12;
      blk.periodic = true;
      blk.style = style;
      blk.settings = "strain small";
      make_block(lmp, blk);
      if (tilt) cmd(lmp, "change_box all triclinic");
      cmd(lmp, "run 0");
      const double L = blk.n * blk.dx;
      cmd(lmp, tilt ? "change_box all xy final " + num(0.04 * L) + " remap units box"
                    : std::string("change_box all x scale 1.02 remap"));
      cmd(lmp, "fix d all nospd/damage stretch 0.01");
      cmd(lmp, "run 1");
      auto *fb =
          static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
      int lo = 1 << 30, hi = 0, full = 0;
      for (int i = 0; i < lmp->atom->nlocal; i++) {
        int intact = 0;
        for (int k = 0; k < fb->npartner[i]; k++) intact += fb->partner[i][k] != 0;
        lo = std::min(lo, intact);
        hi = std::max(hi, intact);
        full = std::max(full, fb->npartner[i]);
      }
      EXPECT_EQ(lo, hi) << "intact bonds per point from " << lo << " to " << hi << " of " << full;
      EXPECT_GT(lo, 0);
      EXPECT_LT(hi, full) << "the deformation must break bonds";
      delete lmp;
    }
}

INSTANTIATE_TEST_SUITE_P(Box, Periodic, ::testing::Values(3, 2),
                         [](const ::testing::TestParamInfo<int> &p) {
                           return std::to_string(p.param) + "D";
                         });

}    // namespace

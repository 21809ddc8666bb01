/* Bad input gets a LAMMPS error that names the command and the value,
   never a crash or a silent NaN.  One test per error the style promises. */

#include "nospd_test_util.h"

#include "comm.h"
#include "gmock/gmock.h"
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include <unistd.h>

using namespace nospdtest;
using ::testing::HasSubstr;

namespace {

// one file per process: ctest -j runs the tests of this program in parallel
// processes in the same folder, which must not write or remove each other's
std::string material_file()
{
  return "nospd_bad_input_test." + std::to_string(getpid()) + ".nospd";
}

class BadInput : public ::testing::Test {
 protected:
  LAMMPS *lmp = nullptr;
  void SetUp() override { lmp = open_lammps(); }
  void TearDown() override { delete lmp; }
  void fresh()
  {
    delete lmp;
    lmp = open_lammps();
  }

  // a valid 3D deck up to (not including) the pair style, all atoms of type 1
  void deck(const std::string &atom_style = "peri", bool map = true,
            const std::string &units = "si", int ntypes = 1)
  {
    cmd(lmp, "units " + units);
    cmd(lmp, "boundary s s s");
    cmd(lmp, "atom_style " + atom_style);
    if (map) cmd(lmp, "atom_modify map array");
    cmd(lmp, "lattice sc 0.001");
    cmd(lmp, "region box block -0.25 5.25 -0.25 5.25 -0.25 5.25");
    cmd(lmp, "create_box " + std::to_string(ntypes) + " box");
    cmd(lmp, "create_atoms 1 box");
    if (atom_style == "peri") {
      cmd(lmp, "set group all density 7850");
      cmd(lmp, "set group all volume 1e-9");
    } else {
      cmd(lmp, "mass 1 1.0");
    }
  }

  // the error of a pair_coeff line (after the default pair style)
  std::string pair_coeff_error(const std::string &args)
  {
    deck();
    cmd(lmp, "pair_style peri/nospd");
    return error_of(lmp, "pair_coeff " + args);
  }

  // the error of `pair_coeff * * FILE name 0.003` for a material file of
  // `body` below a header line, written in the build folder (removed after)
  std::string file_material_error(const std::string &body, const std::string &name = "foo")
  {
    const std::string file = material_file();
    {
      std::ofstream out(file);
      out << "# DATE: 2026-11-27 UNITS: si CONTRIBUTOR: test\n" << body;
    }
    const std::string msg = pair_coeff_error("* * " + file + " " + name + " 0.003");
    std::remove(file.c_str());
    return msg;
  }

  // the error of a command given after a complete steel deck
  std::string error_after_steel(const std::string &line)
  {
    deck();
    cmd(lmp, "pair_style peri/nospd");
    cmd(lmp, "pair_coeff * * 200e9 0.3 0.003");
    return error_of(lmp, line);
  }
};

TEST_F(BadInput, WrongAtomStyle)
{
  deck("atomic");
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("requires atom_style peri"));
}

TEST_F(BadInput, MissingAtomMap)
{
  deck("peri", false);
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("atom_modify map"));
}

TEST_F(BadInput, ZeroVolume)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003");
  // the set command refuses a zero volume itself; a zero from a data file or
  // a variable must still be caught by the pair style
  lmp->atom->vfrac[3] = 0.0;
  const auto msg = error_of(lmp, "run 0");
  EXPECT_THAT(msg, HasSubstr("volume (vfrac) = 0"));
  EXPECT_THAT(msg, HasSubstr("atom 4"));
}

TEST_F(BadInput, NegativeDensity)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003");
  lmp->atom->rmass[0] = -1.0;
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("density (rmass) = -1"));
}

TEST_F(BadInput, PoissonTooLarge)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  EXPECT_THAT(error_of(lmp, "pair_coeff * * 200e9 0.5 0.003"), HasSubstr("nu must be in (-1, 0.5), got 0.5"));
}

TEST_F(BadInput, PoissonPlaneStress)
{
  cmd(lmp, "dimension 2");
  cmd(lmp, "units si");
  cmd(lmp, "boundary s s p");
  cmd(lmp, "atom_style peri");
  cmd(lmp, "atom_modify map array");
  cmd(lmp, "region box block 0 1 0 1 -0.5 0.5");
  cmd(lmp, "create_box 1 box");
  cmd(lmp, "pair_style peri/nospd plane stress");
  // 0.7 is a valid plane-stress Poisson ratio for small strain, 1.0 is not
  EXPECT_EQ(error_of(lmp, "pair_coeff * * 200e9 0.7 0.003"), "");
  EXPECT_THAT(error_of(lmp, "pair_coeff * * 200e9 1.0 0.003"), HasSubstr("(-1, 1) in plane stress, got 1"));
}

TEST_F(BadInput, NegativeModulus)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  EXPECT_THAT(error_of(lmp, "pair_coeff * * -2e9 0.3 0.003"), HasSubstr("Young's modulus E must be > 0, got -2"));
}

TEST_F(BadInput, NegativeHorizon)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  EXPECT_THAT(error_of(lmp, "pair_coeff * * 2e9 0.3 -0.003"), HasSubstr("horizon delta must be > 0, got -0.003"));
}

TEST_F(BadInput, HorizonBelowSpacing)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.0005");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("horizon 0.0005 of type 1 is smaller than the point spacing"));
}

TEST_F(BadInput, UnknownKeyword)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd strain small wobble 3"), HasSubstr("unknown keyword 'wobble'"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd strain large"), HasSubstr("unknown strain 'large'"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd stabilization silling -1"),
              HasSubstr("stabilization silling value must be > 0, got -1"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd plane stress"), HasSubstr("plane applies to 2D only"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd stabilization/fit cubic"),
              HasSubstr("unknown stabilization/fit 'cubic' (linear, quadratic)"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd stabilization hourglass 0.2 stabilization/fit quadratic"),
              HasSubstr("stabilization/fit quadratic applies to stabilization silling (its springs), "
                        "not to stabilization hourglass"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs stabilization/fit quadratic"),
              HasSubstr("stabilization/fit is a keyword of peri/nospd"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs stabilization/fit linear"),
              HasSubstr("stabilization/fit is a keyword of peri/nospd"));
}

// families are built once: a horizon changed between runs is an error
// naming the types and both values; the same horizon, or other constants,
// may be given again
TEST_F(BadInput, HorizonChangedBetweenRuns)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003015");
  cmd(lmp, "run 0");
  cmd(lmp, "pair_coeff * * 100e9 0.25 0.003015");
  EXPECT_EQ(error_of(lmp, "run 0"), "");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.0045");
  const auto msg = error_of(lmp, "run 0");
  EXPECT_THAT(msg, HasSubstr("pair_coeff 1 1: horizon 0.0045 differs from 0.003015"));
  EXPECT_THAT(msg, HasSubstr("families are not rebuilt"));
}

// the bonds fix lives as long as the pair style: unfixing it is an error
// at the next run (it crashed in the force passes), before or after a run
TEST_F(BadInput, UnfixBondsFix)
{
  for (bool after_run : {false, true}) {
    delete lmp;
    lmp = open_lammps();
    deck();
    cmd(lmp, "pair_style peri/nospd");
    cmd(lmp, "pair_coeff * * 200e9 0.3 0.003015");
    if (after_run) cmd(lmp, "run 0");
    cmd(lmp, "unfix NOSPD_BONDS");
    EXPECT_THAT(error_of(lmp, "run 0"),
                HasSubstr("pair_style peri/nospd: fix NOSPD_BONDS was deleted (unfix)"));
  }
}

// 2D: a point off the body's plane would give its bonds an out-of-plane
// part (energy and z forces at rest): an error naming the z range
TEST_F(BadInput, TwoDimensionalPointsOffPlane)
{
  Block b;
  b.dim = 2;
  b.n = 8;
  make_block(lmp, b);
  cmd(lmp, "pair_coeff * * 200e9 0.3 " + num(b.delta()));
  EXPECT_EQ(error_of(lmp, "run 0"), "");
  cmd(lmp, "set atom 5 z 0.0002");
  EXPECT_THAT(error_of(lmp, "run 0"),
              HasSubstr("2D body with points at current z from 0 to 0.0002: all its points must "
                        "lie in one plane"));
}

TEST_F(BadInput, MaterialNotInFile)
{
  EXPECT_THAT(pair_coeff_error("* * materials.nospd unobtainium 0.003"),
              HasSubstr("material 'unobtainium' not found in file materials.nospd"));
}

TEST_F(BadInput, MaterialFileUnits)
{
  deck("peri", true, "metal");
  cmd(lmp, "pair_style peri/nospd");
  const auto msg = error_of(lmp, "pair_coeff * * materials.nospd steel 0.003");
  EXPECT_THAT(msg, HasSubstr("si"));
  EXPECT_THAT(msg, HasSubstr("metal"));
}

// metal and real carry conversion factors between pressure and force per
// area and between force and mass times acceleration that force densities
// and the stable time step do not: an error, not forces 1e3-1e6 off
TEST_F(BadInput, UnitStyleWithConversionFactors)
{
  for (const char *units : {"metal", "real"}) {
    delete lmp;
    lmp = open_lammps();
    deck("peri", true, units);
    cmd(lmp, "pair_style peri/nospd");
    cmd(lmp, "pair_coeff * * 2e6 0.3 3.015");
    EXPECT_THAT(error_of(lmp, "run 0"),
                HasSubstr(std::string("without pressure or force conversion factors (si, cgs, "
                                      "micro, nano, lj), not units ") + units));
  }
  for (const char *units : {"cgs", "micro"}) {
    delete lmp;
    lmp = open_lammps();
    deck("peri", true, units);
    cmd(lmp, "pair_style peri/nospd");
    cmd(lmp, "pair_coeff * * 2e12 0.3 0.003");
    EXPECT_EQ(error_of(lmp, "run 0"), "") << units;
  }
}

TEST_F(BadInput, MaterialFromFileWorks)
{
  deck();
  cmd(lmp, "pair_style peri/nospd");
  EXPECT_EQ(error_of(lmp, "pair_coeff * * materials.nospd steel 0.00301"), "");
  EXPECT_EQ(error_of(lmp, "run 0"), "");
}

/* A line of atoms in 3D has singular shape tensors everywhere: they are
   counted and reported, their own force states dropped, and no NaN. */
TEST_F(BadInput, SingularFamiliesCountedNoNaN)
{
  cmd(lmp, "units si");
  cmd(lmp, "boundary s s s");
  cmd(lmp, "atom_style peri");
  cmd(lmp, "atom_modify map array");
  cmd(lmp, "lattice sc 0.001");
  cmd(lmp, "region box block -0.25 10.25 -0.25 0.25 -0.25 0.25");
  cmd(lmp, "create_box 1 box");
  cmd(lmp, "create_atoms 1 box");
  cmd(lmp, "set group all density 7850");
  cmd(lmp, "set group all volume 1e-9");
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.00301");
  cmd(lmp, "neighbor 0.0005 nsq");
  cmd(lmp, "displace_atoms all random 1e-5 1e-5 1e-5 4711 units box");
  cmd(lmp, "run 0");
  auto *fix = lmp->modify->get_fix_by_id("NOSPD_BONDS");
  ASSERT_NE(fix, nullptr);
  EXPECT_EQ((int) fix->compute_vector(2), (int) lmp->atom->natoms);
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int k = 0; k < 3; k++) EXPECT_TRUE(std::isfinite(lmp->atom->f[i][k]));
}

/* ----------------------------------------------------------------------
   more hostile decks: each command's argument errors name the command and
   the value (the message fragments below are the contract)
------------------------------------------------------------------------- */

TEST_F(BadInput, PairCoeffTooFewValues)
{
  EXPECT_THAT(pair_coeff_error("* * 200e9 0.3"), HasSubstr("expected 'I J E nu delta'"));
}

TEST_F(BadInput, MaterialFileMissing)
{
  EXPECT_THAT(pair_coeff_error("* * no_such_file.nospd steel 0.003"),
              HasSubstr("cannot open peri/nospd material potential file no_such_file.nospd"));
}

/* Lines of any length: LAMMPS's potential-file reader (1024-byte lines)
   hung on a longer comment, joined the rest of a 1030-byte one to the next
   entry, and cut a long entry (its last keywords lost without a word). */
TEST_F(BadInput, MaterialFileLongLines)
{
  const std::string entry = "foo 210e9 0.3 7850 100\n";
  for (size_t n : {1030, 5000}) {
    EXPECT_EQ(file_material_error("# " + std::string(n, 'x') + "\n" + entry), "") << n;
    delete lmp;
    lmp = open_lammps();
  }
  const std::string spaces(1200, ' ');
  EXPECT_THAT(file_material_error("foo 210e9 0.3 7850 100 yield 250e6" + spaces +
                                  "hardening linear -2e9\n"),
              HasSubstr("hardening linear H = -2000000000 would make the flow stress fall"));
}

/* a file entry's bad number names the file, the entry and its line, the
   field and the value; G0 = 0 (no fracture energy) is valid */
TEST_F(BadInput, MaterialFileBadValues)
{
  const std::string entry = "material 'foo' of file " + material_file() + " (line 2): ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"foo inf 0.3 7850 100", entry + "Young's modulus E must be finite, got inf"},
      {"foo 1e308 0.3 7850 100", entry + "Young's modulus E = 1e+308 is beyond any material"},
      {"foo -2e9 0.3 7850 100", entry + "Young's modulus E must be > 0, got -2000000000"},
      {"foo 210e9 0.5 7850 100", entry + "Poisson ratio nu must be in (-1, 0.5), got 0.5"},
      {"foo 210e9 0.3 -7850 100", entry + "density must be finite and > 0, got -7850"},
      {"foo 210e9 0.3 7850 inf", entry + "fracture energy G0 must be finite and >= 0 (0: none), "
                                         "got inf"},
      {"foo 210e9 0.3 7850 -100", entry + "fracture energy G0 must be finite and >= 0 (0: none), "
                                          "got -100"},
      {"foo 210e9 0.3 7850 nan", "G0 must be finite and >= 0 (0: none), got nan"},
      {"foo 210e9 0.3 7850 0", ""},
      {"foo 210e9 0.3 7850", "material file " + material_file() + ", entry 'foo' (line 2): "
                             "the file ends after 4 of its 5 words (name E nu density G0)"},
      {"foo 210e9 0.3 7850\nbar 1e9 0.2 1000 1",
       "material file " + material_file() + ", entry 'foo' (lines 2-3: an entry with fewer "
       "than 5 words continues on the next line): G0 = 'bar' is not a number"},
  };
  for (const auto &c : cases) {
    delete lmp;
    lmp = open_lammps();
    const auto msg = file_material_error(c.first + "\n");
    if (c.second.empty()) EXPECT_EQ(msg, "") << c.first;
    else EXPECT_THAT(msg, HasSubstr(c.second)) << c.first;
  }
}

// inf and nan inline are numbers, not a file name
TEST_F(BadInput, InlineNonFiniteMaterial)
{
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"* * inf 0.3 0.003", "Young's modulus E must be finite, got inf"},
      {"* * nan 0.3 0.003", "Young's modulus E must be finite, got nan"},
      {"* * 200e9 nan 0.003", "Poisson ratio nu must be finite, got nan"},
      {"* * 1e200 0.3 0.003", "Young's modulus E = 1e+200 is beyond any material"},
  };
  for (const auto &c : cases) {
    delete lmp;
    lmp = open_lammps();
    EXPECT_THAT(pair_coeff_error(c.first), HasSubstr("pair_coeff (peri/nospd): " + c.second))
        << c.first;
  }
}

TEST_F(BadInput, MaterialFileIsDirectory)
{
  const std::string dir = "nospd_bad_input_dir.nospd";    // in the build folder
  std::filesystem::create_directory(dir);
  const auto msg = pair_coeff_error("* * " + dir + " foo 0.003");
  std::filesystem::remove(dir);
  EXPECT_THAT(msg, HasSubstr("material file nospd_bad_input_dir.nospd is a directory, not a file"));
}

TEST_F(BadInput, KeywordWithoutValue)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd stabilization"),
              HasSubstr("keyword stabilization needs 1 value(s)"));
}

TEST_F(BadInput, UnknownInfluence)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd influence gaussian"),
              HasSubstr("unknown influence 'gaussian' (constant, inverse)"));
}

TEST_F(BadInput, SingularTolOutOfRange)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd singular_tol -1"), HasSubstr("singular_tol must be in (0,1), got -1"));
}

TEST_F(BadInput, DamagedTolOutOfRange)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd damaged_tol 1"),
              HasSubstr("damaged_tol must be in (0,1), got 1"));
}

TEST_F(BadInput, DamagedLeverageOutOfRange)
{
  deck();
  for (const std::string v : {"0", "1.5", "-0.5"})
    EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs damaged_leverage " + v),
                HasSubstr("damaged_leverage must be in (0,1] (1: no limit), got " + v));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd damaged_leverage"),
              HasSubstr("damaged_leverage"));
}

TEST_F(BadInput, DamagedStateValueAndStyle)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd damaged_state keep"),
              HasSubstr("damaged_state takes carry or refit, got 'keep'"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd damaged_state"),
              HasSubstr("keyword damaged_state needs 1 value(s)"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs damaged_state refit"),
              HasSubstr("damaged_state is a keyword of pair_style peri/nospd"));
}

/* A pair_style command naming the style already in place calls settings()
   on the same instance (LAMMPS keeps it): every keyword the new line does
   not give must take its default again, so that the line means what it
   means in a fresh deck.  Each pair: a randomly displaced block's energy
   under the second line, after a run under the first, against a fresh
   deck with the second line only (each keyword here changes the energy;
   the influence function changes the bond weights, which must be rebuilt). */
TEST_F(BadInput, RepeatedPairStyleTakesDefaults)
{
  auto energy = [&](const std::string &first, const std::string &second) {
    delete lmp;
    lmp = open_lammps();
    deck();
    cmd(lmp, "displace_atoms all random 1e-6 1e-6 1e-6 4321 units box");
    if (!first.empty()) {
      cmd(lmp, "pair_style " + first);
      cmd(lmp, "pair_coeff * * 200e9 0.3 0.003015");
      cmd(lmp, "run 0 post no");
    }
    if (!second.empty()) {
      cmd(lmp, "pair_style " + second);
      cmd(lmp, "pair_coeff * * 200e9 0.3 0.003015");
      cmd(lmp, "run 0 post no");
    }
    return potential_energy(lmp);
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"peri/nospd stabilization hourglass 0.2 strain finite", "peri/nospd"},
      {"peri/nospd influence inverse", "peri/nospd"},
      {"peri/nospd stabilization/fit quadratic", "peri/nospd"},
      {"peri/nospd", "peri/nospd influence inverse"},
      {"peri/nospd/hs form I ratio 1.5 stabilization silling 0.5", "peri/nospd/hs"}};
  for (const auto &c : cases) {
    const double fresh = energy("", c.second), other = energy(c.first, "");
    const double after = energy(c.first, c.second);
    ASSERT_GT(std::abs(other - fresh), 1e-3 * std::abs(fresh)) << c.first;    // they differ
    EXPECT_NEAR(after, fresh, 1e-12 * std::abs(fresh)) << c.first << " then " << c.second;
  }
}

TEST_F(BadInput, DamagedTolBelowSingularTol)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd singular_tol 0.3 damaged_tol 0.2"),
              HasSubstr("damaged_tol 0.2 is below singular_tol 0.3"));
}

/* Poisson's ratio is checked at pair_coeff against the plane and strain
   settings of that moment, and again at the run: a later pair_style line
   that changes them must not let an invalid material through */
TEST_F(BadInput, PoissonCheckedAgainstLaterPairStyle)
{
  const std::vector<std::pair<double, std::pair<std::string, std::string>>> cases = {
      {0.7, {"peri/nospd", "Poisson ratio nu must be in (-1, 0.5), got 0.7"}},
      {0.6, {"peri/nospd plane stress strain finite", "finite-strain plane stress needs nu < 0.5"}}};
  for (const auto &c : cases) {
    delete lmp;
    lmp = open_lammps();
    Block b;
    b.dim = 2;
    b.n = 8;
    b.settings = "plane stress";
    b.nu = c.first;
    make_block(lmp, b);
    cmd(lmp, "run 0 post no");    // valid in small-strain plane stress
    cmd(lmp, "pair_style " + c.second.first);
    EXPECT_THAT(error_of(lmp, "run 0 post no"), HasSubstr(c.second.second)) << c.second.first;
  }
}

/* The bond-associated style raises the communication cutoff for its
   stencil (a periodic box); a later run without the stencil, or another
   pair style, gets the user's cutoff back */
TEST_F(BadInput, StencilCutoffGivenBack)
{
  for (const std::string next : {"peri/nospd", "peri/nospd/hs stencil no"}) {
    delete lmp;
    lmp = open_lammps();
    Block b;
    b.n = 10;
    b.periodic = true;
    b.style = "peri/nospd/hs";
    make_block(lmp, b);
    cmd(lmp, "comm_modify cutoff 0.0");
    cmd(lmp, "run 0 post no");
    EXPECT_GT(lmp->comm->cutghostuser, 2.0 * b.delta()) << next;    // raised
    cmd(lmp, "pair_style " + next);
    cmd(lmp, "pair_coeff * * 200e9 0.3 " + num(b.delta()));
    cmd(lmp, "run 0 post no");
    EXPECT_EQ(lmp->comm->cutghostuser, 0.0) << next;
  }
}

TEST_F(BadInput, NegativeThickness)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd thickness -0.01"), HasSubstr("thickness must be > 0, got -0.01"));
}

// a 3D point volume is a volume: a thickness would be ignored without a word
TEST_F(BadInput, ThicknessIn3D)
{
  deck();
  for (const char *style : {"peri/nospd", "peri/nospd/hs"})
    EXPECT_THAT(error_of(lmp, std::string("pair_style ") + style + " thickness 0.002"),
                HasSubstr("keyword thickness applies to 2D only (dimension 2)"))
        << style;
}

// form and ratio belong to the horizon-stabilized style
TEST_F(BadInput, HsKeywordOnClassicalStyle)
{
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd form II"),
              HasSubstr("unknown keyword 'form' (a keyword of peri/nospd/hs)"));
}

TEST_F(BadInput, ComputeUnknownQuantity)
{
  EXPECT_THAT(error_after_steel("compute s all nospd/atom stress sigma"),
              HasSubstr("unknown quantity 'sigma'"));
}

TEST_F(BadInput, BondComputeUnknownQuantity)
{
  EXPECT_THAT(error_after_steel("compute b all nospd/bond/local id length"),
              HasSubstr("unknown quantity 'length'"));
}

TEST_F(BadInput, ComputeWithoutNospdPairStyle)
{
  deck();
  cmd(lmp, "pair_style peri/pmb");
  cmd(lmp, "pair_coeff * * 1e22 0.003 0.001 0.25");
  cmd(lmp, "compute s all nospd/atom stress");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("requires a peri/nospd pair style"));
}

// output asked for before the first run (Python's extract_compute, a
// variable): the computes have no state to read yet and give zeros, no rows
TEST_F(BadInput, ComputesBeforeFirstRunGiveZeros)
{
  error_after_steel("compute a all nospd/atom F stress zem");
  cmd(lmp, "compute b all nospd/bond/local id F");
  auto *a = lmp->modify->get_compute_by_id("a");
  auto *b = lmp->modify->get_compute_by_id("b");
  a->compute_peratom();
  b->compute_local();
  double largest = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int k = 0; k < a->size_peratom_cols; k++)
      largest = std::max(largest, std::abs(a->array_atom[i][k]));
  EXPECT_EQ(largest, 0.0);
  EXPECT_EQ(b->size_local_rows, 0);
}

// a pair_style command between runs replaces the pair style the computes
// read: the next invocation finds the new one or stops, never reads the old
TEST_F(BadInput, ComputesAfterPairStyleChange)
{
  error_after_steel("compute a all nospd/atom F");
  cmd(lmp, "compute b all nospd/bond/local id");
  cmd(lmp, "run 0");
  auto *a = lmp->modify->get_compute_by_id("a");
  auto *b = lmp->modify->get_compute_by_id("b");
  auto error_of_call = [](auto &&call) -> std::string {
    try {
      call();
    } catch (LAMMPS_NS::LAMMPSException &e) {
      return e.what();
    }
    return "";
  };
  // another PERI-NOSPD style: its state, none before its first run
  cmd(lmp, "pair_style peri/nospd/hs");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003");
  EXPECT_EQ(error_of_call([&] { b->compute_local(); }), "");
  EXPECT_EQ(b->size_local_rows, 0);
  cmd(lmp, "run 0");
  b->compute_local();
  EXPECT_GT(b->size_local_rows, 0);
  // a style of another kind
  cmd(lmp, "pair_style lj/cut 0.003");
  cmd(lmp, "pair_coeff * * 1 0.001");
  EXPECT_THAT(error_of_call([&] { a->compute_peratom(); }),
              HasSubstr("requires a peri/nospd pair style"));
  EXPECT_THAT(error_of_call([&] { b->compute_local(); }),
              HasSubstr("requires a peri/nospd or peri/nospd/hs pair style"));
}

// families are built once: a boundary made periodic or non-periodic after
// them would leave bonds spanning the box or faces unbonded
TEST_F(BadInput, BoundaryChangedAfterFamilies)
{
  error_after_steel("run 0");
  cmd(lmp, "change_box all boundary p s s");
  EXPECT_THAT(error_of(lmp, "run 0"),
              HasSubstr("the box is periodic in x but was periodic in none when the bond "
                        "families were built"));
  cmd(lmp, "change_box all boundary s s s");
  EXPECT_EQ(error_of(lmp, "run 0"), "");
}

// set type after the families: the new type's horizons must be those the
// family was built with (its material may differ)
TEST_F(BadInput, TypeChangedToOtherHorizon)
{
  deck("peri", true, "si", 3);
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff 1 1 200e9 0.3 0.003");
  cmd(lmp, "pair_coeff 2 2 70e9 0.33 0.003");
  cmd(lmp, "pair_coeff 3 3 200e9 0.3 0.0045");
  cmd(lmp, "pair_coeff 1 2 0.003");
  cmd(lmp, "pair_coeff 1 3 0.003");
  cmd(lmp, "pair_coeff 2 3 0.003");
  cmd(lmp, "region half block 2.5 INF INF INF INF INF units lattice");
  cmd(lmp, "run 0");
  cmd(lmp, "set region half type 2");    // same horizons, another material
  EXPECT_EQ(error_of(lmp, "run 0"), "");
  cmd(lmp, "set region half type 3");
  EXPECT_THAT(error_of(lmp, "run 0"),
              HasSubstr("has type 3 but had type 2 in the last run, whose horizons differ"));
}

TEST_F(BadInput, DamageSecondCriterion)
{
  EXPECT_THAT(error_after_steel("fix d all nospd/damage stretch 0.001 stretch 0.002"),
              HasSubstr("a second criterion 'stretch'"));
}

// the bonds fix is the pair style's: defined by the user under another ID,
// or under its own after a run (which replaced the instance holding the
// families: the damage healed, or the run stopped or, on 2 ranks, hung,
// depending on where the new instance landed in memory), an error at once
// (LAMMPS has deleted the old instance by then: the session cannot go on,
// as after any failed replacement of a fix)
TEST_F(BadInput, BondsFixDefinedByTheUser)
{
  EXPECT_THAT(error_after_steel("fix X all PERI_NEIGH/NOSPD"),
              HasSubstr("Fix X PERI_NEIGH/NOSPD: this fix is internal"));
  cmd(lmp, "run 0");
  EXPECT_THAT(error_of(lmp, "fix NOSPD_BONDS all PERI_NEIGH/NOSPD"),
              HasSubstr("Fix NOSPD_BONDS PERI_NEIGH/NOSPD: this fix is internal"));
}

// points that coincide only through a periodic boundary: the message says so
TEST_F(BadInput, CoincidentAcrossPeriodicBoundary)
{
  cmd(lmp, "units si");
  cmd(lmp, "boundary p p p");
  cmd(lmp, "atom_style peri");
  cmd(lmp, "atom_modify map array");
  cmd(lmp, "lattice sc 0.001");
  cmd(lmp, "region box block -0.001 7.004 0 7 0 7 units lattice");
  cmd(lmp, "create_box 1 box");
  cmd(lmp, "create_atoms 1 box");
  cmd(lmp, "set group all density 7850");
  cmd(lmp, "set group all volume 1e-9");
  cmd(lmp, "pair_style peri/nospd");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003015");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("apart in the reference configuration across a "
                                                "periodic boundary (0.007 apart inside the box)"));
}

TEST_F(BadInput, DamageFixWithoutCriterion)
{
  EXPECT_THAT(error_after_steel("fix d all nospd/damage"),
              HasSubstr("Illegal fix nospd/damage command: missing criterion"));
}

TEST_F(BadInput, DamageStretchNotPositive)
{
  EXPECT_THAT(error_after_steel("fix d all nospd/damage stretch -0.001"),
              HasSubstr("critical stretch must be > 0, got -0.001"));
}

/* Numbers out of a double's range and counts out of an int's are errors
   that name the command, the keyword and the word (once an uncaught
   std::out_of_range from std::stod, or a count of 2^31 wrapped to a
   negative int that the run then used as an array size) */
TEST_F(BadInput, OutOfRangeNumbersNamed)
{
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"* * 200e9 0.3 0.003 yield 1e999", "keyword yield expects a number, got 1e999: beyond"},
      {"* * 200e9 0.3 0.003 yield 1e-400", "keyword yield expects a number, got 1e-400: below"},
      {"* * 200e9 0.3 0.003 yield 250e6 hardening linear 1e400",
       "keyword hardening expects a number, got 1e400"},
      {"* * 1e999 0.3 0.003", "Young's modulus E expects a number, got 1e999"},
      {"* * 200e9 0.3 1e-400", "horizon delta expects a number, got 1e-400"},
  };
  for (const auto &c : cases) {
    fresh();
    EXPECT_THAT(pair_coeff_error(c.first), HasSubstr(c.second)) << c.first;
  }
  // a material file's numbers and keywords alike
  fresh();
  EXPECT_THAT(file_material_error("foo 1e999 0.3 7850 100\n"),
              HasSubstr("E = '1e999' is beyond the largest double"));
  fresh();
  EXPECT_THAT(file_material_error("foo 210e9 0.3 7850 100 yield 1e999\n"),
              HasSubstr("material foo in " + material_file() + ": keyword yield expects a "
                        "number, got 1e999"));
  for (const char *count : {"2147483648", "4294967297", "-1", "1e20", "2.5"}) {
    fresh();
    EXPECT_THAT(pair_coeff_error(std::string("* * 200e9 0.3 0.003 umat libx.so statev ") + count),
                HasSubstr(std::string("keyword statev expects an integer in [0, 10000], got ") +
                          (count[1] == 'e' || count[1] == '.' ? "'" : "") + count))
        << count;
    fresh();
    EXPECT_THAT(pair_coeff_error(std::string("* * 200e9 0.3 0.003 umat libx.so props ") + count +
                                 " 1 2"),
                HasSubstr("keyword props expects an integer in [0, 10000]"))
        << count;
  }
  fresh();
  EXPECT_THAT(error_after_steel("fix d all nospd/damage stretch 0.01 every 2147483648"),
              HasSubstr("fix nospd/damage: every expects an integer"));
  fresh();
  EXPECT_THAT(error_after_steel("fix d all nospd/damage stretch 1e999"),
              HasSubstr("fix nospd/damage: stretch expects a number, got 1e999"));
}

/* a material file's entry is unambiguous: a quote opened in its keywords
   closes within it (an unclosed one swallowed the rest of the entry into
   an energy formula that failed only at run), its name appears once in the
   file, and one list names each keyword once */
TEST_F(BadInput, MaterialFileEntryAmbiguities)
{
  EXPECT_THAT(file_material_error("foo 210e9 0.3 7850 100 energy \"0.5*mu*(I1-3) param mu 1\n"),
              HasSubstr("material file " + material_file() + ", entry 'foo' (line 2): the "
                        "quote \" before '0.5*mu*(I1-3) param mu"));
  fresh();
  EXPECT_THAT(file_material_error("foo 210e9 0.3 7850 100\nbar 1e9 0.2 1000 1\n"
                                  "foo 100e9 0.3 7850 100\n"),
              HasSubstr("entry 'foo' (line 4): material 'foo' is defined twice in the file "
                        "(lines 2 and 4)"));
  fresh();
  EXPECT_THAT(file_material_error("foo 210e9 0.3 7850 100 yield 250e6 yield 300e6\n"),
              HasSubstr("keyword yield given twice in one list"));
  fresh();
  EXPECT_THAT(pair_coeff_error("* * 200e9 0.3 0.003 yield 250e6 thermal 1e-5 293 thermal 1e-5 300"),
              HasSubstr("keyword thermal given twice in one list"));
  fresh();
  EXPECT_EQ(file_material_error("foo 210e9 0.3 7850 100 yield 250e6\nbar 1e9 0.2 1000 1\n"), "");
}

}    // namespace

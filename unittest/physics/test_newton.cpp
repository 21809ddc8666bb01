/* min_style nospd/newton through LAMMPS: the same equilibrium as FIRE to
   1e-8 of the displacement on an elastic plate with a hole (and as CG to
   the 1e-5 CG reaches before its line search stalls); quadratic
   convergence at finite strain with tight Krylov solves; the hourglass
   stabilization (no potential) converges with GMRES; a rigid mode nothing
   holds, and bad min_modify values, are clear errors. */

#include "nospd_test_util.h"

#include "atom.h"
#include "group.h"
#include "input.h"
#include "variable.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

using namespace nospdtest;
using LAMMPS_NS::LAMMPS;
using ::testing::HasSubstr;

namespace {
std::string umat_lib(const char *name) { return std::string(NOSPD_UMAT_DIR) + "/" + name; }

class Newton : public ::testing::Test {
 protected:
  LAMMPS *lmp = nullptr;
  void SetUp() override { lmp = open_lammps(); }
  void TearDown() override { delete lmp; }

  // a 2D plate of n x n points, a hole of radius 0.2 n dx in the middle,
  // left column held, the right one pulled by force density `load`
  Block plate(int n, const std::string &settings, double load, bool hold = true)
  {
    Block b;
    b.dim = 2;
    b.n = n;
    b.settings = settings + " plane stress";
    make_block(lmp, b);
    const double c = 0.5 * (n - 1) * b.dx;
    cmd(lmp, "region hole cylinder z " + num(c) + " " + num(c) + " " + num(0.2 * n * b.dx) +
                 " INF INF units box");
    cmd(lmp, "delete_atoms region hole");
    EXPECT_LT(lmp->atom->natoms, n * n - 0.1 * n * n);    // the hole is there
    cmd(lmp, "region left block INF " + num(0.5 * b.dx) + " INF INF INF INF units box");
    cmd(lmp, "region right block " + num((n - 1.5) * b.dx) + " INF INF INF INF INF units box");
    cmd(lmp, "group left region left");
    cmd(lmp, "group right region right");
    EXPECT_EQ(lmp->group->count(lmp->group->find("right")), n);
    cmd(lmp, "fix pull right addforce " + num(load) + " " + num(0.3 * load) + " 0.0");
    cmd(lmp, "fix_modify pull energy yes");
    if (hold) cmd(lmp, "fix hold left setforce 0.0 0.0 0.0");
    cmd(lmp, "compute d all displace/atom");
    return b;
  }
  std::vector<std::array<double, 3>> displacement()
  {
    cmd(lmp, "run 0");
    auto *c = lmp->modify->get_compute_by_id("d");
    c->compute_peratom();
    return by_tag(lmp, c->array_atom);
  }
  // a block of 6 points a side held on its left face and pulled on its
  // right one by the force density (fx, fy); pair_coeff extras in coeff
  Block pulled_block(int dim, const std::string &style, const std::string &settings,
                     const std::string &coeff, double fx, double fy)
  {
    Block b;
    b.dim = dim;
    b.n = 6;
    b.style = style;
    b.settings = settings;
    make_block(lmp, b);
    if (!coeff.empty()) cmd(lmp, "pair_coeff * * 200e9 0.3 " + num(b.delta()) + " " + coeff);
    cmd(lmp, "region left block INF " + num(0.5 * b.dx) + " INF INF INF INF units box");
    cmd(lmp, "region right block " + num((b.n - 1.5) * b.dx) + " INF INF INF INF INF units box");
    cmd(lmp, "group left region left");
    cmd(lmp, "group right region right");
    cmd(lmp, "fix hold left setforce 0.0 0.0 0.0");
    cmd(lmp, "fix pull right addforce " + num(fx) + " " + num(fy) + " 0.0");
    cmd(lmp, "fix_modify pull energy yes");
    cmd(lmp, "min_style nospd/newton");
    return b;
  }
  // steps whose residual fell and whose next step at least doubled the
  // digits gained (order > 1.8), above `floor` of the first residual
  static int quadratic_steps(const std::vector<double> &r, double floor)
  {
    int n = 0;
    for (size_t k = 0; k + 2 < r.size(); k++) {
      if (r[k + 2] < floor * r[0]) break;    // near the rounding floor
      const double p = std::log(r[k + 2] / r[k + 1]) / std::log(r[k + 1] / r[k]);
      if (r[k + 1] < 0.5 * r[k] && p > 1.8) n++;
    }
    return n;
  }
  // |V f| at the start of each Newton step, from the log
  static std::vector<double> residuals(const std::string &log)
  {
    std::vector<double> r;
    const std::regex line(R"(nospd/newton \d+: \|V f\| ([0-9.eE+-]+))");
    for (std::sregex_iterator it(log.begin(), log.end(), line), end; it != end; ++it)
      r.push_back(std::stod((*it)[1]));
    return r;
  }
};
}    // namespace

TEST_F(Newton, SameEquilibriumAsFireAndCgOnAPlateWithAHole)
{
  // FIRE to 3e-10 of the load (CG stalls at 2e-6 of it: "linesearch alpha
  // is zero", the issue's complaint) and CG as far as it goes
  const double load = 2e10;    // force density: about 1e-3 strain
  auto reference = [&](const std::string &style, const std::string &modify, double ftol) {
    delete lmp;
    lmp = open_lammps();
    plate(15, "strain small", load);
    cmd(lmp, "min_style " + style);
    cmd(lmp, "min_modify " + modify);
    cmd(lmp, "minimize 0 " + num(ftol) + " 100000 1000000");
    return displacement();
  };
  const auto fire = reference("fire", "integrator eulerimplicit", 100.0);
  const auto cg = reference("cg", "line quadratic dmax 1e-7", 1e-6);
  delete lmp;
  lmp = open_lammps();
  plate(15, "strain small", load);
  cmd(lmp, "min_style nospd/newton");
  const std::string log = log_of(lmp, {"minimize 0 100 50 100000"});
  EXPECT_THAT(log, HasSubstr("force tolerance"));
  const auto nk = displacement();
  auto differ = [&](const std::vector<std::array<double, 3>> &other, double &umax) {
    double diff = 0.0;
    umax = 0.0;
    for (size_t i = 0; i < other.size(); i++)
      for (int d = 0; d < 2; d++) {
        umax = std::max(umax, std::fabs(other[i][d]));
        diff = std::max(diff, std::fabs(other[i][d] - nk[i][d]));
      }
    return diff;
  };
  double umax = 0.0;
  const double off_fire = differ(fire, umax);
  EXPECT_GT(umax, 1e-6);
  EXPECT_LT(off_fire, 1e-8 * umax) << "umax " << umax;
  const double off_cg = differ(cg, umax);
  EXPECT_LT(off_cg, 1e-5 * umax);
  // held points did not move
  EXPECT_EQ(nk[0][0], 0.0);
  EXPECT_EQ(nk[0][1], 0.0);
}

TEST_F(Newton, ConvergesQuadraticallyAtFiniteStrain)
{
  pulled_block(3, "peri/nospd", "strain neohookean", "", 1.2e13, 4e12);    // about 10 % strain
  cmd(lmp, "min_modify forcing 1e-12 1e-12");
  const auto r = residuals(log_of(lmp, {"minimize 0 0 30 100000"}));
  ASSERT_GE(r.size(), 4u);
  EXPECT_GE(quadratic_steps(r, 1e-9), 1) << ::testing::PrintToString(r);
  std::printf("residuals |V f|: %s\n", ::testing::PrintToString(r).c_str());
  EXPECT_LT(r.back(), 1e-9 * r[0]) << ::testing::PrintToString(r);
}

TEST_F(Newton, PlasticLoadStepConvergesQuadraticallyWithTheLawsTangent)
{
  // J2, perfectly plastic, small strain, 3D: the probes take the return
  // mapping's consistent tangent (on this small block a difference of the
  // return converges quadratically too; the cylinder's is linear there)
  pulled_block(3, "peri/nospd", "strain small", "yield 250e6", 4e11, 1e11);    // beyond yield
  cmd(lmp, "compute p all nospd/atom eqps");
  cmd(lmp, "min_modify forcing 1e-12 1e-12");
  const std::string log = log_of(lmp, {"minimize 0 0 30 100000"});
  EXPECT_THAT(log, HasSubstr("law tangent at " + std::to_string(lmp->atom->natoms) + " points"));
  const auto r = residuals(log);
  ASSERT_GE(r.size(), 3u);
  std::printf("residuals |V f|: %s\n", ::testing::PrintToString(r).c_str());
  EXPECT_GE(quadratic_steps(r, 1e-12), 1) << ::testing::PrintToString(r);
  EXPECT_LE(r.size(), 8u) << ::testing::PrintToString(r);
  // and it did flow
  cmd(lmp, "compute pmax all reduce max c_p[1]");
  cmd(lmp, "variable pmax equal c_pmax");
  cmd(lmp, "run 0");
  EXPECT_GT(lmp->input->variable->compute_equal("v_pmax"), 1e-4);
}

// the operator the Krylov solves apply against central differences of the
// forces (min_modify tangent_check), on a block pulled past yield, every
// Newton step of the load step (its first starts at rest)
TEST_F(Newton, TangentMatchesCentralDifferences)
{
  struct Case {
    int dim;
    std::string style, settings, coeff;
    double tol = 1e-6;
  };
  const std::vector<Case> cases = {
      {3, "peri/nospd", "strain small", "yield 250e6 hardening linear 2e9"},
      {3, "peri/nospd", "strain hencky", "yield 250e6"},
      {3, "peri/nospd", "strain small", "drucker_prager 30 10 2e8 1e9"},
      {3, "peri/nospd", "strain hencky", "johnson_cook 9e7 2.9e8 0.31 0.025 1 1.09 298 1356"},
      {3, "peri/nospd", "strain small stabilization hourglass 0.2", "yield 250e6"},
      {3, "peri/nospd", "strain neohookean stabilization wan", ""},
      {2, "peri/nospd", "strain small plane strain", "yield 250e6"},
      {2, "peri/nospd", "strain svk plane stress", ""},
      // a formula law: the difference of its forces (no law tangent)
      {3, "peri/nospd", "strain formula",
       "energy \"0.5*mu*(I1b-3)+0.5*K*(J-1)^2\" param mu 7.7e10 param K 1.67e11"},
      {3, "peri/nospd/hs", "form II strain formula",
       "energy \"0.5*mu*(I1-3)-mu*log(J)+0.5*lam*log(J)^2\" param mu 7.7e10 param lam 1.15e11"},
      // the bond-associated style: each bond's own return linearized
      {3, "peri/nospd/hs", "form II strain small", "yield 250e6"},
      {3, "peri/nospd/hs", "form I strain hencky", "johnson_cook 9e7 2.9e8 0.31 0.025 1 1.09 298 1356"},
      {3, "peri/nospd/hs", "form II strain small stabilization silling 0.05", "drucker_prager 30 10 2e8 1e9"},
      // (with 2e9 hardening here a bond sits within the probe of its yield
      // surface at the fourth step: the central difference itself kinks)
      {2, "peri/nospd/hs", "form II strain small plane strain", "yield 250e6 hardening linear 5e9"},
      {3, "peri/nospd/hs", "form II strain umat",
       "umat " + umat_lib("umat_elastic.so") + " props 2 200e9 0.3"},
      {2, "peri/nospd/hs", "form I strain finite plane strain", ""},
      // a UMAT's DDSDDE where it writes one (umat_elastic), differences
      // where it leaves it zero (umat_j2)
      {3, "peri/nospd", "strain umat", "umat " + umat_lib("umat_elastic.so") + " props 2 200e9 0.3"},
      {2, "peri/nospd", "strain umat plane strain",
       "umat " + umat_lib("umat_elastic.so") + " props 2 200e9 0.3"},
      {3, "peri/nospd", "strain umat",
       "umat " + umat_lib("umat_j2.so") + " props 4 200e9 0.3 250e6 2e9 statev 7"}};
  for (const Case &c : cases) {
    delete lmp;
    lmp = open_lammps();
    const double load = 2.2e11;    // 220 MPa: plastic near the held edge, below collapse
    pulled_block(c.dim, c.style, c.settings, c.coeff, load, 0.25 * load);
    cmd(lmp, "min_modify tangent_check yes");
    // the built-in flow laws report eqps (a UMAT's plastic strain is its own STATEV)
    const bool plastic = c.coeff.find("yield") != std::string::npos ||
        c.coeff.find("_cook") != std::string::npos || c.coeff.find("drucker") != std::string::npos;
    if (plastic) {
      cmd(lmp, "compute p all nospd/atom eqps");
      cmd(lmp, "compute pm all reduce max c_p[1]");
      cmd(lmp, "variable pm equal c_pm");
    }
    const std::string log = log_of(lmp, {"minimize 0 0 4 100000"});
    if (plastic) {    // the load step did flow
      cmd(lmp, "run 0");
      EXPECT_GT(lmp->input->variable->compute_equal("v_pm"), 1e-6) << c.coeff;
    }
    const std::regex line(R"(tangent check ([0-9.eE+-]+))");
    int n = 0;
    for (std::sregex_iterator it(log.begin(), log.end(), line), end; it != end; ++it, ++n)
      EXPECT_LT(std::stod((*it)[1]), c.tol) << c.style << " " << c.settings << " " << c.coeff
                                          << " step " << n + 1;
    EXPECT_GE(n, 2) << c.style << " " << c.settings;
    std::smatch m;
    std::string worst;
    for (std::sregex_iterator it(log.begin(), log.end(), line), end; it != end; ++it)
      worst += (*it)[1].str() + " ";
    std::printf("%s | %s | %s: %s\n", c.style.c_str(), c.settings.c_str(), c.coeff.c_str(),
                worst.c_str());
  }
}

TEST_F(Newton, HourglassStabilizationConvergesWithGmres)
{
  plate(11, "strain small stabilization hourglass 0.2", 2e12);
  cmd(lmp, "min_style nospd/newton");
  const std::string log = log_of(lmp, {"minimize 0 1e-6 50 100000"});
  EXPECT_THAT(log, HasSubstr("gmres"));
  EXPECT_THAT(log, HasSubstr("force tolerance"));
  EXPECT_THAT(log, ::testing::Not(HasSubstr("need forces that are the gradient")));
}

TEST_F(Newton, AnUnheldBodyIsAClearError)
{
  plate(9, "strain small", 1e12, false);
  cmd(lmp, "fix push left addforce -1e12 -3e11 0.0");
  cmd(lmp, "min_style nospd/newton");
  const std::string err = error_of(lmp, "minimize 0 1e-6 50 1000");
  EXPECT_THAT(err, HasSubstr("the tangent is singular"));
  EXPECT_THAT(err, HasSubstr("translation along x"));
  EXPECT_THAT(err, HasSubstr("fix setforce"));
}

TEST_F(Newton, ARotationNothingHoldsIsAClearError)
{
  // one point held: no translation, but the body turns about it freely
  plate(9, "strain small", 0.0, false);
  cmd(lmp, "group one id 1");
  cmd(lmp, "fix hold one setforce 0.0 0.0 0.0");
  cmd(lmp, "min_style nospd/newton");
  const std::string err = error_of(lmp, "minimize 0 1e-6 50 1000");
  EXPECT_THAT(err, HasSubstr("rotation about z"));
}

TEST_F(Newton, BadModifyValuesAreErrors)
{
  plate(7, "strain small", 1e12);
  cmd(lmp, "min_style nospd/newton");
  EXPECT_THAT(error_of(lmp, "min_modify krylov bicg"), HasSubstr("expected auto, cg or gmres"));
  EXPECT_THAT(error_of(lmp, "min_modify restart 0"), HasSubstr("restart"));
  EXPECT_THAT(error_of(lmp, "min_modify restart 1e99"), HasSubstr("restart"));
  EXPECT_THAT(error_of(lmp, "min_modify krylov_max 99999999999"), HasSubstr("krylov_max"));
  EXPECT_THAT(error_of(lmp, "min_modify forcing 0.5 0.1"), HasSubstr("forcing (largest)"));
  EXPECT_THAT(error_of(lmp, "min_modify forcing nan 0.1"), HasSubstr("forcing (smallest)"));
  EXPECT_THAT(error_of(lmp, "min_modify fd_step -1"), HasSubstr("fd_step"));
  EXPECT_THAT(error_of(lmp, "min_modify precondition ilu"), HasSubstr("surrogate or jacobi"));
  EXPECT_THAT(error_of(lmp, "min_modify forcing 0.1"), HasSubstr("expected 2 value"));
}

TEST_F(Newton, UnsolvableSettingsAreClearErrors)
{
  plate(9, "strain small", 1e12);
  cmd(lmp, "min_style nospd/newton");
  cmd(lmp, "min_modify fd_step 1e-30");
  EXPECT_THAT(error_of(lmp, "minimize 0 1e-6 50 1000"), HasSubstr("fd_step 1e-30 is outside"));
  cmd(lmp, "min_modify fd_step 0 dmax 0");
  EXPECT_THAT(error_of(lmp, "minimize 0 1e-6 50 1000"), HasSubstr("dmax 0 must be positive"));
  cmd(lmp, "min_modify dmax 0.1");
  // loaded points that nothing holds (no pair stiffness): no equilibrium exists
  cmd(lmp, "pair_style zero " + num(4e-3));
  cmd(lmp, "pair_coeff * *");
  const std::string err = error_of(lmp, "minimize 0 1e-6 50 1000");
  EXPECT_THAT(err, HasSubstr("carries a force (1e+12) that no stiffness resists"));
}

TEST_F(Newton, PeriodicBoxRebuildsAcrossTheBoundary)
{
  // neighbor lists rebuilt during the line search in a periodic box: x0 is
  // re-imaged against the box it was stored with (fix MINIMIZE's store_box)
  Block b;
  b.dim = 2;
  b.n = 10;
  b.settings = "strain small plane stress";
  b.periodic = true;
  make_block(lmp, b);
  cmd(lmp, "neighbor 1e-6 bin");
  cmd(lmp, "region low block INF INF INF " + num(0.5 * b.dx) + " INF INF units box");
  cmd(lmp, "region high block INF INF " + num(4.5 * b.dx) + " " + num(5.5 * b.dx) +
               " INF INF units box");
  cmd(lmp, "group low region low");
  cmd(lmp, "group high region high");
  cmd(lmp, "fix hold low setforce 0.0 0.0 0.0");
  cmd(lmp, "fix pull high addforce 0.0 1e11 0.0");
  cmd(lmp, "fix_modify pull energy yes");
  cmd(lmp, "min_style nospd/newton");
  const std::string log = log_of(lmp, {"minimize 0 1e-2 50 100000"});
  EXPECT_THAT(log, HasSubstr("force tolerance"));
  EXPECT_THAT(log, ::testing::Not(HasSubstr("ERROR")));
}

TEST_F(Newton, JacobiPreconditionerReachesTheSameEquilibrium)
{
  plate(11, "strain small", 2e12);
  cmd(lmp, "min_style nospd/newton");
  cmd(lmp, "minimize 0 1e-6 50 100000");
  const auto surrogate = displacement();
  delete lmp;
  lmp = open_lammps();
  plate(11, "strain small", 2e12);
  cmd(lmp, "min_style nospd/newton");
  cmd(lmp, "min_modify precondition jacobi krylov gmres");
  const std::string log = log_of(lmp, {"minimize 0 1e-6 50 100000"});
  EXPECT_THAT(log, HasSubstr("force tolerance"));
  const auto jacobi = displacement();
  double umax = 0.0, diff = 0.0;
  for (size_t i = 0; i < jacobi.size(); i++)
    for (int d = 0; d < 2; d++) {
      umax = std::max(umax, std::fabs(surrogate[i][d]));
      diff = std::max(diff, std::fabs(surrogate[i][d] - jacobi[i][d]));
    }
  EXPECT_LT(diff, 1e-8 * umax);
}

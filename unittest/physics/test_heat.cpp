/* fix nospd/heat through LAMMPS: an insulated body keeps its thermal energy
   (1e-12 over 10,000 thermal steps) and a uniform temperature (1e-14); a
   small body (Biot 1.5e-3) cools by convection as exp(-h A t / (rho c V));
   a 2D plate held on its edges reaches the harmonic field; a bar clamped by
   a periodic box and heated by conduction reaches -E alpha dT; a pre-crack
   insulates exactly; plastic work heats the field by chi W_p; bad input
   gets errors that name the value. */

#include "nospd_test_util.h"

#include "group.h"
#include "variable.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <regex>

using namespace nospdtest;
using LAMMPS_NS::LAMMPS;
using ::testing::HasSubstr;

namespace {
constexpr double DX = 1.0e-3, RHO = 8960.0, K = 400.0, C = 385.0;

class Heat : public ::testing::Test {
 protected:
  LAMMPS *lmp = nullptr;
  void SetUp() override { lmp = open_lammps(); }
  void TearDown() override { delete lmp; }

  // a box-aligned block of nx x ny x nz points of spacing DX (nz = 1: 2D,
  // plane strain, thickness 1 m), copper, horizon 3.015 DX
  void block(int nx, int ny, int nz, const std::string &bc, const std::string &coeff_extra = "",
             const std::string &settings = "")
  {
    const bool two = nz == 1;
    cmd(lmp, "units si");
    cmd(lmp, std::string("dimension ") + (two ? "2" : "3"));
    cmd(lmp, "boundary " + bc);
    cmd(lmp, "atom_style peri");
    cmd(lmp, "atom_modify map array");
    cmd(lmp, std::string("lattice ") + (two ? "sq " : "sc ") + num(DX));
    const bool px = bc[0] == 'p';
    cmd(lmp, "region box block " + std::string(px ? "0 " : "-0.25 ") +
                 (px ? std::to_string(nx) : num(nx - 0.75)) + " -0.25 " + num(ny - 0.75) +
                 (two ? " -0.5 0.5" : " -0.25 " + num(nz - 0.75)));
    cmd(lmp, "create_box 2 box");
    cmd(lmp, "create_atoms 1 box");
    cmd(lmp, "set group all density " + num(RHO));
    cmd(lmp, "set group all volume " + num(two ? DX * DX : DX * DX * DX));
    cmd(lmp, "neighbor " + num(0.5 * DX) + " bin");
    cmd(lmp, "comm_modify cutoff " + num(7.0 * DX));
    cmd(lmp, "pair_style peri/nospd " + settings + (two ? " plane strain" : ""));
    cmd(lmp, "pair_coeff * * 110e9 0.34 " + num(3.015 * DX) + " conduction " + num(K) + " " +
                 num(C) + " " + coeff_extra);
    cmd(lmp, "thermo_modify norm no");
  }
  double *field() { return lmp->modify->get_fix_by_id("heat")->vector_atom; }
  double scalar(const std::string &v) { return lmp->input->variable->compute_equal(v); }
  // the heat fix's stable thermal step (after a run 0)
  double stable() { return scalar("f_heat[1]"); }

  // a copper bar periodic in x (the box holds its length), free sides, its
  // slice at x = 0 held dT above the rest: it ends in uniaxial stress
  static constexpr double BAR_E = 110e9, BAR_ALPHA = 1.7e-5, BAR_DT = 50.0;
  void clamped_bar()
  {
    block(14, 5, 5, "p s s", "thermal " + num(BAR_ALPHA) + " 300");
    cmd(lmp, "region slice block -0.5 0.5 INF INF INF INF");
    cmd(lmp, "group slice region slice");
    cmd(lmp, "fix heat all nospd/heat initial 300 fixed slice " + num(300.0 + BAR_DT));
    cmd(lmp, "compute s all nospd/atom stress");
  }
  // sigma_xx = -E alpha dT within 0.5 % along the bar's axis (sigma_yy 1 %)
  void expect_bar_stress()
  {
    auto *c = lmp->modify->get_compute_by_id("s");
    c->compute_peratom();
    const double expect = -BAR_E * BAR_ALPHA * BAR_DT;
    int checked = 0;
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      const double y = lmp->atom->x[i][1], z = lmp->atom->x[i][2];
      if (std::fabs(y - 2 * DX) > 0.6 * DX || std::fabs(z - 2 * DX) > 0.6 * DX) continue;
      EXPECT_NEAR(c->array_atom[i][0] / expect, 1.0, 0.005) << "atom " << lmp->atom->tag[i];
      EXPECT_LT(std::fabs(c->array_atom[i][1] / expect), 0.01);
      checked++;
    }
    EXPECT_GT(checked, 10);
  }
};
}    // namespace

TEST_F(Heat, InsulatedBodyKeepsItsEnergyAndAUniformTemperature)
{
  block(8, 8, 8, "s s s");
  cmd(lmp, "variable T0 atom 300+50*sin(x*1000)*cos(y*700)+20*z*1000");
  cmd(lmp, "fix heat all nospd/heat initial v_T0");
  cmd(lmp, "timestep 1e-6");
  cmd(lmp, "run 0");
  const double E0 = scalar("f_heat"), dt = stable();
  auto spread = [&]() {
    double lo = 1e300, hi = -1e300;
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      lo = std::min(lo, field()[i]);
      hi = std::max(hi, field()[i]);
    }
    return hi - lo;
  };
  const double spread0 = spread();
  // 1000 steps of 10 stable thermal steps: 10,000 thermal steps
  cmd(lmp, "timestep " + num(10.0 * dt));
  cmd(lmp, "run 1000");
  EXPECT_EQ(scalar("f_heat[2]"), 10.0);
  EXPECT_LT(std::fabs(scalar("f_heat") - E0) / E0, 1e-12);
  EXPECT_LT(spread(), 0.5 * spread0);    // it did conduct

  delete lmp;
  lmp = open_lammps();
  block(8, 8, 8, "s s s");
  cmd(lmp, "fix heat all nospd/heat initial 350");
  cmd(lmp, "timestep 1e-2");
  cmd(lmp, "run 1000");
  for (int i = 0; i < lmp->atom->nlocal; i++) EXPECT_NEAR(field()[i], 350.0, 350.0 * 1e-14);
}

TEST_F(Heat, SmallBodyCoolsByConvectionAsALumpedMass)
{
  // 6 mm copper cube, h = 100: Biot h L / k = 1.5e-3, tau = rho c L / (6 h)
  block(6, 6, 6, "s s s");
  const double h = 100.0, L = 6 * DX, tau = RHO * C * L / (6.0 * h), Tinf = 300.0, T0 = 400.0;
  cmd(lmp, "fix heat all nospd/heat initial 400 convection all " + num(h) + " " + num(Tinf));
  cmd(lmp, "timestep " + num(tau / 400.0));
  cmd(lmp, "run 0");
  const double capacity = RHO * C * L * L * L;
  for (int n = 1; n <= 4; n++) {
    cmd(lmp, "run 100");
    const double t = n * 100 * tau / 400.0;
    const double Tmean = scalar("f_heat") / capacity;
    const double exact = Tinf + (T0 - Tinf) * std::exp(-t / tau);
    EXPECT_NEAR((Tmean - Tinf) / (exact - Tinf), 1.0, 0.01) << "t/tau " << t / tau;
  }
  // what convection took is what the body lost
  EXPECT_NEAR(scalar("f_heat") - capacity * T0, scalar("f_heat[3]"), 1e-9 * capacity * T0);
}

TEST_F(Heat, PlateHeldOnItsEdgesReachesTheHarmonicField)
{
  // 2D plate, 31 x 31 inside, three held rows around it on the exact field
  // T = 300 + 100 sin(pi x / W) sinh(pi y / W) / sinh(pi) (x, y from the
  // inside's corner, W its width), harmonic everywhere
  const int n = 31, m = 3;
  block(n + 2 * m, n + 2 * m, 1, "s s p");
  const double W = (n - 1) * DX, x0 = m * DX;
  const std::string X = "(x-" + num(x0) + ")", Y = "(y-" + num(x0) + ")";
  cmd(lmp, "variable Tex atom 300+100*sin(PI*" + X + "/" + num(W) + ")*(exp(PI*" + Y + "/" + num(W) +
               ")-exp(-PI*" + Y + "/" + num(W) + "))/(exp(PI)-exp(-PI))");
  cmd(lmp, "region in block " + num(m - 0.5) + " " + num(m + n - 0.5) + " " + num(m - 0.5) + " " +
               num(m + n - 0.5) + " INF INF");
  cmd(lmp, "group in region in");
  cmd(lmp, "group rim subtract all in");
  cmd(lmp, "fix heat all nospd/heat initial 300 fixed rim v_Tex");
  cmd(lmp, "timestep 1e-3");
  cmd(lmp, "run 0");
  cmd(lmp, "timestep " + num(50.0 * stable()));
  cmd(lmp, "run 400");    // 20,000 thermal steps: about 8 slowest decay times
  std::vector<double> ex(lmp->atom->nlocal);
  lmp->input->variable->compute_atom(lmp->input->variable->find("Tex"), 0, ex.data(), 1, 0);
  const int inbit = lmp->group->bitmask[lmp->group->find("in")];
  double worst = 0.0;
  int count = 0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    if (!(lmp->atom->mask[i] & inbit)) continue;
    worst = std::max(worst, std::fabs(field()[i] - ex[i]));
    count++;
  }
  EXPECT_EQ(count, n * n);
  EXPECT_LT(worst / 100.0, 0.01);
}

TEST_F(Heat, ClampedBarHeatedByConductionReachesMinusEAlphaDeltaT)
{
  clamped_bar();
  cmd(lmp, "timestep 1e-3");
  cmd(lmp, "run 0");
  cmd(lmp, "timestep " + num(20.0 * stable()));
  cmd(lmp, "run 500");
  for (int i = 0; i < lmp->atom->nlocal; i++) ASSERT_NEAR(field()[i], 300.0 + BAR_DT, 1e-6);
  cmd(lmp, "min_style cg");
  cmd(lmp, "min_modify dmax " + num(0.01 * DX));
  cmd(lmp, "minimize 0 1e-12 20000 40000");
  expect_bar_stress();
}

TEST_F(Heat, StaggeredConductionAndNewtonLoadStepsReachMinusEAlphaDeltaT)
{
  // quasi-static thermo-elasticity: runs without an integrator conduct
  // (the points hold still), each minimize with min_style nospd/newton
  // settles the mechanics on the temperatures reached
  clamped_bar();
  // Newton needs the rigid motions held: the slice's centre point wholly,
  // the one below it along y (rotation about x); the free expansion of the
  // section, symmetric about both, moves neither
  cmd(lmp, "region centre block -0.5 0.5 1.5 2.5 1.5 2.5");
  cmd(lmp, "region below block -0.5 0.5 1.5 2.5 -0.5 0.5");
  cmd(lmp, "group centre region centre");
  cmd(lmp, "group below region below");
  cmd(lmp, "fix hold centre setforce 0 0 0");
  cmd(lmp, "fix turn below setforce NULL 0 NULL");
  cmd(lmp, "min_style nospd/newton");
  cmd(lmp, "timestep 1e-3");
  cmd(lmp, "run 0");
  cmd(lmp, "timestep " + num(20.0 * stable()));
  // the load: |E alpha dT| / DX per point; each step to 1e-8 of it
  const std::string ftol = num(1e-8 * BAR_E * BAR_ALPHA * BAR_DT / DX);
  // six load steps while the heat spreads, then one on the steady field
  std::string log;
  for (int step = 0; step < 6; step++)
    log += log_of(lmp, {"run 3", "minimize 0 " + ftol + " 20 2000"});
  log += log_of(lmp, {"run 500", "minimize 0 " + ftol + " 20 2000"});
  for (int i = 0; i < lmp->atom->nlocal; i++) ASSERT_NEAR(field()[i], 300.0 + BAR_DT, 1e-6);
  int settled = 0, moved = 0;
  for (size_t at = log.find("criterion = force tolerance"); at != std::string::npos;
       at = log.find("criterion = force tolerance", at + 1))
    settled++;
  const std::regex steps(R"(Iterations, force evaluations = (\d+))");
  for (std::sregex_iterator it(log.begin(), log.end(), steps), end; it != end; ++it)
    moved += std::stoi((*it)[1]) > 0;
  EXPECT_EQ(settled, 7) << log;
  EXPECT_GE(moved, 6) << log;    // the temperatures moved the body at every step
  expect_bar_stress();
}

TEST_F(Heat, DamageCriteriaSeeTheMechanicalStrainOnly)
{
  // a block at 400 K (thermal strain e = alpha 100 = 1.7e-3 over T_ref 300):
  // moved to its free expansion x = (1 + e) X it holds no stress and no
  // criterion below e may break a bond; held at X while cooled to 250 K
  // (e = -0.85e-3) every bond is stretched mechanically by 0.85e-3 and
  // breaks under 0.8e-3, none under 1e-3 (alpha 0.1: 1e-3 - 0.1 s_min);
  // the energy criterion sees the mechanical displacement U - e xi (a bond
  // of one spacing holds about 1e12 J/m^6, sigma |e| xi.K^-1 xi).  Each case:
  // the criterion with its value X, low (the cooled block breaks) and high
  struct Case {
    std::string law, criterion, low, high;
  };
  const std::vector<Case> cases = {{"small", "stretch X", "0.8e-3", "1e-3"},
                                   {"hencky", "stretch X", "0.8e-3", "1e-3"},
                                   {"small", "stretch X alpha 0.1", "0.8e-3", "1e-3"},
                                   {"hencky", "strain principal X", "0.8e-3", "1e-3"},
                                   {"small", "energy X", "1e11", "1e14"}};
  for (const auto &cs : cases) {
    for (const bool cooled : {false, true}) {
      for (const bool low : {true, false}) {
        std::string crit = cs.criterion;
        crit.replace(crit.find('X'), 1, low ? cs.low : cs.high);
        SCOPED_TRACE(cs.law + " " + crit + (cooled ? " cooled" : " free"));
        delete lmp;
        lmp = open_lammps();
        block(6, 5, 5, "s s s", "thermal 1.7e-5 300", "strain " + cs.law);
        cmd(lmp, "fix dmg all nospd/damage " + crit);
        cmd(lmp, std::string("fix heat all nospd/heat initial ") + (cooled ? "250" : "400"));
        if (!cooled) {
          cmd(lmp, "variable sx atom x*(1+1.7e-3)");
          cmd(lmp, "variable sy atom y*(1+1.7e-3)");
          cmd(lmp, "variable sz atom z*(1+1.7e-3)");
          cmd(lmp, "set group all x v_sx y v_sy z v_sz");
        }
        cmd(lmp, "timestep 1e-9");
        cmd(lmp, "run 1");
        const double broken = scalar("f_dmg[1]");
        const bool breaks = cooled && low;
        if (breaks) EXPECT_GT(broken, 1000.0);
        else EXPECT_EQ(broken, 0.0);
      }
    }
  }
}

TEST_F(Heat, EnergyAuditStandsAsideWhileTheTemperatureMoves)
{
  // a free block cooled fast at its surface: the temperature alone raises
  // the stored energy where nothing has moved yet, which fix nospd/damage's
  // audit would count as energy the material created (broken bonds aside)
  block(6, 5, 5, "s s s", "thermal 1.7e-5 300");
  cmd(lmp, "fix dmg all nospd/damage stretch 0.01");
  cmd(lmp, "fix heat all nospd/heat initial 400 convection all 1e7 300");
  cmd(lmp, "fix nve all nve");
  cmd(lmp, "thermo 10");
  cmd(lmp, "thermo_style custom step pe ke f_dmg[6] f_dmg[7]");
  cmd(lmp, "timestep 5e-8");
  const auto log = log_of(lmp, {"run 200"});
  EXPECT_LT(field()[0], 399.0);    // the surface cooled
  EXPECT_EQ(scalar("f_dmg[6]"), 0.0) << log;
  EXPECT_EQ(log.find("created energy"), std::string::npos) << log;
}

TEST_F(Heat, PreCrackInsulatesExactly)
{
  block(20, 5, 5, "s s s");
  // a plane between the rows x = 9 and x = 10 across the whole section
  const double xc = 9.5 * DX, lo = -0.2 * DX, hi = 4.2 * DX;
  cmd(lmp, "fix cut all nospd/damage none precrack " + num(xc) + " " + num(lo) + " " + num(lo) +
               " " + num(xc) + " " + num(hi) + " " + num(lo) + " " + num(xc) + " " + num(lo) +
               " " + num(hi));
  cmd(lmp, "region hot block INF 0.5 INF INF INF INF");
  cmd(lmp, "group hot region hot");
  cmd(lmp, "fix heat all nospd/heat initial 300 fixed hot 400");
  cmd(lmp, "timestep 1e-3");
  cmd(lmp, "run 0");
  cmd(lmp, "timestep " + num(20.0 * stable()));
  cmd(lmp, "run 200");
  double near_side = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const double x = lmp->atom->x[i][0];
    if (x > xc)
      EXPECT_NEAR(field()[i], 300.0, 1e-12) << "atom " << lmp->atom->tag[i];
    else if (std::fabs(x - 9 * DX) < 0.1 * DX)
      near_side = std::max(near_side, field()[i]);
  }
  EXPECT_GT(near_side, 310.0);    // the heat reached the crack
}

TEST_F(Heat, BondsBrokenDuringARunStopConducting)
{
  // the right half pulled off at 1 m/s breaks the bonds across x = 9.5 DX
  // within 3 microseconds; a fast conductor (alpha 10 m^2/s) carries heat
  // across in that time, then nothing
  const double c = 1.0, k = 10.0 * RHO * c;
  block(20, 5, 5, "s s s");
  cmd(lmp, "pair_coeff * * 110e9 0.34 " + num(3.015 * DX) + " conduction " + num(k) + " " + num(c));
  cmd(lmp, "fix dmg all nospd/damage stretch 0.0005");
  cmd(lmp, "region right block 9.5 INF INF INF INF INF");
  cmd(lmp, "group right region right");
  cmd(lmp, "group left subtract all right");
  cmd(lmp, "region hot block INF 0.5 INF INF INF INF");
  cmd(lmp, "group hot region hot");
  cmd(lmp, "fix heat all nospd/heat initial 300 fixed hot 400");
  cmd(lmp, "velocity right set 1 0 0 units box");
  cmd(lmp, "fix hold all setforce 0 0 0");
  cmd(lmp, "fix nve all nve");
  cmd(lmp, "variable e atom f_heat");
  cmd(lmp, "compute er right reduce sum v_e");
  cmd(lmp, "compute el left reduce sum v_e");
  cmd(lmp, "variable er equal c_er");
  cmd(lmp, "variable el equal c_el");
  cmd(lmp, "timestep 1e-8");
  cmd(lmp, "thermo_style custom step v_er v_el");
  // one run (a new run's setup would rebuild what a break left stale):
  // the sums at step 800, when every bond across has broken, and at 1200
  cmd(lmp, "fix at800 all ave/time 1 1 800 v_er v_el");
  cmd(lmp, "run 1200");
  const double er = scalar("f_at800[1]"), el = scalar("f_at800[2]");
  EXPECT_GT(er, 250 * 300.0 + 100.0);    // heat crossed before the break (sum of T)
  EXPECT_LT(er, 250 * 400.0 - 100.0);    // but not all of it
  EXPECT_NEAR(scalar("v_er"), er, 1e-12 * er);
  EXPECT_GT(scalar("v_el"), el + 1.0);    // the left side still warms
}

TEST_F(Heat, CurrentFrameConductsInTheDeformedBar)
{
  // a bar stretched 2x along x after its families are built (J = 2, no
  // lateral change), its end x = 0 held: the current frame diffuses along
  // the current length with alpha = k / (rho_current c) = 2 k / (rho c);
  // the reference frame along the undeformed bonds (in x: 4 k / (rho c)).
  // The two erfc profiles differ by up to 17 % of the step.
  auto errors = [&](const std::string &frame) {
    delete lmp;
    lmp = open_lammps();
    block(40, 5, 5, "s s s");
    cmd(lmp, "region hot block INF 0.5 INF INF INF INF");
    cmd(lmp, "group hot region hot");
    cmd(lmp, "fix heat all nospd/heat initial 300 fixed hot 400 frame " + frame);
    const double t = 1.0, alpha = 2.0 * K / (RHO * C);
    cmd(lmp, "timestep " + num(t / 20));
    cmd(lmp, "run 0");    // the families, then the stretch
    cmd(lmp, "variable ux atom 1.0*x");
    cmd(lmp, "displace_atoms all move v_ux 0 0 units box");
    cmd(lmp, "run 20");
    std::array<double, 2> worst = {0.0, 0.0};    // against the current, the reference frame's
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      const double x = lmp->atom->x[i][0];
      if (x < 0.5 * DX) continue;
      for (int f = 0; f < 2; f++) {
        const double a = f == 0 ? alpha : 2.0 * alpha;
        const double exact = 300.0 + 100.0 * std::erfc(x / (2.0 * std::sqrt(a * t)));
        worst[f] = std::max(worst[f], std::fabs(field()[i] - exact) / 100.0);
      }
    }
    return worst;
  };
  const auto cur = errors("current"), ref = errors("reference");
  EXPECT_LT(cur[0], 0.03);    // measured 1.7 %
  EXPECT_LT(ref[1], 0.05);    // 3.3 %: consistent, in the undeformed geometry
  EXPECT_GT(ref[0], 0.10);    // 15 % off the deformed body's solution
}

TEST_F(Heat, ReferenceFrameWarnsUnderLargeDeformation)
{
  block(8, 8, 8, "s s s");
  cmd(lmp, "fix heat all nospd/heat");
  cmd(lmp, "timestep 1e-3");
  cmd(lmp, "run 0");
  cmd(lmp, "variable ux atom 0.3*x");
  cmd(lmp, "displace_atoms all move v_ux 0 0 units box");
  const std::string log = log_of(lmp, {"run 200"});
  EXPECT_THAT(log, HasSubstr("use frame current for large deformation"));
  cmd(lmp, "unfix heat");
  cmd(lmp, "fix heat all nospd/heat frame current");
  EXPECT_THAT(log_of(lmp, {"run 200"}), ::testing::Not(HasSubstr("use frame current")));
}

TEST_F(Heat, ConditionsByRegionFollowItsPoints)
{
  // held by region = held by the group of the same points; a region that
  // moves onto the body heats it from then on
  auto run = [&](const std::string &where) {
    delete lmp;
    lmp = open_lammps();
    block(10, 5, 5, "s s s");
    cmd(lmp, "region hot block INF 0.5 INF INF INF INF");
    cmd(lmp, "group hot region hot");
    cmd(lmp, "fix heat all nospd/heat initial 300 fixed " + where + " 400");
    cmd(lmp, "timestep 1e-3");
    cmd(lmp, "run 50");
    return std::vector<double>(field(), field() + lmp->atom->nlocal);
  };
  const auto by_group = run("hot"), by_region = run("region hot");
  ASSERT_EQ(by_group.size(), by_region.size());
  for (size_t i = 0; i < by_group.size(); i++) EXPECT_EQ(by_group[i], by_region[i]);
  EXPECT_GT(*std::max_element(by_group.begin(), by_group.end() - 1), 300.0);

  delete lmp;
  lmp = open_lammps();
  block(10, 5, 5, "s s s");
  // a torch 1.5 mm across, moving along x from outside the body at 0.1 m/s
  cmd(lmp, "variable xt equal -0.004+0.1*time");
  cmd(lmp, "region torch sphere 0 0.002 0.002 0.0015 move v_xt NULL NULL units box");
  const std::string log = log_of(lmp, {"fix heat all nospd/heat initial 300 flux region torch 1e6",
                                       "timestep 1e-3", "run 10"});
  EXPECT_THAT(log, HasSubstr("region torch holds no atoms of group all now"));
  for (int i = 0; i < lmp->atom->nlocal; i++) EXPECT_EQ(field()[i], 300.0);    // not there yet
  cmd(lmp, "run 60");    // the torch reaches x = 0.003
  double hottest = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++) hottest = std::max(hottest, field()[i]);
  EXPECT_GT(hottest, 300.5);
}

TEST_F(Heat, PlasticWorkHeatsTheFieldByTaylorQuinney)
{
  // copper (Johnson-Cook) block, one face pushed: the field gains chi W_p
  block(8, 8, 8, "s s s",
        "johnson_cook 90e6 292e6 0.31 0.025 1.0 1.09 293 1356 heat 385 0.9");
  cmd(lmp, "fix heat all nospd/heat");
  cmd(lmp, "compute p all nospd/atom plastic_work");
  cmd(lmp, "variable wv atom c_p[1]*" + num(DX * DX * DX));
  cmd(lmp, "compute wp all reduce sum v_wv");
  cmd(lmp, "region face block INF 0.5 INF INF INF INF");
  cmd(lmp, "group face region face");
  cmd(lmp, "velocity face set 100 0 0 units box");
  cmd(lmp, "fix v face setforce 0 0 0");
  cmd(lmp, "fix nve all nve");
  cmd(lmp, "timestep 2e-8");
  cmd(lmp, "thermo_style custom step c_wp f_heat f_heat[4]");
  cmd(lmp, "run 0");
  const double E0 = scalar("f_heat");
  cmd(lmp, "run 400");
  cmd(lmp, "variable wp equal c_wp");
  cmd(lmp, "run 0");    // the computes current
  const double wp = scalar("v_wp"), moved = scalar("f_heat[4]");
  ASSERT_GT(wp, 0.0);
  EXPECT_NEAR(moved / (0.9 * wp), 1.0, 1e-9);    // the accepted steps' heating, all counted
  EXPECT_NEAR((scalar("f_heat") - E0) / moved, 1.0, 1e-9);
  // and it is in the field itself (the per-atom temperature, which the
  // scalar and vector complete with the last step's heating, not yet moved)
  double field_gain = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    field_gain += RHO * 385.0 * DX * DX * DX * (field()[i] - 293.0);
  EXPECT_GT(field_gain / moved, 0.9);
  EXPECT_LT(field_gain / moved, 1.0 + 1e-9);
}

TEST_F(Heat, BadInputNamesTheValue)
{
  block(6, 6, 6, "s s s");
  EXPECT_THAT(error_of(lmp, "pair_coeff * * 1e9 0.3 0.003 conduction 0 385"),
              HasSubstr("conduction k (conductivity) must be > 0 and finite, got 0"));
  EXPECT_THAT(error_of(lmp, "pair_coeff * * 1e9 0.3 0.003 conduction 400 -1"),
              HasSubstr("conduction c (specific heat) must be > 0 and finite, got -1"));
  EXPECT_THAT(error_of(lmp, "pair_coeff * * 1e9 0.3 0.003 conduction 400 nan"),
              HasSubstr("keyword conduction must be finite, got nan"));
  EXPECT_THAT(error_of(lmp, "fix h all nospd/heat convection all 0 300"),
              HasSubstr("convection h must be > 0 (W/m^2/K), got 0"));
  EXPECT_THAT(error_of(lmp, "fix h all nospd/heat convection all -5 300"),
              HasSubstr("got -5"));
  EXPECT_THAT(error_of(lmp, "fix h all nospd/heat fixed nogroup 300"),
              HasSubstr("fixed group nogroup does not exist"));
  EXPECT_THAT(error_of(lmp, "fix h all nospd/heat substeps 0"), HasSubstr("substeps"));
  EXPECT_THAT(error_of(lmp, "fix h all nospd/heat initial 1e999"), HasSubstr("initial"));
  EXPECT_THAT(error_of(lmp, "fix h all nospd/heat bogus 1"), HasSubstr("unknown keyword 'bogus'"));
  cmd(lmp, "group none empty");
  cmd(lmp, "fix h all nospd/heat fixed none 300");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("group none has no atoms of group all"));
  cmd(lmp, "unfix h");
  // a type of the group without conduction
  cmd(lmp, "pair_coeff 2 2 110e9 0.34 0.003015");
  cmd(lmp, "set atom 1 type 2");
  cmd(lmp, "fix h all nospd/heat");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("atoms of type 2 in group all have no conduction"));
  cmd(lmp, "unfix h");
}

TEST_F(Heat, ConflictsAndAThermalStepAboveTheBound)
{
  block(6, 6, 6, "s s s");
  cmd(lmp, "fix h all nospd/heat substeps 1");
  cmd(lmp, "timestep 1");
  const std::string log = log_of(lmp, {"run 0"});
  EXPECT_THAT(log, HasSubstr("is above the stable bound"));
  EXPECT_THAT(log, HasSubstr("use substeps auto"));
  cmd(lmp, "unfix h");
  cmd(lmp, "fix T all property/atom d_T");
  cmd(lmp, "set group all d_T 300");
  cmd(lmp, "pair_style peri/nospd temperature d_T");
  cmd(lmp, "pair_coeff * * 110e9 0.34 0.003015 conduction 400 385");
  cmd(lmp, "fix h all nospd/heat");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("drop the pair style's temperature keyword"));

  delete lmp;
  lmp = open_lammps();
  cmd(lmp, "units si");
  cmd(lmp, "atom_style peri");
  cmd(lmp, "atom_modify map array");
  cmd(lmp, "region box block 0 1 0 1 0 1");
  cmd(lmp, "create_box 1 box");
  cmd(lmp, "create_atoms 1 single 0.5 0.5 0.5");
  cmd(lmp, "pair_style peri/pmb");
  cmd(lmp, "pair_coeff * * 1e20 0.1 0.1 1");
  cmd(lmp, "set group all volume 1 density 1");
  cmd(lmp, "fix h all nospd/heat");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("needs pair_style peri/nospd"));
}

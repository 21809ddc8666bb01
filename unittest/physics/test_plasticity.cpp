/* Inelastic correspondence through LAMMPS: thermal expansion (free and
   clamped), uniaxial tension of a periodic body against the closed-form
   J2 curve (quasi-static, minimize), energy balance ke + pe + plastic work
   in NVE, objectivity of the finite-strain model after plastic flow, the
   history surviving repeated evaluations, damage on plastic strain, and
   the errors of bad inelastic input.

   Every physics check runs for the classical style and for the
   horizon-stabilized style in forms I and II, whose history is kept per
   bond-associated family (a plastic state per bond). */

#include "nospd_test_util.h"
#include "nospd_drucker_prager.h"
#include "nospd_plasticity.h"

#include "domain.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "modify.h"
#include "pair.h"
#include "min.h"
#include "output.h"
#include "thermo.h"
#include "variable.h"

#include "gmock/gmock.h"
#include <fstream>

#include <Eigen/Geometry>

using namespace nospdtest;
using ::testing::HasSubstr;

namespace {

constexpr double E = 200e9, NU = 0.3, ALPHA = 1.2e-5;

// per-atom column c of compute nospd/atom ID (called now)
std::vector<double> peratom(LAMMPS *lmp, const std::string &id, int c)
{
  auto *comp = lmp->modify->get_compute_by_id(id);
  comp->compute_peratom();
  std::vector<double> out(lmp->atom->natoms);
  for (int i = 0; i < lmp->atom->nlocal; i++) out[lmp->atom->tag[i] - 1] = comp->array_atom[i][c];
  return out;
}

double fmax(LAMMPS *lmp)
{
  double m = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int k = 0; k < 3; k++) m = std::max(m, std::abs(lmp->atom->f[i][k]));
  return m;
}

void place_affine(LAMMPS *lmp, const NOSPD::Mat3 &F, const NOSPD::Vec3 &c)
{
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const NOSPD::Vec3 X(x0[i][0], x0[i][1], x0[i][2]);
    const NOSPD::Vec3 y = c + F * (X - c);
    for (int k = 0; k < 3; k++) x[i][k] = y[k];
  }
}

// the pair styles under test: classical, and bond-associated forms II and I
struct StyleCase {
  const char *name, *style, *settings;
};
const StyleCase STYLES[] = {{"classical", "peri/nospd", ""},
                            {"hs_form2", "peri/nospd/hs", "form II "},
                            {"hs_form1", "peri/nospd/hs", "form I "}};

void PrintTo(const StyleCase &c, std::ostream *os) { *os << c.name; }

class Inelastic : public ::testing::TestWithParam<StyleCase> {
 protected:
  LAMMPS *lmp = nullptr;
  void SetUp() override { lmp = open_lammps(); }
  void TearDown() override { delete lmp; }
  bool hs() const { return std::string(GetParam().style) != "peri/nospd"; }

  void block(const std::string &settings, const std::string &coeff_extra, int n = 9,
             bool periodic = false)
  {
    Block b;
    b.n = n;
    b.periodic = periodic;
    b.style = GetParam().style;
    b.settings = GetParam().settings + settings;
    b.E = E;
    b.nu = NU;
    make_block(lmp, b);
    cmd(lmp, "pair_coeff * * " + num(E) + " " + num(NU) + " " + num(b.delta()) + " " + coeff_extra);
  }
};

// A free heated block expands without stress: zero force (relative to the
// clamped block's) at every point, surfaces included, for both kinematics.
TEST_P(Inelastic, ThermalFreeBlockIsForceFree)
{
  for (std::string law : {"small", "hencky"}) {
    delete lmp;
    lmp = open_lammps();
    block("strain " + law + " temperature v_T", "thermal 1.2e-5 293");
    cmd(lmp, "variable T atom 493.0");
    const double s = 1.0 + ALPHA * 200.0;
    place_affine(lmp, s * NOSPD::Mat3::Identity(), NOSPD::Vec3(0.004, 0.004, 0.004));
    cmd(lmp, "run 0");
    const double free = fmax(lmp);
    place_affine(lmp, NOSPD::Mat3::Identity(), NOSPD::Vec3::Zero());
    cmd(lmp, "run 0");
    const double clamped = fmax(lmp);
    EXPECT_GT(clamped, 0.0);
    EXPECT_LT(free, 1e-12 * clamped) << law;
  }
}

// A temperature where the thermal law is undefined (a stretch
// 1 + alpha dT <= 0 under Hencky, a thermal strain of 100 % or more under
// small strain) is an error that says so, not a return mapping that "did
// not converge" (hostile sweep N); 1 + alpha dT = -0.2 (alpha 0.01, the
// temperature still absolute) and 6.
TEST_P(Inelastic, ThermalStretchOutsideTheLawIsNamed)
{
  for (std::string law : {"small", "hencky"}) {
    for (double dT : {-120.0, 5.0 / ALPHA}) {
      delete lmp;
      lmp = open_lammps();
      block("strain " + law + " temperature v_T",
            dT < 0.0 ? "thermal 0.01 293" : "thermal 1.2e-5 293");
      cmd(lmp, "variable T atom " + num(293.0 + dT));
      const std::string msg = error_of(lmp, "run 0");
      if (law == "hencky" && dT > 0.0) {
        EXPECT_EQ(msg, "") << "a stretch of 6 is defined";
        continue;
      }
      EXPECT_THAT(msg, HasSubstr(dT < 0.0 ? "has temperature 173," : "has temperature 416960,"))
          << law;
      EXPECT_THAT(msg, HasSubstr(law == "small" ? "thermal strain alpha (T - T_ref) of type 1"
                                                : "thermal stretch 1 + alpha (T - T_ref) of type 1"))
          << law;
    }
  }
}

// The temperature of a plastic or thermal law is absolute: a per-atom
// temperature at or below zero stops the run, naming the step, the atom and
// the value, whether it starts there or a variable reaches it during the
// run (295 - 1e10 t is -5 K at step 30 of 1 ns).
TEST_P(Inelastic, NonPositiveTemperatureStopsTheRun)
{
  const std::string jc = "johnson_cook 792e6 510e6 0.26 0.014 1.0 1.03 293 1793";
  block("strain small temperature v_T", jc);
  cmd(lmp, "variable T atom -50");
  std::string msg = error_of(lmp, "run 0");
  EXPECT_THAT(msg, HasSubstr("step 0: atom 1 has temperature -50 from v_T"));
  EXPECT_THAT(msg, HasSubstr("absolute"));
  delete lmp;
  lmp = open_lammps();
  block("strain hencky temperature v_T", jc + " thermal 1.2e-5 293");
  cmd(lmp, "variable T atom 295-1e10*time");
  msg = error_of(lmp, "run 100");
  EXPECT_THAT(msg, HasSubstr("step 30: atom 1 has temperature -5")) << msg;
}

// A clamped heated body (periodic: no surface) carries
// sigma = -E alpha dT / (1 - 2 nu) on the diagonal; the temperature comes
// from a per-atom property set with the set command.
TEST_P(Inelastic, ThermalClampedStress)
{
  for (std::string law : {"small", "hencky"}) {
    delete lmp;
    lmp = open_lammps();
    block("strain " + law + " temperature d_temp", "thermal 1.2e-5 293", 8, true);
    cmd(lmp, "fix temp all property/atom d_temp");
    cmd(lmp, "set group all d_temp 393.0");
    cmd(lmp, "compute s all nospd/atom stress temperature");
    cmd(lmp, "run 0");
    const double expect = -E * ALPHA * 100.0 / (1.0 - 2.0 * NU);
    for (int c = 0; c < 3; c++) {
      const auto sig = peratom(lmp, "s", c);
      for (double v : sig) EXPECT_NEAR(v, expect, 0.005 * std::abs(expect)) << law;
    }
    for (double T : peratom(lmp, "s", 6)) EXPECT_DOUBLE_EQ(T, 393.0);
    const auto fmx = fmax(lmp);
    EXPECT_LT(fmx, 1e-9 * std::abs(expect) / 1e-3);    // periodic: no net force density
  }
}

/* Uniaxial tension of a periodic body: the box is stretched along x in
   steps; at each the lateral box lengths are found (secant on the mean
   lateral stress, run 0 evaluations, which accept nothing) so that the
   lateral stress vanishes, and the step is then accepted by one step
   without an integrator.  The axial stress follows sigma_y + E_t (eps -
   eps_y) with E_t = E H/(E + H), unloading the elastic slope, and the
   plastic strain stays at its peak value while unloading. */
TEST_P(Inelastic, UniaxialTensionFollowsCurve)
{
  const double SY = 250e6, H = 10e9;
  block("strain small", "yield " + num(SY) + " hardening linear " + num(H), 8, true);
  cmd(lmp, "compute s all nospd/atom stress eqps");
  cmd(lmp, "run 0");    // families and the reference box from the undeformed body
  const double ey = SY / E, Et = E * H / (E + H);
  double eps = 0.0, lat = 0.0, emax = 0.0;
  auto set_strain = [&](double ex, double ey_) {
    cmd(lmp, "change_box all x scale " + num((1.0 + ex) / (1.0 + eps)) + " y scale " +
                 num((1.0 + ey_) / (1.0 + lat)) + " z scale " + num((1.0 + ey_) / (1.0 + lat)) +
                 " remap units box");
    eps = ex;
    lat = ey_;
  };
  auto mean = [&](int c) {
    const auto v = peratom(lmp, "s", c);
    double m = 0.0;
    for (double x : v) m += x / v.size();
    return m;
  };
  auto lateral_stress = [&](double ex, double l) {
    set_strain(ex, l);
    cmd(lmp, "run 0");
    return mean(1);
  };
  std::vector<double> path;
  for (int k = 1; k <= 12; k++) path.push_back(0.5 * k * ey);             // to 6 ey
  for (int k = 1; k <= 4; k++) path.push_back(6.0 * ey - 0.5 * k * ey);   // unload by 2 ey
  int checked = 0;
  for (double target : path) {
    double l0 = lat, l1 = lat - 0.3 * (target - eps) - 1e-7;
    double g0 = lateral_stress(target, l0), g1 = lateral_stress(target, l1);
    for (int it = 0; it < 30 && std::abs(g1) > 1e-6 * SY && g1 != g0; it++) {
      const double l2 = l1 - g1 * (l1 - l0) / (g1 - g0);
      l0 = l1;
      g0 = g1;
      l1 = l2;
      g1 = lateral_stress(target, l1);
    }
    cmd(lmp, "run 1");    // accept the load step
    emax = std::max(emax, eps);
    const double smax = emax > ey ? SY + Et * (emax - ey) : E * emax;
    const double expect = eps >= emax ? smax : smax - E * (emax - eps);
    const auto sxx = peratom(lmp, "s", 0);
    const auto syy = peratom(lmp, "s", 1);
    for (size_t i = 0; i < sxx.size(); i++) {
      EXPECT_NEAR(sxx[i], expect, 0.01 * std::abs(expect)) << "eps = " << eps;
      EXPECT_LT(std::abs(syy[i]), 0.01 * SY) << "lateral stress at eps = " << eps;
    }
    checked++;
  }
  EXPECT_EQ(checked, 16);
  // the accepted history: the axial plastic strain of the peak, unchanged by unloading
  const double ep_peak = 6.0 * ey - (SY + Et * 5.0 * ey) / E;
  for (double a : peratom(lmp, "s", 6)) EXPECT_NEAR(a, ep_peak, 0.01 * ep_peak);
}

/* NVE: ke + pe + plastic work (f_NOSPD_BONDS[4]) stays constant while a
   free block expands, yields and rings; the plastic work is a sizeable
   share of the initial kinetic energy. */
void nve_balance(LAMMPS *lmp, double dt, int nsteps, double *share)
{
  // about the block's centre (xc from the shrink-wrapped box)
  cmd(lmp, "variable xc equal 0.5*(xlo+xhi)");
  const std::string c = num(lmp->input->variable->compute_equal("v_xc"));
  cmd(lmp, "variable vx atom 8.0*(x-" + c + ")/0.004");
  cmd(lmp, "variable vy atom -3.0*(y-" + c + ")/0.004");
  cmd(lmp, "velocity all set v_vx v_vy NULL");
  cmd(lmp, "fix 1 all nve");
  cmd(lmp, "timestep " + num(dt));
  cmd(lmp, "variable etot equal ke+pe+f_NOSPD_BONDS[4]");
  cmd(lmp, "thermo_style custom step ke pe f_NOSPD_BONDS[4] v_etot");
  cmd(lmp, "run 0");
  auto *var = lmp->input->variable;
  const double e0 = var->compute_equal("v_etot");
  const double ke0 = var->compute_equal("ke");
  double worst = 0.0;
  for (int k = 0; k < nsteps / 25; k++) {
    cmd(lmp, "run 25");
    worst = std::max(worst, std::abs(var->compute_equal("v_etot") - e0));
  }
  *share = var->compute_equal("f_NOSPD_BONDS[4]") / ke0;
  EXPECT_LT(worst, 1e-4 * e0);
}

// the styles that are potentials (form I is not: no energy balance)
class InelasticPotential : public Inelastic {};

TEST_P(InelasticPotential, NveEnergyBalanceJ2Small)
{
  block("strain small", "yield 1e8 hardening linear 2e9 kinematic 1e9");
  double share = 0.0;
  nve_balance(lmp, 5e-9, 1200, &share);
  EXPECT_GT(share, 0.1);
}

// Johnson-Cook at finite strain and a raised temperature: strain
// hardening, thermal softening, the rate term (lagged strain rate) and
// adiabatic heating all on.
// (peri/nospd/hs: without the energy a moving surface releases, which
// stays below the tolerance here; a smaller block for its cost)
TEST_P(InelasticPotential, NveEnergyBalanceJohnsonCookHencky)
{
  block("strain hencky temperature v_T",
        "johnson_cook 9e7 2.92e8 0.31 0.025 1.0 1.09 298 1356 heat 383 0.9", hs() ? 7 : 9);
  cmd(lmp, "variable T atom 500.0");
  double share = 0.0;
  nve_balance(lmp, 5e-9, 1200, &share);
  EXPECT_GT(share, 0.1);
}

/* Objectivity after plastic flow (strain hencky): a rigid rotation of the
   plastically deformed body changes neither the von Mises stress nor the
   equivalent plastic strain at any point. */
TEST_P(Inelastic, HenckyRotationAfterPlasticFlow)
{
  block("strain hencky", "yield 2e8 hardening power 3e8 0.3", 7);
  cmd(lmp, "compute s all nospd/atom vonmises eqps");
  NOSPD::Mat3 F;
  F << 1.004, 0.003, 0.0, 0.001, 0.998, 0.002, 0.0, -0.001, 0.999;
  const NOSPD::Vec3 c(0.003, 0.003, 0.003);
  place_affine(lmp, F, c);
  cmd(lmp, "run 1");    // one step without an integrator: accepted, atoms stay
  place_affine(lmp, 1.5 * F - 0.5 * NOSPD::Mat3::Identity(), c);
  cmd(lmp, "run 1");
  const auto vm0 = peratom(lmp, "s", 0);
  const auto ep0 = peratom(lmp, "s", 1);
  double epmax = 0.0;
  for (double a : ep0) epmax = std::max(epmax, a);
  ASSERT_GT(epmax, 1e-3);
  const NOSPD::Mat3 Q =
      Eigen::AngleAxisd(0.7, NOSPD::Vec3(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  place_affine(lmp, Q * (1.5 * F - 0.5 * NOSPD::Mat3::Identity()), c);
  cmd(lmp, "run 0");    // evaluated from the same accepted history
  const auto vm1 = peratom(lmp, "s", 0);
  const auto ep1 = peratom(lmp, "s", 1);
  double vmmax = 0.0;
  for (double v : vm0) vmmax = std::max(vmmax, v);
  for (size_t i = 0; i < vm0.size(); i++) {
    EXPECT_NEAR(vm1[i], vm0[i], 1e-9 * vmmax);
    EXPECT_NEAR(ep1[i], ep0[i], 1e-9 * epmax);
  }
}

// Force evaluations without an accepted step (run 0, trial states) never
// accumulate plastic strain; a step accepts it, and more evaluations at
// the same configuration leave it as it is.
TEST_P(Inelastic, TrialEvaluationsDoNotAccumulate)
{
  block("strain small", "yield 1e8", 7);
  cmd(lmp, "compute s all nospd/atom eqps");
  NOSPD::Mat3 F = NOSPD::Mat3::Identity();
  F(0, 0) += 0.003;
  place_affine(lmp, F, NOSPD::Vec3(0.003, 0.003, 0.003));
  for (int k = 0; k < 3; k++) cmd(lmp, "run 0");
  for (double a : peratom(lmp, "s", 0)) EXPECT_EQ(a, 0.0);
  cmd(lmp, "run 1");    // no integrator: the atoms stay, the step is accepted
  const auto a1 = peratom(lmp, "s", 0);
  for (int k = 0; k < 3; k++) cmd(lmp, "run 0");
  cmd(lmp, "run 1");
  const auto a2 = peratom(lmp, "s", 0);
  double amax = 0.0;
  for (size_t i = 0; i < a1.size(); i++) {
    amax = std::max(amax, a1[i]);
    EXPECT_NEAR(a2[i], a1[i], 1e-12 * std::max(a1[i], 1e-6));
  }
  EXPECT_GT(amax, 1e-3);
}

// compute nospd/atom strain_rate is the rate of the last accepted step that
// the Johnson-Cook term uses: a simple shear at the steady rate g gives
// sqrt(2/3) |dev D| = g / sqrt(3) at every point, surfaces included, for
// both kinematics (for a simple shear dF F^-1 = dF); one step more at
// twice the rate doubles it (the last step's rate, not a mean).
TEST_P(Inelastic, StrainRateOfSteadyShear)
{
  const double g = 250.0, dt = 1e-6;
  for (const char *kinematics : {"strain small", "strain hencky"}) {
    delete lmp;
    lmp = open_lammps();
    block(kinematics, "johnson_cook 300e6 200e6 0.3 0.02 1.0 1.0 293 1700", 7);
    cmd(lmp, "compute s all nospd/atom strain_rate eqps");
    cmd(lmp, "timestep " + num(dt));
    cmd(lmp, "run 0");
    NOSPD::Mat3 F = NOSPD::Mat3::Identity();
    for (int k = 1; k <= 3; k++) {
      F(0, 1) = k * g * dt;
      place_affine(lmp, F, NOSPD::Vec3(0.003, 0.003, 0.003));
      cmd(lmp, "run 1");    // no integrator: the atoms stay, the step is accepted
    }
    const auto rate = peratom(lmp, "s", 0);
    for (double r : rate) EXPECT_NEAR(r, g / std::sqrt(3.0), 1e-6 * g) << kinematics;
    for (double a : peratom(lmp, "s", 1)) EXPECT_EQ(a, 0.0) << "elastic: " << kinematics;
    F(0, 1) += 2.0 * g * dt;
    place_affine(lmp, F, NOSPD::Vec3(0.003, 0.003, 0.003));
    cmd(lmp, "run 1");
    for (double r : peratom(lmp, "s", 0))
      EXPECT_NEAR(r, 2.0 * g / std::sqrt(3.0), 2e-6 * g) << kinematics;
  }
}

// An evaluation at the configuration of the last accepted step (run 0 after
// it, a thermo or restart setup) gives that step's forces and energy, even
// where the step changed what the next one starts from: under Johnson-Cook
// with the rate term and adiabatic heating, a step at a third of the rate
// of the one before leaves a lower lagged rate and a hotter body, but its
// own return used the earlier rate and temperature.  Taking the new ones
// instead would lower the flow stress below the accepted stress of every
// yielding point, which would yield again.
TEST_P(Inelastic, AcceptedConfigurationGivesTheStepsForces)
{
  const double g = 1000.0, dt = 1e-6;
  block("strain hencky temperature v_T",
        "johnson_cook 9e7 2.92e8 0.31 0.025 1.0 1.09 298 1356 heat 383 0.9", 7);
  cmd(lmp, "variable T atom 400.0");
  cmd(lmp, "compute s all nospd/atom strain_rate eqps");
  cmd(lmp, "timestep " + num(dt));
  cmd(lmp, "run 0");
  const NOSPD::Vec3 c(0.003, 0.003, 0.003);
  NOSPD::Mat3 F = NOSPD::Mat3::Identity();
  for (double rate : {3.0 * g, 3.0 * g, g}) {
    F(0, 1) += rate * dt;
    F(0, 0) += 0.3 * rate * dt;
    place_affine(lmp, F, c);
    cmd(lmp, "run 1");    // no integrator: the atoms stay, the step is accepted
  }
  const auto f_step = by_tag(lmp, lmp->atom->f);
  const double pe_step = potential_energy(lmp);
  // the step yielded and left a rate below the one it used
  double eqmax = 0.0, rmax = 0.0;
  for (double a : peratom(lmp, "s", 1)) eqmax = std::max(eqmax, a);
  for (double r : peratom(lmp, "s", 0)) rmax = std::max(rmax, r);
  ASSERT_GT(eqmax, 1e-3);
  ASSERT_LT(rmax, 2.0 * g / std::sqrt(3.0));

  cmd(lmp, "run 0");
  const auto f_again = by_tag(lmp, lmp->atom->f);
  double fscale = 0.0;
  for (const auto &f : f_step)
    for (double v : f) fscale = std::max(fscale, std::abs(v));
  ASSERT_GT(fscale, 0.0);
  for (size_t i = 0; i < f_step.size(); i++)
    for (int k = 0; k < 3; k++)
      ASSERT_NEAR(f_again[i][k], f_step[i][k], 1e-12 * fscale) << "atom " << i + 1;
  EXPECT_NEAR(potential_energy(lmp), pe_step, 1e-12 * std::abs(pe_step));
}

// minimize is one load step: its line-search evaluations accept nothing,
// its converged state is accepted at its end.  A periodic body strained
// past yield and perturbed relaxes back to the uniform state; its plastic
// strain is that of the same strain accepted by one step without
// perturbation (line searches that accumulated plastic strain would
// overshoot it).
TEST_P(Inelastic, MinimizeIsOneLoadStep)
{
  std::vector<double> eq[2];
  for (int k = 0; k < 2; k++) {
    delete lmp;
    lmp = open_lammps();
    block("strain small", "yield 1e8 hardening linear 2e9", 8, true);
    cmd(lmp, "compute s all nospd/atom eqps");
    cmd(lmp, "run 0");
    cmd(lmp, "change_box all x scale 1.003 y scale 0.999 remap units box");
    if (k == 0) {
      cmd(lmp, "displace_atoms all random 2e-6 2e-6 2e-6 4411 units box");
      // the largest trial move of the line search: a fraction of the spacing
      cmd(lmp, "min_modify dmax 1e-5");
      cmd(lmp, "minimize 0.0 1e-12 2000 20000");
      EXPECT_GT(lmp->update->minimize->niter, 3);
    } else {
      cmd(lmp, "run 1");
    }
    eq[k] = peratom(lmp, "s", 0);
    for (int r = 0; r < 2; r++) cmd(lmp, "run 0");    // evaluations keep it
    const auto again = peratom(lmp, "s", 0);
    for (size_t i = 0; i < again.size(); i++) EXPECT_EQ(again[i], eq[k][i]);
  }
  double amax = 0.0;
  for (size_t i = 0; i < eq[1].size(); i++) {
    amax = std::max(amax, eq[1][i]);
    EXPECT_NEAR(eq[0][i], eq[1][i], 1e-4 * eq[1][i]);
  }
  EXPECT_GT(amax, 1e-3);
}

// minimize accepts its state at its end (post_run), after its last output:
// that output (thermo, here the mean eqps and the plastic work sum) shows
// the state of its latest force evaluation, which is the one accepted.  A
// periodic body under eps = diag(0.003, -0.001, 0): one radial return with
// linear hardening gives eqps = (q_trial - sigma_y) / (3 G + H) at every
// point, q_trial = 2 G sqrt(3/2) |dev eps|.
TEST_P(Inelastic, MinimizeOutputShowsItsState)
{
  const double sy = 1e8, H = 2e9, G = E / (2 * (1 + NU));
  block("strain small", "yield " + num(sy) + " hardening linear " + num(H), 8, true);
  cmd(lmp, "compute s all nospd/atom eqps");
  cmd(lmp, "compute ea all reduce ave c_s[1]");
  cmd(lmp, "thermo_style custom step c_ea f_NOSPD_BONDS[4]");
  cmd(lmp, "run 0");
  cmd(lmp, "change_box all x scale 1.003 y scale 0.999 remap units box");
  cmd(lmp, "displace_atoms all random 2e-6 2e-6 2e-6 4411 units box");
  cmd(lmp, "min_modify dmax 1e-5");
  cmd(lmp, "minimize 0.0 1e-12 2000 20000");
  const auto &last = lmp->output->thermo->get_fields();    // the minimization's last line
  const double eq_out = last[1].data.d, work_out = last[2].data.d;
  const auto eq = peratom(lmp, "s", 0);
  double mean = 0.0;
  for (double v : eq) mean += v / eq.size();
  const double work = lmp->modify->get_fix_by_id("NOSPD_BONDS")->compute_vector(3);
  const double tr = 0.002, dev[3] = {0.003 - tr / 3, -0.001 - tr / 3, -tr / 3};
  const double q = 2 * G * std::sqrt(1.5 * (dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2]));
  const double expect = (q - sy) / (3 * G + H);
  EXPECT_NEAR(mean, expect, 1e-3 * expect);
  EXPECT_NEAR(eq_out, mean, 1e-12 * mean);
  EXPECT_GT(work, 0.0);
  EXPECT_NEAR(work_out, work, 1e-12 * work);
}

// A minimize step is quasi-static: the Johnson-Cook rate term stays off,
// whatever the time step (which would turn the step's strain into a rate).
// Two load steps (the second starts from the first's accepted state) give
// the plastic strain of the same law with C = 0, for two time steps.
TEST_P(Inelastic, MinimizeHasNoStrainRate)
{
  std::vector<double> eq[3];
  const char *C[3] = {"0.0", "0.05", "0.05"};
  const char *dt[3] = {"1e-9", "1e-9", "1.0"};
  for (int k = 0; k < 3; k++) {
    delete lmp;
    lmp = open_lammps();
    block("strain small", std::string("johnson_cook 1e8 2e9 1.0 ") + C[k] + " 1.0 1.0 293 1500",
          8, true);
    cmd(lmp, "compute s all nospd/atom eqps");
    cmd(lmp, std::string("timestep ") + dt[k]);
    cmd(lmp, "run 0");
    cmd(lmp, "min_modify dmax 1e-5");
    for (int step = 0; step < 2; step++) {
      cmd(lmp, "change_box all x scale 1.002 y scale 0.999 remap units box");
      cmd(lmp, "minimize 0.0 1e-12 2000 20000");
    }
    eq[k] = peratom(lmp, "s", 0);
  }
  double amax = 0.0;
  for (size_t i = 0; i < eq[0].size(); i++) {
    amax = std::max(amax, eq[0][i]);
    EXPECT_NEAR(eq[1][i], eq[0][i], 1e-8 * eq[0][i]) << "atom " << i + 1;
    EXPECT_NEAR(eq[2][i], eq[0][i], 1e-8 * eq[0][i]) << "atom " << i + 1;
  }
  EXPECT_GT(amax, 1e-3);
}

// During minimize the energy of a yielding point is the step's incremental
// potential W_e + dD, whose gradient the returned stress is (kernel tests
// StressIsIncrementalPotentialGradient, FormIIIsIncrementalPotentialGradient);
// outside it is W_e.  At the start of a minimization the energy therefore
// exceeds that of a run 0 at the same positions by the step's plastic work.
TEST_P(Inelastic, MinimizeEnergyIsIncrementalPotential)
{
  block("strain small", "yield 1e8 hardening linear 2e9", 8, true);
  cmd(lmp, "run 0");
  cmd(lmp, "change_box all x scale 1.003 y scale 0.9995 remap units box");
  cmd(lmp, "run 0");
  const double pe = potential_energy(lmp);
  auto *fb = static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  double work = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    work += fb->history_trial[i][NOSPD::Hist::WORK] - fb->history[i][NOSPD::Hist::WORK];
  ASSERT_GT(work, 1e-3 * pe);
  cmd(lmp, "min_modify dmax 1e-6");
  cmd(lmp, "minimize 0.0 0.0 0 0");
  EXPECT_NEAR(lmp->update->minimize->einitial, pe + work, 1e-10 * (pe + work));
}

// fix nospd/damage eqps: points past the critical plastic strain lose their
// bonds; with the critical value above the reached strain nothing breaks.
TEST_P(Inelastic, DamageOnEquivalentPlasticStrain)
{
  for (double crit : {1e-3, 0.1}) {
    delete lmp;
    lmp = open_lammps();
    block("strain small", "yield 1e8", 7);
    cmd(lmp, "fix dmg all nospd/damage eqps " + num(crit));
    cmd(lmp, "fix 1 all nve");
    NOSPD::Mat3 F = NOSPD::Mat3::Identity();
    F(0, 0) += 0.004;
    place_affine(lmp, F, NOSPD::Vec3(0.003, 0.003, 0.003));
    cmd(lmp, "run 2");
    const double broken = lmp->modify->get_fix_by_id("NOSPD_BONDS")->compute_vector(1);
    if (crit < 0.01) EXPECT_GT(broken, 0.5 * lmp->modify->get_fix_by_id("NOSPD_BONDS")->compute_vector(0));
    else EXPECT_EQ(broken, 0.0);
  }
}

// compute nospd/bond/local on a plastically stretched periodic body: every
// bond shows the accepted stress and plastic strain, which under a
// homogeneous deformation are the points' (the elastic law at the bond's F
// would give a stress off by E times the plastic strain)
TEST_P(Inelastic, BondLocalShowsAcceptedState)
{
  block("strain small", "yield 1e8 hardening linear 2e9", 8, true);
  cmd(lmp, "compute s all nospd/atom stress eqps");
  cmd(lmp, "compute b all nospd/bond/local id stress eqps");
  cmd(lmp, "run 0");
  cmd(lmp, "change_box all x scale 1.004 y scale 0.999 remap units box");
  cmd(lmp, "run 1");
  std::vector<std::vector<double>> atom_cols;
  for (int c = 0; c < 7; c++) atom_cols.push_back(peratom(lmp, "s", c));
  auto *b = lmp->modify->get_compute_by_id("b");
  b->compute_local();
  ASSERT_GT(b->size_local_rows, 0);
  double smax = 0.0, eqmax = 0.0;
  for (int r = 0; r < b->size_local_rows; r++) {
    const double *row = b->array_local[r];
    const int i = (int) row[0] - 1;
    for (int c = 0; c < 6; c++) {
      smax = std::max(smax, std::abs(atom_cols[c][i]));
      ASSERT_NEAR(row[2 + c], atom_cols[c][i], 1e-9 * 1e8) << "bond row " << r;
    }
    eqmax = std::max(eqmax, row[8]);
    ASSERT_NEAR(row[8], atom_cols[6][i], 1e-9 * atom_cols[6][i]);
  }
  EXPECT_GT(eqmax, 1e-3);
  EXPECT_GT(smax, 1e8);
}

std::string style_name(const ::testing::TestParamInfo<StyleCase> &info)
{
  return info.param.name;
}
INSTANTIATE_TEST_SUITE_P(Styles, Inelastic, ::testing::ValuesIn(STYLES), style_name);
INSTANTIATE_TEST_SUITE_P(Styles, InelasticPotential, ::testing::Values(STYLES[0], STYLES[1]),
                         style_name);

/* Drucker-Prager through pair_coeff (the material interface): a periodic
   block compressed along x in steps of change_box ... remap, each accepted
   by a run (F = diag(s, 1, 1) at every point, no surface), has at every
   point the first Piola-Kirchhoff stress of the kernel driven along the same
   F path, under both kinematics and in both styles (the bond-associated
   one runs the law per bond through NOSPD::FamilyMaterial: every bond's F
   is the block's); the path yields on the cone. */
TEST(DruckerPragerBody, UniformCompressionFollowsTheKernel)
{
  for (const std::string style : {"peri/nospd", "peri/nospd/hs"})
  for (const std::string law : {"small", "hencky"}) {
    SCOPED_TRACE(style + " " + law);
    LAMMPS *lmp = open_lammps();
    Block b;
    b.n = 8;
    b.style = style;
    b.periodic = true;
    b.E = 30e9;
    b.nu = 0.2;
    b.settings = "strain " + law;
    make_block(lmp, b);
    cmd(lmp, "pair_coeff * * 30e9 0.2 " + num(b.delta()) + " drucker_prager 30 10 5e6 2e9");
    cmd(lmp, "run 0");
    const NOSPD::Lame m = NOSPD::Lame::from_young(30e9, 0.2);
    const NOSPD::DruckerPrager dp =
        NOSPD::DruckerPrager::from_angles(30.0 * M_PI / 180.0, 10.0 * M_PI / 180.0, 5e6, 2e9);
    std::vector<double> h(NOSPD::Hist::SIZE, 0.0), h1(NOSPD::Hist::SIZE);
    auto *fb =
        static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
    double s = 1.0;
    for (int k = 1; k <= 12; k++) {
      cmd(lmp, "change_box all x scale 0.9996 remap");
      cmd(lmp, "run 1");
      s *= 0.9996;
      NOSPD::Mat3 F = NOSPD::Mat3::Identity(), P;
      F(0, 0) = s;
      double W;
      const auto st = law == "small" ? NOSPD::drucker_prager_small(m, dp, F, h.data(), h1.data(), P, W)
                                     : NOSPD::drucker_prager_hencky(m, dp, F, h.data(), h1.data(), P, W);
      ASSERT_EQ(st, NOSPD::ReturnStatus::OK);
      h = h1;
      double worst = 0.0;
      for (int i = 0; i < lmp->atom->nlocal; i++)
        for (int c = 0; c < 9; c++)
          worst = std::max(worst, std::abs(fb->pk1[i][c] - P(c / 3, c % 3)));
      EXPECT_LT(worst, 1e-8 * P.cwiseAbs().maxCoeff()) << "step " << k;
    }
    EXPECT_GT(h[NOSPD::Hist::EQPS], 0.0) << "the path must yield";
    EXPECT_GT(fb->history[0][NOSPD::Hist::EQPS], 0.0);
    delete lmp;
  }
}

/* The Berea sandstone entry of potentials/plasticity.nospd, read by
   pair_coeff from the repository's file, behaves as its published constants
   say (E = 14.7 GPa, nu = 0.20, Mohr-Coulomb c = 27.2 MPa, phi = 27.8 deg;
   written here, not read back from the file).  A periodic block in uniaxial
   strain, F = diag(1 + e, 1, 1) (change_box ... remap, strain small), is on
   Mohr-Coulomb's compression meridian (the two lateral stresses equal, above
   the axial one), where the file's cone must coincide with Mohr-Coulomb:
       f = (s1 - s3)/2 + (s1 + s3)/2 sin(phi) - c cos(phi),
   elastic s_xx = (lambda + 2 mu) e, s_yy = s_zz = lambda e, so first yield
   at e_y = -c cos(phi) / (mu - (lambda + mu) sin(phi)) = -1.764 %.  At
   0.5 e_y the stress is Hooke's of E and nu; at 0.99 e_y no point yields and
   f = -1 % of c cos(phi); at 1.01 e_y and 1.5 e_y every point yields and sits
   on f = 0 at two different pressures (the flow moves the stress along the
   meridian), which pins c and phi both. */
TEST(DruckerPragerBody, BereaSandstoneEntryYieldsOnMohrCoulomb)
{
  const double E = 14.7e9, nu = 0.20, c = 27.2e6, phi = 27.8 * M_PI / 180.0;
  const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), mu = E / (2.0 * (1.0 + nu));
  const double ccos = c * std::cos(phi);
  const double ey = -ccos / (mu - (lambda + mu) * std::sin(phi));
  LAMMPS *lmp = open_lammps();
  Block b;
  b.n = 8;
  b.periodic = true;
  b.E = E;
  b.nu = nu;
  b.settings = "strain small";
  make_block(lmp, b);
  ASSERT_EQ(error_of(lmp, "pair_coeff * * plasticity.nospd berea_sandstone_dp " + num(b.delta())), "");
  cmd(lmp, "run 0");
  auto *fb = static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  double s = 1.0;    // box stretch along x so far
  auto strain_to = [&](double e) {
    cmd(lmp, "change_box all x scale " + num((1.0 + e) / s) + " remap");
    cmd(lmp, "run 1");
    s = 1.0 + e;
  };
  // principal stresses (sorted) of point i, and its Mohr-Coulomb f / (c cos phi)
  auto principal = [&](int i) {
    NOSPD::Mat3 P;
    for (int k = 0; k < 9; k++) P(k / 3, k % 3) = fb->pk1[i][k];
    Eigen::SelfAdjointEigenSolver<NOSPD::Mat3> eig(0.5 * (P + P.transpose()));
    return NOSPD::Vec3(eig.eigenvalues());    // ascending: s3, s2, s1
  };
  auto mc = [&](int i) {
    const NOSPD::Vec3 sp = principal(i);
    return (0.5 * (sp(2) - sp(0)) + 0.5 * (sp(2) + sp(0)) * std::sin(phi) - ccos) / ccos;
  };
  const int n = lmp->atom->nlocal;
  ASSERT_EQ(n, 512);

  // points with plastic strain, and those whose last increment returned to the cone
  auto count = [&](int &plastic, int &cone) {
    plastic = cone = 0;
    for (int i = 0; i < n; i++) {
      plastic += fb->history[i][NOSPD::Hist::EQPS] > 0.0;
      cone += fb->history[i][NOSPD::Hist::YIELDING] == 1.0;
    }
  };
  int plastic, cone;

  strain_to(0.5 * ey);    // elastic: Hooke's law of the entry's E and nu
  const double want[3] = {(lambda + 2.0 * mu) * 0.5 * ey, lambda * 0.5 * ey, lambda * 0.5 * ey};
  double worst = 0.0;
  for (int i = 0; i < n; i++)
    for (int a = 0; a < 3; a++) worst = std::max(worst, std::abs(fb->pk1[i][4 * a] - want[a]));
  EXPECT_LT(worst, 1e-6 * std::abs(want[0])) << "s_xx, s_yy, s_zz against (lambda + 2 mu) e, lambda e";
  count(plastic, cone);
  EXPECT_EQ(plastic, 0);

  strain_to(0.99 * ey);    // just below the predicted onset
  count(plastic, cone);
  EXPECT_EQ(plastic, 0) << "points yield before e_y";
  worst = 0.0;
  for (int i = 0; i < n; i++) worst = std::max(worst, std::abs(mc(i) - (-0.01)));
  EXPECT_LT(worst, 1e-6) << "f/(c cos phi) at 0.99 e_y, expected -0.01; point 0: " << mc(0);

  std::vector<double> pressure;
  for (double r : {1.01, 1.5}) {    // just past the onset, and well into flow
    SCOPED_TRACE("e = " + std::to_string(r) + " e_y");
    strain_to(r * ey);
    count(plastic, cone);
    EXPECT_EQ(plastic, n) << "every point must yield";
    EXPECT_EQ(cone, n) << "every point's return must be onto the cone";
    worst = 0.0;
    for (int i = 0; i < n; i++) worst = std::max(worst, std::abs(mc(i)));
    EXPECT_LT(worst, 1e-6) << "f/(c cos phi): the stress must lie on Mohr-Coulomb; point 0: "
                           << mc(0);
    const NOSPD::Vec3 sp = principal(0);
    EXPECT_NEAR(sp(1), sp(2), 1e-9 * std::abs(sp(0))) << "compression meridian: lateral equal";
    pressure.push_back(sp.sum() / 3.0);
  }
  EXPECT_LT(pressure[1], 1.2 * pressure[0]) << "two distinct pressures on the meridian";
  delete lmp;
}

// ---------------------------------------------------------------------------
// bad input

class InelasticBadInput : public ::testing::Test {
 protected:
  LAMMPS *lmp = nullptr;
  void SetUp() override { lmp = open_lammps(); }
  void TearDown() override { delete lmp; }
  std::string coeff_error(const std::string &settings, const std::string &extra)
  {
    Block b;
    b.n = 5;
    b.settings = settings;
    make_block(lmp, b);
    return error_of(lmp, "pair_coeff * * 200e9 0.3 0.003 " + extra);
  }
};

/* johnson_cook excludes yield and hardening within one list in any order
   (once, yield after johnson_cook was an error while johnson_cook after
   yield silently dropped the yield, and hardening silently replaced B, n) */
TEST_F(InelasticBadInput, JohnsonCookExcludesYieldInAnyOrder)
{
  const std::string jc = "johnson_cook 300e6 500e6 0.3 0.01 1.0 1.0 250 1800";
  for (const std::string &extra : {"yield 250e6 " + jc, jc + " yield 250e6",
                                   jc + " hardening linear 0", jc + " hardening power 1e9 0.5"}) {
    delete lmp;
    lmp = open_lammps();
    EXPECT_THAT(coeff_error("", extra), HasSubstr("johnson_cook excludes yield and hardening"))
        << extra;
  }
}

/* A type made elastic again (no plastic flow yet) leaves no history behind:
   the run goes on as a fresh elastic one, with the same energy and, in the
   bond-associated style, the same points on the stencil (which history
   would switch off) */
TEST_F(InelasticBadInput, ElasticAgainDropsHistory)
{
  for (const std::string style : {"peri/nospd", "peri/nospd/hs"}) {
    auto run = [&](bool plastic_first, int &nhist, double &stencil) {
      delete lmp;
      lmp = open_lammps();
      Block b;
      b.n = 10;
      b.style = style;
      make_block(lmp, b);
      cmd(lmp, "displace_atoms all random 1e-6 1e-6 1e-6 4321 units box");
      if (plastic_first) {
        cmd(lmp, "pair_coeff * * 200e9 0.3 " + num(b.delta()) + " yield 250e6");
        cmd(lmp, "run 0 post no");
        cmd(lmp, "pair_coeff * * 200e9 0.3 " + num(b.delta()));
      }
      cmd(lmp, "run 0 post no");
      nhist = static_cast<LAMMPS_NS::FixNospdBonds *>(
                  lmp->modify->get_fix_by_id("NOSPD_BONDS"))->nhistory;
      stencil = style == "peri/nospd/hs" ? lmp->force->pair->pvector[1] : 0.0;
      return potential_energy(lmp);
    };
    int nh_fresh = 0, nh_again = 0;
    double st_fresh = 0.0, st_again = 0.0;
    const double fresh = run(false, nh_fresh, st_fresh), again = run(true, nh_again, st_again);
    EXPECT_EQ(nh_again, 0) << style;
    EXPECT_EQ(st_again, st_fresh) << style;
    EXPECT_NEAR(again, fresh, 1e-12 * std::abs(fresh)) << style;
  }
}

/* The type's T_ref is that of *thermal* if given, in the material file or
   on the line: a johnson_cook on the pair_coeff line (its own T_ref 250 K)
   must not replace a file entry's thermal T_ref (300 K).  A stretched block
   at 300 K: the file entry plus the line equals the same keywords on one
   line; with T_ref 250 the thermal strain alpha 50 K would show. */
TEST_F(InelasticBadInput, ThermalRefOfFileKept)
{
  const std::string file = "nospd_thermal_ref_test.nospd";    // in the build folder
  {
    std::ofstream out(file);
    out << "# DATE: 2026-11-27 UNITS: si CONTRIBUTOR: test\n"
        << "mythermal 200e9 0.3 7850 0 thermal 1e-5 300\n";
  }
  const std::string jc = " johnson_cook 300e6 500e6 0.3 0.01 1.0 1.0 250 1800";
  auto energy = [&](const std::string &coeff) {
    delete lmp;
    lmp = open_lammps();
    Block b;
    b.n = 8;
    make_block(lmp, b);
    cmd(lmp, "fix T all property/atom d_T");
    cmd(lmp, "set group all d_T 300");
    cmd(lmp, "pair_style peri/nospd temperature d_T");
    cmd(lmp, "pair_coeff * * " + coeff);
    cmd(lmp, "displace_atoms all ramp x 0 4e-5 x 0 0.008 units box");
    cmd(lmp, "run 0 post no");
    return potential_energy(lmp);
  };
  const double both = energy(file + " mythermal 0.003015" + jc),
               one_line = energy("200e9 0.3 0.003015 thermal 1e-5 300" + jc),
               ref250 = energy("200e9 0.3 0.003015 thermal 1e-5 250" + jc);
  ASSERT_GT(std::abs(ref250 - one_line), 1e-3 * one_line);    // T_ref shows
  EXPECT_NEAR(both, one_line, 1e-12 * one_line);
}

TEST_F(InelasticBadInput, NonPositiveYield)
{
  EXPECT_THAT(coeff_error("", "yield -1e8"), HasSubstr("yield stress must be > 0, got -1"));
}
TEST_F(InelasticBadInput, ZeroYield)
{
  EXPECT_THAT(coeff_error("", "yield 0"), HasSubstr("yield stress must be > 0, got 0"));
}
TEST_F(InelasticBadInput, SofteningLinear)
{
  EXPECT_THAT(coeff_error("", "yield 1e8 hardening linear -5e8"),
              HasSubstr("hardening linear H = -500000000 would make the flow stress fall"));
}
TEST_F(InelasticBadInput, SofteningPower)
{
  EXPECT_THAT(coeff_error("", "yield 1e8 hardening power -1e8 0.3"),
              HasSubstr("would make the flow stress fall"));
}
TEST_F(InelasticBadInput, JohnsonCookMeltBelowReference)
{
  EXPECT_THAT(coeff_error("", "johnson_cook 9e7 2.9e8 0.31 0.025 1 1.09 298 250"),
              HasSubstr("T_melt = 250 must exceed T_ref = 298"));
}
TEST_F(InelasticBadInput, MissingValues)
{
  EXPECT_THAT(coeff_error("", "johnson_cook 9e7 2.9e8"), HasSubstr("johnson_cook needs 8 value(s)"));
}
TEST_F(InelasticBadInput, UnknownKeyword)
{
  EXPECT_THAT(coeff_error("", "yeild 1e8"), HasSubstr("unknown keyword 'yeild'"));
}
TEST_F(InelasticBadInput, HardeningWithoutYield)
{
  EXPECT_THAT(coeff_error("", "hardening linear 1e9"), HasSubstr("need a yield stress"));
}
TEST_F(InelasticBadInput, LawWithoutInelasticForm)
{
  coeff_error("strain svk", "yield 1e8");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("strain svk has no inelastic form"));
}
TEST_F(InelasticBadInput, KinematicFiniteStrain)
{
  coeff_error("strain hencky", "yield 1e8 kinematic 1e9");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("kinematic hardening is implemented for strain small only"));
}
// an inverted body (a mirror image, det F = -1 everywhere) stops the run
// with an atom and the step named, in both styles, never with NaN
TEST_F(InelasticBadInput, InvertedFamilyNamed)
{
  for (const char *style : {"peri/nospd", "peri/nospd/hs"}) {
    delete lmp;
    lmp = open_lammps();
    Block b;
    b.n = 5;
    b.style = style;
    b.settings = "strain hencky";
    make_block(lmp, b);
    cmd(lmp, "pair_coeff * * 200e9 0.3 " + num(b.delta()) + " yield 1e8");
    cmd(lmp, "run 0");
    cmd(lmp, "variable mx atom 0.004-x");
    cmd(lmp, "set group all x v_mx");
    EXPECT_THAT(error_of(lmp, "run 0"),
                ::testing::AllOf(HasSubstr("on step 0"), HasSubstr("det F"),
                                 HasSubstr("undefined"), HasSubstr("atom")))
        << style;
  }
}
TEST_F(InelasticBadInput, MissingTemperatureProperty)
{
  coeff_error("temperature d_nothere", "thermal 1e-5 293");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("temperature d_nothere is not a per-atom"));
}
TEST_F(InelasticBadInput, TemperatureNotAtomVariable)
{
  coeff_error("temperature v_T", "thermal 1e-5 293");
  cmd(lmp, "variable T equal 300");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("temperature variable T is not atom-style"));
}
TEST_F(InelasticBadInput, DamageEqpsWithoutPlasticity)
{
  coeff_error("", "");
  cmd(lmp, "fix dmg all nospd/damage eqps 0.1");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("criterion eqps needs a type with plasticity"));
}
// a line search's first trial move (min_modify dmax, 0.1 m by default in SI)
// throws atoms out of reach: the error says what to change
TEST_F(InelasticBadInput, MinimizeDefaultDmaxNamed)
{
  Block b;
  b.n = 8;
  b.periodic = true;
  make_block(lmp, b);
  cmd(lmp, "run 0");
  cmd(lmp, "displace_atoms all random 2e-6 2e-6 2e-6 4411 units box");
  EXPECT_THAT(error_of(lmp, "minimize 0.0 1e-12 100 1000"), HasSubstr("min_modify dmax"));
}
// a Johnson-Cook failure strain <= 0 in shear or uniaxial tension would
// break every yielding bond at once
TEST_F(InelasticBadInput, JohnsonCookFailureStrainNotPositive)
{
  const std::string jc = "johnson_cook 300e6 500e6 0.3 0.01 1.0 1.0 250 1800 jc_failure ";
  EXPECT_THAT(coeff_error("", jc + "-0.5 0.2 1 0 0"),
              HasSubstr("give a failure strain -0.3 <= 0 at triaxiality 0"));
  delete lmp;
  lmp = open_lammps();
  EXPECT_THAT(coeff_error("", jc + "0.1 -0.2 1 0 0"),
              HasSubstr("<= 0 at triaxiality 0"));
  delete lmp;
  lmp = open_lammps();
  // Ti-6Al-4V's (D1 < 0) is positive in shear and tension
  EXPECT_EQ(coeff_error("", jc + "-0.09 0.25 -0.5 0.014 3.87"), "");
}

// minimize with forces that are no energy gradient warns once, naming FIRE
TEST_F(InelasticBadInput, MinimizeWithoutPotentialWarns)
{
  Block b;
  b.n = 6;
  b.settings = "stabilization hourglass 0.2";
  make_block(lmp, b);
  cmd(lmp, "min_modify dmax 1e-6");
  cmd(lmp, "displace_atoms all random 1e-7 1e-7 1e-7 4411 units box");
  const std::string log = log_of(lmp, {"minimize 0.0 1e-12 5 20", "minimize 0.0 1e-12 5 20"});
  EXPECT_THAT(log, HasSubstr("stabilization hourglass is not a potential): CG and the line "
                             "searches need forces that are the gradient of the energy; use "
                             "min_style fire"));
  const auto first = log.find("not a potential");
  EXPECT_EQ(log.find("not a potential", first + 1), std::string::npos) << "warned once";
  delete lmp;
  lmp = open_lammps();
  make_block(lmp, b);
  cmd(lmp, "min_modify dmax 1e-6");
  cmd(lmp, "min_style fire");
  cmd(lmp, "timestep 1e-8");
  EXPECT_EQ(log_of(lmp, {"minimize 0.0 1e-12 5 20"}).find("not a potential"), std::string::npos)
      << "FIRE needs no potential";
  delete lmp;
  lmp = open_lammps();
  b.settings = "";
  make_block(lmp, b);
  cmd(lmp, "min_modify dmax 1e-6");
  EXPECT_EQ(log_of(lmp, {"minimize 0.0 1e-12 5 20"}).find("not a potential"), std::string::npos);
}

TEST_F(InelasticBadInput, DruckerPragerInput)
{
  const std::pair<std::string, std::string> cases[] = {
      {"drucker_prager 0 0 5e6 0", "friction angle phi must be in (0, 90) degrees, got 0"},
      {"drucker_prager 30 40 5e6 0", "dilatancy angle psi must be in [0, phi = 30] degrees"},
      {"drucker_prager 30 10 -1 0", "cohesion c must be > 0, got -1"},
      {"drucker_prager 30 10 5e6 -1", "H must be >= 0"},
      {"drucker_prager 30 10 5e6 0 yield 1e8", "drucker_prager excludes yield and johnson_cook"},
      {"drucker_prager 30 10 5e6 0 thermal 1e-5 293", "no thermal strain"},
  };
  for (const auto &c : cases) {
    delete lmp;
    lmp = open_lammps();
    EXPECT_THAT(coeff_error("", c.first), HasSubstr(c.second)) << c.first;
  }
  // the law needs an inelastic form (small or hencky)
  delete lmp;
  lmp = open_lammps();
  EXPECT_EQ(coeff_error("strain svk", "drucker_prager 30 10 5e6 0"), "");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("type 1 has drucker_prager but strain svk"));
  delete lmp;
  lmp = open_lammps();
  EXPECT_EQ(coeff_error("", "drucker_prager 30 0 5e6 0"), "");
  place_affine(lmp, 1.01 * NOSPD::Mat3::Identity(), NOSPD::Vec3(0.002, 0.002, 0.002));
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("cannot return without dilatancy"));
}

TEST_F(InelasticBadInput, HeatWithoutPlasticity)
{
  EXPECT_THAT(coeff_error("", "heat 450 0.9"), HasSubstr("heat and jc_failure need plasticity"));
}

// plastic state of an earlier run needs a law that reads it: an elastic
// law or the other strain measure is an error; the same law with other
// constants is not, nor is a law change for a type that never yielded
TEST_F(InelasticBadInput, PlasticStateKeepsItsLaw)
{
  Block b;
  b.n = 5;
  b.settings = "strain small";
  make_block(lmp, b);
  const std::string elastic = "pair_coeff * * 200e9 0.3 0.003";
  cmd(lmp, elastic + " yield 1e8");
  cmd(lmp, "run 0");
  cmd(lmp, "change_box all x scale 1.01 remap units box");
  cmd(lmp, "run 1");    // yields, and the step is accepted
  cmd(lmp, elastic + " yield 2e8");
  EXPECT_EQ(error_of(lmp, "run 0"), "");
  cmd(lmp, elastic);
  EXPECT_THAT(error_of(lmp, "run 0"),
              HasSubstr("pair_coeff 1 1: the atoms of type 1 carry plastic state from plasticity "
                        "under strain small of an earlier run, which an elastic law would not "
                        "read"));
  cmd(lmp, "pair_style peri/nospd strain hencky");
  cmd(lmp, elastic + " yield 1e8");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("which plasticity under strain hencky would not"));
}

// The same rule for an atom that changes type: `set type` between runs to a
// type of another law is refused as a pair_coeff changing its type's law
// is (before, the atoms' plastic strain was silently dropped: pe 58 times
// higher at the same positions); to a type of the same law it is allowed,
// and after a run under the new type the atom's history is that type's.
TEST_F(InelasticBadInput, SetTypeKeepsThePlasticLaw)
{
  Block b;
  b.n = 5;
  b.settings = "strain small";
  make_block(lmp, b);
  const std::string coeff = " 200e9 0.3 0.00301";    // the block's horizon, 1-2 too
  cmd(lmp, "pair_coeff 1 1" + coeff + " yield 1e8");
  cmd(lmp, "pair_coeff 2 2" + coeff);
  cmd(lmp, "run 0");
  cmd(lmp, "change_box all x scale 1.01 remap units box");
  cmd(lmp, "run 1");    // yields, and the step is accepted
  cmd(lmp, "set atom 3 type 2");
  EXPECT_THAT(error_of(lmp, "run 0"),
              HasSubstr("set type: atom 3 changed from type 1 to type 2 after an earlier run and "
                        "carries plastic state from plasticity under strain small (type 1), "
                        "which an elastic law (type 2) would not read"));
  cmd(lmp, "set atom 3 type 1");
  cmd(lmp, "pair_coeff 2 2" + coeff + " yield 2e8");
  cmd(lmp, "set atom 3 type 2");
  EXPECT_EQ(error_of(lmp, "run 0"), "");
  // type 2 keeps its law: atom 3's history is now type 2's, which may not
  // become elastic, while type 1 may
  cmd(lmp, "pair_coeff 2 2" + coeff);
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("pair_coeff 2 2: the atoms of type 2 carry"));
}

// A restart holds what the families were built with: the same changes of
// law or horizon that a continued session refuses are refused after
// read_restart, and a restart read under the other pair style starts new
// families, as a pair_style command between runs does.
TEST_F(InelasticBadInput, RestartKeepsTheChecksOfAContinuedSession)
{
  const std::string rfile = "nospd_law_check.restart";
  Block b;
  b.n = 5;
  b.settings = "strain small";
  make_block(lmp, b);
  const std::string elastic = "pair_coeff * * 200e9 0.3 0.003";
  cmd(lmp, elastic + " yield 1e8");
  cmd(lmp, "run 0");
  cmd(lmp, "change_box all x scale 1.01 remap units box");
  cmd(lmp, "run 1");
  auto plastic_work = [&] {
    return lmp->modify->get_fix_by_id("NOSPD_BONDS")->compute_vector(3);
  };
  const double work = plastic_work();
  ASSERT_GT(work, 0.0);
  cmd(lmp, "write_restart " + rfile);
  auto restart_then = [&](const std::vector<std::string> &lines) {
    delete lmp;
    lmp = open_lammps();
    cmd(lmp, "read_restart " + rfile);
    for (const auto &l : lines) cmd(lmp, l);
    return error_of(lmp, "run 0");
  };
  EXPECT_EQ(restart_then({elastic + " yield 1e8"}), "");
  EXPECT_DOUBLE_EQ(plastic_work(), work);
  EXPECT_THAT(restart_then({elastic}), HasSubstr("which an elastic law would not read"));
  EXPECT_THAT(restart_then({"pair_style peri/nospd strain hencky", elastic + " yield 1e8"}),
              HasSubstr("which plasticity under strain hencky would not"));
  EXPECT_THAT(restart_then({"pair_coeff * * 200e9 0.3 0.004 yield 1e8"}),
              HasSubstr("horizon 0.004 differs from 0.003"));
  EXPECT_EQ(restart_then({"pair_style peri/nospd/hs strain small", elastic + " yield 1e8"}), "");
  EXPECT_EQ(plastic_work(), 0.0);
  std::remove(rfile.c_str());
}

TEST_F(InelasticBadInput, LawChangeWithoutPlasticStateAllowed)
{
  Block b;
  b.n = 5;
  b.settings = "strain small";
  make_block(lmp, b);
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003 yield 1e12");
  cmd(lmp, "change_box all x scale 1.001 remap units box");
  cmd(lmp, "run 1");    // elastic range
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.003");
  EXPECT_EQ(error_of(lmp, "run 0"), "");
}

}    // namespace

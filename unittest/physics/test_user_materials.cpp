/* Materials the user brings, through LAMMPS:
   - strain formula: the Neo-Hooke and SVK energies typed as formulas give
     the built-in laws' forces to 1e-12 on random irregular deformed bodies
     (3D, plane strain, plane stress; classical and horizon-stabilized);
     a rigid rotation gives zero force with every formula; force is the
     energy's gradient; minimize relaxes;
   - strain umat: a linear-elastic and a J2 UMAT (Fortran, unittest/umat)
     reproduce the built-in small-strain and J2 laws over a dynamic run to
     1e-10, including the state variables and a restart split;
   - their bad input: clear errors naming the command, the formula or the
     library, and the atom. */

#include "nospd_test_util.h"

#include "fix_nospd_bonds.h"
#include "variable.h"
#include "nospd_plasticity.h"
#include "nospd_umat.h"

#include "gmock/gmock.h"

#include <array>
#include <cstdio>

using namespace nospdtest;
using LAMMPS_NS::FixNospdBonds;
using ::testing::HasSubstr;

namespace {

const double E = 200e9, NU = 0.3;

std::string lame_params()
{
  const double lam = E * NU / ((1 + NU) * (1 - 2 * NU)), mu = E / (2 * (1 + NU));
  return " param lambda " + num(lam) + " param mu " + num(mu);
}
const char *NEOHOOKE_W = "0.5*mu*(I1-3) - mu*log(J) + 0.5*lambda*log(J)^2";
const char *SVK_W = "lambda/8*(I1-3)^2 + mu/4*(I1^2 - 2*I2 - 2*I1 + 3)";

std::string umat_lib(const char *name) { return std::string(NOSPD_UMAT_DIR) + "/" + name; }

FixNospdBonds *bonds_of(LAMMPS *lmp)
{
  return static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
}

// a block whose reference points are jittered (an irregular body), with
// the families built from it
void irregular_block(LAMMPS *lmp, Block &b, const std::string &coeff_extra)
{
  make_block(lmp, b);
  if (!coeff_extra.empty())
    cmd(lmp, "pair_coeff * * " + num(b.E) + " " + num(b.nu) + " " + num(b.delta()) + " " +
                 coeff_extra);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(-0.2 * b.dx, 0.2 * b.dx);
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int k = 0; k < b.dim; k++) x[i][k] = x0[i][k] = x0[i][k] + U(rng);
  cmd(lmp, "thermo_style custom step pe");
  cmd(lmp, "run 0");
}

// x = x0 + G x0 + random part
void deform(LAMMPS *lmp, int dim, double amp, double dx, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  double G[3][3];
  for (auto &r : G)
    for (double &c : r) c = amp * U(rng);
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int k = 0; k < dim; k++) {
      double d = 0.01 * amp * dx * U(rng) * 10;
      for (int l = 0; l < dim; l++) d += G[k][l] * x0[i][l];
      x[i][k] = x0[i][k] + d;
    }
}

double max_abs(const std::vector<std::array<double, 3>> &v)
{
  double m = 0.0;
  for (auto &a : v)
    for (double c : a) m = std::max(m, std::abs(c));
  return m;
}

double max_diff(const std::vector<std::array<double, 3>> &a,
                const std::vector<std::array<double, 3>> &b)
{
  double m = 0.0;
  for (size_t i = 0; i < a.size(); i++)
    for (int k = 0; k < 3; k++) m = std::max(m, std::abs(a[i][k] - b[i][k]));
  return m;
}

struct FormulaCase {
  int dim;
  std::string plane;    // "", "strain", "stress"
  std::string style;    // peri/nospd, peri/nospd/hs
  std::string law;      // neohookean, svk
  std::string name() const
  {
    std::string s = std::to_string(dim) + "D_" + (plane.empty() ? "" : plane + "_") + law + "_" +
        (style == "peri/nospd" ? "classical" : "hs");
    return s;
  }
};

void PrintTo(const FormulaCase &c, std::ostream *os) { *os << c.name(); }

class FormulaMatchesBuiltin : public ::testing::TestWithParam<FormulaCase> {};

// forces (and energy) of the formula equal the built-in law's on a random
// irregular body deformed by a random gradient and random displacements
TEST_P(FormulaMatchesBuiltin, Forces)
{
  const auto &c = GetParam();
  std::vector<std::array<double, 3>> f[2];
  double pe[2];
  for (int pass = 0; pass < 2; pass++) {
    LAMMPS *lmp = open_lammps();
    Block b;
    b.dim = c.dim;
    b.n = c.dim == 3 ? 9 : 15;
    b.style = c.style;
    const std::string plane = c.plane.empty() ? "" : " plane " + c.plane;
    b.settings = (pass == 0 ? "strain " + c.law : std::string("strain formula")) + plane;
    if (c.style == "peri/nospd/hs") b.settings += " form II";
    const std::string w = (c.law == "neohookean") ? NEOHOOKE_W : SVK_W;
    irregular_block(lmp, b, pass == 0 ? "" : "energy \"" + w + "\"" + lame_params());
    deform(lmp, c.dim, 0.05, b.dx, 23);
    cmd(lmp, "run 0");
    f[pass] = by_tag(lmp, lmp->atom->f);
    pe[pass] = potential_energy(lmp);
    delete lmp;
  }
  const double scale = max_abs(f[0]);
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(max_diff(f[0], f[1]), 1e-12 * scale);
  EXPECT_NEAR(pe[1], pe[0], 1e-12 * std::abs(pe[0]));
}

std::vector<FormulaCase> formula_cases()
{
  std::vector<FormulaCase> v;
  for (const char *style : {"peri/nospd", "peri/nospd/hs"})
    for (const char *law : {"neohookean", "svk"}) {
      v.push_back({3, "", style, law});
      v.push_back({2, "strain", style, law});
      v.push_back({2, "stress", style, law});
    }
  return v;
}

INSTANTIATE_TEST_SUITE_P(UserFormula, FormulaMatchesBuiltin, ::testing::ValuesIn(formula_cases()),
                         [](const auto &info) { return info.param.name(); });

const std::vector<std::string> &nontrivial_formulas()
{
  // E = 200 GPa, nu = 0.3 at small strain: mu = 76.9 GPa, K = 166.7 GPa
  static const std::vector<std::string> w = {
      "energy \"C10*(I1b-3) + C01*(I2b-3) + 0.5*K*(J-1)^2\" param C10 3.0e10 param C01 "
      "8.46153846153846e9 param K 1.66666666666667e11",
      "energy \"-0.5*mu*Jm*log(1-(I1b-3)/Jm) + 0.5*K*log(J)^2; Jm=30\" param mu "
      "7.69230769230769e10 param K 1.66666666666667e11",
      "energy \"2*mu/a^2*((l1^a + l2^a + l3^a)*J^(-a/3) - 3) + 0.5*K*(J-1)^2; a=2.5\" param mu "
      "7.69230769230769e10 param K 1.66666666666667e11"};
  return w;
}

// a rigid rotation of a deformed-then-rotated body: forces rotate with it;
// of the undeformed body: zero force, for every formula
TEST(UserFormula, RigidRotationGivesNoForce)
{
  for (const auto &w : nontrivial_formulas()) {
    for (const char *style : {"peri/nospd", "peri/nospd/hs"}) {
      LAMMPS *lmp = open_lammps();
      Block b;
      b.n = 9;
      b.style = style;
      b.settings = std::string("strain formula") + (b.style == "peri/nospd/hs" ? " form II" : "");
      irregular_block(lmp, b, w);
      // reference: 1 % stretch for the force scale
      double **x = lmp->atom->x, **x0 = lmp->atom->x0;
      for (int i = 0; i < lmp->atom->nlocal; i++) x[i][0] = 1.01 * x0[i][0];
      cmd(lmp, "run 0");
      const double scale = max_abs(by_tag(lmp, lmp->atom->f));
      const double e_scale = potential_energy(lmp);
      const Eigen::Matrix3d Q =
          Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
      for (int i = 0; i < lmp->atom->nlocal; i++) {
        const Eigen::Vector3d X(x0[i][0], x0[i][1], x0[i][2]);
        const Eigen::Vector3d y = Q * X;
        for (int k = 0; k < 3; k++) x[i][k] = y(k);
      }
      cmd(lmp, "run 0");
      EXPECT_LT(max_abs(by_tag(lmp, lmp->atom->f)), 1e-10 * scale) << w << " " << style;
      EXPECT_LT(std::abs(potential_energy(lmp)), 1e-10 * e_scale) << w << " " << style;
      delete lmp;
    }
  }
}

// force = -dE/dx (what minimize and NVE rely on), and minimize relaxes a
// randomly displaced free body to (near) zero energy
TEST(UserFormula, EnergyGradientAndMinimize)
{
  for (const auto &w : nontrivial_formulas()) {
    LAMMPS *lmp = open_lammps();
    Block b;
    b.n = 7;
    b.settings = "strain formula stabilization none";
    irregular_block(lmp, b, w);
    expect_force_is_energy_gradient(lmp, b, {0, 24, 171});
    const double e0 = potential_energy(lmp);
    ASSERT_GT(e0, 0.0);
    cmd(lmp, "min_modify dmax 1e-5");    // SI: the default 0.1 m would invert families
    cmd(lmp, "minimize 0 1e-20 400 4000");
    EXPECT_LT(potential_energy(lmp), 1e-4 * e0) << w;
    delete lmp;
  }
}

// NVE with a formula law: the energy error of velocity Verlet is second
// order in the time step (forces are the energy's gradient) and small, for
// an invariant and a stretch-based W
double nve_energy_error(const std::string &w, double dt, int steps)
{
  LAMMPS *lmp = open_lammps();
  Block b;
  b.n = 7;
  b.settings = "strain formula";
  irregular_block(lmp, b, w);
  cmd(lmp, "variable vx atom 2.0*(x-0.003)/0.006");
  cmd(lmp, "variable vy atom -1.0*(y-0.003)/0.006");
  cmd(lmp, "velocity all set v_vx v_vy NULL units box");
  cmd(lmp, "fix 1 all nve");
  cmd(lmp, "timestep " + num(dt));
  cmd(lmp, "thermo_style custom step ke pe etotal");
  cmd(lmp, "variable et equal etotal");
  cmd(lmp, "run 0");
  const double e0 = lmp->input->variable->compute_equal("v_et");
  double emax = 0.0;
  for (int k = 0; k < 10; k++) {
    cmd(lmp, "run " + std::to_string(steps / 10));
    emax = std::max(emax, std::abs(lmp->input->variable->compute_equal("v_et") - e0));
  }
  EXPECT_GT(potential_energy(lmp), 0.1 * e0) << "the body must be strained";
  delete lmp;
  return emax / e0;
}

TEST(UserFormula, NveConservesEnergy)
{
  for (const auto &w : {nontrivial_formulas()[0], nontrivial_formulas()[2]}) {
    const double e1 = nve_energy_error(w, 1e-8, 400), e2 = nve_energy_error(w, 5e-9, 800);
    EXPECT_GT(e1 / e2, 3.0) << w << ": errors " << e1 << " " << e2;
    EXPECT_LT(e2, 1e-4) << w;
  }
}

std::string error_of_deck(const std::string &settings, const std::string &coeff_extra,
                          const std::string &style = "peri/nospd", int dim = 3)
{
  LAMMPS *lmp = open_lammps();
  Block b;
  b.n = 5;
  b.dim = dim;
  b.style = style;
  b.settings = settings;
  std::string err;
  make_block(lmp, b);
  err = error_of(lmp, "pair_coeff * * " + num(E) + " " + num(NU) + " " + num(b.delta()) + " " +
                          coeff_extra);
  if (err.empty()) err = error_of(lmp, "run 0");
  delete lmp;
  return err;
}

TEST(UserFormula, BadInput)
{
  EXPECT_THAT(error_of_deck("strain formula", "energy \"0.5*mu*(I1-3\""),
              HasSubstr("cannot parse W = '0.5*mu*(I1-3'"));
  EXPECT_THAT(error_of_deck("strain formula", "energy \"0.5*mu*(I1-3) - mu*log(J)\""),
              HasSubstr("unknown variable 'mu'"));
  EXPECT_THAT(error_of_deck("strain formula", "energy \"0.5*mu*(I1-3)\" param mu 1e9"),
              HasSubstr("has stress at F = I"));
  EXPECT_THAT(error_of_deck("strain formula", "energy \"l1^2 + 2*l2^2 + l3^2 - 4\""),
              HasSubstr("not symmetric in l1, l2, l3"));
  EXPECT_THAT(error_of_deck("strain formula", ""), HasSubstr("strain formula needs an energy for type 1"));
  EXPECT_THAT(error_of_deck("strain small", std::string("energy \"") + NEOHOOKE_W + "\"" + lame_params()),
              HasSubstr("neither formula nor umat"));
  // a linearization that no solid has is an error, not a mismatch warning
  EXPECT_THAT(error_of_deck("strain formula", std::string("energy \"") + NEOHOOKE_W +
                                                 "\" param lambda 1e9 param mu -7e10"),
              HasSubstr("linearizes to shear modulus mu = -7e+10"));
  EXPECT_THAT(error_of_deck("strain formula", std::string("energy \"") + NEOHOOKE_W +
                                                 "\" param lambda -3e11 param mu 7e10"),
              HasSubstr("a solid needs both finite and > 0"));
  EXPECT_THAT(error_of_deck("strain formula", "energy \"1e9*(I1-3)\" param 3x 1"),
              HasSubstr("param name '3x' is not a valid name"));
  EXPECT_THAT(error_of_deck("strain formula", std::string("energy \"") + NEOHOOKE_W + "\"" +
                                                 lame_params() + " yield 1e8"),
              HasSubstr("strain formula has no inelastic form"));
}

// a material file in the build folder: the header line, then `entries`
bool write_material_file(const char *file, const char *entries)
{
  FILE *fp = fopen(file, "w");
  if (!fp) return false;
  fprintf(fp, "# DATE: 2026-11-24 UNITS: si CONTRIBUTOR: test CITATION: none\n%s", entries);
  fclose(fp);
  return true;
}

// the energy of a strain formula block of n^3 points stretched along x,
// under `pair_coeff * * coeff` (E and nu: those of the block's first line)
double stretched_energy(const std::string &coeff, double e, double nu, int n, double stretch)
{
  LAMMPS *lmp = open_lammps();
  Block b;
  b.n = n;
  b.settings = "strain formula";
  b.E = e;
  b.nu = nu;
  make_block(lmp, b);
  cmd(lmp, "pair_coeff * * " + coeff);
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  for (int i = 0; i < lmp->atom->nlocal; i++) x[i][0] = stretch * x0[i][0];
  cmd(lmp, "run 0");
  const double pe = potential_energy(lmp);
  delete lmp;
  return pe;
}

// a material file entry may carry the energy and its constants; pair_coeff
// keywords after it override them (the file is written to the build folder)
TEST(UserFormula, MaterialFileEntry)
{
  const char *file = "user_materials_test.nospd";
  ASSERT_TRUE(write_material_file(file, "# a Mooney-Rivlin rubber for the test only\n"
                                        "mr_test 2.9032e6 0.45161 1100 0 energy \"C10*(I1b-3) + "
                                        "C01*(I2b-3) + 0.5*K*(J-1)^2\" param C10 0.4e6 param "
                                        "C01 0.1e6 param K 10.0e6\n"));
  double pe[3];
  const std::string coeff[3] = {
      std::string("mr_test 0.00301"), std::string("mr_test 0.00301 param C01 0.2e6"),
      std::string("2.9032e6 0.45161 0.00301 energy \"C10*(I1b-3) + C01*(I2b-3) + 0.5*K*(J-1)^2\" "
                  "param C10 0.4e6 param C01 0.1e6 param K 10.0e6")};
  for (int c = 0; c < 3; c++)
    pe[c] = stretched_energy(std::string(c < 2 ? file : "") + " " + coeff[c], 2.9032e6, 0.45161,
                             6, 1.1);
  std::remove(file);
  EXPECT_GT(pe[0], 0.0);
  EXPECT_NEAR(pe[0], pe[2], 1e-12 * pe[0]);    // file = inline
  EXPECT_GT(pe[1], pe[0] * 1.01);              // the override took
}

// a Yeoh-like rubber stretched by 1 % (file: a material file of the build folder)
double yeoh_energy(const std::string &coeff, const std::string &file = "")
{
  return stretched_energy(file + " " + coeff, 3.0e6, 0.45, 5, 1.01);
}

// param replaces a constant of the formula's own, inline or in a material
// file entry (the pair_coeff line's keywords override the entry's)
TEST(UserFormula, ParamReplacesConstantOfTheFormula)
{
  const std::string W = "energy \"C10*(I1b-3) + 0.5*K*(J-1)^2";
  const std::string head = "3e6 0.45 0.00301 ";
  const double k7 = yeoh_energy(head + W + "\" param C10 5.17e5 param K 1e7");
  const double k9 = yeoh_energy(head + W + "\" param C10 5.17e5 param K 1e9");
  ASSERT_GT(k9, 2.0 * k7);
  EXPECT_NEAR(yeoh_energy(head + W + "; K=1e7; C10=5.17e5\""), k7, 1e-12 * k7);
  EXPECT_NEAR(yeoh_energy(head + W + "; K=1e7; C10=5.17e5\" param K 1e9"), k9, 1e-12 * k9);
  // a definition that uses another sees the replaced value
  EXPECT_NEAR(yeoh_energy(head + W + "; K=100*K0; K0=1e5; C10=5.17e5\" param K0 1e7"), k9,
              1e-12 * k9);
  const char *file = "user_materials_param_test.nospd";
  ASSERT_TRUE(write_material_file(file, "yeoh_inline 3e6 0.45 1100 0 energy \"C10*(I1b-3) + "
                                        "0.5*K*(J-1)^2; C10=5.17e5; K=1e7\"\n"
                                        "yeoh_param 3e6 0.45 1100 0 energy \"C10*(I1b-3) + "
                                        "0.5*K*(J-1)^2\" param C10 5.17e5 param K 1e7\n"));
  const double file_k9[2] = {yeoh_energy("yeoh_inline 0.00301 param K 1e9", file),
                             yeoh_energy("yeoh_param 0.00301 param K 1e9", file)};
  std::remove(file);
  for (double e : file_k9) EXPECT_NEAR(e, k9, 1e-12 * k9);
}

// W's small-strain moduli are held against E and nu; the warning gives the
// constants W was evaluated with (a param replaces the formula's own)
TEST(UserFormula, LinearizationWarningNamesTheConstants)
{
  LAMMPS *lmp = open_lammps();
  Block b;
  b.n = 5;
  b.settings = "strain formula";
  make_block(lmp, b);
  const std::string text =
      log_of(lmp, {"pair_coeff * * " + num(E) + " " + num(NU) + " " + num(b.delta()) +
                       " energy \"C10*(I1b-3) + 0.5*K*(J-1)^2; K=1e9\" param C10 5.17e5 param K 1e7",
                   "run 0"});
  delete lmp;
  EXPECT_THAT(text, HasSubstr("with C10 = 517000, K = 1e+07 linearizes to E = "));
}

// a name defined twice, or given twice by param in one keyword list, and a
// constant named like a variable of W (which would replace it) are errors
TEST(UserFormula, AmbiguousConstantsAreErrors)
{
  const std::string W = "energy \"C10*(I1b-3) + 0.5*K*(J-1)^2";
  EXPECT_THAT(error_of_deck("strain formula", W + "; K=1e7; K=1e9; C10=5e5\""),
              HasSubstr("the constant 'K' is defined twice"));
  EXPECT_THAT(error_of_deck("strain formula", W + "\" param C10 5e5 param K 1e7 param K 1e9"),
              HasSubstr("param K given twice (the second: 1e9)"));
  for (const char *name : {"J", "I1", "I2", "I1b", "I2b", "l1", "l2", "l3"}) {
    EXPECT_THAT(error_of_deck("strain formula", W + "\" param C10 5e5 param K 1e7 param " +
                                                    name + " 1.0"),
                HasSubstr(std::string("param ") + name + " names a variable of W"));
    EXPECT_THAT(error_of_deck("strain formula", W + "; " + name + "=1; C10=5e5; K=1e7\""),
                HasSubstr(std::string("the constant '") + name + "' is a variable of W"));
  }
}

// a formula that goes non-finite under load names the formula and the atom;
// below the stable time step the cause is the formula, not an instability
// (a stiff contact, an overlap), past it the time step
TEST(UserFormula, NonFiniteStressIsReported)
{
  for (const char *style : {"peri/nospd", "peri/nospd/hs"})
    for (const char *dt : {"1e-9", "1e-5"}) {
      SCOPED_TRACE(std::string(style) + " timestep " + dt);
      LAMMPS *lmp = open_lammps();
      Block b;
      b.n = 5;
      b.style = style;
      b.settings = "strain formula";
      // Gent's limit: I1b - 3 reaches Jm under this stretch
      irregular_block(lmp, b, "energy \"-0.5*mu*Jm*log(1-(I1b-3)/Jm) + 0.5*K*log(J)^2; Jm=0.01\" "
                              "param mu 7.69230769230769e10 param K 1.66666666666667e11");
      cmd(lmp, std::string("timestep ") + dt);
      double **x = lmp->atom->x, **x0 = lmp->atom->x0;
      for (int i = 0; i < lmp->atom->nlocal; i++) x[i][0] = 1.2 * x0[i][0];
      const auto msg = error_of(lmp, "run 0");
      EXPECT_THAT(msg, ::testing::AllOf(HasSubstr("the energy formula of type 1"),
                                        HasSubstr("non-finite stress at atom"),
                                        ::testing::Not(HasSubstr("stiff contact"))));
      EXPECT_THAT(msg, HasSubstr(dt == std::string("1e-9") ? "the formula itself gives it"
                                                           : "exceeds the stable estimate"));
      delete lmp;
    }
}

/* ---------------------------------------------------------------------- */

// the same dynamic run with the built-in law and the UMAT: positions,
// energy and (J2) the state after 60 steps agree to 1e-10
struct UmatRun {
  std::vector<std::array<double, 3>> x, f;
  std::vector<double> eqps;
  double pe;
  double work, work_column;    // the bonds fix's plastic work, compute nospd/atom's column summed
};

UmatRun run_dynamic(int dim, const std::string &settings, const std::string &coeff, int steps,
                    const std::string &restart_split = "", const std::string &style = "peri/nospd")
{
  LAMMPS *lmp = open_lammps();
  Block b;
  b.style = style;
  b.dim = dim;
  b.n = dim == 3 ? 7 : 11;
  b.settings = settings;
  make_block(lmp, b);
  cmd(lmp, "pair_coeff * * " + num(E) + " " + num(NU) + " " + num(b.delta()) + " " + coeff);
  // a stretching velocity field, large enough to yield within the run
  cmd(lmp, "variable vx atom 40.0*(x-0.003)/0.006");
  cmd(lmp, "variable vy atom -15.0*(y-0.003)/0.006");
  cmd(lmp, "velocity all set v_vx v_vy NULL");
  cmd(lmp, "fix 1 all nve");
  cmd(lmp, "timestep 2e-8");
  cmd(lmp, "thermo_style custom step pe");
  if (!restart_split.empty()) {
    cmd(lmp, "run " + std::to_string(steps / 2));
    cmd(lmp, "write_restart " + restart_split);
    delete lmp;
    lmp = open_lammps();
    cmd(lmp, "read_restart " + restart_split);
    cmd(lmp, "fix 1 all nve");
    cmd(lmp, "thermo_style custom step pe");
    cmd(lmp, "run " + std::to_string(steps - steps / 2));
    std::remove(restart_split.c_str());
  } else {
    cmd(lmp, "run " + std::to_string(steps));
  }
  UmatRun r;
  // compute nospd/atom plastic_work sums to the bonds fix's global plastic
  // work for every law, a UMAT's SPD + SCD included
  cmd(lmp, "compute pw all nospd/atom plastic_work");
  auto *pw = lmp->modify->get_compute_by_id("pw");
  pw->compute_peratom();
  r.work = lmp->modify->get_fix_by_id("NOSPD_BONDS")->compute_vector(3);
  r.work_column = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++) r.work_column += pw->array_atom[i][0];
  r.x = by_tag(lmp, lmp->atom->x);
  r.f = by_tag(lmp, lmp->atom->f);
  r.pe = potential_energy(lmp);
  auto *fb = bonds_of(lmp);
  r.eqps.assign(lmp->atom->natoms, 0.0);
  const bool umat = settings.find("umat") != std::string::npos;
  const int k_eqps = umat ? NOSPD::UmatHist::STATEV + 6 : NOSPD::Hist::EQPS;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    if (fb->nhistory > k_eqps)
      r.eqps[lmp->atom->tag[i] - 1] =
          fb->history[i][k_eqps];
  delete lmp;
  return r;
}

void expect_same_run(const UmatRun &a, const UmatRun &b, double tol)
{
  EXPECT_LT(max_diff(a.f, b.f), tol * max_abs(a.f));
  double dx = 0.0;
  for (size_t i = 0; i < a.x.size(); i++)
    for (int k = 0; k < 3; k++) dx = std::max(dx, std::abs(a.x[i][k] - b.x[i][k]));
  EXPECT_LT(dx, tol * 1e-3);    // positions, relative to the 1 mm spacing
  EXPECT_NEAR(a.pe, b.pe, tol * std::abs(a.pe));
  double emax = 0.0, ediff = 0.0;
  for (size_t i = 0; i < a.eqps.size(); i++) {
    emax = std::max(emax, a.eqps[i]);
    ediff = std::max(ediff, std::abs(a.eqps[i] - b.eqps[i]));
  }
  EXPECT_LE(ediff, tol * std::max(emax, 1e-300));
}

TEST(UserUmat, ElasticMatchesSmallStrain)
{
  for (int dim : {3, 2}) {
    const auto ref = run_dynamic(dim, "strain small", "", 60);
    const auto um = run_dynamic(dim, "strain umat", "umat " + umat_lib("umat_elastic.so") +
                                                        " props 2 " + num(E) + " " + num(NU), 60);
    SCOPED_TRACE("dim " + std::to_string(dim));
    expect_same_run(ref, um, 1e-10);
  }
}

// TIME(1) and TIME(2) hold the time at the start of the increment, DTIME
// the increment, as Abaqus passes them (the UMAT stores them in STATEV 1-3)
TEST(UserUmat, TimeIsTheStartOfTheIncrement)
{
  LAMMPS *lmp = open_lammps();
  Block b;
  b.n = 5;
  b.settings = "strain umat";
  make_block(lmp, b);
  cmd(lmp, "pair_coeff * * " + num(E) + " " + num(NU) + " " + num(b.delta()) + " umat " +
               umat_lib("umat_elastic.so") + " props 6 " + num(E) + " " + num(NU) +
               " 0 0 0 1 statev 3");
  cmd(lmp, "timestep 2e-9");
  cmd(lmp, "fix 1 all nve");
  cmd(lmp, "run 3");
  auto *fb = static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  const double *h = fb->history[0] + NOSPD::UmatHist::STATEV;    // accepted at the run's end
  EXPECT_DOUBLE_EQ(h[0], 4e-9);    // step 3 runs from t = 4 ns to 6 ns
  EXPECT_DOUBLE_EQ(h[1], 4e-9);
  EXPECT_DOUBLE_EQ(h[2], 2e-9);
  delete lmp;
}

// a run continued from a restart reads the stored STATEV only with the
// count that wrote them: another count is an error naming both
TEST(UserUmat, RestartWithAnotherStatevCountIsAnError)
{
  const std::string file = "umat_statev_" + std::to_string(getpid()) + ".restart";
  LAMMPS *lmp = open_lammps();
  Block b;
  b.n = 5;
  b.settings = "strain umat";
  make_block(lmp, b);
  const std::string coeff = "pair_coeff * * " + num(E) + " " + num(NU) + " " + num(b.delta());
  cmd(lmp, coeff + " umat " + umat_lib("umat_j2.so") + " props 4 " + num(E) + " " + num(NU) +
               " 3e8 2e10 statev 7");
  cmd(lmp, "run 0");
  cmd(lmp, "write_restart " + file);
  delete lmp;
  for (int statev : {7, 9}) {
    lmp = open_lammps();
    cmd(lmp, "read_restart " + file);
    cmd(lmp, coeff + " umat " + umat_lib("umat_elastic.so") + " props 2 " + num(E) + " " +
                 num(NU) + " statev " + std::to_string(statev));
    if (statev == 9) {
      EXPECT_THAT(error_of(lmp, "run 0"),
                  HasSubstr("umat_j2.so with statev 7, but this run declares statev 9"));
    } else {
      EXPECT_THAT(log_of(lmp, {"run 0"}),
                  HasSubstr("the restart file's state variables were written by UMAT"));
    }
    delete lmp;
  }
  std::remove(file.c_str());
}

/* The integration points a UMAT sees (umat_elastic.f with PROPS(7) stores
   NPT and NOEL): the classical style calls it once per point, NPT 1 and NOEL
   the atom ID; the bond-associated style once per bond, each bond of a
   family an integration point of its own, NPT 2 .. n + 1 over its n bonds. */
TEST(UserUmat, EachBondIsAnIntegrationPoint)
{
  using NOSPD::UmatHist::STATEV;
  for (const std::string style : {"peri/nospd", "peri/nospd/hs"}) {
    SCOPED_TRACE(style);
    LAMMPS *lmp = open_lammps();
    Block b;
    b.n = 5;
    b.style = style;
    b.settings = "strain umat";
    make_block(lmp, b);
    cmd(lmp, "pair_coeff * * " + num(E) + " " + num(NU) + " " + num(b.delta()) + " umat " +
                 umat_lib("umat_elastic.so") + " props 7 " + num(E) + " " + num(NU) +
                 " 0 0 0 0 1 statev 5");
    cmd(lmp, "run 1");    // the step's states, accepted
    auto *fb = static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
    int checked = 0;
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      const double tag = (double) lmp->atom->tag[i];
      double *row = fb->history[i];
      if (style == "peri/nospd") {
        ASSERT_EQ(row[STATEV + 3], 1.0) << "atom " << tag;
        ASSERT_EQ(row[STATEV + 4], tag);
        checked++;
        continue;
      }
      const int n = fb->npartner[i];
      std::vector<double> npt;
      for (int s = 0; s < n; s++) {
        const double *e = fb->bond_history(row, s);
        ASSERT_EQ(e[STATEV + 4], tag) << "atom " << tag << " slot " << s;
        npt.push_back(e[STATEV + 3]);
      }
      std::sort(npt.begin(), npt.end());
      for (int s = 0; s < n; s++) ASSERT_EQ(npt[s], s + 2.0) << "atom " << tag;
      checked += n;
    }
    EXPECT_GT(checked, style == "peri/nospd" ? 100 : 2000);
    delete lmp;
  }
}

TEST(UserUmat, J2MatchesBuiltinWithRestart)
{
  const std::string j2 = "yield 3e8 hardening linear 2e10";
  const std::string umat = "umat " + umat_lib("umat_j2.so") + " props 4 " + num(E) + " " +
      num(NU) + " 3e8 2e10 statev 7";
  for (int dim : {3, 2}) {
    SCOPED_TRACE("dim " + std::to_string(dim));
    const auto ref = run_dynamic(dim, "strain small", j2, 60);
    const auto um = run_dynamic(dim, "strain umat", umat, 60);
    double emax = 0.0;
    for (double e : ref.eqps) emax = std::max(emax, e);
    ASSERT_GT(emax, 1e-4) << "the run must yield";
    expect_same_run(ref, um, 1e-10);
    for (const UmatRun *r : {&ref, &um}) {
      EXPECT_GT(r->work, 0.0);
      EXPECT_NEAR(r->work_column, r->work, 1e-12 * r->work);
    }
    // restart split: the state variables travel through the restart file
    const auto split = run_dynamic(dim, "strain umat", umat, 60, "umat_split.restart");
    expect_same_run(um, split, 1e-12);
  }
}

// peri/nospd/hs form II: every bond is an integration point of the UMAT
// with its own state variables; they follow the built-in J2 of that style
// (a plastic state per bond) and travel through the restart
TEST(UserUmat, BondAssociatedMatchesBuiltin)
{
  const std::string hs = "peri/nospd/hs";
  const std::string j2 = "yield 3e8 hardening linear 2e10";
  const std::string umat = "umat " + umat_lib("umat_j2.so") + " props 4 " + num(E) + " " +
      num(NU) + " 3e8 2e10 statev 7";
  for (int dim : {3, 2}) {
    SCOPED_TRACE("dim " + std::to_string(dim));
    const auto el = run_dynamic(dim, "strain small form II", "", 40, "", hs);
    const auto uel = run_dynamic(dim, "strain umat form II", "umat " + umat_lib("umat_elastic.so") +
                                     " props 2 " + num(E) + " " + num(NU), 40, "", hs);
    expect_same_run(el, uel, 1e-10);
    const auto ref = run_dynamic(dim, "strain small form II", j2, 40, "", hs);
    const auto um = run_dynamic(dim, "strain umat form II", umat, 40, "", hs);
    double emax = 0.0;
    for (double e : ref.eqps) emax = std::max(emax, e);
    ASSERT_GT(emax, 1e-4) << "the run must yield";
    expect_same_run(ref, um, 1e-10);
    for (const UmatRun *r : {&ref, &um}) {
      EXPECT_GT(r->work, 0.0);
      EXPECT_NEAR(r->work_column, r->work, 1e-12 * r->work);
    }
    const auto split = run_dynamic(dim, "strain umat form II", umat, 40, "umat_hs_split.restart", hs);
    expect_same_run(um, split, 1e-12);
  }
}

TEST(UserUmat, BadInput)
{
  EXPECT_THAT(error_of_deck("strain umat", "umat /nonexistent/libumat.so props 2 1 0.3"),
              ::testing::AllOf(HasSubstr("cannot open UMAT library /nonexistent/libumat.so"),
                               HasSubstr("type 1")));
  EXPECT_THAT(error_of_deck("strain umat", "umat " + umat_lib("umat_elastic.so") + " symbol vumat_"),
              HasSubstr("has no symbol 'vumat_'"));
  EXPECT_THAT(error_of_deck("strain umat", "umat " + umat_lib("umat_j2.so") + " props 2 200e9 0.3 statev 7"),
              ::testing::AllOf(HasSubstr("stopped at atom"), HasSubstr("umat_j2 needs 4 PROPS, got 2")));
  EXPECT_THAT(error_of_deck("strain umat", "umat " + umat_lib("umat_j2.so") + " props 4 200e9 0.3 3e8 0"),
              HasSubstr("umat_j2 needs 7 STATEV, got 0"));
  EXPECT_THAT(error_of_deck("strain umat", "umat " + umat_lib("umat_elastic.so") + " props 3 200e9 0.3 1"),
              ::testing::AllOf(HasSubstr("returned a non-finite stress"),
                               HasSubstr("the UMAT itself gives it")));
  EXPECT_THAT(error_of_deck("strain umat", "umat " + umat_lib("umat_elastic.so") + " props 3 200e9 0.3"),
              HasSubstr("props 3 needs 3 values, got 2"));
  EXPECT_THAT(error_of_deck("strain umat", ""), HasSubstr("strain umat needs a library for type 1"));
  // a UMAT that writes more STATEV than declared stops before the heap suffers
  for (const char *style : {"peri/nospd", "peri/nospd/hs"})
    for (int declared : {0, 2})
      EXPECT_THAT(error_of_deck("strain umat", "umat " + umat_lib("umat_elastic.so") +
                                                   " props 4 200e9 0.3 0 " +
                                                   std::to_string(declared + 3) + " statev " +
                                                   std::to_string(declared), style),
                  ::testing::AllOf(HasSubstr("umat_elastic.so, symbol umat_) wrote past its "
                                             "NSTATV = " + std::to_string(declared)),
                                   ::testing::ContainsRegex("at atom [0-9]+ on step 0")))
          << style;
  // ... also one that accumulates into the slots past NSTATV (STATEV(I) =
  // STATEV(I) + I), which a NaN guard would survive unchanged
  for (const char *style : {"peri/nospd", "peri/nospd/hs"})
    EXPECT_THAT(error_of_deck("strain umat", "umat " + umat_lib("umat_elastic.so") +
                                                 " props 5 200e9 0.3 0 6 1 statev 2", style),
                HasSubstr("wrote past its NSTATV = 2"))
        << style;
  EXPECT_EQ(error_of_deck("strain umat", "umat " + umat_lib("umat_elastic.so") +
                                             " props 5 200e9 0.3 0 2 1 statev 2"), "");
  EXPECT_EQ(error_of_deck("strain umat", "umat " + umat_lib("umat_elastic.so") +
                                             " props 4 200e9 0.3 0 2 statev 2"), "");
  EXPECT_THAT(error_of_deck("strain umat plane stress",
                            "umat " + umat_lib("umat_elastic.so") + " props 2 200e9 0.3",
                            "peri/nospd", 2),
              HasSubstr("strain umat supports 3D and plane strain, not plane stress"));
}

}    // namespace

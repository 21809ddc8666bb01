/* Physics checks of formulations.md section E for the horizon-stabilized
   (bond-associated) style peri/nospd/hs, Forms I and II, every strain
   measure, 3D and 2D: patch test (bond-associated F included), bulk
   stress (Form I: its factor c, checked against the lattice sum), linear
   and angular momentum, energy consistency (Form II), objectivity, the
   zero-energy checkerboard against the classical style without
   stabilization, broken bonds in an undeformed body, restart, and the
   style's bad-input errors. */

#include "nospd_test_util.h"

#include "comm.h"
#include "fix_nospd_bonds.h"
#include "neighbor.h"
#include "nospd_bond_associated.h"
#include "nospd_constitutive.h"
#include "pair_peri_nospd_hs.h"

#include "gmock/gmock.h"

#include <array>
#include <cstdio>
#include <memory>
#include <unistd.h>

using namespace nospdtest;
using LAMMPS_NS::bigint;
using LAMMPS_NS::FixNospdBonds;
using LAMMPS_NS::PairPeriNospdHS;
using NOSPD::Mat3;
using ::testing::HasSubstr;

namespace {

struct Variant {
  int dim;
  std::string strain;    // small finite svk neohookean
  std::string form;      // I II
  std::string name() const { return std::to_string(dim) + "D_" + strain + "_form" + form; }
  bool two() const { return form == "II"; }
  bool objective() const { return strain != "small"; }
  NOSPD::Law law() const
  {
    if (strain == "small") return NOSPD::Law::SMALL;
    if (strain == "finite") return NOSPD::Law::COROTATIONAL;
    if (strain == "svk") return NOSPD::Law::SVK;
    return NOSPD::Law::NEOHOOKE;
  }
};

void PrintTo(const Variant &v, std::ostream *os) { *os << v.name(); }

/* Form I's bulk factor from the lattice alone: in a homogeneous deformation
   the interior virial is P M, M = sum_j (V_h/V_H) omega V K_j^-1 xi (x) xi,
   which the cubic (square) symmetry makes c I. */
double form_one_factor(int dim, double mfactor, double ratio)
{
  const int R = (int) std::ceil(mfactor);
  std::vector<double> b, w, v;
  std::vector<int64_t> key;
  for (int z = (dim == 3 ? -R : 0); z <= (dim == 3 ? R : 0); z++)
    for (int y = -R; y <= R; y++)
      for (int x = -R; x <= R; x++) {
        const double r2 = x * x + y * y + z * z;
        if (r2 == 0 || r2 > mfactor * mfactor) continue;
        b.insert(b.end(), {(double) x, (double) y, (double) z});
        key.insert(key.end(), {x, y, z});
        w.push_back(1.0);
        v.push_back(1.0);
      }
  NOSPD::BondPattern p;
  NOSPD::build_pattern(p, dim, (int) w.size(), b.data(), w.data(), v.data(), key,
                       ratio * mfactor, NOSPD::HSForm::I, 1e-4);
  const int nc = dim * dim;
  double tr = 0.0;
  for (int s = 0; s < p.n; s++)
    for (int a = 0; a < dim; a++)
      for (int c = 0; c < dim; c++)
        tr += p.cforce[s] * p.w[s] * p.kinv[nc * s + a * dim + c] * p.b[3 * s + c] * p.b[3 * s + a];
  return tr / dim;
}

class HS : public ::testing::TestWithParam<Variant> {
 protected:
  LAMMPS *lmp = nullptr;
  Block blk;

  void SetUp() override
  {
    const Variant &v = GetParam();
    lmp = open_lammps();
    blk.dim = v.dim;
    blk.n = v.dim == 3 ? 15 : 25;
    blk.style = "peri/nospd/hs";
    blk.settings = "strain " + v.strain + " form " + v.form;
  }
  void TearDown() override { delete lmp; }

  void build(bool periodic = false, int n = 0)
  {
    blk.periodic = periodic;
    if (n) blk.n = n;
    make_block(lmp, blk);
    cmd(lmp, "compute S all nospd/atom F stress");
    cmd(lmp, "compute V all stress/atom NULL virial");
    cmd(lmp, "thermo_style custom step pe");
    cmd(lmp, "run 0");    // reference families from x0
  }

  FixNospdBonds *bonds()
  {
    return static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  }
  PairPeriNospdHS *pair() { return static_cast<PairPeriNospdHS *>(lmp->force->pair); }

  template <class Fn> void displace(Fn u)
  {
    double **x = lmp->atom->x, **x0 = lmp->atom->x0;
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      const auto d = u(x0[i]);
      for (int k = 0; k < blk.dim; k++) x[i][k] = x0[i][k] + d[k];
    }
  }

  void affine(const Mat3 &F0)
  {
    const auto c = center();
    displace([&](const double *X) {
      NOSPD::Vec3 d(X[0] - c[0], X[1] - c[1], X[2] - c[2]);
      NOSPD::Vec3 u = (F0 - Mat3::Identity()) * d;
      return std::array<double, 3>{u[0], u[1], u[2]};
    });
  }

  Mat3 random_F(std::mt19937 &rng, double amp)
  {
    std::uniform_real_distribution<double> U(-amp, amp);
    Mat3 F = Mat3::Identity();
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) F(r, c) += U(rng);
    if (blk.dim == 2) {
      F(0, 2) = F(1, 2) = F(2, 0) = F(2, 1) = 0.0;
      F(2, 2) = 1.0;
    }
    return F;
  }

  Mat3 law_P(const Mat3 &F0)
  {
    Mat3 P, Fp = F0;
    double W;
    NOSPD::first_piola(GetParam().law(),
                       blk.dim == 2 ? NOSPD::Plane::STRAIN : NOSPD::Plane::NONE,
                       NOSPD::Lame::from_young(blk.E, blk.nu), Fp, P, W);
    return P;
  }

  double depth(const double *X)
  {
    const double lo = 0.0, hi = (blk.n - 1) * blk.dx;
    double d = 1e30;
    for (int k = 0; k < blk.dim; k++) d = std::min({d, X[k] - lo, hi - X[k]});
    return d;
  }

  std::array<double, 3> center() const
  {
    const double c = 0.5 * (blk.n - 1) * blk.dx;
    return {c, c, blk.dim == 2 ? 0.0 : c};
  }

  double max_force()
  {
    double fmax = 0.0;
    for (int i = 0; i < lmp->atom->nlocal; i++)
      for (int k = 0; k < 3; k++) fmax = std::max(fmax, std::abs(lmp->atom->f[i][k]));
    return fmax;
  }
};

/* 1. Patch test: y = F0 X.  Every bond-associated F_ij and every family F
      is F0 (corners included); the force vanishes at depth >= 2 delta. */
TEST_P(HS, PatchTest)
{
  build();
  std::mt19937 rng(7);
  const Mat3 F0 = random_F(rng, 0.02);
  affine(F0);
  cmd(lmp, "run 0");
  auto *fb = bonds();
  ASSERT_EQ(fb->nsingular, 0);
  double maxdF = 0.0, maxdFb = 0.0, maxf = 0.0;
  bigint nown = 0, nfall = 0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    maxdF = std::max(maxdF, (NOSPD::load(fb->defgrad[i]) - F0).cwiseAbs().maxCoeff());
    for (int b = fb->bond_first[i]; b < fb->bond_first[i + 1]; b++) {
      double Fb[9];
      const int own = pair()->bond_defgrad(i, b, Fb);
      ASSERT_GE(own, 0);
      (own ? nown : nfall)++;
      maxdFb = std::max(maxdFb, (NOSPD::load(Fb) - F0).cwiseAbs().maxCoeff());
    }
    if (depth(lmp->atom->x0[i]) >= 2.0 * blk.delta() - 1e-12)
      for (int k = 0; k < 3; k++) maxf = std::max(maxf, std::abs(lmp->atom->f[i][k]));
  }
  EXPECT_GT(nown, 0);
  EXPECT_EQ(nfall, pair()->singular_bond_families());
  EXPECT_LT(maxdF, 1e-13);
  EXPECT_LT(maxdFb, 1e-13);
  EXPECT_LT(maxf, 1e-11 * law_P(F0).norm() / blk.dx);
}

/* 2. Bulk stress: away from surfaces the per-atom virial is the Kirchhoff
      stress F P(F0)^T for Form II and c F P^T for Form I, c the lattice
      factor; compute nospd/atom reports the law's Cauchy stress (the mean
      of the bonds' P) for both. */
TEST_P(HS, BulkStress)
{
  build();
  std::mt19937 rng(11);
  const Mat3 F0 = random_F(rng, 0.01);
  affine(F0);
  cmd(lmp, "thermo_style custom step pe press");    // global virial too
  cmd(lmp, "run 0");
  // the global virial is the sum of the per-atom ones
  double **vatom = lmp->force->pair->vatom;
  double vsum[6] = {0, 0, 0, 0, 0, 0}, vnorm = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int k = 0; k < 6; k++) vsum[k] += vatom[i][k];
  for (int k = 0; k < 6; k++) vnorm = std::max(vnorm, std::abs(vsum[k]));
  ASSERT_GT(vnorm, 0.0);
  for (int k = 0; k < 6; k++)
    EXPECT_NEAR(lmp->force->pair->virial[k], vsum[k], 1e-12 * vnorm) << "global virial " << k;
  const Mat3 P0 = law_P(F0);
  const double c = GetParam().two() ? 1.0 : form_one_factor(blk.dim, blk.mfactor, 1.0);
  const Mat3 tau = c * F0 * P0.transpose();
  const Mat3 sigma = GetParam().strain == "small" ? Mat3(0.5 * (P0 + P0.transpose()))
                                                  : Mat3(F0 * P0.transpose() / F0.determinant());
  auto *cv = lmp->modify->get_compute_by_id("V");
  cv->compute_peratom();
  auto *cs = lmp->modify->get_compute_by_id("S");
  cs->compute_peratom();
  const int nk = blk.dim == 2 ? 4 : 6;
  int checked = 0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    if (depth(lmp->atom->x0[i]) < 2.0 * blk.delta() - 1e-12) continue;
    const double *s = cv->array_atom[i];
    const double vt[6] = {tau(0, 0), tau(1, 1), tau(2, 2), tau(0, 1), tau(0, 2), tau(1, 2)};
    for (int k = 0; k < nk; k++)
      if (!(blk.dim == 2 && k == 2)) EXPECT_NEAR(s[k], vt[k], 1e-9 * tau.norm()) << "virial " << k;
    const double *o = cs->array_atom[i] + 9;
    const double st[6] = {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(0, 2), sigma(1, 2)};
    for (int k = 0; k < nk; k++)
      if (!(blk.dim == 2 && k == 2)) EXPECT_NEAR(o[k], st[k], 1e-9 * sigma.norm()) << "stress " << k;
    checked++;
  }
  EXPECT_GT(checked, 0);
  EXPECT_GT(sigma.norm(), 1e8);
  if (!GetParam().two()) {
    // the documented factor, and that it is not 1
    EXPECT_GT(c, 0.5);
    EXPECT_LT(c, 1.5);
    std::printf("[ INFO ] Form I bulk factor c (%dD, delta = %g dx, ratio 1) = %.6f\n", blk.dim,
                blk.mfactor, c);
  }
}

/* 3. Momentum: forces sum to zero for any displacement (the true forces of
      every bond are equal and opposite); Form II with an objective law
      also conserves angular momentum (sum_j beta_j P_j F_j^T is
      symmetric).  Form I does not, and the test says so. */
TEST_P(HS, Momentum)
{
  build();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-0.01 * blk.dx, 0.01 * blk.dx);
  displace([&](const double *) {
    return std::array<double, 3>{U(rng), U(rng), blk.dim == 3 ? U(rng) : 0.0};
  });
  cmd(lmp, "run 0");
  double **x = lmp->atom->x, **f = lmp->atom->f;
  NOSPD::Vec3 sum = NOSPD::Vec3::Zero(), torque = NOSPD::Vec3::Zero();
  double fabs = 0.0, tabs = 0.0;
  const auto c = center();
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const NOSPD::Vec3 fi(f[i][0], f[i][1], f[i][2]);
    const NOSPD::Vec3 r(x[i][0] - c[0], x[i][1] - c[1], x[i][2] - c[2]);
    sum += fi;
    torque += r.cross(fi);
    fabs += fi.norm();
    tabs += r.norm() * fi.norm();
  }
  ASSERT_GT(fabs, 0.0);
  EXPECT_LT(sum.norm(), 1e-12 * fabs);
  if (GetParam().objective() && GetParam().two()) EXPECT_LT(torque.norm(), 1e-11 * tabs);
}

/* 4. Energy consistency (Form II, an exact potential): -dE/dy by central
      differences equals the force.  Form I is not a potential. */
TEST_P(HS, EnergyConsistency)
{
  if (!GetParam().two()) GTEST_SKIP() << "Form I is not derived from an energy";
  build(false, GetParam().dim == 3 ? 9 : 17);
  const int natoms = lmp->atom->natoms;
  expect_force_is_energy_gradient(lmp, blk, {0, natoms / 3, natoms / 2, natoms - 1});
}

/* 4b. The same with 30 % of the bonds broken: a damaged body keeps the
       force the exact derivative of its energy, with the families'
       patterns, fallbacks and partial sums rebuilt for the damage; a force
       that is not must inject energy in a fracture run. */
TEST_P(HS, EnergyConsistencyDamaged)
{
  if (!GetParam().two()) GTEST_SKIP() << "Form I is not derived from an energy";
  build(false, GetParam().dim == 3 ? 9 : 17);
  ASSERT_GT(break_random_bonds(lmp, 0.3, 29), 100);
  std::vector<int> probes;
  const int natoms = lmp->atom->natoms;
  for (int p = 0; p < natoms; p += std::max(1, natoms / 23)) probes.push_back(p);
  expect_force_is_energy_gradient(lmp, blk, probes);
}

/* 5. Objectivity: a rigid rotation gives no force and no energy under the
      finite-strain laws (every F_ij is the rotation); the small-strain law
      is not objective and produces both. */
TEST_P(HS, Objectivity)
{
  build();
  const double ang = 0.6;
  Mat3 Q = Mat3::Identity();
  if (blk.dim == 2) Q << cos(ang), -sin(ang), 0, sin(ang), cos(ang), 0, 0, 0, 1;
  else Q = Eigen::AngleAxisd(ang, NOSPD::Vec3(1, 2, 3).normalized()).toRotationMatrix();
  affine(Q);
  cmd(lmp, "compute E all pe");
  cmd(lmp, "run 0");
  const double fmax = max_force();
  const double E = lmp->force->pair->eng_vdwl;
  const double fscale = blk.E / blk.dx;
  if (GetParam().objective()) {
    EXPECT_LT(fmax, 1e-11 * fscale);
    EXPECT_LT(std::abs(E), 1e-12 * blk.E * lmp->atom->natoms);
  } else {
    EXPECT_GT(fmax, 1e-3 * fscale);
    EXPECT_GT(E, 1e-3 * blk.E * lmp->atom->natoms);
  }
}

/* 6. Zero-energy mode: periodic even block, u = a (-1)^(i+j+k) e_x.  The
      classical style without stabilization sees F = I and neither stores
      energy nor resists; the bond-associated families are not centrally
      symmetric, so both forms resist (f.u < 0) and Form II stores energy. */
TEST_P(HS, ZeroEnergyMode)
{
  const double a = 1e-3 * blk.dx;
  auto checkerboard = [&](const double *X) {
    int s = 0;
    for (int k = 0; k < blk.dim; k++) s += (int) std::lround(X[k] / blk.dx);
    return std::array<double, 3>{(s % 2 ? -a : a), 0.0, 0.0};
  };
  auto measure = [&](double &fu, double &frms, double &E) {
    auto *fb = bonds();
    fu = 0.0;
    double f2 = 0.0;
    const int nlocal = lmp->atom->nlocal;
    for (int i = 0; i < nlocal; i++) {
      fu += lmp->atom->f[i][0] * (lmp->atom->x[i][0] - fb->x0s[i][0]);
      for (int k = 0; k < 3; k++) f2 += lmp->atom->f[i][k] * lmp->atom->f[i][k];
    }
    frms = std::sqrt(f2 / nlocal);
    E = lmp->force->pair->eng_vdwl;
  };
  const double band = 0.5 * blk.E * (2.0 * a / blk.dx) / blk.delta();

  // the classical style, unstabilized: the mode is free
  {
    Block cb = blk;
    cb.style = "peri/nospd";
    cb.settings = "strain " + GetParam().strain + " stabilization none";
    cb.periodic = true;
    cb.n = 8;
    LAMMPS *keep = lmp;
    lmp = open_lammps();
    make_block(lmp, cb);
    cmd(lmp, "thermo_style custom step pe");
    cmd(lmp, "run 0");
    displace(checkerboard);
    cmd(lmp, "run 0");
    double fu, frms, E;
    measure(fu, frms, E);
    EXPECT_LT(frms, 1e-9 * band) << "classical, stabilization none";
    EXPECT_LT(std::abs(E), 1e-9 * blk.E * 1e-6 * lmp->atom->natoms);
    delete lmp;
    lmp = keep;
  }

  build(true, 8);
  displace(checkerboard);
  cmd(lmp, "run 0");
  double fu, frms, E;
  measure(fu, frms, E);
  // the family F is I, the bond-associated ones are not
  auto *fb = bonds();
  double dF = 0.0, dFb = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    dF = std::max(dF, (NOSPD::load(fb->defgrad[i]) - Mat3::Identity()).cwiseAbs().maxCoeff());
    double Fb[9];
    pair()->bond_defgrad(i, fb->bond_first[i], Fb);
    dFb = std::max(dFb, (NOSPD::load(Fb) - Mat3::Identity()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(dF, 1e-12);
  EXPECT_GT(dFb, 1e-2 * (2.0 * a / blk.dx));
  EXPECT_LT(fu, 0.0);
  EXPECT_GT(frms, 0.25 * band);
  std::printf("[ INFO ] checkerboard: rms restoring force / (E (2a/dx) / delta) = %.3f, "
              "E = %.4g\n", frms / (2.0 * band), E);
  if (GetParam().two()) EXPECT_GT(E, 0.0);
}

/* 7. Broken bonds in an undeformed body: every F stays I and every force 0,
      whatever the families have become (new patterns, fallbacks). */
TEST_P(HS, BrokenBondsUndeformed)
{
  build();
  auto *fb = bonds();
  const int nlocal = lmp->atom->nlocal;
  const int nbroken = break_random_bonds(lmp, 0.3, 13);
  ASSERT_GT(nbroken, 100);
  cmd(lmp, "run 0");
  EXPECT_EQ((bigint) fb->compute_vector(1), 2 * (bigint) nbroken);
  double dF = 0.0;
  for (int i = 0; i < nlocal; i++) {
    if (fb->singular[i]) continue;
    dF = std::max(dF, (NOSPD::load(fb->defgrad[i]) - Mat3::Identity()).cwiseAbs().maxCoeff());
    for (int k = 0; k < 3; k++) EXPECT_FALSE(std::isnan(lmp->atom->f[i][k]));
  }
  EXPECT_LT(dF, 1e-14);
  EXPECT_LT(max_force(), 1e-20 * blk.E / blk.dx);
}

std::vector<Variant> all_variants()
{
  std::vector<Variant> v;
  for (int dim : {3, 2})
    for (const char *strain : {"small", "finite", "svk", "neohookean"})
      for (const char *form : {"II", "I"}) v.push_back({dim, strain, form});
  return v;
}

INSTANTIATE_TEST_SUITE_P(BondAssociated, HS, ::testing::ValuesIn(all_variants()),
                         [](const ::testing::TestParamInfo<Variant> &p) { return p.param.name(); });

/* ---------------------------------------------------------------------- */

class HSDeck : public ::testing::Test {
 protected:
  LAMMPS *lmp = nullptr;
  void SetUp() override { lmp = open_lammps(); }
  void TearDown() override { delete lmp; }
};

/* The same forces after write_restart / read_restart: form and ratio come
   back with the pair style, the families with the bonds fix. */
TEST_F(HSDeck, Restart)
{
  Block b;
  b.n = 9;
  b.style = "peri/nospd/hs";
  b.settings = "strain svk form II ratio 1.2 stabilization silling 0.4 stencil no";
  make_block(lmp, b);
  cmd(lmp, "displace_atoms all random 2e-6 2e-6 2e-6 8811 units box");
  cmd(lmp, "run 0");
  const auto f0 = by_tag(lmp, lmp->atom->f);
  const double e0 = lmp->force->pair->eng_vdwl;
  char path[] = "/tmp/nospd_hs_restartXXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  close(fd);
  cmd(lmp, std::string("write_restart ") + path);
  delete lmp;
  lmp = open_lammps();
  cmd(lmp, std::string("read_restart ") + path);
  std::remove(path);
  auto *p = static_cast<PairPeriNospdHS *>(lmp->force->pair);
  EXPECT_EQ(std::string(lmp->force->pair_style), "peri/nospd/hs");
  EXPECT_EQ(p->ratio(), 1.2);
  EXPECT_TRUE(p->form() == NOSPD::HSForm::II);
  EXPECT_FALSE(p->stencil_enabled());
  cmd(lmp, "run 0");
  expect_same_vectors(f0, by_tag(lmp, lmp->atom->f), 1e-12);
  EXPECT_NEAR(lmp->force->pair->eng_vdwl, e0, 1e-12 * std::abs(e0));
}

/* Plane stress: F_zz of compute nospd/atom (the bonds' mean) and of each
   bond in compute nospd/bond/local is the stretch the law solves,
   1 - nu/(1 - nu) (e_xx + e_yy) under strain small, on the stencil and
   the family path (surfaces) alike. */
TEST_F(HSDeck, PlaneStressOutOfPlaneStretch)
{
  for (const char *stencil : {"yes", "no"}) {
    delete lmp;
    lmp = open_lammps();
    Block b;
    b.dim = 2;
    b.n = 14;
    b.style = "peri/nospd/hs";
    b.settings = std::string("strain small plane stress stencil ") + stencil;
    make_block(lmp, b);
    cmd(lmp, "compute a all nospd/atom F");
    cmd(lmp, "compute b all nospd/bond/local F");
    cmd(lmp, "run 0");
    cmd(lmp, "variable ux atom 0.001*x");
    cmd(lmp, "variable uy atom -0.0005*y");
    cmd(lmp, "displace_atoms all move v_ux v_uy 0 units box");
    cmd(lmp, "run 0");
    const double f33 = 1.0 - b.nu / (1.0 - b.nu) * (0.001 - 0.0005);
    auto *a = lmp->modify->get_compute_by_id("a");
    auto *c = lmp->modify->get_compute_by_id("b");
    a->compute_peratom();
    c->compute_local();
    ASSERT_GT(c->size_local_rows, 0);
    double da = 0.0, db = 0.0;
    for (int i = 0; i < lmp->atom->nlocal; i++) da = std::max(da, std::abs(a->array_atom[i][8] - f33));
    for (int r = 0; r < c->size_local_rows; r++) db = std::max(db, std::abs(c->array_local[r][8] - f33));
    EXPECT_LT(da, 1e-12) << "stencil " << stencil;
    EXPECT_LT(db, 1e-12) << "stencil " << stencil;
  }
}

/* Singular bond-associated families (small ratio, corners) fall back to the
   family's F: counted, and the patch test still holds there. */
TEST_F(HSDeck, SingularFallback)
{
  Block b;
  b.n = 9;
  b.style = "peri/nospd/hs";
  b.settings = "form II ratio 0.4";
  make_block(lmp, b);
  cmd(lmp, "run 0");
  auto *p = static_cast<PairPeriNospdHS *>(lmp->force->pair);
  const bigint nsing = p->singular_bond_families();
  EXPECT_GT(nsing, 0);
  Mat3 F0;
  F0 << 1.01, 0.002, -0.003, 0.004, 0.995, 0.001, -0.002, 0.003, 1.007;
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    NOSPD::Vec3 X(x0[i][0], x0[i][1], x0[i][2]);
    NOSPD::Vec3 y = F0 * X;
    for (int k = 0; k < 3; k++) x[i][k] = y[k];
  }
  cmd(lmp, "run 0");
  auto *fb = static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  bigint nfall = 0;
  double maxd = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int bnd = fb->bond_first[i]; bnd < fb->bond_first[i + 1]; bnd++) {
      double Fb[9];
      if (p->bond_defgrad(i, bnd, Fb) == 0) nfall++;
      maxd = std::max(maxd, (NOSPD::load(Fb) - F0).cwiseAbs().maxCoeff());
    }
  EXPECT_EQ(nfall, nsing);
  EXPECT_LT(maxd, 1e-13);
  // reported through compute pair
  cmd(lmp, "compute P all pair peri/nospd/hs");
  cmd(lmp, "thermo_style custom step pe c_P[1]");
  cmd(lmp, "run 0");
  auto *cp = lmp->modify->get_compute_by_id("P");
  cp->compute_vector();
  EXPECT_EQ((bigint) cp->vector[0], nsing);
}

/* Form I/II differ, ratio 2 is the classical model again (every member of
   the family lies within 2 delta of every other). */
TEST_F(HSDeck, RatioTwoIsClassical)
{
  // without stabilization, and with the same Silling term in both styles
  for (const std::string stab : {"none", "silling 0.4", "hourglass 0.3"}) {
    std::vector<std::array<double, 3>> f[2];
    double e[2];
    for (int m = 0; m < 2; m++) {
      LAMMPS *l = open_lammps();
      Block b;
      b.n = 9;
      b.style = m ? "peri/nospd/hs" : "peri/nospd";
      b.settings = (m ? "form II ratio 2.0" : "") + std::string(" stabilization ") + stab;
      make_block(l, b);
      cmd(l, "displace_atoms all random 2e-6 2e-6 2e-6 8811 units box");
      cmd(l, "run 0");
      f[m] = by_tag(l, l->atom->f);
      e[m] = l->force->pair->eng_vdwl;
      delete l;
    }
    double fmax = 0.0, df = 0.0;
    for (size_t i = 0; i < f[0].size(); i++)
      for (int k = 0; k < 3; k++) {
        fmax = std::max(fmax, std::abs(f[0][i][k]));
        df = std::max(df, std::abs(f[1][i][k] - f[0][i][k]));
      }
    EXPECT_GT(fmax, 0.0) << stab;
    EXPECT_LT(df, 1e-10 * fmax) << stab;
    EXPECT_NEAR(e[1], e[0], 1e-10 * std::abs(e[0])) << stab;
  }
}

/* Silling stabilization on top of the bond-associated forces (form II,
   ratio 1): nothing under a homogeneous deformation (the patch test is
   the bond-associated model's), a restoring force against the non-affine
   part, and still the exact gradient of the energy in a damaged body.
   (The hourglass term, not a potential, is checked against the classical
   style in RatioTwoIsClassical.) */
TEST_F(HSDeck, SillingStabilization)
{
  auto deck = [&](const std::string &stab) {
    delete lmp;
    lmp = open_lammps();
    Block b;
    b.n = 9;
    b.style = "peri/nospd/hs";
    b.settings = "strain finite form II stabilization " + stab;
    make_block(lmp, b);
    return b;
  };
  auto forces_after = [&](const std::string &displace) {
    cmd(lmp, displace);
    cmd(lmp, "run 0");
    return by_tag(lmp, lmp->atom->f);
  };
  auto max_diff = [](const std::vector<std::array<double, 3>> &a,
                     const std::vector<std::array<double, 3>> &b, double &amax) {
    double d = 0.0;
    amax = 0.0;
    for (size_t i = 0; i < a.size(); i++)
      for (int k = 0; k < 3; k++) {
        amax = std::max(amax, std::abs(a[i][k]));
        d = std::max(d, std::abs(a[i][k] - b[i][k]));
      }
    return d;
  };
  // homogeneous deformation: a stretched and sheared box of points
  std::vector<std::array<double, 3>> f[2];
  for (int m = 0; m < 2; m++) {
    deck(m ? "silling 0.5" : "none");
    cmd(lmp, "variable ux atom 0.002*x+0.001*y");
    cmd(lmp, "variable uy atom 0.0015*z");
    cmd(lmp, "variable uz atom -0.001*x");
    f[m] = forces_after("displace_atoms all move v_ux v_uy v_uz units box");
  }
  double fmax;
  const double dhom = max_diff(f[1], f[0], fmax);
  EXPECT_GT(fmax, 0.0);
  EXPECT_LT(dhom, 1e-9 * fmax) << "homogeneous deformation: the Silling term must vanish";

  for (int m = 0; m < 2; m++) {
    deck(m ? "silling 0.5" : "none");
    f[m] = forces_after("displace_atoms all random 2e-6 2e-6 2e-6 8811 units box");
  }
  EXPECT_GT(max_diff(f[1], f[0], fmax), 1e-3 * fmax) << "non-affine: the term must act";

  const Block b = deck("silling 0.5");
  cmd(lmp, "run 0");
  ASSERT_GT(break_random_bonds(lmp, 0.3, 31), 100);
  const int natoms = lmp->atom->natoms;
  expect_force_is_energy_gradient(lmp, b, {0, natoms / 4, natoms / 2, 3 * natoms / 4, natoms - 1});
}

/* Bad input: LAMMPS errors naming the value. */
/* The linear law's stencil (nospd_stencil.h) against the families on a
   step that needs no energy and no virial (pair->compute(0, 0)): forces,
   the family's F and the stress.  Free surfaces (the points within 2 delta
   take one-sided stencils, shared along the faces, the corners the
   families, those that feed only stencil points are left out), a periodic
   box (every point on the stencil, their far cells ghosts), two materials
   or volumes (one-sided stencils at the interface) and broken bonds
   (families of many patterns). */
struct StencilCase {
  int dim;
  bool periodic;
  const char *form;
  double broken;        // fraction of bonds broken (a few bonds)
  double ratio = 1.0;    // 0.4: singular bond families inside (the family's F)
  int halves = 0;        // the upper half x >= n/2: 1 another material, 2 another volume
  int layers = 0;        // 3D free: a plate of this many layers (no inside at 2 delta)
  std::string name() const
  {
    return std::to_string(dim) + "D_" + (periodic ? "periodic" : "free") + "_form" + form +
        (broken > 0.0 ? "_broken" : "") + (ratio != 1.0 ? "_ratio04" : "") +
        (halves == 1 ? "_two_materials" : halves == 2 ? "_two_volumes" : "") +
        (layers ? "_plate" : "");
  }
};

void PrintTo(const StencilCase &c, std::ostream *os) { *os << c.name(); }

class HSStencil : public ::testing::TestWithParam<StencilCase> {
 protected:
  LAMMPS *lmp = nullptr;
  void SetUp() override { lmp = open_lammps(); }
  void TearDown() override { delete lmp; }
};

TEST_P(HSStencil, MatchesFamilies)
{
  const StencilCase &c = GetParam();
  Block b;
  b.dim = c.dim;
  b.periodic = c.periodic;
  // halves: each half wide enough for points 2 delta from both its interfaces
  const int n3 = c.periodic ? (c.halves ? 26 : 13) : 16;
  const int n2 = c.periodic ? (c.halves ? 40 : 20) : 30;
  b.n = c.dim == 3 ? n3 : n2;
  b.style = "peri/nospd/hs";
  b.settings = std::string("form ") + c.form + (c.dim == 2 ? " plane stress" : "") +
      " ratio " + num(c.ratio);
  make_block(lmp, b);
  if (c.halves) {
    const double half = 0.5 * b.n * b.dx;
    cmd(lmp, "region upper block " + num(half) + " INF INF INF INF INF units box");
    if (c.halves == 1) {
      cmd(lmp, "set region upper type 2");
      cmd(lmp, "pair_coeff 2 2 70e9 0.33 " + num(b.delta()));
    } else {
      const double vol = c.dim == 2 ? b.dx * b.dx : b.dx * b.dx * b.dx;
      cmd(lmp, "set region upper volume " + num(1.1 * vol));
    }
  }
  if (c.layers) {
    cmd(lmp, "region above block INF INF INF INF " + num((c.layers - 0.5) * b.dx) +
                 " INF units box");
    cmd(lmp, "delete_atoms region above");
  }
  cmd(lmp, c.dim == 3 ? "displace_atoms all random 2e-6 2e-6 2e-6 8811 units box"
                      : "displace_atoms all random 2e-6 2e-6 0 8811 units box");
  cmd(lmp, "run 0");
  auto *p = static_cast<PairPeriNospdHS *>(lmp->force->pair);
  auto *fb = static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  const bigint natoms = lmp->atom->natoms;
  const int nall = lmp->atom->nlocal + lmp->atom->nghost;
  auto clear = [&]() {
    for (int i = 0; i < nall; i++)
      for (int k = 0; k < 3; k++) lmp->atom->f[i][k] = 0.0;
    for (int i = 0; i < lmp->atom->nlocal; i++)
      for (int k = 0; k < 9; k++) fb->defgrad[i][k] = fb->pk1[i][k] = 0.0;
  };
  if (c.broken > 0.0) {
    // bonds break within a run, the fix's arrays rebuilt as at a
    // reneighboring: the style remaps its families at once (this step
    // wants energy: the families) and its stencils before the next step
    // that takes them
    ASSERT_GT(break_random_bonds(lmp, c.broken, 17), 0);
    fb->post_neighbor();
    clear();
    p->compute(1, 0);
  }

  // run 0 (or the step above) took the families; then the stencil
  auto state = [&]() {
    std::vector<std::array<double, 21>> s(natoms);
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      auto &r = s[lmp->atom->tag[i] - 1];
      for (int k = 0; k < 3; k++) r[k] = lmp->atom->f[i][k];
      for (int k = 0; k < 9; k++) r[3 + k] = fb->defgrad[i][k];
      for (int k = 0; k < 9; k++) r[12 + k] = fb->pk1[i][k];
    }
    return s;
  };
  const auto full = state();
  clear();
  lmp->force->pair->compute(0, 0);
  const auto sten = state();

  const bigint on = p->stencil_points();
  EXPECT_GT(on, 0);
  // whole bodies take the stencil, but for the points of a free block
  // within 2 delta (6 spacings) of a face along every axis: those have a
  // neighbourhood of their own, the others share theirs with at least 4
  // (the block's inside positions along the other axes)
  if (c.broken > 0.0 || (c.halves && !c.periodic)) EXPECT_LT(on, natoms);
  else if (c.periodic) EXPECT_EQ(on, natoms);
  else if (c.layers) EXPECT_EQ(on, natoms - 12 * 12 * c.layers);
  else EXPECT_EQ(on, natoms - (c.dim == 3 ? 12 * 12 * 12 : 12 * 12));
  if (c.ratio != 1.0) EXPECT_GT(p->singular_bond_families(), 0);

  double big[3] = {0.0, 0.0, 0.0}, diff[3] = {0.0, 0.0, 0.0};
  const int from[3] = {0, 3, 12}, to[3] = {3, 12, 21};
  for (bigint i = 0; i < natoms; i++)
    for (int q = 0; q < 3; q++)
      for (int k = from[q]; k < to[q]; k++) {
        const double ref = q == 1 ? full[i][k] - (k == 3 || k == 7 || k == 11) : full[i][k];
        big[q] = std::max(big[q], std::abs(ref));
        diff[q] = std::max(diff[q], std::abs(sten[i][k] - full[i][k]));
      }
  EXPECT_GT(big[0], 0.0);
  EXPECT_LE(diff[0], 1e-12 * big[0]) << "force";
  EXPECT_LE(diff[1], 1e-12 * big[1]) << "F - I";
  EXPECT_LE(diff[2], 1e-12 * big[2]) << "stress";
}

INSTANTIATE_TEST_SUITE_P(BondAssociated, HSStencil,
                         ::testing::Values(StencilCase{3, false, "II", 0.0},
                                           StencilCase{3, true, "II", 0.0},
                                           StencilCase{3, true, "I", 0.0},
                                           StencilCase{3, true, "II", 3e-5},
                                           StencilCase{3, true, "II", 0.0, 0.4},
                                           StencilCase{2, true, "I", 0.0, 0.4},
                                           StencilCase{3, true, "II", 0.0, 1.0, 1},
                                           StencilCase{2, true, "II", 0.0, 1.0, 1},
                                           StencilCase{2, true, "II", 0.0, 1.0, 2},
                                           StencilCase{2, false, "II", 0.0},
                                           StencilCase{2, false, "I", 0.0},
                                           StencilCase{2, true, "II", 0.0},
                                           StencilCase{2, true, "II", 8e-4},
                                           StencilCase{3, false, "II", 0.0, 0.4},
                                           StencilCase{3, false, "II", 0.0, 1.0, 0, 6},
                                           StencilCase{2, false, "II", 0.0, 1.0, 2}),
                         [](const ::testing::TestParamInfo<StencilCase> &p) {
                           return p.param.name();
                         });

/* The stencils are kept from one run command to the next while the law
   they were built for stays (building them takes seconds on a large
   grid), and built anew when a pair_coeff changes it: each time the
   stencil's forces are the families' to 1e-12. */
TEST_F(HSDeck, StencilsKeptBetweenRunsUntilTheLawChanges)
{
  Block b;
  b.n = 16;
  b.style = "peri/nospd/hs";
  make_block(lmp, b);
  cmd(lmp, "displace_atoms all random 2e-6 2e-6 2e-6 8811 units box");
  auto *p = static_cast<PairPeriNospdHS *>(lmp->force->pair);
  const bigint natoms = lmp->atom->natoms;
  // the families' forces (a step with energy) and the stencil's, by tag
  using Forces = std::vector<std::array<double, 3>>;
  auto forces = [&](int eflag) {
    double **f = lmp->atom->f;
    const int nall = lmp->atom->nlocal + lmp->atom->nghost;
    for (int i = 0; i < nall; i++) f[i][0] = f[i][1] = f[i][2] = 0.0;
    p->compute(eflag, 0);
    return by_tag(lmp, f);
  };
  auto stencil_matches_families = [&]() {
    const Forces fam = forces(1), sten = forces(0);
    EXPECT_GT(p->stencil_points(), natoms / 2);
    expect_same_vectors(sten, fam, 1e-12);
    return fam;
  };
  cmd(lmp, "run 0");
  const bigint built = p->stencils_built();
  ASSERT_GT(built, 0);
  const Forces first = stencil_matches_families();
  cmd(lmp, "run 0");
  EXPECT_EQ(p->stencils_built(), built);    // kept
  const Forces again = stencil_matches_families();
  expect_same_vectors(again, first, 0.0);
  // twice the modulus: stencils anew, forces twice as large
  cmd(lmp, "pair_coeff * * " + num(2.0 * b.E) + " " + num(b.nu) + " " + num(b.delta()));
  cmd(lmp, "run 0");
  EXPECT_GT(p->stencils_built(), built);
  const Forces stiffer = stencil_matches_families();
  Forces doubled(first);
  for (auto &v : doubled)
    for (double &c : v) c *= 2.0;
  expect_same_vectors(stiffer, doubled, 1e-12);
}

/* The stencil only for the linear law, and not when switched off.  It
   reads 2 delta around a point: where it applies, the style raises a
   shorter ghost cutoff to 2 delta plus the skin (then every point of a
   periodic box takes it); otherwise the user's cutoff stays. */
TEST_F(HSDeck, StencilOnlyForTheLinearLawWithItsGhosts)
{
  for (const char *settings : {"", "stencil no", "strain finite", "strain neohookean"}) {
    delete lmp;
    lmp = open_lammps();
    Block b;
    b.n = 14;
    b.periodic = true;
    b.style = "peri/nospd/hs";
    b.settings = settings;
    make_block(lmp, b);
    const double user = 1.2 * b.delta();
    cmd(lmp, "comm_modify cutoff " + num(user));
    cmd(lmp, "run 0");
    const double need = 2.0 * b.delta() + lmp->neighbor->skin;
    const bool stencil = std::string(settings).empty();
    EXPECT_DOUBLE_EQ(lmp->comm->get_comm_cutoff(), stencil ? need : user) << settings;
    EXPECT_EQ(static_cast<PairPeriNospdHS *>(lmp->force->pair)->stencil_points(),
              stencil ? lmp->atom->natoms : 0)
        << settings;
  }
}

TEST_F(HSDeck, BadInput)
{
  auto deck = [&]() {
    cmd(lmp, "units si");
    cmd(lmp, "boundary s s s");
    cmd(lmp, "atom_style peri");
    cmd(lmp, "atom_modify map array");
    cmd(lmp, "lattice sc 0.001");
    cmd(lmp, "region box block -0.25 5.25 -0.25 5.25 -0.25 5.25");
    cmd(lmp, "create_box 1 box");
    cmd(lmp, "create_atoms 1 box");
    cmd(lmp, "set group all density 7850");
    cmd(lmp, "set group all volume 1e-9");
  };
  deck();
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs ratio 0"), HasSubstr("ratio must be > 0"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs ratio -1"), HasSubstr("ratio must be > 0"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs form III"), HasSubstr("unknown form 'III'"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs stabilization wan"),
              HasSubstr("stabilization must be none, silling G or hourglass C, got 'wan'"));
  EXPECT_EQ(error_of(lmp, "pair_style peri/nospd/hs stabilization hourglass 0.2"), "");
  EXPECT_NE(error_of(lmp, "pair_style peri/nospd/hs stabilization hourglass 0"), "");
  EXPECT_NE(error_of(lmp, "pair_style peri/nospd/hs stabilization silling -1"), "");
  EXPECT_EQ(error_of(lmp, "pair_style peri/nospd/hs stabilization silling 0.5 form II"), "");
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs strain bogus"), HasSubstr("unknown strain"));
  EXPECT_THAT(error_of(lmp, "pair_style peri/nospd/hs stencil maybe"),
              HasSubstr("pair_style peri/nospd/hs: stencil must be yes or no, got 'maybe'"));
  EXPECT_EQ(error_of(lmp, "pair_style peri/nospd/hs stabilization none form I ratio 1.5"), "");
  // a ratio that leaves the bond-associated families degenerate
  cmd(lmp, "pair_style peri/nospd/hs ratio 0.2");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.00301");
  EXPECT_THAT(error_of(lmp, "run 0"), HasSubstr("is too small"));
  // or a singular_tol that calls whole families degenerate: the message
  // names it (hostile sweep N: it blamed the ratio alone)
  cmd(lmp, "pair_style peri/nospd/hs singular_tol 0.9");
  cmd(lmp, "pair_coeff * * 200e9 0.3 0.00301");
  const std::string msg = error_of(lmp, "run 0");
  EXPECT_THAT(msg, HasSubstr("ratio 1 is too small for singular_tol 0.9"));
  EXPECT_THAT(msg, HasSubstr("or a smaller singular_tol"));
}

}    // namespace

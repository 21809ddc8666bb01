/* Physics checks of formulations.md section E for the classical
   correspondence style, over every strain measure, stabilization and
   dimension:  patch test, bulk stress, linear and angular momentum,
   energy consistency, objectivity, zero-energy checkerboard, and broken
   bonds in an undeformed body. */

#include "nospd_test_util.h"

#include "domain.h"

#include "fix_nospd_bonds.h"
#include "nospd_constitutive.h"

#include <array>
#include <memory>

using namespace nospdtest;
using NOSPD::Mat3;
using LAMMPS_NS::FixNospdBonds;
using LAMMPS_NS::bigint;

namespace {

struct Variant {
  int dim;
  std::string strain;    // small finite svk neohookean
  std::string stab;      // "none", "silling 0.5", "hourglass 0.2", "wan",
                         // "silling 0.5 stabilization/fit quadratic"
  std::string name() const
  {
    std::string s = std::to_string(dim) + "D_" + strain + "_" + stab;
    for (auto &c : s)
      if (c == ' ' || c == '.' || c == '/') c = '_';
    return s;
  }
  bool potential() const { return stab.rfind("hourglass", 0) != 0; }
  bool objective() const { return strain != "small" && stab != "wan"; }
  NOSPD::Law law() const
  {
    if (strain == "small") return NOSPD::Law::SMALL;
    if (strain == "finite") return NOSPD::Law::COROTATIONAL;
    if (strain == "svk") return NOSPD::Law::SVK;
    return NOSPD::Law::NEOHOOKE;
  }
};

void PrintTo(const Variant &v, std::ostream *os) { *os << v.name(); }

class Physics : public ::testing::TestWithParam<Variant> {
 protected:
  LAMMPS *lmp = nullptr;
  Block blk;

  void SetUp() override
  {
    const Variant &v = GetParam();
    lmp = open_lammps();
    blk.dim = v.dim;
    blk.n = v.dim == 3 ? 15 : 25;
    blk.settings = "strain " + v.strain + " stabilization " + v.stab;
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

  FixNospdBonds *bonds() { return static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS")); }

  // displace every atom: x = X + u(X)
  template <class Fn> void displace(Fn u)
  {
    double **x = lmp->atom->x, **x0 = lmp->atom->x0;
    for (int i = 0; i < lmp->atom->nlocal; i++) {
      const auto d = u(x0[i]);
      for (int k = 0; k < blk.dim; k++) x[i][k] = x0[i][k] + d[k];
    }
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

  // depth of atom i below the block's free surfaces
  double depth(const double *X)
  {
    const double lo = 0.0, hi = (blk.n - 1) * blk.dx;
    double d = 1e30;
    for (int k = 0; k < blk.dim; k++) d = std::min({d, X[k] - lo, hi - X[k]});
    return d;
  }

  // y = F (X - c) + c about the block's centre, then a force evaluation
  void deform_affine(const Mat3 &F)
  {
    const auto c = center();
    displace([&](const double *X) {
      const NOSPD::Vec3 d(X[0] - c[0], X[1] - c[1], X[2] - c[2]);
      const NOSPD::Vec3 u = (F - Mat3::Identity()) * d;
      return std::array<double, 3>{u[0], u[1], u[2]};
    });
    cmd(lmp, "run 0");
  }

  std::array<double, 3> center() const
  {
    const double c = 0.5 * (blk.n - 1) * blk.dx;
    return {c, c, blk.dim == 2 ? 0.0 : c};
  }

  double force_scale(const Mat3 &P) { return P.norm() / blk.dx; }
};

/* 1. Patch test: y = F0 X.  F is F0 at every atom with invertible K,
      corners included; the force vanishes at depth >= 2 delta. */
TEST_P(Physics, PatchTest)
{
  build();
  std::mt19937 rng(7);
  const Mat3 F0 = random_F(rng, 0.02);
  deform_affine(F0);
  auto *fb = bonds();
  ASSERT_EQ(fb->nsingular, 0);
  Mat3 P0;
  double W0;
  Mat3 Fp = F0;
  ASSERT_TRUE(NOSPD::first_piola(GetParam().law(),
                                 blk.dim == 2 ? NOSPD::Plane::STRAIN : NOSPD::Plane::NONE,
                                 NOSPD::Lame::from_young(blk.E, blk.nu), Fp, P0, W0));
  const double fscale = force_scale(P0);
  int ninterior = 0;
  double maxdF = 0.0, maxf = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const Mat3 F = NOSPD::load(fb->defgrad[i]);
    maxdF = std::max(maxdF, (F - F0).cwiseAbs().maxCoeff());
    if (depth(lmp->atom->x0[i]) >= 2.0 * blk.delta() - 1e-12) {
      ninterior++;
      for (int k = 0; k < 3; k++) maxf = std::max(maxf, std::abs(lmp->atom->f[i][k]));
    }
  }
  EXPECT_GT(ninterior, 0);
  EXPECT_LT(maxdF, 1e-13);
  EXPECT_LT(maxf, 1e-11 * fscale);
}

/* 2. Bulk stress: away from surfaces the per-atom virial of the bond forces
      is -F P(F0)^T (the Kirchhoff stress), and compute nospd/atom reports
      the Cauchy stress P F^T / J. */
TEST_P(Physics, BulkStress)
{
  build();
  std::mt19937 rng(11);
  const Mat3 F0 = random_F(rng, 0.01);
  deform_affine(F0);
  Mat3 P0;
  double W0;
  Mat3 Fp = F0;
  NOSPD::first_piola(GetParam().law(), blk.dim == 2 ? NOSPD::Plane::STRAIN : NOSPD::Plane::NONE,
                     NOSPD::Lame::from_young(blk.E, blk.nu), Fp, P0, W0);
  const Mat3 tau = F0 * P0.transpose();    // Kirchhoff stress J sigma
  auto *cv = lmp->modify->get_compute_by_id("V");
  cv->compute_peratom();
  auto *cs = lmp->modify->get_compute_by_id("S");
  cs->compute_peratom();
  // small strain: sigma = P by definition; finite strain: sigma = P F^T / J
  const Mat3 sigma = GetParam().strain == "small" ? Mat3(0.5 * (P0 + P0.transpose()))
                                                  : Mat3(tau / F0.determinant());
  int checked = 0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    if (depth(lmp->atom->x0[i]) < 2.0 * blk.delta() - 1e-12) continue;
    const double *s = cv->array_atom[i];    // -virial: xx yy zz xy xz yz
    const double vt[6] = {tau(0, 0), tau(1, 1), tau(2, 2), tau(0, 1), tau(0, 2), tau(1, 2)};
    const int nk = blk.dim == 2 ? 4 : 6;
    for (int k = 0; k < nk; k++) {
      if (blk.dim == 2 && k == 2) continue;
      EXPECT_NEAR(s[k], vt[k], 1e-9 * tau.norm()) << "virial component " << k;
    }
    const double *o = cs->array_atom[i] + 9;    // F first (9), then stress
    const double st[6] = {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(0, 2), sigma(1, 2)};
    for (int k = 0; k < nk; k++)
      if (!(blk.dim == 2 && k == 2)) EXPECT_NEAR(o[k], st[k], 1e-9 * sigma.norm());
    checked++;
  }
  EXPECT_GT(checked, 0);
  // the stress is the law's answer, not a trivially small number
  EXPECT_GT(sigma.norm(), 1e8);
}

/* 3. Momentum: for a random displacement field the forces sum to zero;
      objective variants also conserve angular momentum. */
TEST_P(Physics, Momentum)
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
  if (GetParam().objective()) EXPECT_LT(torque.norm(), 1e-11 * tabs);
}

/* 4. Energy consistency: where the model derives from an energy,
      -dE/dy by central differences equals the force. */
TEST_P(Physics, EnergyConsistency)
{
  if (!GetParam().potential()) GTEST_SKIP() << "hourglass control is not a potential";
  build(false, GetParam().dim == 3 ? 9 : 17);
  const int natoms = lmp->atom->natoms;
  expect_force_is_energy_gradient(lmp, blk, {0, natoms / 3, natoms / 2, natoms - 1});
}

/* 5. Objectivity: a rigid rotation of the whole body produces no force and
      no energy under the finite-strain laws; the small-strain law does
      produce both (it is not objective), and the test says by how much. */
TEST_P(Physics, Objectivity)
{
  build();
  const double ang = 0.6;    // radians
  Mat3 Q = Mat3::Identity();
  if (blk.dim == 2) {
    Q << cos(ang), -sin(ang), 0, sin(ang), cos(ang), 0, 0, 0, 1;
  } else {
    Q = Eigen::AngleAxisd(ang, NOSPD::Vec3(1, 2, 3).normalized()).toRotationMatrix();
  }
  deform_affine(Q);
  double fmax = 0.0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int k = 0; k < 3; k++) fmax = std::max(fmax, std::abs(lmp->atom->f[i][k]));
  const double E = lmp->force->pair->eng_vdwl;
  const double fscale = blk.E / blk.dx;    // the force of a unit strain
  if (GetParam().objective()) {
    EXPECT_LT(fmax, 1e-11 * fscale);
    EXPECT_LT(std::abs(E), 1e-12 * blk.E * lmp->atom->natoms);
  } else if (GetParam().strain == "small") {
    EXPECT_GT(fmax, 1e-3 * fscale);
    EXPECT_GT(E, 1e-3 * blk.E * lmp->atom->natoms);
  }
}

/* 6. Zero-energy mode: periodic block, u = a (-1)^(i+j+k) e_x.  F stays I,
      so the unstabilized model neither stores energy nor resists; every
      stabilized model resists (f.u < 0, E > 0) with an RMS restoring force
      above 0.5 E (2a/dx)/delta. */
TEST_P(Physics, ZeroEnergyMode)
{
  build(true, 8);
  const double a = 1e-3 * blk.dx;
  displace([&](const double *X) {
    int s = 0;
    for (int k = 0; k < blk.dim; k++) s += (int) std::lround(X[k] / blk.dx);
    return std::array<double, 3>{(s % 2 ? -a : a), 0.0, 0.0};
  });
  cmd(lmp, "run 0");
  auto *fb = bonds();
  double fu = 0.0, f2 = 0.0, dF = 0.0;
  const int nlocal = lmp->atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    const double ux = lmp->atom->x[i][0] - fb->x0s[i][0];
    fu += lmp->atom->f[i][0] * ux;
    for (int k = 0; k < 3; k++) f2 += lmp->atom->f[i][k] * lmp->atom->f[i][k];
    dF = std::max(dF, (NOSPD::load(fb->defgrad[i]) - Mat3::Identity()).cwiseAbs().maxCoeff());
  }
  const double frms = std::sqrt(f2 / nlocal);
  const double E = lmp->force->pair->eng_vdwl;
  const double band = 0.5 * blk.E * (2.0 * a / blk.dx) / blk.delta();
  EXPECT_LT(dF, 1e-12);
  if (GetParam().stab == "none") {
    EXPECT_LT(frms, 1e-9 * band);
    EXPECT_LT(std::abs(E), 1e-9 * blk.E * 1e-6 * nlocal);
  } else {
    EXPECT_LT(fu, 0.0);
    EXPECT_GT(frms, band);
    if (GetParam().potential()) EXPECT_GT(E, 0.0);
  }
}

/* 7. Broken bonds in an undeformed body: F stays I and f stays 0, because
      a broken bond leaves both the K and the F sums. */
TEST_P(Physics, BrokenBondsUndeformed)
{
  build();
  auto *fb = bonds();
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int nlocal = lmp->atom->nlocal;
  int nbroken = 0;
  for (int i = 0; i < nlocal; i++)
    for (int s = 0; s < fb->npartner[i]; s++) {
      const auto tj = fb->partner[i][s];
      if (tj == 0 || tj < lmp->atom->tag[i] || U(rng) > 0.3) continue;
      fb->partner[i][s] = 0;
      const int j = lmp->atom->map(tj);
      for (int t = 0; t < fb->npartner[j]; t++)
        if (fb->partner[j][t] == lmp->atom->tag[i]) fb->partner[j][t] = 0;
      nbroken++;
    }
  ASSERT_GT(nbroken, 100);
  cmd(lmp, "run 0");
  EXPECT_EQ((bigint) fb->compute_vector(1), 2 * (bigint) nbroken);
  double dF = 0.0, fmax = 0.0;
  for (int i = 0; i < nlocal; i++) {
    if (fb->singular[i]) continue;
    dF = std::max(dF, (NOSPD::load(fb->defgrad[i]) - Mat3::Identity()).cwiseAbs().maxCoeff());
    for (int k = 0; k < 3; k++) fmax = std::max(fmax, std::abs(lmp->atom->f[i][k]));
    for (int k = 0; k < 3; k++) EXPECT_FALSE(std::isnan(lmp->atom->f[i][k]));
  }
  EXPECT_LT(dF, 1e-14);
  EXPECT_LT(fmax, 1e-20 * blk.E / blk.dx);
}

/* 8. The hourglass pass over pairs of points (peri/nospd on one thread:
      each bond i-j of two owned points once, the partner's force as the
      opposite, nospd_bond_sums.h) against the pass over each end's bonds
      (peri/nospd/omp, one thread), on an irregular body of uneven volumes,
      inverse influence, deformed at random: forces and per-atom virial to
      1e-12; again with bonds broken at both ends, by hand and by the damage
      fix in a run; and with a bond left at one end only, where the pair
      order must not be used.  The periodic
      box gives bonds to ghosts, which each end takes on its own. */
struct PairsRun {
  std::vector<std::array<double, 3>> f, v;    // by atom ID - 1; v: xx yy zz
  bool ordered = false;
};

// cut: 0 none, 1 random bonds at both ends, 2 also one bond at one end,
// 3 bonds broken by fix nospd/damage in a run of three steps
PairsRun hourglass_pairs_run(int dim, bool periodic, const std::string &style, int cut)
{
  LAMMPS *lmp = open_lammps();
  Block b;
  b.dim = dim;
  b.periodic = periodic;
  b.n = dim == 3 ? 9 : 17;
  b.style = style;
  b.settings = std::string("strain finite stabilization hourglass 0.2 influence inverse") +
      (dim == 2 ? " plane strain" : "");
  make_block(lmp, b);
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  const int nlocal = lmp->atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    for (int k = 0; k < dim; k++) x[i][k] = x0[i][k] = x0[i][k] + 0.2 * b.dx * U(rng);
    lmp->atom->vfrac[i] *= 1.0 + 0.3 * U(rng);
  }
  cmd(lmp, "compute V all stress/atom NULL virial");
  cmd(lmp, "thermo_style custom step pe");
  cmd(lmp, "run 0");
  auto *fb = static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  if (cut) {
    const auto *tag = lmp->atom->tag;
    for (int i = 0; i < nlocal; i++)
      for (int s = 0; s < fb->npartner[i]; s++) {
        const auto tj = fb->partner[i][s];
        if (tj == 0 || tj < tag[i] || U(rng) < 0.7) continue;
        fb->partner[i][s] = 0;
        const int j = lmp->atom->map(tj);
        for (int t = 0; t < fb->npartner[j]; t++)
          if (fb->partner[j][t] == tag[i]) fb->partner[j][t] = 0;
      }
    // one end only: point 0 forgets its first partner whose bond is to an
    // owned atom (not a ghost image), which keeps it
    if (cut == 2)
      for (int s = 0; s < fb->npartner[0]; s++) {
        if (!fb->partner[0][s]) continue;
        const int j = lmp->atom->map(fb->partner[0][s]);
        if (lmp->domain->closest_image(0, j) >= nlocal) continue;
        fb->partner[0][s] = 0;
        break;
      }
  }
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < dim; k++) x[i][k] = x0[i][k] + 0.02 * b.dx * U(rng) + 0.01 * x0[i][(k + 1) % dim];
  if (cut == 3) {
    // bonds broken by the damage fix during a run: the bond arrays are
    // compacted in place, in pair order
    cmd(lmp, "fix D all nospd/damage stretch 0.012");
    cmd(lmp, "fix I all nve");
    cmd(lmp, "run 3");
    EXPECT_GT((bigint) fb->compute_vector(1), 0);
  } else {
    cmd(lmp, "run 0");
  }
  PairsRun r;
  r.f = by_tag(lmp, lmp->atom->f);
  auto *V = lmp->modify->get_compute_by_id("V");
  V->compute_peratom();
  r.v = by_tag(lmp, V->array_atom);
  r.ordered = fb->pairs_ordered();
  delete lmp;
  return r;
}

double rel_max_diff(const std::vector<std::array<double, 3>> &a,
                    const std::vector<std::array<double, 3>> &b)
{
  double d = 0.0, m = 0.0;
  for (size_t i = 0; i < a.size(); i++)
    for (int k = 0; k < 3; k++) {
      d = std::max(d, std::abs(a[i][k] - b[i][k]));
      m = std::max(m, std::abs(b[i][k]));
    }
  return d / m;
}

TEST(HourglassPairs, MatchEachEndsSums)
{
  for (int dim : {3, 2})
    for (bool periodic : {false, true})
      for (int cut : {0, 1, 2, 3}) {
        SCOPED_TRACE("dim " + std::to_string(dim) + (periodic ? ", periodic" : "") + ", cut " +
                     std::to_string(cut));
        const PairsRun pairs = hourglass_pairs_run(dim, periodic, "peri/nospd", cut);
        const PairsRun ends = hourglass_pairs_run(dim, periodic, "peri/nospd/omp", cut);
        EXPECT_EQ(pairs.ordered, cut != 2);    // one end only: back to each end's sums
        EXPECT_FALSE(ends.ordered);
        EXPECT_LT(rel_max_diff(pairs.f, ends.f), 1e-12);
        EXPECT_LT(rel_max_diff(pairs.v, ends.v), 1e-12);
      }
}

/* Silling's springs on the quadratic fit's residual: under a smooth curved
   motion, y = X + H X + 1/2 G:XX + c (a quadratic field, here of 1 %
   strain and a curvature of 1 % per horizon), every family with a quadratic fit
   (all points of the block, surfaces and corners included) has z2 = 0,
   so the springs store nothing and push nothing: energy and forces are
   those of the unstabilized model.  The springs on the linear fit store
   the curvature's share, z = 1/2 G:xi xi, as energy. */
TEST(QuadraticFit, CurvedMotionCostsTheSpringsNothing)
{
  for (int dim : {3, 2}) {
    SCOPED_TRACE("dim " + std::to_string(dim));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    Mat3 H;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) H(r, c) = 0.01 * U(rng);
    double G[3][3][3];    // symmetric in the last two
    for (int r = 0; r < 3; r++)
      for (int a = 0; a < 3; a++)
        for (int b = a; b < 3; b++) G[r][a][b] = G[r][b][a] = 0.01 / (3.01e-3) * U(rng);
    auto run = [&](const std::string &stab, double &pe) {
      LAMMPS *lmp = open_lammps();
      Block blk;
      blk.dim = dim;
      blk.n = dim == 3 ? 9 : 15;
      blk.settings = "strain finite stabilization " + stab;
      make_block(lmp, blk);
      cmd(lmp, "run 0");
      double **x = lmp->atom->x, **x0 = lmp->atom->x0;
      for (int i = 0; i < lmp->atom->nlocal; i++) {
        const double X[3] = {x0[i][0] - 4e-3, x0[i][1] - 4e-3, dim == 3 ? x0[i][2] - 4e-3 : 0.0};
        for (int r = 0; r < dim; r++) {
          double u = 0.0;
          for (int a = 0; a < dim; a++) {
            u += H(r, a) * X[a];
            for (int b = 0; b < dim; b++) u += 0.5 * G[r][a][b] * X[a] * X[b];
          }
          x[i][r] = x0[i][r] + u;
        }
      }
      cmd(lmp, "run 0");
      pe = lmp->force->pair->eng_vdwl;
      auto f = by_tag(lmp, lmp->atom->f);
      delete lmp;
      return f;
    };
    double pe_none, pe_lin, pe_quad;
    const auto f_none = run("none", pe_none);
    const auto f_lin = run("silling 0.5", pe_lin);
    const auto f_quad = run("silling 0.5 stabilization/fit quadratic", pe_quad);
    ASSERT_GT(pe_none, 0.0);
    EXPECT_LT(std::abs(pe_quad - pe_none), 1e-10 * pe_none);
    EXPECT_LT(rel_max_diff(f_quad, f_none), 1e-9);
    // the linear fit's springs: the curvature costs energy and force
    EXPECT_GT(pe_lin - pe_none, 1e-3 * pe_none);
    EXPECT_GT(rel_max_diff(f_lin, f_none), 1e-2);
  }
}

/* The quadratic fit's springs on a step that wants neither energy nor
   virial (pair->compute(0, 0): the i-terms from the point's sums) against
   the evaluation with both (every term bond by bond), after random
   displacements, free surfaces, 3D and 2D. */
TEST(QuadraticFit, StepWithoutVirialMatchesStepWithIt)
{
  for (int dim : {3, 2}) {
    SCOPED_TRACE("dim " + std::to_string(dim));
    LAMMPS *lmp = open_lammps();
    Block blk;
    blk.dim = dim;
    blk.n = dim == 3 ? 9 : 15;
    blk.settings = "strain finite stabilization silling 0.5 stabilization/fit quadratic";
    make_block(lmp, blk);
    cmd(lmp, "run 0");
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-0.02 * blk.dx, 0.02 * blk.dx);
    double **x = lmp->atom->x, **x0 = lmp->atom->x0;
    for (int i = 0; i < lmp->atom->nlocal; i++)
      for (int k = 0; k < dim; k++) x[i][k] = x0[i][k] + U(rng);
    cmd(lmp, "run 0");
    const auto with = by_tag(lmp, lmp->atom->f);
    double **f = lmp->atom->f;
    for (int i = 0; i < lmp->atom->nlocal; i++) f[i][0] = f[i][1] = f[i][2] = 0.0;
    lmp->force->pair->compute(0, 0);
    const auto without = by_tag(lmp, lmp->atom->f);
    EXPECT_LT(rel_max_diff(without, with), 1e-12);    // NaN (all forces zero) fails too
    delete lmp;
  }
}

/* A family that has lost bonds fits no quadratic (its ragged partners fit
   one poorly: the projectile scene ran away with them).  Under the default
   damaged_state carry it keeps the curvature of its last fit (a carried
   record, nospd_quadratic_carry.h); under refit the linear fit.  An intact
   family keeps its quadratic fit. */
TEST(QuadraticFit, FamiliesThatLostBondsCarryOrKeepTheLinearFit)
{
  for (const std::string state : {"", " damaged_state refit"}) {
    LAMMPS *lmp = open_lammps();
    Block blk;
    blk.n = 9;
    blk.settings = "strain small stabilization silling 0.5 stabilization/fit quadratic" + state;
    make_block(lmp, blk);
    cmd(lmp, "run 0");
    auto *fb = static_cast<FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
    const int nlocal = lmp->atom->nlocal;
    const int flag = NOSPD::QuadraticFit::PACKED;
    int fitted = 0;
    for (int i = 0; i < nlocal; i++) fitted += fb->kinv2[i][flag] == 1.0;
    EXPECT_EQ(fitted, nlocal);    // every family of the block, corners included
    ASSERT_GT(break_random_bonds(lmp, 0.02, 3), 0);
    cmd(lmp, "run 0");
    const double damaged = state.empty() ? NOSPD::CarriedQuadratic::FLAG : 0.0;
    int lost = 0, intact_fitted = 0;
    for (int i = 0; i < nlocal; i++) {
      if (fb->bond_first[i + 1] - fb->bond_first[i] < fb->family_size[i]) {
        lost++;
        EXPECT_EQ(fb->kinv2[i][flag], damaged) << "atom " << lmp->atom->tag[i] << state;
      } else
        intact_fitted += fb->kinv2[i][flag] == 1.0;
    }
    EXPECT_GT(lost, 0);
    EXPECT_EQ(intact_fitted, nlocal - lost);
    delete lmp;
  }
}

std::vector<Variant> all_variants()
{
  std::vector<Variant> v;
  for (int dim : {3, 2})
    for (const char *strain : {"small", "finite", "svk", "neohookean"})
      for (const char *stab : {"none", "silling 0.5", "hourglass 0.2", "wan"})
        v.push_back({dim, strain, stab});
  // Silling's springs on the quadratic fit's residual
  for (int dim : {3, 2})
    for (const char *strain : {"small", "finite"})
      v.push_back({dim, strain, "silling 0.5 stabilization/fit quadratic"});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Classical, Physics, ::testing::ValuesIn(all_variants()),
                         [](const ::testing::TestParamInfo<Variant> &p) { return p.param.name(); });

}    // namespace

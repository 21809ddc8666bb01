/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of inelastic history per bond-associated family
   (nospd_bond_history.h) on one family, without LAMMPS.

   - A homogeneous deformation gives every bond the family's F: each bond
     and the family's means must then follow the single material point of
     nospd_plasticity.h increment by increment (its closed forms are
     tested in test_plasticity.cpp).
   - Form II is the gradient of E = sum_j beta_j W(F_j); with history per
     bond the force state must be the gradient of the step's incremental
     potential sum_j beta_j (W_e(F_j) + dD_j) (central differences on a
     non-uniform, yielding family).
   - The accepted row is never written; an evaluation at the accepted
     configuration returns the accepted force state and keeps the history
     (a Johnson-Cook law whose rate term would move the surface).
------------------------------------------------------------------------- */

#include "nospd_bond_history.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace NOSPD;

namespace {

constexpr double E = 200.0e9, NU = 0.3;

// a grid family of radius 3.01 spacings (unit spacing)
BondPattern grid_pattern(HSForm form)
{
  std::vector<double> b, w, v;
  std::vector<int64_t> key;
  for (int z = -3; z <= 3; z++)
    for (int y = -3; y <= 3; y++)
      for (int x = -3; x <= 3; x++) {
        const int r2 = x * x + y * y + z * z;
        if (r2 == 0 || r2 > 9.06) continue;
        b.insert(b.end(), {(double) x, (double) y, (double) z});
        key.insert(key.end(), {x, y, z});
        w.push_back(1.0);
        v.push_back(1.0);
      }
  BondPattern p;
  build_pattern(p, 3, (int) w.size(), b.data(), w.data(), v.data(), key, 3.01, form, 1e-4);
  return p;
}

// One family with its rows, evaluated as the pair style does.
struct Family {
  Family(Law law, HSForm f) : form(f), p(grid_pattern(f))
  {
    fp.law = law;
    fp.m = &m;
    fp.fl = &fl;
    fp.th = &th;
    fp.pattern = &p;
    slots.resize(p.n);
    // partner slots in reverse pattern order: the mapping must be honoured
    for (int s = 0; s < p.n; s++) slots[s] = p.n - 1 - s;
    fp.slot_of = slots.data();
    fp.bond_offset = FamilyHist::SIZE;
    fp.bond_stride = BondHist::SIZE;
    hn.assign(FamilyHist::SIZE + BondHist::SIZE * p.n, 0.0);
    h1 = hn;
  }
  HSForm form;
  BondPattern p;
  Lame m = Lame::from_young(E, NU);
  FlowLaw fl;
  ThermalLaw th;
  FamilyPlasticity fp;
  std::vector<int> slots;
  std::vector<double> hn, h1, t;
  StateScratch scratch;
  StateOutput out;

  // force state t (3 per slot) at displacement differences U; true if OK
  bool eval(const std::vector<double> &U)
  {
    h1 = hn;
    fp.hn = hn.data();
    fp.h1 = h1.data();
    t.assign(3 * p.n, 0.0);
    const bool ok = evaluate_family<3>(p, form, fp.law, Plane::NONE, m, LinearLaw(), true,
                                       U.data(), t.data(), scratch, out, &fp);
    if (ok) fp.finish();
    return ok;
  }
  std::vector<double> affine(const Mat3 &F) const
  {
    std::vector<double> U(3 * p.n);
    for (int s = 0; s < p.n; s++) {
      const Vec3 bs(p.b[3 * s], p.b[3 * s + 1], p.b[3 * s + 2]);
      const Vec3 u = (F - Mat3::Identity()) * bs;
      for (int a = 0; a < 3; a++) U[3 * s + a] = u[a];
    }
    return U;
  }
  const double *bond(int s) const { return hn.data() + FamilyHist::SIZE + BondHist::SIZE * slots[s]; }
};

// F of uniaxial-like loading, then unloading, at increment k
Mat3 path_F(int k)
{
  const double e = (k <= 8 ? k : 16 - k) * 1.5e-3;
  Mat3 F = Mat3::Identity();
  F(0, 0) += e;
  F(1, 1) -= 0.3 * e;
  F(2, 2) -= 0.2 * e;
  F(0, 1) += 0.4 * e;
  return F;
}

void check_homogeneous(Law law, HSForm form, bool kinematic)
{
  Family fam(law, form);
  fam.fl.active = true;
  fam.fl.sigma_y0 = 250e6;
  if (law == Law::SMALL) {
    fam.fl.H = 2e9;
    fam.fl.Hkin = kinematic ? 3e9 : 0.0;
  } else {
    fam.fl.kind = Hardening::POWER;
    fam.fl.K = 4e8;
    fam.fl.n = 0.4;
  }
  std::vector<double> hp(Hist::SIZE, 0.0), hp1(Hist::SIZE);
  double eqps_max = 0.0;
  for (int k = 1; k <= 12; k++) {
    const Mat3 F = path_F(k);
    ASSERT_TRUE(fam.eval(fam.affine(F)));
    Mat3 Fp = F, P;
    double W;
    ASSERT_EQ(inelastic_point_3d(law, fam.m, fam.fl, fam.th, fam.fp.env, Fp, hp.data(), hp1.data(),
                                 P, W),
              ReturnStatus::OK);
    const double scale = P.norm();
    EXPECT_LT((fam.out.P - P).norm(), 1e-10 * scale) << "increment " << k;
    EXPECT_NEAR(fam.out.W, W, 1e-10 * std::abs(W));
    const double *h = fam.h1.data();
    EXPECT_NEAR(h[Hist::EQPS], hp1[Hist::EQPS], 1e-10 * std::max(hp1[Hist::EQPS], 1e-3));
    EXPECT_NEAR(h[Hist::WORK], hp1[Hist::WORK], 1e-10 * std::max(hp1[Hist::WORK], 1.0));
    for (int c = 0; c < 6; c++) {
      EXPECT_NEAR(h[Hist::PLASTIC + c], hp1[Hist::PLASTIC + c], 1e-10 * std::max(hp1[Hist::EQPS], 1e-3));
      EXPECT_NEAR(h[Hist::BACK + c], hp1[Hist::BACK + c], 1e-10 * fam.fl.sigma_y0);
    }
    fam.hn = fam.h1;
    hp = hp1;
    for (int s = 0; s < fam.p.n; s++)
      ASSERT_NEAR(fam.bond(s)[BondHist::EQPS], hp[Hist::EQPS], 1e-10 * std::max(hp[Hist::EQPS], 1e-3));
    eqps_max = std::max(eqps_max, hp[Hist::EQPS]);
  }
  EXPECT_GT(eqps_max, 1e-3);    // the path went well past yield
}

TEST(BondHistory, HomogeneousFamilyIsThePointSmallFormII) { check_homogeneous(Law::SMALL, HSForm::II, true); }
TEST(BondHistory, HomogeneousFamilyIsThePointSmallFormI) { check_homogeneous(Law::SMALL, HSForm::I, false); }
TEST(BondHistory, HomogeneousFamilyIsThePointHenckyFormII) { check_homogeneous(Law::HENCKY, HSForm::II, false); }

/* Form II with history: w_k t_k = dE/dU_k for the incremental potential
   E(U) = sum_j beta_j (W_e(F_j) + dD_j(F_j)) of one step from a fixed
   accepted history (which each evaluation leaves untouched). */
void check_incremental_gradient(Law law)
{
  Family fam(law, HSForm::II);
  fam.fl.active = true;
  fam.fl.sigma_y0 = 250e6;
  fam.fl.H = 1e9;
  if (law == Law::SMALL) fam.fl.Hkin = 2e9;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> R(-1.0, 1.0);
  // a first accepted step, then a non-uniform second one
  Mat3 F = path_F(2);
  ASSERT_TRUE(fam.eval(fam.affine(F)));
  fam.hn = fam.h1;
  const std::vector<double> accepted = fam.hn;
  std::vector<double> U = fam.affine(path_F(4));
  for (double &u : U) u += 2e-4 * R(rng);
  ASSERT_TRUE(fam.eval(U));
  const std::vector<double> t0 = fam.t;
  int yielded = 0;
  for (int s = 0; s < fam.p.n; s++) {
    const double *b = fam.h1.data() + FamilyHist::SIZE + BondHist::SIZE * fam.slots[s];
    yielded += b[BondHist::EQPS] > fam.bond(s)[BondHist::EQPS];
  }
  EXPECT_GT(yielded, fam.p.n / 2);
  auto energy = [&](const std::vector<double> &Ux) {
    EXPECT_TRUE(fam.eval(Ux));
    return fam.out.W + fam.h1[Hist::WORK] - fam.hn[Hist::WORK];
  };
  double tmax = 0.0;
  for (int s = 0; s < fam.p.n; s++)
    for (int a = 0; a < 3; a++) tmax = std::max(tmax, std::abs(fam.p.w[s] * t0[3 * s + a]));
  const double h = 1e-7;
  for (int s = 0; s < fam.p.n; s += 7)
    for (int a = 0; a < 3; a++) {
      std::vector<double> Up = U, Um = U;
      Up[3 * s + a] += h;
      Um[3 * s + a] -= h;
      const double fd = (energy(Up) - energy(Um)) / (2.0 * h);
      EXPECT_NEAR(fd, fam.p.w[s] * t0[3 * s + a], 1e-6 * tmax) << "slot " << s << " dir " << a;
    }
  EXPECT_EQ(fam.hn, accepted);    // evaluations never write the accepted row
}

TEST(BondHistory, FormIIIsIncrementalPotentialGradientSmall) { check_incremental_gradient(Law::SMALL); }
TEST(BondHistory, FormIIIsIncrementalPotentialGradientHencky) { check_incremental_gradient(Law::HENCKY); }

/* Johnson-Cook with a rate term and adiabatic heating: the surface of the
   next step differs from that of the accepted one (here lower: the last
   step was slower), so a plain return at the accepted configuration would
   relax the stress.  At the accepted
   configuration the family returns the accepted force state and keeps its
   history; one step further it moves on. */
TEST(BondHistory, AcceptedConfigurationReturnsAcceptedState)
{
  Family fam(Law::SMALL, HSForm::II);
  fam.fl.active = true;
  fam.fl.kind = Hardening::JOHNSON_COOK;
  fam.fl.sigma_y0 = 90e6;
  fam.fl.K = 292e6;
  fam.fl.n = 0.31;
  fam.fl.C = 0.025;
  fam.fl.rate0 = 1.0;
  fam.fl.m = 1.09;
  fam.fl.T_ref = 298.0;
  fam.fl.T_melt = 1356.0;
  fam.th.cp = 383.0;
  fam.fp.env.dt = 1e-7;
  fam.fp.env.rho = 8960.0;
  fam.fp.env.T_base = 298.0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> R(-1.0, 1.0);
  std::vector<double> U;
  for (int k = 1; k <= 5; k++) {
    // the last increment is slower than the one before: its rate lowers
    // the surface the next step starts from
    const Mat3 F = k < 5 ? path_F(k) : Mat3(path_F(4) + 0.2 * (path_F(5) - path_F(4)));
    U = fam.affine(F);
    for (double &u : U) u += 1e-4 * R(rng);
    ASSERT_TRUE(fam.eval(U));
    fam.hn = fam.h1;
  }
  const std::vector<double> t_acc = fam.t, accepted = fam.hn;
  ASSERT_GT(accepted[Hist::RATE], 1.0e3);    // the rate term is on
  ASSERT_GT(accepted[Hist::HEAT], 0.0);
  ASSERT_TRUE(fam.eval(U));
  EXPECT_TRUE(fam.fp.replaying());
  double tmax = 0.0, diff = 0.0;
  for (size_t k = 0; k < t_acc.size(); k++) {
    tmax = std::max(tmax, std::abs(t_acc[k]));
    diff = std::max(diff, std::abs(fam.t[k] - t_acc[k]));
  }
  EXPECT_LT(diff, 1e-12 * tmax);
  EXPECT_EQ(fam.h1, accepted);
  // without the replay (the accepted step's rate and heat forgotten) the
  // same configuration gives other forces: the check above can fail
  fam.hn[Hist::VALID] = 0.0;
  ASSERT_TRUE(fam.eval(U));
  diff = 0.0;
  for (size_t k = 0; k < t_acc.size(); k++) diff = std::max(diff, std::abs(fam.t[k] - t_acc[k]));
  EXPECT_GT(diff, 1e-6 * tmax);
}

/* The compact per-bond state of J2 (FamilyPlasticity: 7 values per bond)
   is a storage of the same law, not another one: on a non-uniform path
   through yield and unloading, the family evaluated through the material
   interface (FamilyMaterial on J2Material, the law's whole history per
   bond) gives the same force states and family means, with isotropic and
   kinematic hardening, small strain and Hencky (rate-independent: the
   compact state shares the family's rate, the interface would give each
   bond its own). */
void check_compact_is_the_interface(Law law, double Hkin)
{
  Family fam(law, HSForm::II);
  fam.fl.active = true;
  fam.fl.sigma_y0 = 250e6;
  fam.fl.H = 1e9;
  fam.fl.Hkin = Hkin;
  const J2Material j2(law, Plane::NONE, fam.m, fam.fl, fam.th);
  FamilyMaterial fm;
  fm.mat = &j2;
  fm.pattern = &fam.p;
  fm.slot_of = fam.slots.data();
  fm.bond_offset = FamilyMaterial::family_size(j2);
  fm.bond_stride = j2.history_size();
  std::vector<double> gn(fm.bond_offset + fm.bond_stride * fam.p.n, 0.0), g1, t;
  StateScratch scratch;
  StateOutput out;

  std::mt19937 rng(17);
  std::uniform_real_distribution<double> R(-1.0, 1.0);
  double eqps = 0.0;
  for (int k = 1; k <= 14; k++) {
    std::vector<double> U = fam.affine(path_F(k));
    for (double &u : U) u += 3e-4 * R(rng);
    ASSERT_TRUE(fam.eval(U));
    g1 = gn;
    fm.hn = gn.data();
    fm.h1 = g1.data();
    t.assign(3 * fam.p.n, 0.0);
    ASSERT_TRUE(evaluate_family<3>(fam.p, fam.form, law, Plane::NONE, fam.m, LinearLaw(), true,
                                   U.data(), t.data(), scratch, out, &fm));
    fm.finish();
    double tmax = 0.0, diff = 0.0;
    for (size_t q = 0; q < t.size(); q++) {
      tmax = std::max(tmax, std::abs(fam.t[q]));
      diff = std::max(diff, std::abs(t[q] - fam.t[q]));
    }
    EXPECT_LT(diff, 1e-12 * tmax) << "increment " << k;
    EXPECT_NEAR(g1[Hist::EQPS], fam.h1[Hist::EQPS], 1e-12 * std::max(fam.h1[Hist::EQPS], 1e-3));
    EXPECT_NEAR(g1[Hist::WORK], fam.h1[Hist::WORK], 1e-12 * std::max(fam.h1[Hist::WORK], 1.0));
    for (int c = 0; c < 6; c++)
      EXPECT_NEAR(g1[Hist::PLASTIC + c], fam.h1[Hist::PLASTIC + c], 1e-12 * std::max(eqps, 1e-3));
    fam.hn = fam.h1;
    gn = g1;
    eqps = std::max(eqps, fam.h1[Hist::EQPS]);
  }
  EXPECT_GT(eqps, 1e-3);    // well past yield
}

TEST(BondHistory, CompactJ2StateIsTheInterfaceSmall) { check_compact_is_the_interface(Law::SMALL, 2e9); }
TEST(BondHistory, CompactJ2StateIsTheInterfaceHencky) { check_compact_is_the_interface(Law::HENCKY, 0.0); }

}    // namespace

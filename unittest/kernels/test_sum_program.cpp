/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the bond-associated sums
   (nospd_bond_associated.h): the sum program a pattern shared by many
   families gets, and the prefix-sum runs every pattern has, against the
   member lists summed one by one; and a family evaluated with the program
   against the same family evaluated with the runs.
------------------------------------------------------------------------- */

#include "nospd_bond_associated.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace NOSPD;

namespace {

// a grid family of horizon 3.0003 spacings (dim 2 or 3), bond-associated
// radius ratio * horizon, weights 1/|xi|
BondPattern grid_pattern(int dim, double ratio, HSForm form)
{
  const double delta = 3.0003;
  std::vector<double> b, w, v;
  std::vector<int64_t> key;
  const int zr = dim == 3 ? 3 : 0;
  for (int z = -zr; z <= zr; z++)
    for (int y = -3; y <= 3; y++)
      for (int x = -3; x <= 3; x++) {
        const int r2 = x * x + y * y + z * z;
        if (r2 == 0 || r2 > delta * delta) continue;
        b.insert(b.end(), {(double) x, (double) y, (double) z});
        key.insert(key.end(), {x, y, z});
        w.push_back(1.0 / std::sqrt((double) r2));
        v.push_back(1.0);
      }
  BondPattern p;
  build_pattern(p, dim, (int) w.size(), b.data(), w.data(), v.data(), key, ratio * delta, form,
                1e-8);
  return p;
}

// S_j for random rows X by the program (if built) or the runs, and one by one
template <int DIM> void check_sums(const BondPattern &p)
{
  constexpr int NC = DIM * DIM;
  using RL = RowLayout<DIM, 1>;
  const int n = p.n;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<double> X(NC * n);
  for (double &x : X) x = U(rng);
  StateScratch s;
  s.reserve(n, std::max(n, p.program.nrow), 1);
  double *w = s.main_rows();
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < NC; ++c) {
      if (c < RL::NM) w[RL::RM * k + c] = X[NC * k + c];
      else s.side[k] = X[NC * k + c];
    }
  std::vector<double> out(NC * n, 0.0);
  bond_sums<DIM, 1>(p, s, out.data());
  const auto sets = member_sets(p);
  long members = 0;
  for (int j = 0; j < n; ++j) {
    for (int c = 0; c < NC; ++c) {
      double ref = 0.0, mag = 0.0;
      for (int k : sets[j]) {
        ref += X[NC * k + c];
        mag += std::abs(X[NC * k + c]);
      }
      EXPECT_NEAR(out[NC * j + c], ref, 1e-14 * mag) << "slot " << j << " value " << c;
    }
    members += (long) sets[j].size();
  }
  EXPECT_EQ(members, p.members);
}

}    // namespace

// the program of a 3D grid family (the interior of a cubic lattice) and
// of a 2D one, with bond-associated horizons of 1 and 0.6 times the
// horizon; the same sums by the runs
TEST(SumProgram, EqualsMemberSums)
{
  for (double ratio : {1.0, 0.6}) {
    BondPattern p3 = grid_pattern(3, ratio, HSForm::II), p2 = grid_pattern(2, ratio, HSForm::II);
    ASSERT_FALSE(p3.program.ready());
    check_sums<3>(p3);    // runs
    check_sums<2>(p2);
    p3.program = build_sum_program(member_sets(p3), p3.n);
    p2.program = build_sum_program(member_sets(p2), p2.n);
    ASSERT_TRUE(p3.program.ready());
    ASSERT_TRUE(p2.program.ready());
    check_sums<3>(p3);    // program
    check_sums<2>(p2);
  }
}

// the program shares partial sums: far fewer additions than members
TEST(SumProgram, SharesPartialSums)
{
  BondPattern p = grid_pattern(3, 1.0, HSForm::II);
  const SumProgram pg = build_sum_program(member_sets(p), p.n);
  long adds = 0;
  for (size_t q = 0; q < pg.code.size();) {
    if (pg.code[q] != SumProgram::OUTPUT) {
      adds++;
      q += 4;
    } else {
      adds += pg.code[q + 2] - 1;
      q += 4 + ((pg.code[q + 2] + 3) & ~3);
    }
  }
  EXPECT_LT(adds, p.members / 4) << "members " << p.members;
}

// a whole family (Form I and II, small strain and finite strain) gives
// the same force state with the program as with the runs
TEST(SumProgram, FamilyEvaluationAgreesWithRuns)
{
  Lame m = Lame::from_young(200e9, 0.3);
  for (HSForm form : {HSForm::I, HSForm::II})
    for (Law law : {Law::SMALL, Law::SVK}) {
      BondPattern runs = grid_pattern(3, 1.0, form), prog = runs;
      prog.program = build_sum_program(member_sets(prog), prog.n);
      const LinearLaw lin = probe_linear_law(law, Plane::NONE, m, 3);
      std::mt19937 rng(9);
      std::uniform_real_distribution<double> U(-1e-3, 1e-3);
      std::vector<double> u(3 * runs.n), t1(3 * runs.n), t2(3 * runs.n);
      for (double &x : u) x = U(rng);
      StateScratch s;
      StateOutput o1, o2;
      ASSERT_TRUE(evaluate_family<3>(runs, form, law, Plane::NONE, m, lin, true, u.data(),
                                     t1.data(), s, o1));
      ASSERT_TRUE(evaluate_family<3>(prog, form, law, Plane::NONE, m, lin, true, u.data(),
                                     t2.data(), s, o2));
      double tmax = 0.0;
      for (double x : t1) tmax = std::max(tmax, std::abs(x));
      ASSERT_GT(tmax, 0.0);
      for (int k = 0; k < 3 * runs.n; ++k) EXPECT_NEAR(t2[k], t1[k], 1e-13 * tmax);
      EXPECT_NEAR(o2.W, o1.W, 1e-13 * std::abs(o1.W));
    }
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the bond-associated sums
   (nospd_bond_associated.h): the sum program a pattern shared by many
   families gets, and the prefix-sum runs every pattern has, against the
   member lists summed one by one; and a family evaluated with the program
   against the same family evaluated with the runs; and the rows of the
   stable time step's stiffness bound (family_row_bounds) against the
   family's exact operator.
------------------------------------------------------------------------- */

#include "nospd_bond_associated.h"
#include "nospd_stencil.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace NOSPD;

namespace {

// a grid family of horizon 3.0003 spacings (dim 2 or 3), bond-associated
// radius ratio * horizon, weights 1/|xi|; zmin 0: the half above a surface;
// jitter > 0: each offset moved by up to that fraction of the spacing
BondPattern grid_pattern(int dim, double ratio, HSForm form, int zmin = -3, double jitter = 0.0)
{
  const double delta = 3.0003;
  std::vector<double> b, w, v;
  std::vector<int64_t> key;
  const int zr = dim == 3 ? 3 : 0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> J(-jitter, jitter);
  for (int z = std::max(-zr, dim == 3 ? zmin : 0); z <= zr; z++)
    for (int y = -3; y <= 3; y++)
      for (int x = -3; x <= 3; x++) {
        const int r2 = x * x + y * y + z * z;
        if (r2 == 0 || r2 > delta * delta) continue;
        if (jitter > 0.0)
          b.insert(b.end(), {x + J(rng), y + J(rng), dim == 3 ? z + J(rng) : 0.0});
        else
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

/* ----------------------------------------------------------------------
   The stable time step bound's rows (family_row_bounds) bound the family's
   exact linear operator: the blocks A_km of its force state read off the
   family evaluation (family_operator, one evaluation per unit
   displacement), the force on member k being w_k t_k = w_k sum_m A_km
   (u_m - u_i) and on the centre the sum of those.  Per point, the sum over
   the displacements of the blocks' 2-norms must stay below |C| times the
   row: whole, cut (half-space, with singular bond families at ratio 0.34),
   one-sided, all-singular and jittered families, both forms, 2D and 3D.
------------------------------------------------------------------------- */

namespace {
double norm2(const Mat3 &A)
{
  return Eigen::JacobiSVD<Mat3>(A).singularValues()(0);
}

template <int DIM> void check_row_bounds(const BondPattern &p, HSForm form, double &tightest)
{
  const Lame m = Lame::from_young(200e9, 0.3);
  const LinearLaw lin = probe_linear_law(Law::SMALL, Plane::STRAIN, m, DIM);
  ASSERT_TRUE(lin.ok);
  std::vector<double> A, rows;
  ASSERT_TRUE(family_operator<DIM>(p, form, Law::SMALL, Plane::STRAIN, m, lin, 1.0, A));
  family_row_bounds<DIM>(p, form, rows);
  const int n = p.n;
  ASSERT_EQ((int) rows.size(), n + 1);
  const double cnorm = DIM * m.lambda + 2.0 * m.mu;
  auto block = [&](int k, int mm) {
    Mat3 B;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) B(r, c) = A[((size_t) k * n + mm) * 9 + 3 * r + c];
    return B;
  };
  // members
  for (int k = 0; k < n; ++k) {
    Mat3 self = Mat3::Zero();
    double exact = 0.0;
    for (int mm = 0; mm < n; ++mm) {
      const Mat3 B = p.w[k] * block(k, mm);
      exact += norm2(B);
      self -= B;
    }
    exact += norm2(self);
    EXPECT_LE(exact, cnorm * rows[k] * (1.0 + 1e-12)) << "member " << k;
    if (exact > 0.0) tightest = std::min(tightest, cnorm * rows[k] / exact);
  }
  // the centre
  Mat3 self = Mat3::Zero();
  double exact = 0.0;
  for (int mm = 0; mm < n; ++mm) {
    Mat3 col = Mat3::Zero();
    for (int k = 0; k < n; ++k) col += p.w[k] * block(k, mm);
    exact += norm2(col);
    self -= col;
  }
  exact += norm2(self);
  EXPECT_LE(exact, cnorm * rows[n] * (1.0 + 1e-12)) << "centre";
  tightest = std::min(tightest, cnorm * rows[n] / exact);
}
}    // namespace

TEST(RowBounds, BoundTheFamilyOperator)
{
  for (HSForm form : {HSForm::I, HSForm::II}) {
    double tightest = 1e300;
    const BondPattern whole = grid_pattern(3, 1.0, form);
    check_row_bounds<3>(whole, form, tightest);
    const BondPattern cut = grid_pattern(3, 0.34, form, 0);
    EXPECT_GT(cut.nsingular, 0);    // the singular bond families' terms are exercised
    check_row_bounds<3>(cut, form, tightest);
    check_row_bounds<3>(grid_pattern(3, 1.0, form, -1, 0.3), form, tightest);
    // every bond family singular (r below the spacing: h_ij = {j}), and a
    // family all on one side of its centre (the centre's column dominates)
    const BondPattern all_singular = grid_pattern(3, 0.2, form);
    EXPECT_EQ(all_singular.nsingular, all_singular.n);
    check_row_bounds<3>(all_singular, form, tightest);
    check_row_bounds<3>(grid_pattern(3, 1.0, form, 1), form, tightest);
    check_row_bounds<2>(grid_pattern(2, 1.0, form), form, tightest);
    check_row_bounds<2>(grid_pattern(2, 0.8, form, 0, 0.3), form, tightest);
    // the bound is not slack everywhere: some row within 2.5 times the exact
    printf("  form %d: tightest row %.3f times the exact sum\n", (int) form, tightest);
    EXPECT_LT(tightest, 2.5);
  }
}

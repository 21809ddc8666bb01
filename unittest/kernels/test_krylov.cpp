/* The Newton minimizer's linear algebra (nospd_krylov.h,
   nospd_surrogate.h): GMRES and CG solve against a dense direct solve, also
   restarted and preconditioned; GMRES's reported residual is the true one;
   CG flags an indefinite operator; a non-finite operator stops both at
   once.  The bond-based surrogate is symmetric,
   positive definite with its held rows decoupled, exerts no force on
   interior points under an affine displacement (a patch test), and its
   direct factor inverts it. */

#include "nospd_krylov.h"
#include "nospd_surrogate.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {
using Eigen::MatrixXd;
using Eigen::VectorXd;

struct Dense {
  const MatrixXd &A;
  void operator()(const double *v, double *out) const
  {
    Eigen::Map<VectorXd>(out, A.rows()) = A * Eigen::Map<const VectorXd>(v, A.cols());
  }
};
auto dot = [](int n) {
  return [n](const double *a, const double *b) {
    double s = 0.0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
  };
};

MatrixXd nonsymmetric(int n, unsigned seed)
{
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatrixXd A(n, n);
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) A(i, j) = u(g) / std::sqrt(n);
  for (int i = 0; i < n; i++) A(i, i) += 2.0 + i * 0.05;
  return A;
}

MatrixXd laplacian(int n)
{
  MatrixXd A = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; i++) {
    A(i, i) = 2.0 + 1e-3 * i;
    if (i > 0) A(i, i - 1) = -1.0;
    if (i + 1 < n) A(i, i + 1) = -1.0;
  }
  return A;
}
}    // namespace

TEST(Krylov, GmresMatchesDirectSolveWithRestartsAndJacobi)
{
  const int n = 60;
  const MatrixXd A = nonsymmetric(n, 7);
  VectorXd b = VectorXd::LinSpaced(n, -1.0, 2.0);
  const VectorXd exact = A.partialPivLu().solve(b);
  for (int restart : {5, 20, 80}) {
    VectorXd x(n);
    auto jacobi = [&](const double *r, double *z) {
      for (int i = 0; i < n; i++) z[i] = r[i] / A(i, i);
    };
    const auto res = NOSPD::gmres(n, b.data(), x.data(), Dense{A}, jacobi, dot(n), 1e-12, restart, 2000);
    EXPECT_TRUE(res.converged) << "restart " << restart;
    EXPECT_LT((x - exact).norm() / exact.norm(), 1e-10) << "restart " << restart;
    // the reported residual is the true one
    EXPECT_NEAR(res.residual, (b - A * x).norm(), 1e-9 * b.norm());
  }
}

TEST(Krylov, CgMatchesDirectSolveAndStopsAtItsTolerance)
{
  const int n = 100;
  const MatrixXd A = laplacian(n);
  VectorXd b = VectorXd::Ones(n);
  const VectorXd exact = A.llt().solve(b);
  VectorXd x(n);
  auto none = [&](const double *r, double *z) {
    for (int i = 0; i < n; i++) z[i] = r[i];
  };
  auto res = NOSPD::cg(n, b.data(), x.data(), Dense{A}, none, dot(n), 1e-12, 1000);
  EXPECT_TRUE(res.converged);
  EXPECT_LE(res.iterations, n + 5);
  EXPECT_LT((x - exact).norm() / exact.norm(), 1e-9);
  // a loose tolerance stops early, with the residual it claims
  res = NOSPD::cg(n, b.data(), x.data(), Dense{A}, none, dot(n), 1e-2, 1000);
  EXPECT_TRUE(res.converged);
  EXPECT_LT(res.iterations, 60);
  EXPECT_LE((b - A * x).norm(), 1e-2 * b.norm() * (1 + 1e-9));
}

TEST(Krylov, CgFlagsAnIndefiniteOperator)
{
  const int n = 10;
  MatrixXd A = laplacian(n);
  A(0, 0) = -5.0;
  VectorXd b = VectorXd::Zero(n);
  b(0) = 1.0;
  VectorXd x(n);
  auto none = [&](const double *r, double *z) {
    for (int i = 0; i < n; i++) z[i] = r[i];
  };
  const auto res = NOSPD::cg(n, b.data(), x.data(), Dense{A}, none, dot(n), 1e-12, 100);
  EXPECT_TRUE(res.indefinite);
  EXPECT_FALSE(res.converged);
}

TEST(Krylov, ZeroRightHandSideIsSolvedWithoutApplications)
{
  const int n = 4;
  const MatrixXd A = laplacian(n);
  VectorXd b = VectorXd::Zero(n), x = VectorXd::Ones(n);
  auto none = [&](const double *r, double *z) {
    for (int i = 0; i < n; i++) z[i] = r[i];
  };
  const auto g = NOSPD::gmres(n, b.data(), x.data(), Dense{A}, none, dot(n), 1e-8, 10, 10);
  EXPECT_TRUE(g.converged);
  EXPECT_EQ(g.iterations, 0);
  EXPECT_EQ(x.norm(), 0.0);
}

namespace {
// an n x n square lattice (2D, z held), bonds within 2.01 dx
struct Square {
  int n;
  double dx = 1e-3;
  std::vector<NOSPD::SurrogatePreconditioner::Bond> bonds;
  std::vector<double> mask;
  std::vector<std::array<double, 3>> x;
  Square(int n_, bool hold_corner) : n(n_)
  {
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++) x.push_back({i * dx, j * dx, 0.0});
    for (int a = 0; a < n * n; a++)
      for (int b = 0; b < n * n; b++) {
        if (a == b) continue;
        NOSPD::SurrogatePreconditioner::Bond bd;
        bd.i = a;
        bd.j = b;
        for (int k = 0; k < 3; k++) bd.xi[k] = x[b][k] - x[a][k];
        const double l = std::sqrt(bd.xi[0] * bd.xi[0] + bd.xi[1] * bd.xi[1]);
        if (l > 2.01 * dx) continue;
        bd.c = 3.0e20 * dx * dx * dx;
        bonds.push_back(bd);
      }
    mask.assign(3 * n * n, 1.0);
    for (int a = 0; a < n * n; a++) mask[3 * a + 2] = 0.0;
    if (hold_corner) mask[0] = mask[1] = mask[3 * (n - 1) + 1] = 0.0;
  }
};
}    // namespace

TEST(Surrogate, SymmetricPositiveDefiniteAndInvertedByItsFactor)
{
  Square sq(6, true);
  NOSPD::SurrogatePreconditioner P;
  ASSERT_TRUE(P.build(36, sq.bonds, sq.mask.data(), NOSPD::SurrogatePreconditioner::Kind::DIRECT));
  EXPECT_EQ(P.kind(), NOSPD::SurrogatePreconditioner::Kind::DIRECT);
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int N = 108;
  std::vector<double> a(N), b(N), Pa(N), Pb(N), z(N);
  for (int k = 0; k < N; k++) {
    a[k] = u(g) * sq.mask[k];
    b[k] = u(g) * sq.mask[k];
  }
  P.multiply(a.data(), Pa.data());
  P.multiply(b.data(), Pb.data());
  double aPb = 0, bPa = 0, aPa = 0, scale = 0;
  for (int k = 0; k < N; k++) {
    aPb += a[k] * Pb[k];
    bPa += b[k] * Pa[k];
    aPa += a[k] * Pa[k];
    scale += std::fabs(a[k] * Pb[k]);
  }
  EXPECT_NEAR(aPb, bPa, 1e-12 * scale);
  EXPECT_GT(aPa, 0.0);
  // held components are decoupled: a free vector gives nothing on them
  for (int k = 0; k < N; k++)
    if (sq.mask[k] == 0.0) {
      EXPECT_EQ(Pa[k], 0.0) << k;
    }
  P.apply(Pa.data(), z.data());
  double err = 0, norm = 0;
  for (int k = 0; k < N; k++) {
    err = std::max(err, std::fabs(z[k] - a[k]));
    norm = std::max(norm, std::fabs(a[k]));
  }
  EXPECT_LT(err, 1e-10 * norm);
}

TEST(Surrogate, AffineDisplacementLeavesInteriorPointsUnloaded)
{
  Square sq(9, false);
  NOSPD::SurrogatePreconditioner P;
  ASSERT_TRUE(P.build(81, sq.bonds, sq.mask.data(),
                      NOSPD::SurrogatePreconditioner::Kind::INCOMPLETE));
  const double H[2][2] = {{1e-3, 4e-4}, {-2e-4, 7e-4}};
  std::vector<double> u(243, 0.0), f(243);
  for (int a = 0; a < 81; a++)
    for (int d = 0; d < 2; d++) u[3 * a + d] = H[d][0] * sq.x[a][0] + H[d][1] * sq.x[a][1];
  P.multiply(u.data(), f.data());
  double interior = 0.0, edge = 0.0;
  for (int j = 0; j < 9; j++)
    for (int i = 0; i < 9; i++) {
      const int a = 9 * j + i;
      const double m = std::hypot(f[3 * a], f[3 * a + 1]);
      if (i >= 2 && i <= 6 && j >= 2 && j <= 6) interior = std::max(interior, m);
      else edge = std::max(edge, m);
    }
  EXPECT_GT(edge, 0.0);
  EXPECT_LT(interior, 1e-12 * edge);
}

TEST(Krylov, NonFiniteOperatorStopsAtOnce)
{
  const int n = 8;
  int applications = 0;
  auto nan_op = [&](const double *, double *out) {
    applications++;
    for (int i = 0; i < n; i++) out[i] = std::nan("");
  };
  auto none = [&](const double *r, double *z) {
    for (int i = 0; i < n; i++) z[i] = r[i];
  };
  std::vector<double> b(n, 1.0), x(n);
  const auto g = NOSPD::gmres(n, b.data(), x.data(), nan_op, none, dot(n), 1e-8, 20, 1000);
  EXPECT_FALSE(g.converged);
  EXPECT_LE(applications, 2);
  applications = 0;
  const auto c = NOSPD::cg(n, b.data(), x.data(), nan_op, none, dot(n), 1e-8, 1000);
  EXPECT_FALSE(c.converged);
  EXPECT_LE(applications, 2);
}

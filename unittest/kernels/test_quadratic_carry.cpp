/* Silling's springs on the quadratic fit of a family that lost bonds: the
   carried curvature (nospd_quadratic_carry.h).  Written from the energy
       E = 1/2 sum_j w_j |z_j|^2,  z = U - H xi - (I + H) F_c G psi(xi),
   evaluated here directly over the bonds (H the least-squares linear fit,
   psi the quadratic basis made w-orthogonal to the linear one): the
   kernel's force state is its gradient (central differences), its energy
   this sum; a break loses no more than it had (the energy after <= before)
   and starts from the last intact fit's curvature; a rigid rotation
   afterwards keeps the energy; without a carried curvature the springs
   are the linear fit's. */

#include "nospd_quadratic_carry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using NOSPD::Mat3;
using NOSPD::Mat36;
using NOSPD::Vec3;

namespace {

using Vec9 = Eigen::Matrix<double, 9, 1>;

struct Family {
  std::vector<Vec3> xi, U;
  std::vector<double> w;
  std::vector<bool> cut;
};

Vec9 phi(const Vec3 &x)
{
  Vec9 p;
  p << x(0), x(1), x(2), 0, 0, 0, 0, 0, 0;
  NOSPD::quadratic_terms(x.data(), p.data() + 3);
  return p;
}

// a grid family (spacing 1, horizon 3.015; 2D: the z = 0 plane), weights
// 1/|xi|, displaced by an affine part, a curvature and noise
Family make_family(unsigned seed, int dim = 3)
{
  Family f;
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3 A = Mat3::Zero();
  for (int r = 0; r < dim; r++)
    for (int c = 0; c < dim; c++) A(r, c) = 0.05 * u(gen);
  for (int a = -3; a <= 3; a++)
    for (int b = -3; b <= 3; b++)
      for (int c = (dim == 3 ? -3 : 0); c <= (dim == 3 ? 3 : 0); c++) {
        const Vec3 x(a, b, c);
        if (x.norm() == 0.0 || x.norm() > 3.015) continue;
        Vec3 y = A * x;
        y(0) += 0.01 * x(1) * x(1) + 0.004 * x(0) * x(1);
        y(1) += 0.006 * x(0) * x(0);
        if (dim == 3) y(2) += 0.008 * x(0) * x(2);
        for (int d = 0; d < dim; d++) y(d) += 0.002 * u(gen);
        f.xi.push_back(x);
        f.U.push_back(y);
        f.w.push_back(1.0 / x.norm());
        f.cut.push_back(false);
      }
  return f;
}

// K (2D: the out-of-plane placeholder 1), K2, N2 = sum w U phi^T, over the bonds left
struct Sums {
  Mat3 K, Kinv, H;
  Eigen::Matrix<double, 9, 9> K2;
  Eigen::Matrix<double, 3, 9> N2;
};

Sums sums(const Family &f, int dim = 3)
{
  Sums s;
  s.K.setZero();
  s.K2.setZero();
  s.N2.setZero();
  for (size_t b = 0; b < f.xi.size(); b++) {
    if (f.cut[b]) continue;
    const Vec9 p = phi(f.xi[b]);
    s.K += f.w[b] * f.xi[b] * f.xi[b].transpose();
    s.K2 += f.w[b] * p * p.transpose();
    s.N2 += f.w[b] * f.U[b] * p.transpose();
  }
  if (dim == 2) s.K(2, 2) = 1.0;
  s.Kinv = s.K.inverse();
  s.H = s.N2.leftCols<3>() * s.Kinv;
  return s;
}

// the energy, bond by bond
double energy(const Family &f, const Mat36 &FcG, int dim = 3)
{
  const Sums s = sums(f, dim);
  const Eigen::Matrix<double, 6, 3> MK = s.K2.block<6, 3>(3, 0) * s.Kinv;
  const Mat36 Q = (Mat3::Identity() + s.H) * FcG;
  double e = 0.0;
  for (size_t b = 0; b < f.xi.size(); b++) {
    if (f.cut[b]) continue;
    const Vec9 p = phi(f.xi[b]);
    const Eigen::Matrix<double, 6, 1> psi = p.tail<6>() - MK * f.xi[b];
    e += 0.5 * f.w[b] * (f.U[b] - s.H * f.xi[b] - Q * psi).squaredNorm();
  }
  return e;
}

struct Kernel {
  Mat3 H2;
  Mat36 Q;
  double e2;
};

Kernel kernel(const Family &f, const Mat36 &FcG, int dim = 3)
{
  const Sums s = sums(f, dim);
  double rec[NOSPD::QuadraticFit::RECORD];
  NOSPD::carried_quadratic_record(s.K2, s.Kinv, rec);
  double elin = 0.0;
  for (size_t b = 0; b < f.xi.size(); b++)
    if (!f.cut[b]) elin += f.w[b] * (f.U[b] - s.H * f.xi[b]).squaredNorm();
  Kernel k;
  NOSPD::carried_quadratic_spring(s.H, FcG, s.N2, rec, s.Kinv, elin, true, k.H2, k.Q, k.e2);
  return k;
}

Mat36 random_curvature(unsigned seed, int dim = 3)
{
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat36 G = Mat36::Zero();
  for (int r = 0; r < dim; r++)
    for (int c = 0; c < 6; c++) G(r, c) = 0.01 * u(gen);
  return G;
}

void cut_some(Family &f, unsigned seed, double fraction)
{
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (size_t b = 0; b < f.xi.size(); b++)
    if (f.xi[b](0) > 0.5 && u(gen) < fraction) f.cut[b] = true;    // a crack on one side
}

}    // namespace

TEST(QuadraticCarry, ForceStateIsTheEnergysGradient)
{
  for (int dim : {3, 2}) {
    Family f = make_family(7 + dim, dim);
    cut_some(f, 3, 0.5);
    Mat3 Fc = Mat3::Identity();
    Fc(0, 1) = 0.03;
    Fc(1, 0) = -0.02;
    const Mat36 FcG = Fc * random_curvature(11, dim);
    const Kernel k = kernel(f, FcG, dim);
    EXPECT_NEAR(0.5 * k.e2, energy(f, FcG, dim), 1e-12 * std::abs(k.e2)) << "dim " << dim;
    double worst = 0.0, scale = 0.0;
    const double h = 1e-6;
    for (size_t b = 0; b < f.xi.size(); b++) {
      if (f.cut[b]) continue;
      Eigen::Matrix<double, 6, 1> q;
      NOSPD::quadratic_terms(f.xi[b].data(), q.data());
      const Vec3 T = f.w[b] * (f.U[b] - k.H2 * f.xi[b] - k.Q * q);
      for (int d = 0; d < dim; d++) {
        Family p = f, m = f;
        p.U[b](d) += h;
        m.U[b](d) -= h;
        const double g = (energy(p, FcG, dim) - energy(m, FcG, dim)) / (2 * h);
        worst = std::max(worst, std::abs(g - T(d)));
        scale = std::max(scale, std::abs(T(d)));
      }
    }
    EXPECT_LT(worst, 1e-7 * scale) << "dim " << dim;
  }
}

TEST(QuadraticCarry, BreakStartsFromTheLastFitAndReleasesEnergy)
{
  for (unsigned seed : {1u, 2u, 3u}) {
    Family f = make_family(seed);
    // intact: the quadratic fit's residual energy and curvature Q_s
    const Sums s0 = sums(f);
    double rec0[NOSPD::QuadraticFit::RECORD];
    ASSERT_TRUE(NOSPD::quadratic_fit_inverse(s0.K2, rec0));
    const Eigen::Matrix<double, 3, 9> A = NOSPD::quadratic_fit(s0.N2, rec0);
    double before = 0.0;
    for (size_t b = 0; b < f.xi.size(); b++)
      before += 0.5 * f.w[b] * (f.U[b] - A * phi(f.xi[b])).squaredNorm();
    const Mat36 Qs = A.rightCols<6>();
    const Mat3 Fold = Mat3::Identity() + s0.H;
    // cut; F_c carries the refit (F_new F_c = F_old), G from Q_s
    cut_some(f, seed + 10, 0.6);
    const Sums s1 = sums(f);
    const Mat3 Fc = (Mat3::Identity() + s1.H).inverse() * Fold;
    const Mat36 G = NOSPD::carried_quadratic_start(Qs, Fold);
    const Kernel k = kernel(f, Fc * G);
    EXPECT_LT((k.Q - Qs).norm(), 1e-12 * Qs.norm());
    EXPECT_LE(0.5 * k.e2, before * (1.0 + 1e-12)) << "seed " << seed;
    // the linear fit's springs instead: loaded by the curvature
    const Kernel lin = kernel(f, Mat36::Zero());
    EXPECT_GT(lin.e2, 5.0 * k.e2) << "seed " << seed;
    EXPECT_LT((lin.H2 - s1.H).norm(), 1e-14);
    EXPECT_EQ(lin.Q.norm(), 0.0);
  }
}

TEST(QuadraticCarry, RigidRotationAfterwardsKeepsTheEnergy)
{
  Family f = make_family(5);
  cut_some(f, 6, 0.5);
  const Mat36 FcG = random_curvature(8);
  const double e = energy(f, FcG);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (size_t b = 0; b < f.xi.size(); b++) f.U[b] = R * (f.xi[b] + f.U[b]) - f.xi[b];
  const Kernel k = kernel(f, FcG);
  EXPECT_NEAR(0.5 * k.e2, e, 1e-10 * e);
  EXPECT_NEAR(energy(f, FcG), e, 1e-10 * e);
}

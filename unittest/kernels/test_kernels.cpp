/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the LAMMPS-free physics kernels.

   Every expectation below is derived from the governing equations (energy
   gradients by finite differences, frame indifference, linearization,
   Hooke's law, uniqueness of the polar decomposition, energy equivalence of
   bond-based peridynamics, Newton's third law), not copied from the kernels'
   implementation.
------------------------------------------------------------------------- */

#include "nospd_constitutive.h"
#include "nospd_stabilization.h"
#include "nospd_tensor.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace NOSPD;

namespace {

// ---------------------------------------------------------------------------
// helpers

constexpr double E_YOUNG = 2.5;    // arbitrary units; all checks are relative
constexpr double NU = 0.3;

const Law ALL_LAWS[] = {Law::SMALL, Law::COROTATIONAL, Law::SVK, Law::NEOHOOKE, Law::HENCKY};

const char *law_name(Law law)
{
  switch (law) {
    case Law::SMALL: return "SMALL";
    case Law::COROTATIONAL: return "COROTATIONAL";
    case Law::SVK: return "SVK";
    case Law::NEOHOOKE: return "NEOHOOKE";
    case Law::HENCKY: return "HENCKY";
    default: break;    // user laws are tested in test_formula.cpp, test_umat.cpp
  }
  return "?";
}

double maxabs(const Mat3 &A)
{
  return A.cwiseAbs().maxCoeff();
}

// max |A - B| / max |B|
double relerr(const Mat3 &A, const Mat3 &B)
{
  const double s = maxabs(B);
  return maxabs(A - B) / (s > 0.0 ? s : 1.0);
}

struct Rng {
  std::mt19937_64 gen;
  explicit Rng(unsigned long long seed) : gen(seed) {}
  double uniform(double a = -1.0, double b = 1.0)
  {
    return std::uniform_real_distribution<double>(a, b)(gen);
  }
  double normal() { return std::normal_distribution<double>(0.0, 1.0)(gen); }
  Mat3 matrix(double scale)
  {
    Mat3 m;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m(r, c) = scale * uniform();
    return m;
  }
  Vec3 vector(double scale)
  {
    return Vec3(scale * uniform(), scale * uniform(), scale * uniform());
  }
  // uniformly distributed rotation from a normalized Gaussian quaternion
  Mat3 rotation()
  {
    Eigen::Quaterniond q(normal(), normal(), normal(), normal());
    q.normalize();
    return q.toRotationMatrix();
  }
};

Mat3 rotation(const Vec3 &axis, double degrees)
{
  return Eigen::AngleAxisd(degrees * PI / 180.0, axis.normalized()).toRotationMatrix();
}

// symmetric positive definite stretch with principal values s and principal axes V
Mat3 stretch(const Mat3 &V, double s0, double s1, double s2)
{
  return V * Vec3(s0, s1, s2).asDiagonal() * V.transpose();
}

// deformation gradient near the identity (|F - I| <= 0.08, det F > 0)
Mat3 near_identity_F(Rng &rng)
{
  return Mat3::Identity() + rng.matrix(0.08);
}

// a moderately large deformation: principal stretches 1.3, 0.8, 1.15 on
// oblique axes, followed by a 50 degree rotation about an oblique axis
Mat3 large_F()
{
  const Mat3 V = rotation(Vec3(0.3, -1.0, 0.4), 37.0);
  const Mat3 Q = rotation(Vec3(1.0, 2.0, -0.5), 50.0);
  return Q * stretch(V, 1.3, 0.8, 1.15);
}

double energy(Law law, const Lame &m, const Mat3 &F)
{
  Mat3 P;
  double W = 0.0;
  EXPECT_TRUE(first_piola_3d(law, m, F, P, W)) << law_name(law);
  return W;
}

Mat3 piola(Law law, const Lame &m, const Mat3 &F)
{
  Mat3 P;
  double W = 0.0;
  EXPECT_TRUE(first_piola_3d(law, m, F, P, W)) << law_name(law);
  return P;
}

// dW/dF by central differences with step h relative to |F|
Mat3 numerical_gradient(const std::function<double(const Mat3 &)> &W, const Mat3 &F,
                        int nrows = 3, int ncols = 3)
{
  const double h = 1e-6 * std::max(1.0, maxabs(F));
  Mat3 G = Mat3::Zero();
  for (int r = 0; r < nrows; ++r)
    for (int c = 0; c < ncols; ++c) {
      Mat3 Fp = F, Fm = F;
      Fp(r, c) += h;
      Fm(r, c) -= h;
      G(r, c) = (W(Fp) - W(Fm)) / (2.0 * h);
    }
  return G;
}

// isotropic elasticity tensor C_ijkl = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk)
double d(int i, int j)
{
  return i == j ? 1.0 : 0.0;
}
double Ciso(double lambda, double mu, int i, int j, int k, int l)
{
  return lambda * d(i, j) * d(k, l) + mu * (d(i, k) * d(j, l) + d(i, l) * d(j, k));
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n)
void gauss_legendre(int n, std::vector<double> &x, std::vector<double> &w)
{
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(PI * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

/* Bond-based (prototype microelastic brittle) energy density of a point of a
   3D body under a homogeneous deformation:
       W = 1/2 * integral_{|xi| < delta} w(xi) dV_xi,   w = 1/2 c s^2 |xi|
   (the factor 1/2 because each bond's energy is shared by its two ends), s
   the bond stretch.  Full spherical quadrature: Gauss-Legendre in r and in
   cos(theta), the trapezoidal (exact for trigonometric polynomials) rule in
   phi.  `stretch` maps a bond vector xi to its stretch. */
double bond_energy_density_3d(double c, double delta,
                              const std::function<double(const Vec3 &)> &stretch)
{
  std::vector<double> xr, wr, xm, wm;
  gauss_legendre(6, xr, wr);
  gauss_legendre(24, xm, wm);
  const int nphi = 48;
  double sum = 0.0;
  for (size_t a = 0; a < xr.size(); ++a) {
    const double r = 0.5 * delta * (1.0 + xr[a]);
    const double dr = 0.5 * delta * wr[a];
    for (size_t b = 0; b < xm.size(); ++b) {
      const double ct = xm[b], st = std::sqrt(1.0 - ct * ct);
      for (int k = 0; k < nphi; ++k) {
        const double phi = 2.0 * PI * k / nphi;
        const Vec3 xi = r * Vec3(st * std::cos(phi), st * std::sin(phi), ct);
        const double dV = r * r * dr * wm[b] * (2.0 * PI / nphi);
        const double s = stretch(xi);
        sum += 0.5 * c * s * s * r * dV;
      }
    }
  }
  return 0.5 * sum;
}

// The 2D analogue on a disk of radius delta, volume element t dA.
double bond_energy_density_2d(double c, double delta, double t,
                              const std::function<double(const Vec3 &)> &stretch)
{
  std::vector<double> xr, wr;
  gauss_legendre(6, xr, wr);
  const int ntheta = 64;
  double sum = 0.0;
  for (size_t a = 0; a < xr.size(); ++a) {
    const double r = 0.5 * delta * (1.0 + xr[a]);
    const double dr = 0.5 * delta * wr[a];
    for (int k = 0; k < ntheta; ++k) {
      const double th = 2.0 * PI * k / ntheta;
      const Vec3 xi = r * Vec3(std::cos(th), std::sin(th), 0.0);
      const double dV = t * r * dr * (2.0 * PI / ntheta);
      const double s = stretch(xi);
      sum += 0.5 * c * s * s * r * dV;
    }
  }
  return 0.5 * sum;
}

// exact bond stretch (|F xi| - |xi|) / |xi| under deformation gradient F
std::function<double(const Vec3 &)> exact_stretch(const Mat3 &F)
{
  return [F](const Vec3 &xi) { return ((F * xi).norm() - xi.norm()) / xi.norm(); };
}

// linearized bond stretch xihat . eps xihat under small strain eps
std::function<double(const Vec3 &)> linear_stretch(const Mat3 &eps)
{
  return [eps](const Vec3 &xi) { return xi.dot(eps * xi) / xi.squaredNorm(); };
}

// shape tensor K = sum xi xi^T V of a family of bonds (unit volumes)
Mat3 shape_tensor(const std::vector<Vec3> &family)
{
  Mat3 K = Mat3::Zero();
  for (const Vec3 &xi : family) K += xi * xi.transpose();
  return K;
}

}    // namespace

// ===========================================================================
// nospd_tensor.h

TEST(Tensor, LoadStoreAreRowMajorAndInverse)
{
  const double p[9] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  const Mat3 m = load(p);
  EXPECT_EQ(m(0, 1), 2.0);    // row 0, column 1 is the second entry
  EXPECT_EQ(m(1, 0), 4.0);
  EXPECT_EQ(m(2, 1), 8.0);
  double q[9];
  store(m, q);
  for (int k = 0; k < 9; ++k) EXPECT_EQ(q[k], p[k]);
}

TEST(Tensor, ShapeConditioningIsOneForIsotropicFamilies)
{
  // 3D simple cubic family, first and second neighbours: cubic symmetry makes
  // the second-moment tensor isotropic, K = k I
  std::vector<Vec3> cubic;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k) {
        const int n2 = i * i + j * j + k * k;
        if (n2 == 1 || n2 == 2) cubic.emplace_back(0.1 * i, 0.1 * j, 0.1 * k);
      }
  const Mat3 K3 = shape_tensor(cubic);
  EXPECT_NEAR(shape_conditioning(K3, 3), 1.0, 1e-14);
  // a dimensionless measure: independent of the lattice spacing and volumes
  EXPECT_NEAR(shape_conditioning(1e-9 * K3, 3), 1.0, 1e-14);
  EXPECT_NEAR(shape_conditioning(7.3 * Mat3::Identity(), 3), 1.0, 1e-14);

  // 2D hexagonal family (6 neighbours at 60 degrees), K(2,2) = 1 placeholder
  std::vector<Vec3> hex;
  for (int k = 0; k < 6; ++k)
    hex.emplace_back(0.02 * std::cos(k * PI / 3.0), 0.02 * std::sin(k * PI / 3.0), 0.0);
  Mat3 K2 = shape_tensor(hex);
  K2(2, 2) = 1.0;
  EXPECT_NEAR(shape_conditioning(K2, 2), 1.0, 1e-14);

  // anisotropic families are below 1 (AM-GM on the eigenvalues)
  const Mat3 Kani = Vec3(1.0, 2.0, 3.0).asDiagonal();
  EXPECT_LT(shape_conditioning(Kani, 3), 1.0);
  EXPECT_GT(shape_conditioning(Kani, 3), 0.0);
}

TEST(Tensor, SafeInverseRejectsCoplanarFamily3D)
{
  // all bonds in the plane n . xi = 0 with an oblique normal n: K n = 0
  const Vec3 n = Vec3(1.0, -2.0, 0.5).normalized();
  const Vec3 a = n.unitOrthogonal(), b = n.cross(a);
  std::vector<Vec3> family;
  Rng rng(11);
  for (int k = 0; k < 20; ++k) family.push_back(rng.uniform() * a + rng.uniform() * b);
  const Mat3 K = shape_tensor(family);
  EXPECT_LT(shape_conditioning(K, 3), 1e-12);
  Mat3 Kinv = Mat3::Constant(3.0);
  EXPECT_FALSE(safe_inverse(K, 3, 1e-8, Kinv));
  EXPECT_EQ(maxabs(Kinv), 0.0);
}

TEST(Tensor, SafeInverseRejectsCollinearFamily2D)
{
  // in-plane bonds all along one line; the out-of-plane placeholder K(2,2) = 1
  // must not hide the singular in-plane block
  const Vec3 e = Vec3(1.0, 1.0, 0.0).normalized();
  std::vector<Vec3> family;
  for (int k = 1; k <= 4; ++k) {
    family.push_back(0.1 * k * e);
    family.push_back(-0.1 * k * e);
  }
  Mat3 K = shape_tensor(family);
  K(2, 2) = 1.0;
  EXPECT_LT(shape_conditioning(K, 2), 1e-12);
  Mat3 Kinv = Mat3::Constant(3.0);
  EXPECT_FALSE(safe_inverse(K, 2, 1e-8, Kinv));
  EXPECT_EQ(maxabs(Kinv), 0.0);
}

TEST(Tensor, SafeInverseOfWellConditionedFamilies)
{
  Rng rng(12);
  // 3D: random bonds in a ball
  std::vector<Vec3> family;
  for (int k = 0; k < 40; ++k) family.push_back(rng.vector(0.3));
  const Mat3 K = shape_tensor(family);
  Mat3 Kinv;
  ASSERT_TRUE(safe_inverse(K, 3, 1e-8, Kinv));
  EXPECT_LT(maxabs(K * Kinv - Mat3::Identity()), 1e-12);
  EXPECT_LT(maxabs(Kinv * K - Mat3::Identity()), 1e-12);

  // 2D: random in-plane bonds, placeholder K(2,2) = 1
  std::vector<Vec3> fam2;
  for (int k = 0; k < 12; ++k) fam2.emplace_back(rng.uniform(), rng.uniform(), 0.0);
  Mat3 K2 = shape_tensor(fam2);
  K2(2, 2) = 1.0;
  ASSERT_TRUE(safe_inverse(K2, 2, 1e-8, Kinv));
  EXPECT_LT(maxabs(K2 * Kinv - Mat3::Identity()), 1e-12);
}

// ---------------------------------------------------------------------------
// polar decomposition F = R U: R proper orthogonal, U symmetric positive
// definite.  For det F > 0 the factors are unique, so a F built as Q Utrue
// must give back exactly Q and Utrue.

namespace {
void check_polar(const Mat3 &F, const char *what)
{
  SCOPED_TRACE(what);
  Mat3 R, U;
  ASSERT_TRUE(polar_decomposition(F, R, U));
  const double tol = 1e-12 * std::max(1.0, maxabs(F));
  EXPECT_LT(maxabs(R.transpose() * R - Mat3::Identity()), 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_LT(maxabs(U - U.transpose()), tol);
  Eigen::SelfAdjointEigenSolver<Mat3> es(U);
  EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
  EXPECT_LT(maxabs(R * U - F), tol);
  // U^2 = F^T F (right Cauchy-Green tensor)
  EXPECT_LT(maxabs(U * U - F.transpose() * F), tol * std::max(1.0, maxabs(F)));
}

void check_polar_known(const Mat3 &Q, const Mat3 &Utrue, const char *what)
{
  SCOPED_TRACE(what);
  const Mat3 F = Q * Utrue;
  check_polar(F, what);
  Mat3 R, U;
  ASSERT_TRUE(polar_decomposition(F, R, U));
  EXPECT_LT(maxabs(R - Q), 1e-12);
  EXPECT_LT(maxabs(U - Utrue), 1e-12 * maxabs(Utrue));
}
}    // namespace

TEST(Polar, NearIdentity)
{
  Rng rng(21);
  for (int k = 0; k < 10; ++k) check_polar(near_identity_F(rng), "random near identity");
  check_polar(Mat3::Identity(), "identity");
}

TEST(Polar, LargeRotation170Degrees)
{
  const Mat3 Q = rotation(Vec3(1.0, 2.0, -0.5), 170.0);
  const Mat3 V = rotation(Vec3(-0.2, 0.7, 1.0), 25.0);
  check_polar_known(Q, Mat3::Identity(), "pure 170 degree rotation");
  check_polar_known(Q, stretch(V, 1.3, 0.8, 1.1), "170 degree rotation of a stretch");
  check_polar_known(rotation(Vec3(0.0, 0.0, 1.0), 179.0), stretch(V, 1.2, 0.9, 1.0),
                    "179 degrees about z");
}

TEST(Polar, StretchedAndSheared)
{
  const Mat3 V = rotation(Vec3(1.0, 1.0, 1.0), 40.0);
  check_polar_known(Mat3::Identity(), stretch(V, 1.3, 0.7, 1.2), "pure stretch");
  check_polar_known(rotation(Vec3(0.5, -1.0, 0.2), 60.0), stretch(V, 2.5, 0.4, 1.0),
                    "strong stretch, rotated");
  Mat3 F;    // simple shear plus stretch: F not symmetric, det = 1.3*0.9*1.1
  F << 1.3, 0.6, 0.0, 0.0, 0.9, 0.3, 0.0, 0.0, 1.1;
  check_polar(F, "simple shear with stretch");
}

// ===========================================================================
// nospd_constitutive.h

class LawTest : public ::testing::TestWithParam<Law> {};

INSTANTIATE_TEST_SUITE_P(Constitutive, LawTest, ::testing::ValuesIn(ALL_LAWS),
                         [](const ::testing::TestParamInfo<Law> &info) {
                           return std::string(law_name(info.param));
                         });

// Hyperelasticity: the first Piola-Kirchhoff stress is the work conjugate of
// F, P = dW/dF.  Central differences, h = 1e-6 |F|.
TEST_P(LawTest, FirstPiolaIsEnergyGradient)
{
  const Law law = GetParam();
  const Lame m = Lame::from_young(E_YOUNG, NU);
  auto W = [&](const Mat3 &F) { return energy(law, m, F); };

  Rng rng(31);
  std::vector<std::pair<Mat3, std::string>> cases;
  for (int k = 0; k < 3; ++k) cases.emplace_back(near_identity_F(rng), "near identity");
  cases.emplace_back(large_F(), "stretches 1.3/0.8/1.15 with 50 deg rotation");
  for (const auto &c : cases) {
    SCOPED_TRACE(c.second);
    const Mat3 &F = c.first;
    ASSERT_GT(F.determinant(), 0.0);
    const Mat3 P = piola(law, m, F);
    const Mat3 Pfd = numerical_gradient(W, F);
    EXPECT_LT(relerr(P, Pfd), 1e-6) << "P =\n" << P << "\ndW/dF =\n" << Pfd;
  }
}

// The Hencky law from its definition, in the principal frame of b = F F^T:
// tau = sum_a (lambda tr e + 2 mu e_a) n_a (x) n_a, e_a = ln(lambda_a), for
// stretches near isotropy (where the law takes the series of ln b) and far
// from it (where it takes the eigenpairs), rotated, to 1e-13.
TEST(Constitutive, HenckyMatchesPrincipalFrameDefinition)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Rng rng(47);
  std::vector<Mat3> cases;
  for (double a : {1e-6, 1e-3, 1e-2, 0.03}) {
    for (int k = 0; k < 5; ++k) {
      const Mat3 R = rotation(Vec3(rng.uniform(), rng.uniform(), rng.uniform() + 0.1),
                              180.0 * rng.uniform());
      const double s = 1.0 + 0.2 * rng.uniform();
      cases.push_back(R * (s * (Mat3::Identity() + rng.matrix(a))));
    }
  }
  cases.push_back(large_F());
  for (const Mat3 &F : cases) {
    ASSERT_GT(F.determinant(), 0.0);
    Eigen::SelfAdjointEigenSolver<Mat3> eig(F * F.transpose());
    Vec3 e;
    for (int a = 0; a < 3; ++a) e(a) = 0.5 * std::log(eig.eigenvalues()(a));
    const Vec3 t = (m.lambda * e.sum()) * Vec3::Ones() + 2.0 * m.mu * e;
    const Mat3 tau = eig.eigenvectors() * t.asDiagonal() * eig.eigenvectors().transpose();
    const double Wref = 0.5 * m.lambda * e.sum() * e.sum() + m.mu * e.squaredNorm();
    Mat3 P;
    double W;
    ASSERT_TRUE(first_piola_3d(Law::HENCKY, m, F, P, W));
    EXPECT_LT(relerr(P * F.transpose(), tau), 1e-13) << "F =\n" << F;
    EXPECT_NEAR(W, Wref, 1e-13 * Wref);
  }
}

// The reference configuration is stress and energy free.
TEST_P(LawTest, ReferenceIsStressFree)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Mat3 P;
  double W = 1.0;
  ASSERT_TRUE(first_piola_3d(GetParam(), m, Mat3::Identity(), P, W));
  EXPECT_EQ(maxabs(P), 0.0);
  EXPECT_EQ(W, 0.0);
}

// Every law linearizes to Hooke's law: for F = I + eps G, P(F)/eps and
// P_small(F)/eps differ by O(eps).
TEST_P(LawTest, AgreesWithSmallStrainToFirstOrder)
{
  const Law law = GetParam();
  const Lame m = Lame::from_young(E_YOUNG, NU);
  const double eps = 1e-7;
  Rng rng(32);
  for (int k = 0; k < 4; ++k) {
    const Mat3 G = rng.matrix(1.0);    // general: stretch, shear and rotation
    const Mat3 F = Mat3::Identity() + eps * G;
    const Mat3 P = piola(law, m, F) / eps;
    const Mat3 Ps = piola(Law::SMALL, m, F) / eps;
    EXPECT_LT(relerr(P, Ps), 1e-5) << "G =\n" << G;
    // and the energies agree at leading (second) order, W = Ws (1 + O(eps)).
    // Checked at eps = 1e-4: at 1e-7 the Neo-Hooke energy, a difference of
    // O(eps) terms (tr C - 3, ln J) of size O(eps^2), has lost most digits to
    // cancellation (absolute error ~1e-16 E, immaterial for the forces).
    const Mat3 F4 = Mat3::Identity() + 1e-4 * G;
    const double W = energy(law, m, F4), Ws = energy(Law::SMALL, m, F4);
    EXPECT_NEAR(W / Ws, 1.0, 2e-3);
  }
  // same under plane stress: in-plane P and the solved thickness stretch
  for (int k = 0; k < 3; ++k) {
    Mat3 G = Mat3::Zero();
    G.topLeftCorner<2, 2>() = rng.matrix(1.0).topLeftCorner<2, 2>();
    Mat3 F = Mat3::Identity() + eps * G, Fs = F, P, Ps;
    double W, Ws;
    ASSERT_TRUE(first_piola(law, Plane::STRESS, m, F, P, W));
    ASSERT_TRUE(first_piola(Law::SMALL, Plane::STRESS, m, Fs, Ps, Ws));
    EXPECT_LT(relerr(P / eps, Ps / eps), 1e-5);
    EXPECT_NEAR((F(2, 2) - 1.0) / (Fs(2, 2) - 1.0), 1.0, 1e-5);
  }
}

// Plane stress: the solved thickness stretch F33 makes P33 (and so sigma33,
// F being block diagonal) vanish, and the reduced energy
// W_ps(F2D) = W(F2D, F33(F2D)) has in-plane gradient P_ab: dW_ps/dF_ab =
// P_ab + P_33 dF33/dF_ab = P_ab since P_33 = 0.
TEST_P(LawTest, PlaneStressHasZeroOutOfPlaneStress)
{
  const Law law = GetParam();
  for (double nu : {0.3, 0.45}) {
    const Lame m = Lame::from_young(E_YOUNG, nu);
    Rng rng(33);
    std::vector<Mat3> cases;
    for (int k = 0; k < 3; ++k) {
      Mat3 F = Mat3::Identity();
      F.topLeftCorner<2, 2>() += rng.matrix(0.08).topLeftCorner<2, 2>();
      cases.push_back(F);
    }
    {    // large: in-plane stretches 1.25, 0.85 on axes at 20 deg, rotated 35 deg
      const Mat3 F = rotation(Vec3(0, 0, 1), 35.0) *
          stretch(rotation(Vec3(0, 0, 1), 20.0), 1.25, 0.85, 1.0);
      cases.push_back(F);
    }
    for (const Mat3 &F0 : cases) {
      SCOPED_TRACE(std::string(law_name(law)) + " nu=" + std::to_string(nu));
      Mat3 F = F0, P;
      double W;
      ASSERT_TRUE(first_piola(law, Plane::STRESS, m, F, P, W));
      EXPECT_LE(std::abs(P(2, 2)), 1e-10 * maxabs(P)) << "P =\n" << P << "\nF =\n" << F;
      EXPECT_GT(F(2, 2), 0.0);
      // nothing but F33 was changed
      Mat3 dF = F - F0;
      dF(2, 2) = 0.0;
      EXPECT_EQ(maxabs(dF), 0.0);
      if (law != Law::SMALL) {
        // the stress is the 3D law's at the solved F
        Mat3 P3;
        double W3;
        ASSERT_TRUE(first_piola_3d(law, m, F, P3, W3));
        EXPECT_LT(relerr(P, P3), 1e-14);
      }
      auto Wps = [&](const Mat3 &Fin) {
        Mat3 Ft = Fin, Pt;
        Ft(2, 2) = 1.0;
        double Wt = 0.0;
        EXPECT_TRUE(first_piola(law, Plane::STRESS, m, Ft, Pt, Wt));
        return Wt;
      };
      const Mat3 Pfd = numerical_gradient(Wps, F0, 2, 2);
      const double err_ps = (P - Pfd).topLeftCorner<2, 2>().cwiseAbs().maxCoeff();
      EXPECT_LT(err_ps, 1e-6 * maxabs(P))
          << "P =\n" << P << "\ndW_ps/dF =\n" << Pfd;
    }
  }
}

// Plane strain is the 3D law at F33 = 1.
TEST_P(LawTest, PlaneStrainIsThreeDimensionalAtUnitThicknessStretch)
{
  const Law law = GetParam();
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Mat3 F = rotation(Vec3(0, 0, 1), -25.0) * stretch(Mat3::Identity(), 1.1, 0.95, 1.0);
  const Mat3 F0 = F;
  Mat3 P, P3;
  double W, W3;
  ASSERT_TRUE(first_piola(law, Plane::STRAIN, m, F, P, W));
  ASSERT_TRUE(first_piola_3d(law, m, F0, P3, W3));
  EXPECT_EQ(F(2, 2), 1.0);
  EXPECT_EQ(maxabs(F - F0), 0.0);
  EXPECT_LT(relerr(P, P3), 1e-15);
  // the constrained direction carries stress (Poisson effect), nu > 0
  EXPECT_GT(std::abs(P(2, 2)), 1e-3 * maxabs(P));
}

// ---------------------------------------------------------------------------
// Objectivity (frame indifference): superposing a rigid rotation Q on the
// deformation rotates P from the left and leaves W unchanged.

class ObjectiveLawTest : public ::testing::TestWithParam<Law> {};

INSTANTIATE_TEST_SUITE_P(Constitutive, ObjectiveLawTest,
                         ::testing::Values(Law::COROTATIONAL, Law::SVK, Law::NEOHOOKE),
                         [](const ::testing::TestParamInfo<Law> &info) {
                           return std::string(law_name(info.param));
                         });

TEST_P(ObjectiveLawTest, SuperposedRotation)
{
  const Law law = GetParam();
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Rng rng(41);
  std::vector<Mat3> Fs = {near_identity_F(rng), large_F(), Mat3::Identity()};
  for (const Mat3 &F : Fs)
    for (int k = 0; k < 5; ++k) {
      const Mat3 Q = (k == 0) ? rotation(Vec3(0.3, 0.3, -1.0), 170.0) : rng.rotation();
      const Mat3 P = piola(law, m, F), PQ = piola(law, m, Q * F);
      const double W = energy(law, m, F), WQ = energy(law, m, Q * F);
      const double scale = std::max(maxabs(P), 1e-3 * E_YOUNG);
      EXPECT_LT(maxabs(PQ - Q * P), 1e-12 * scale) << "F =\n" << F << "\nQ =\n" << Q;
      // (W(I) = 0 is reached by cancellation: allow roundoff ~1e-15 E)
      EXPECT_NEAR(WQ, W, 1e-12 * std::max(std::abs(W), 1e-3 * E_YOUNG));
    }
}

// ---------------------------------------------------------------------------
// small-strain law

TEST(SmallStrain, SymmetricStressAndUniaxialHooke)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Rng rng(51);
  const Mat3 P = piola(Law::SMALL, m, near_identity_F(rng));
  EXPECT_LT(maxabs(P - P.transpose()), 1e-15 * maxabs(P));

  // uniaxial stress state: eps = diag(e, -nu e, -nu e) gives sigma = diag(E e, 0, 0)
  const double e = 1.7e-3;
  Mat3 F = Mat3::Identity() + Vec3(e, -NU * e, -NU * e).asDiagonal().toDenseMatrix();
  // an infinitesimal rotation (skew part of grad u) carries no stress
  const Mat3 skew = (Mat3() << 0, 2e-4, -1e-4, -2e-4, 0, 3e-4, 1e-4, -3e-4, 0).finished();
  for (const Mat3 &Fc : {F, Mat3(F + skew)}) {
    const Mat3 S = piola(Law::SMALL, m, Fc);
    EXPECT_NEAR(S(0, 0), E_YOUNG * e, 1e-12 * E_YOUNG * e);
    EXPECT_NEAR(S(1, 1), 0.0, 1e-12 * E_YOUNG * e);
    EXPECT_NEAR(S(2, 2), 0.0, 1e-12 * E_YOUNG * e);
    EXPECT_NEAR(maxabs(S - Vec3(S(0, 0), S(1, 1), S(2, 2)).asDiagonal().toDenseMatrix()), 0.0,
                1e-12 * E_YOUNG * e);
    // W = sigma : eps / 2 = E e^2 / 2
    EXPECT_NEAR(energy(Law::SMALL, m, Fc), 0.5 * E_YOUNG * e * e, 1e-12 * E_YOUNG * e * e);
  }
  // simple shear gamma: sigma_xy = G gamma, G = E / (2 (1 + nu))
  const double g = 2e-3;
  Mat3 Fsh = Mat3::Identity();
  Fsh(0, 1) = g;
  const Mat3 Ssh = piola(Law::SMALL, m, Fsh);
  EXPECT_NEAR(Ssh(0, 1), E_YOUNG / (2.0 * (1.0 + NU)) * g, 1e-12 * E_YOUNG * g);
  // hydrostatic: p = K tr(eps), K = E / (3 (1 - 2 nu))
  const Mat3 Shy = piola(Law::SMALL, m, (1.0 + e) * Mat3::Identity());
  EXPECT_NEAR(Shy.trace() / 3.0, E_YOUNG / (3.0 * (1.0 - 2.0 * NU)) * 3.0 * e, 1e-12 * E_YOUNG * e);
  EXPECT_NEAR(m.bulk(), E_YOUNG / (3.0 * (1.0 - 2.0 * NU)), 1e-14 * E_YOUNG);
}

// Documents that the small-strain law is NOT objective: a finite rigid
// rotation of the unstrained body produces strain energy (and stress).
TEST(SmallStrain, NotObjectiveUnderFiniteRotation)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  const Mat3 Q = rotation(Vec3(0.0, 0.0, 1.0), 30.0);
  EXPECT_EQ(energy(Law::SMALL, m, Mat3::Identity()), 0.0);
  // eps = sym(Q) - I = (cos 30 - 1) diag(1, 1, 0): spurious biaxial compression
  const double c = std::cos(PI / 6.0) - 1.0;
  const double Wexp = 0.5 * m.lambda * (2.0 * c) * (2.0 * c) + m.mu * 2.0 * c * c;
  const double WQ = energy(Law::SMALL, m, Q);
  EXPECT_GT(WQ, 1e-3 * E_YOUNG);
  EXPECT_NEAR(WQ, Wexp, 1e-12 * Wexp);
  EXPECT_GT(maxabs(piola(Law::SMALL, m, Q)), 1e-2 * E_YOUNG);
}

// 2D plane-stress Hooke's law: sigma = E/(1-nu^2) [(1-nu) eps + nu tr(eps) I],
// valid for -1 < nu < 1 (so nu = 0.7 is admissible in 2D).
TEST(SmallStrain, PlaneStressHooke)
{
  Rng rng(52);
  for (double nu : {0.3, 0.7, -0.2}) {
    SCOPED_TRACE("nu = " + std::to_string(nu));
    const Lame m = Lame::from_young(E_YOUNG, nu);
    for (int k = 0; k < 3; ++k) {
      Mat3 F = Mat3::Identity();
      F.topLeftCorner<2, 2>() += rng.matrix(1e-3).topLeftCorner<2, 2>();
      const Mat3 F0 = F;
      Mat3 P;
      double W;
      ASSERT_TRUE(first_piola(Law::SMALL, Plane::STRESS, m, F, P, W));
      const Eigen::Matrix2d eps =
          0.5 * (F0.topLeftCorner<2, 2>() + F0.topLeftCorner<2, 2>().transpose()) -
          Eigen::Matrix2d::Identity();
      const Eigen::Matrix2d sig = E_YOUNG / (1.0 - nu * nu) *
          ((1.0 - nu) * eps + nu * eps.trace() * Eigen::Matrix2d::Identity());
      const double s = sig.cwiseAbs().maxCoeff();
      EXPECT_LT((P.topLeftCorner<2, 2>() - sig).cwiseAbs().maxCoeff(), 1e-12 * s);
      EXPECT_EQ(P(2, 2), 0.0);
      EXPECT_EQ(P(0, 2), 0.0);
      EXPECT_EQ(P(1, 2), 0.0);
      EXPECT_EQ(P(2, 0), 0.0);
      EXPECT_EQ(P(2, 1), 0.0);
      // W = sigma : eps / 2
      EXPECT_NEAR(W, 0.5 * (sig.array() * eps.array()).sum(), 1e-12 * s * eps.cwiseAbs().maxCoeff());
      if (nu < 0.5) {
        // 3D Hooke with sigma33 = 0: eps33 = -nu/E (s11 + s22) = -nu/(1-nu) tr(eps)
        EXPECT_NEAR(F(2, 2) - 1.0, -nu / (1.0 - nu) * eps.trace(), 1e-12 * std::abs(eps.trace()));
        // and the 3D small-strain law at that F indeed has no sigma33
        const Mat3 P3 = piola(Law::SMALL, m, F);
        EXPECT_LT(std::abs(P3(2, 2)), 1e-12 * s);
        EXPECT_LT((P3.topLeftCorner<2, 2>() - sig).cwiseAbs().maxCoeff(), 1e-12 * s);
      }
    }
  }
}

// Plane strain: eps33 = 0, the constraint stress is sigma33 = lambda (eps11 + eps22).
TEST(SmallStrain, PlaneStrainHooke)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Rng rng(53);
  for (int k = 0; k < 3; ++k) {
    Mat3 F = Mat3::Identity();
    F.topLeftCorner<2, 2>() += rng.matrix(1e-3).topLeftCorner<2, 2>();
    const Mat3 F0 = F;
    Mat3 P;
    double W;
    ASSERT_TRUE(first_piola(Law::SMALL, Plane::STRAIN, m, F, P, W));
    EXPECT_EQ(F(2, 2), 1.0);
    const double e11 = F0(0, 0) - 1.0, e22 = F0(1, 1) - 1.0, e12 = 0.5 * (F0(0, 1) + F0(1, 0));
    const double lam = E_YOUNG * NU / ((1.0 + NU) * (1.0 - 2.0 * NU));
    const double G = E_YOUNG / (2.0 * (1.0 + NU));
    const double s = E_YOUNG * 1e-3;
    EXPECT_NEAR(P(2, 2), lam * (e11 + e22), 1e-12 * s);
    EXPECT_NEAR(P(0, 0), lam * (e11 + e22) + 2.0 * G * e11, 1e-12 * s);
    EXPECT_NEAR(P(1, 1), lam * (e11 + e22) + 2.0 * G * e22, 1e-12 * s);
    EXPECT_NEAR(P(0, 1), 2.0 * G * e12, 1e-12 * s);
  }
}

TEST(FiniteStrain, UndefinedForInvertedElements)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  const Mat3 Finv = Vec3(1.0, 1.0, -0.5).asDiagonal();    // det < 0
  Mat3 P;
  double W;
  EXPECT_FALSE(first_piola_3d(Law::COROTATIONAL, m, Finv, P, W));
  EXPECT_FALSE(first_piola_3d(Law::NEOHOOKE, m, Finv, P, W));
  EXPECT_FALSE(first_piola_3d(Law::NEOHOOKE, m, Mat3::Zero(), P, W));
}

// Cauchy stress sigma = P F^T / J.  Neo-Hooke in spatial form:
// sigma = mu/J (b - I) + lambda ln(J)/J I, b = F F^T.
TEST(Stress, CauchyOfNeoHookeAndSmallStrain)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  const Mat3 F = large_F();
  const double J = F.determinant();
  const Mat3 sig = cauchy_stress(Law::NEOHOOKE, F, piola(Law::NEOHOOKE, m, F));
  const Mat3 b = F * F.transpose();
  const Mat3 sexp = m.mu / J * (b - Mat3::Identity()) + m.lambda * std::log(J) / J * Mat3::Identity();
  EXPECT_LT(relerr(sig, sexp), 1e-13);

  Rng rng(61);
  const Mat3 Fs = near_identity_F(rng);
  const Mat3 Ps = piola(Law::SMALL, m, Fs);
  EXPECT_LT(relerr(cauchy_stress(Law::SMALL, Fs, Ps), Ps), 1e-15);
}

TEST(Stress, VonMises)
{
  // uniaxial: sigma_vm = |s|; pure shear: sqrt(3) tau; hydrostatic: 0
  EXPECT_NEAR(von_mises(Vec3(-4.0, 0.0, 0.0).asDiagonal().toDenseMatrix()), 4.0, 1e-14);
  Mat3 tau = Mat3::Zero();
  tau(1, 2) = tau(2, 1) = 1.5;
  EXPECT_NEAR(von_mises(tau), std::sqrt(3.0) * 1.5, 1e-14);
  EXPECT_NEAR(von_mises(7.0 * Mat3::Identity()), 0.0, 1e-14);
  // invariant under a superposed pressure and a change of frame
  Rng rng(62);
  Mat3 s = rng.matrix(1.0);
  s = 0.5 * (s + s.transpose()).eval();
  const Mat3 Q = rng.rotation();
  EXPECT_NEAR(von_mises(Q * s * Q.transpose() + 3.0 * Mat3::Identity()), von_mises(s), 1e-13);
}

// ===========================================================================
// nospd_stabilization.h

// Bond-based micromodulus from energy equivalence (Silling & Askari 2005):
// under isotropic expansion with bond stretch s (dilatation 3s) the
// bond-based energy density must equal the bulk energy density K (3s)^2 / 2.
TEST(Micromodulus, ThreeDimensionalBulkEnergy)
{
  // quadrature self-check: integral of 1 over the ball with w = 1/2 c s^2 r
  // replaced by a constant is the ball's volume
  const double delta = 0.37;
  for (double nu : {0.3, 0.25, 0.1}) {
    SCOPED_TRACE("nu = " + std::to_string(nu));
    const double c = micromodulus(3, Plane::NONE, E_YOUNG, nu, delta, 1.0);
    const double K = E_YOUNG / (3.0 * (1.0 - 2.0 * nu));
    EXPECT_NEAR(c, 18.0 * K / (PI * std::pow(delta, 4)), 1e-13 * c);
    const double s = 1e-3;
    const double W = bond_energy_density_3d(c, delta, exact_stretch((1.0 + s) * Mat3::Identity()));
    const double Wbulk = 0.5 * K * (3.0 * s) * (3.0 * s);
    EXPECT_NEAR(W, Wbulk, 1e-12 * Wbulk);
    EXPECT_NEAR(W, 4.5 * K * s * s, 1e-12 * Wbulk);
  }
  // Bond-based 3D material has nu = 1/4 (Cauchy relation lambda = mu); there
  // the same c reproduces the full isotropic energy for ANY small strain,
  // W = lambda/2 tr(eps)^2 + mu eps:eps (e.g. uniaxial strain (lambda+2mu) e^2/2).
  const Lame m = Lame::from_young(E_YOUNG, 0.25);
  const double c = micromodulus(3, Plane::NONE, E_YOUNG, 0.25, delta, 1.0);
  Rng rng(71);
  Mat3 eps = rng.matrix(1e-3);
  eps = 0.5 * (eps + eps.transpose()).eval();
  for (const Mat3 &e : {eps, Mat3(Vec3(1e-3, 0, 0).asDiagonal())}) {
    const double W = bond_energy_density_3d(c, delta, linear_stretch(e));
    const double Wc = 0.5 * m.lambda * e.trace() * e.trace() + m.mu * e.squaredNorm();
    EXPECT_NEAR(W, Wc, 1e-12 * Wc);
  }
}

// 2D plane stress: bond-based 2D material has nu = 1/3 (2D Cauchy relation
// lambda* = mu).  Energy of an isotropic expansion s in plane stress:
// sigma = E/(1-nu) s I2, W = sigma:eps/2 = E s^2/(1-nu) = 3/2 E s^2 at nu = 1/3.
// The peridynamic integral runs over the disk of radius delta, dV = t dA.
TEST(Micromodulus, PlaneStressEnergy)
{
  const double delta = 0.21, t = 0.05, nu = 1.0 / 3.0;
  const double c = micromodulus(2, Plane::STRESS, E_YOUNG, nu, delta, t);
  EXPECT_NEAR(c, 9.0 * E_YOUNG / (PI * t * std::pow(delta, 3)), 1e-13 * c);
  const double s = 1e-3;
  Mat3 F = Mat3::Identity();
  F(0, 0) = F(1, 1) = 1.0 + s;
  const double W = bond_energy_density_2d(c, delta, t, exact_stretch(F));
  const double Wps = E_YOUNG / (1.0 - nu) * s * s;
  EXPECT_NEAR(W, Wps, 1e-12 * Wps);
  // at nu = 1/3 the match holds for any in-plane strain:
  // W = lambda*/2 tr(eps)^2 + mu eps:eps with lambda* = E nu/(1-nu^2)
  const Lame m = Lame::from_young(E_YOUNG, nu);
  Rng rng(72);
  Mat3 eps = Mat3::Zero();
  eps.topLeftCorner<2, 2>() = rng.matrix(1e-3).topLeftCorner<2, 2>();
  eps = 0.5 * (eps + eps.transpose()).eval();
  const double We = bond_energy_density_2d(c, delta, t, linear_stretch(eps));
  const double Wc = 0.5 * m.lambda_ps * eps.trace() * eps.trace() + m.mu * eps.squaredNorm();
  EXPECT_NEAR(We, Wc, 1e-12 * Wc);
}

// 2D plane strain: the 3D bond-based restriction nu = 1/4; isotropic in-plane
// expansion s: W = 2 (lambda + mu) s^2 = 1.6 E s^2.
TEST(Micromodulus, PlaneStrainEnergy)
{
  const double delta = 0.21, t = 0.05, nu = 0.25;
  const double c = micromodulus(2, Plane::STRAIN, E_YOUNG, nu, delta, t);
  const Lame m = Lame::from_young(E_YOUNG, nu);
  Mat3 F = Mat3::Identity();
  const double s = 1e-3;
  F(0, 0) = F(1, 1) = 1.0 + s;
  const double W = bond_energy_density_2d(c, delta, t, exact_stretch(F));
  const double Wpe = 2.0 * (m.lambda + m.mu) * s * s;
  EXPECT_NEAR(W, Wpe, 1e-12 * Wpe);
  const Mat3 eps = Vec3(1e-3, 0.0, 0.0).asDiagonal();    // uniaxial strain
  const double We = bond_energy_density_2d(c, delta, t, linear_stretch(eps));
  EXPECT_NEAR(We, 0.5 * (m.lambda + 2.0 * m.mu) * 1e-6, 1e-12 * We);
}

// Wan et al.'s S = C : K^-1, contracted here index by index from the
// isotropic elasticity tensor.
TEST(WanTensor, ThreeDimensionalIsElasticityContraction)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Rng rng(81);
  std::vector<Mat3> Kinvs;
  for (int k = 0; k < 3; ++k) {
    std::vector<Vec3> fam;
    for (int b = 0; b < 30; ++b) fam.push_back(rng.vector(0.2));
    Kinvs.push_back(shape_tensor(fam).inverse());
  }
  const Mat3 V = rng.rotation();    // strongly anisotropic SPD
  Kinvs.push_back(stretch(V, 1.0, 1e-3, 50.0));
  for (const Mat3 &Kinv : Kinvs) {
    Mat3 Sexp = Mat3::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l) Sexp(i, j) += Ciso(m.lambda, m.mu, i, j, k, l) * Kinv(k, l);
    const Mat3 S = wan_tensor(m, 3, Plane::NONE, Kinv);
    EXPECT_LT(relerr(S, Sexp), 1e-13);
    EXPECT_LT(maxabs(S - S.transpose()), 1e-14 * maxabs(S));
    Eigen::SelfAdjointEigenSolver<Mat3> es(S);
    EXPECT_GT(es.eigenvalues().minCoeff(), 0.0) << "S =\n" << S;
  }
}

// 2D: plane strain uses the in-plane block of C; plane stress the statically
// condensed C* (sigma33 = 0 eliminated): C*_abcd = C_abcd - C_ab33 C_33cd / C_3333.
TEST(WanTensor, TwoDimensionalPlaneStressAndStrain)
{
  const Lame m = Lame::from_young(E_YOUNG, NU);
  Rng rng(82);
  std::vector<Vec3> fam;
  for (int b = 0; b < 12; ++b) fam.emplace_back(rng.uniform(), rng.uniform(), 0.0);
  Mat3 K = shape_tensor(fam);
  K(2, 2) = 1.0;
  Mat3 Kinv = K.inverse();
  Kinv(2, 2) = 123.0;    // placeholder entry: must not matter
  for (Plane plane : {Plane::STRAIN, Plane::STRESS}) {
    Mat3 Sexp = Mat3::Zero();
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c)
          for (int e = 0; e < 2; ++e) {
            double C = Ciso(m.lambda, m.mu, a, b, c, e);
            if (plane == Plane::STRESS)
              C -= Ciso(m.lambda, m.mu, a, b, 2, 2) * Ciso(m.lambda, m.mu, 2, 2, c, e) /
                  Ciso(m.lambda, m.mu, 2, 2, 2, 2);
            Sexp(a, b) += C * Kinv(c, e);
          }
    const Mat3 S = wan_tensor(m, 2, plane, Kinv);
    EXPECT_LT(relerr(S, Sexp), 1e-13) << (plane == Plane::STRESS ? "plane stress" : "plane strain");
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(S.topLeftCorner<2, 2>());
    EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
  }
}

// ---------------------------------------------------------------------------
// Hourglass pair force  f = (T_i<xi> - T_j<-xi>) / omega, the force on i
// from the bond i->j.  Written with the nonuniform part of the relative
// displacement of j, z = U - H xi (U = u_j - u_i, H = F - I):
//     f = (c_i z_i + c_j z_j) . yhat / |xi| * yhat .
// Since f acts on i, -f acts on j.  If j has moved away from i beyond what
// the local F predicts (z along yhat, f . z > 0), f pulls i toward j and -f
// pulls j back toward i: the force opposes the hourglass mode.  So the
// restoring direction is f . z > 0 (for H = 0: f . U > 0).
/* The quadratic fit's operator (stabilization/fit quadratic): K2 K2^-1 = I
   over the basis functions the family spans; in 2D the out-of-plane ones
   are left out; a family on one line has no quadratic fit. */
namespace {
Eigen::Matrix<double, 9, 9> fit_matrix(const std::vector<NOSPD::Vec3> &xi)
{
  Eigen::Matrix<double, 9, 9> K2 = Eigen::Matrix<double, 9, 9>::Zero();
  for (const auto &e : xi) {
    double phi[9] = {e[0], e[1], e[2]};
    NOSPD::quadratic_terms(phi, phi + 3);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> p(phi);
    K2 += p * p.transpose();
  }
  return K2;
}
std::vector<NOSPD::Vec3> grid_family(int dim, double dx, double delta)
{
  std::vector<NOSPD::Vec3> xi;
  const int m = (int) std::ceil(delta / dx);
  for (int a = -m; a <= m; a++)
    for (int b = -m; b <= m; b++)
      for (int c = (dim == 3 ? -m : 0); c <= (dim == 3 ? m : 0); c++) {
        const NOSPD::Vec3 e(a * dx, b * dx, c * dx);
        if (e.norm() > 0.0 && e.norm() <= delta) xi.push_back(e);
      }
  return xi;
}
}    // namespace

TEST(QuadraticFit, InverseOverTheSpannedBasis)
{
  for (int dim : {3, 2}) {
    // a one-sided family (a point on a free surface) with a millimetre spacing
    std::vector<NOSPD::Vec3> xi;
    for (const auto &e : grid_family(dim, 1e-3, 3.01e-3))
      if (e[0] >= 0.0) xi.push_back(e);
    const auto K2 = fit_matrix(xi);
    double rec[NOSPD::QuadraticFit::RECORD];
    ASSERT_TRUE(NOSPD::quadratic_fit_inverse(K2, rec));
    EXPECT_EQ(rec[NOSPD::QuadraticFit::PACKED], 1.0);
    Eigen::Matrix<double, 9, 9> K2i;
    for (int r = 0; r < 9; r++)
      for (int c = 0; c < 9; c++) K2i(r, c) = rec[NOSPD::packed_index(r, c)];
    // the basis functions the family spans: all in 3D, xi_x xi_y xi_x^2 xi_y^2 xi_x xi_y in 2D
    std::vector<int> in = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    if (dim == 2) in = {0, 1, 3, 4, 6};
    const Eigen::Matrix<double, 9, 9> P = K2 * K2i;
    for (int r : in)
      for (int c : in) EXPECT_NEAR(P(r, c), r == c ? 1.0 : 0.0, 1e-10) << r << " " << c;
    if (dim == 2) {
      for (int k : {2, 5, 7, 8})
        for (int c = 0; c < 9; c++) EXPECT_EQ(K2i(k, c), 0.0);
    }
    // the fit of an exact quadratic field is exact
    Eigen::Matrix<double, 3, 9> Atrue = Eigen::Matrix<double, 3, 9>::Zero();
    for (int r = 0; r < 3; r++)
      for (int k : in) Atrue(r, k) = 0.01 * (1 + r + k) * (k < 3 ? 1.0 : 1e3);
    Eigen::Matrix<double, 3, 9> N2 = Eigen::Matrix<double, 3, 9>::Zero();
    for (const auto &e : xi) {
      double phi[9] = {e[0], e[1], e[2]};
      NOSPD::quadratic_terms(phi, phi + 3);
      const Eigen::Map<const Eigen::Matrix<double, 9, 1>> p(phi);
      N2 += (Atrue * p) * p.transpose();
    }
    const auto A = NOSPD::quadratic_fit(N2, rec);
    EXPECT_LT((A - Atrue).norm(), 1e-9 * Atrue.norm()) << "dim " << dim;
  }
  // a point on the face of a plate two layers thick: its partners have
  // xi_z = 0 or dx only, so xi_z^2 = dx xi_z and no quadratic is fit
  std::vector<NOSPD::Vec3> plate;
  for (const auto &e : grid_family(3, 1e-3, 3.01e-3))
    if (e[2] >= 0.0 && e[2] <= 1.5e-3) plate.push_back(e);
  double rec[NOSPD::QuadraticFit::RECORD];
  EXPECT_FALSE(NOSPD::quadratic_fit_inverse(fit_matrix(plate), rec));
  EXPECT_EQ(rec[NOSPD::QuadraticFit::PACKED], 0.0);
}

TEST(Hourglass, VanishesForHomogeneousDeformation)
{
  Rng rng(91);
  for (int k = 0; k < 10; ++k) {
    const Mat3 H = rng.matrix(0.3);
    const Vec3 xi = rng.vector(0.1);
    const Vec3 U = H * xi;
    const Vec3 f = hourglass_pair(2.0, H, 3.5, H, xi, U);
    EXPECT_LE(f.norm(), 1e-14 * 5.5 * U.norm() / xi.norm());
  }
}

// Newton's third law: the pair force computed from j's side (roles of i and
// j swapped, xi -> -xi, U -> -U) is the negative.
TEST(Hourglass, AntisymmetricUnderExchangeOfBondEnds)
{
  Rng rng(92);
  for (int k = 0; k < 10; ++k) {
    const Mat3 Hi = rng.matrix(0.2), Hj = rng.matrix(0.2);
    const double ci = 1.0 + rng.uniform(0.0, 1.0), cj = 1.0 + rng.uniform(0.0, 1.0);
    const Vec3 xi = rng.vector(0.1), U = rng.vector(0.02);
    const Vec3 fij = hourglass_pair(ci, Hi, cj, Hj, xi, U);
    const Vec3 fji = hourglass_pair(cj, Hj, ci, Hi, -xi, -U);
    EXPECT_LT((fij + fji).norm(), 1e-14 * fij.norm());
    EXPECT_GT(fij.norm(), 0.0);
  }
}

TEST(Hourglass, OpposesNonuniformDisplacement)
{
  const double ci = 1.3, cj = 0.7, csum = ci + cj;
  const Vec3 xi(0.08, -0.03, 0.05);
  const Vec3 xhat = xi.normalized();
  const Vec3 n = xhat.unitOrthogonal();

  // pure longitudinal (H = 0, U = a xhat), extension and compression: a linear
  // spring along the bond, f = (c_i + c_j) a / |xi| xhat, f . U > 0
  for (double a : {1e-3, -1e-3}) {
    const Vec3 U = a * xhat;
    const Vec3 f = hourglass_pair(ci, Mat3::Zero(), cj, Mat3::Zero(), xi, U);
    EXPECT_GT(f.dot(U), 0.0);
    EXPECT_LT((f - csum * a / xi.norm() * xhat).norm(), 1e-13 * f.norm());
  }

  // pure transverse (H = 0, U = b n, n perpendicular to xi): the bond-aligned
  // projection sees the displacement only through the bond rotation, z . yhat
  // = b^2 / |xi + b n| -- restoring (f . U > 0) but of second order in b (a
  // known weakness of this form of hourglass control)
  double fprev = 0.0;
  for (double b : {1e-3, 2e-3}) {
    const Vec3 U = b * n;
    const Vec3 f = hourglass_pair(ci, Mat3::Zero(), cj, Mat3::Zero(), xi, U);
    const Vec3 yhat = (xi + U).normalized();
    EXPECT_GT(f.dot(U), 0.0);
    EXPECT_LT((f - f.dot(yhat) * yhat).norm(), 1e-14 * f.norm());    // along the bond
    if (fprev > 0.0) {
      EXPECT_NEAR(f.norm() / fprev, 4.0, 4.0 * 1e-3);
    }
    fprev = f.norm();
  }

  // on top of an arbitrary homogeneous deformation H: f . z >= 0 for any
  // nonuniform part z, and -f (the force on j) does negative work on z
  Rng rng(93);
  const Mat3 H = rng.matrix(0.2);
  for (int k = 0; k < 20; ++k) {
    const Vec3 z = rng.vector(1e-3);
    const Vec3 f = hourglass_pair(ci, H, cj, H, xi, H * xi + z);
    EXPECT_GE(f.dot(z), 0.0);
    EXPECT_LE((-f).dot(z), 0.0);
  }
  // longitudinal along the deformed bond: magnitude (c_i + c_j) |a| / |xi|
  const Vec3 yhat0 = ((Mat3::Identity() + H) * xi).normalized();
  const Vec3 f = hourglass_pair(ci, H, cj, H, xi, H * xi + 1e-3 * yhat0);
  EXPECT_NEAR(f.norm(), csum * 1e-3 / xi.norm(), 1e-12 * f.norm());
  EXPECT_GT(f.dot(yhat0), 0.0);
}

// Frame indifference: rotating the deformed configuration (Y -> Q Y,
// F -> Q F) rotates the force.
TEST(Hourglass, Objective)
{
  Rng rng(94);
  for (int k = 0; k < 5; ++k) {
    const Mat3 Fi = Mat3::Identity() + rng.matrix(0.1), Fj = Mat3::Identity() + rng.matrix(0.1);
    const Vec3 xi = rng.vector(0.1);
    const Vec3 Y = 0.5 * (Fi + Fj) * xi + rng.vector(0.005);
    const Mat3 Q = rng.rotation();
    const Mat3 I = Mat3::Identity();
    const Vec3 f = hourglass_pair(1.1, Fi - I, 0.9, Fj - I, xi, Y - xi);
    const Vec3 fQ = hourglass_pair(1.1, Q * Fi - I, 0.9, Q * Fj - I, xi, Q * Y - xi);
    EXPECT_LT((fQ - Q * f).norm(), 1e-12 * f.norm());
  }
}

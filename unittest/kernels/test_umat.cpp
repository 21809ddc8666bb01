/* Kernel tests of the UMAT bridge (nospd_umat.h) with a UMAT written
   here in C (linear elasticity, the Abaqus interface as gfortran passes
   it): small kinematics reproduce the built-in small-strain law over a
   path of increments; finite kinematics rotate the stress with a rigid
   rotation (objectivity); Voigt packing; a UMAT's abort request. */

#include "nospd_constitutive.h"
#include "nospd_umat.h"

#include "gtest/gtest.h"

#include <random>

using NOSPD::Mat3;

namespace {

const double E = 2.0e9, NU = 0.25;
int umat_calls = 0;

// the Abaqus argument list; this law reads only what it needs
extern "C" void elastic_umat(double *stress, double *statev, double *, double *sse, double *,
                             double *, double *, double *, double *, double *, double *,
                             double *dstran, double *, double *, double *, double *, double *,
                             double *, char *, int *, int *, int *ntens, int *nstatv,
                             double *props, int *, double *, double *, double *, double *,
                             double *, double *, int *, int *, int *, int *, int *, int *,
                             size_t)
{
  umat_calls++;
  const double e = props[0], nu = props[1];
  const double lam = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
  const int n = *ntens;
  double old[6];
  for (int i = 0; i < n; i++) old[i] = stress[i];
  double tr = dstran[0] + dstran[1] + dstran[2];
  for (int i = 0; i < 3; i++) stress[i] += lam * tr + 2 * mu * dstran[i];
  for (int i = 3; i < n; i++) stress[i] += mu * dstran[i];
  for (int i = 0; i < n; i++) *sse += 0.5 * (old[i] + stress[i]) * dstran[i];
  if (*nstatv > 0) statev[0] += 1.0;    // counts increments
  if (props[2] != 0.0) {
    NOSPD::umat_report().abort = true;
    NOSPD::umat_report().message = "asked to stop";
  }
}

NOSPD::UmatMaterial material(bool finite, double stop = 0.0)
{
  NOSPD::UmatMaterial m;
  m.fn = elastic_umat;
  m.props = {E, NU, stop};
  m.nstatev = 1;
  m.ntens = 6;
  m.finite = finite;
  m.set_name("TEST");
  return m;
}

}    // namespace

TEST(Umat, VoigtRoundTrip)
{
  Mat3 a;
  a << 1, 4, 5, 4, 2, 6, 5, 6, 3;
  double v[6];
  NOSPD::to_voigt(a, 6, 1.0, v);
  EXPECT_EQ(v[3], 4);    // 12
  EXPECT_EQ(v[4], 5);    // 13
  EXPECT_EQ(v[5], 6);    // 23
  EXPECT_EQ((NOSPD::from_voigt(v, 6) - a).norm(), 0.0);
  NOSPD::to_voigt(a, 4, 2.0, v);
  EXPECT_EQ(v[3], 8);
}

TEST(Umat, SmallKinematicsMatchBuiltinLaw)
{
  const auto m = material(false);
  const NOSPD::Lame lame = NOSPD::Lame::from_young(E, NU);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(-1e-3, 1e-3);
  std::vector<double> hn(NOSPD::UmatHist::size(1), 0.0), h1(hn.size());
  Mat3 F = Mat3::Identity();
  NOSPD::UmatPoint pt;
  for (int step = 0; step < 20; step++) {
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) F(r, c) += U(rng);
    Mat3 P, Pb;
    double W, Wb;
    ASSERT_EQ(NOSPD::umat_point(m, pt, F, hn.data(), h1.data(), P, W), NOSPD::UmatStatus::OK);
    ASSERT_TRUE(NOSPD::first_piola_3d(NOSPD::Law::SMALL, lame, F, Pb, Wb));
    EXPECT_LT((P - Pb).norm(), 1e-10 * Pb.norm()) << "step " << step;
    EXPECT_NEAR(W, Wb, 1e-10 * std::abs(Wb));
    hn = h1;
  }
  EXPECT_EQ(hn[NOSPD::UmatHist::STATEV], 20.0);
}

TEST(Umat, FiniteKinematicsRotateStressWithBody)
{
  const auto m = material(true);
  std::vector<double> h0(NOSPD::UmatHist::size(1), 0.0), h1(h0.size()), h2(h0.size());
  NOSPD::UmatPoint pt;
  Mat3 U;
  U << 1.02, 0.003, 0.0, 0.003, 0.99, 0.001, 0.0, 0.001, 1.01;
  Mat3 P1, P2;
  double W1, W2;
  ASSERT_EQ(NOSPD::umat_point(m, pt, U, h0.data(), h1.data(), P1, W1), NOSPD::UmatStatus::OK);
  const Mat3 Q = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  ASSERT_EQ(NOSPD::umat_point(m, pt, Q * U, h1.data(), h2.data(), P2, W2), NOSPD::UmatStatus::OK);
  EXPECT_LT((P2 - Q * P1).norm(), 1e-12 * P1.norm());
  EXPECT_NEAR(W2, W1, 1e-12 * W1);
}

TEST(Umat, AbortRequestIsReported)
{
  const auto m = material(false, 1.0);
  std::vector<double> h0(NOSPD::UmatHist::size(1), 0.0), h1(h0.size());
  NOSPD::UmatPoint pt;
  Mat3 P;
  double W;
  EXPECT_EQ(NOSPD::umat_point(m, pt, 1.001 * Mat3::Identity(), h0.data(), h1.data(), P, W),
            NOSPD::UmatStatus::ABORT);
  EXPECT_EQ(NOSPD::umat_report().message, "asked to stop");
}

/* The heat conduction kernel (nospd_heat.h): the calibrated operator gives
   k tr H on a quadratic field (3D and 2D, full families, any H), nothing on a
   linear one, the published 6 k / (pi delta^4) for a fine ball; bonds are
   symmetric bit for bit so the exchange conserves energy; the step bound
   keeps forward Euler free of new extremes and is close to the true limit;
   exposed faces add up to the surface of a cube and a square. */

#include "nospd_heat.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

using namespace NOSPD::Heat;

namespace {
struct Lattice {
  std::vector<std::array<double, 3>> x;
  std::vector<int> first, j;    // CSR bonds within delta
  std::vector<double> len;
};

// n^dim points of spacing dx, bonds within delta (m dx, m not an integer)
Lattice lattice(int dim, int n, double dx, double delta)
{
  Lattice L;
  const int nz = dim == 3 ? n : 1;
  for (int a = 0; a < n; a++)
    for (int b = 0; b < n; b++)
      for (int c = 0; c < nz; c++) L.x.push_back({a * dx, b * dx, c * dx});
  L.first.push_back(0);
  for (size_t p = 0; p < L.x.size(); p++) {
    for (size_t q = 0; q < L.x.size(); q++) {
      if (p == q) continue;
      double r2 = 0.0;
      for (int k = 0; k < 3; k++) r2 += (L.x[q][k] - L.x[p][k]) * (L.x[q][k] - L.x[p][k]);
      if (r2 <= delta * delta) {
        L.j.push_back(q);
        L.len.push_back(std::sqrt(r2));
      }
    }
    L.first.push_back(L.j.size());
  }
  return L;
}

NOSPD::Mat3 moment(const Lattice &L, int p, double V)
{
  NOSPD::Mat3 M = NOSPD::Mat3::Zero();
  for (int b = L.first[p]; b < L.first[p + 1]; b++) {
    double xi[3];
    for (int k = 0; k < 3; k++) xi[k] = L.x[L.j[b]][k] - L.x[p][k];
    add_moment(M, xi, V);
  }
  return M;
}

// the point in the middle of the lattice
int middle(int dim, int n) { return dim == 3 ? (n / 2) * n * n + (n / 2) * n + n / 2 : (n / 2) * n + n / 2; }
}    // namespace

TEST(Heat, QuadraticFieldGivesConductivityTimesLaplacian)
{
  for (int dim : {3, 2}) {
    const double dx = 1.0e-3, delta = 3.01 * dx, k = 45.0, t = 2.0e-3;
    const double V = dim == 3 ? dx * dx * dx : dx * dx * t;
    const Lattice L = lattice(dim, 9, dx, delta);
    const int p = middle(dim, 9);
    const double kappa = micro_conductivity(k, moment(L, p, V));
    const double H[3][3] = {{3.0, 0.7, -1.1}, {0.7, -2.0, 0.4}, {-1.1, 0.4, 5.0}};
    auto T = [&](const std::array<double, 3> &x) {
      double s = 0.0;
      for (int a = 0; a < dim; a++)
        for (int b = 0; b < dim; b++) s += 0.5 * x[a] * H[a][b] * x[b];
      return s + 2.0 * x[0] - x[1];    // plus a linear part
    };
    double rate = 0.0;
    for (int b = L.first[p]; b < L.first[p + 1]; b++)
      rate += kappa / L.len[b] * (T(L.x[L.j[b]]) - T(L.x[p])) * V;
    double trH = 0.0;
    for (int a = 0; a < dim; a++) trH += H[a][a];
    EXPECT_NEAR(rate / (k * trH), 1.0, 1e-9) << "dim " << dim;
  }
}

TEST(Heat, LinearFieldExchangesNothingInside)
{
  const double dx = 1.0, delta = 3.01;
  const Lattice L = lattice(3, 9, dx, delta);
  const int p = middle(3, 9);
  double rate = 0.0;
  for (int b = L.first[p]; b < L.first[p + 1]; b++) {
    const auto &xj = L.x[L.j[b]], &xi = L.x[p];
    rate += (1.5 * (xj[0] - xi[0]) - 0.5 * (xj[1] - xi[1]) + 2.0 * (xj[2] - xi[2])) / L.len[b];
  }
  EXPECT_NEAR(rate, 0.0, 1e-12);
}

TEST(Heat, FineBallGivesThePublishedMicroConductivity)
{
  // 6 k / (pi delta^4) (Bobaru and Duangpanya 2010) in the continuum limit
  const double delta = 24.01, k = 1.0;
  NOSPD::Mat3 M = NOSPD::Mat3::Zero();
  const int m = 25;
  for (int a = -m; a <= m; a++)
    for (int b = -m; b <= m; b++)
      for (int c = -m; c <= m; c++) {
        const double xi[3] = {double(a), double(b), double(c)};
        if (a * a + b * b + c * c <= delta * delta) add_moment(M, xi, 1.0);
      }
  const double published = 6.0 * k / (M_PI * std::pow(delta, 4));
  EXPECT_NEAR(micro_conductivity(k, M) / published, 1.0, 0.01);
}

TEST(Heat, SurfacePointConductsKAlongTheSurfaceAndLessAcross)
{
  const double dx = 1.0, V = 1.0, k = 3.0;
  const int n = 9;
  const Lattice L = lattice(3, n, dx, 3.01 * dx);
  const int p = 4 * n * n + 4 * n + 0;    // (4, 4, 0): on the face z = 0
  const double kappa = micro_conductivity(k, moment(L, p, V));
  double along = 0.0, across = 0.0;    // T = x^2/2 and z^2/2: k tr H = k
  for (int b = L.first[p]; b < L.first[p + 1]; b++) {
    const auto &xj = L.x[L.j[b]], &xi = L.x[p];
    along += kappa / L.len[b] * 0.5 * (xj[0] * xj[0] - xi[0] * xi[0]) * V;
    const double dz = xj[2] - xi[2];
    across += kappa / L.len[b] * 0.5 * dz * dz * V;    // the z^2/2 field's quadratic part
  }
  EXPECT_NEAR(along / k, 1.0, 1e-12);
  EXPECT_LT(across / k, 0.9);
}

TEST(Heat, BondCoefficientIsSymmetricBitForBit)
{
  std::mt19937 g(7);
  std::uniform_real_distribution<double> u(0.1, 10.0);
  for (int n = 0; n < 1000; n++) {
    const double ki = u(g), kj = u(g), len = u(g) * 1e-3, vi = u(g) * 1e-9, vj = u(g) * 1e-9;
    EXPECT_EQ(bond_coefficient(ki, kj, len, vi, vj), bond_coefficient(kj, ki, len, vj, vi));
  }
  // harmonic mean: equal kappas conduct with that kappa, a zero one not at all
  EXPECT_DOUBLE_EQ(bond_coefficient(2.0, 2.0, 0.5, 1.0, 3.0), 2.0 * 3.0 / 0.5);
  EXPECT_EQ(bond_coefficient(0.0, 2.0, 0.5, 1.0, 3.0), 0.0);
}

TEST(Heat, ExchangeConservesAndTheBoundKeepsTheMaximumPrinciple)
{
  const double dx = 1.0e-3, V = dx * dx * dx, k = 400.0, rhoc = 3.4e6;
  const Lattice L = lattice(3, 7, dx, 3.01 * dx);
  const int n = L.x.size();
  std::vector<double> kappa(n), c(L.j.size()), T(n), dE(n);
  for (int p = 0; p < n; p++) kappa[p] = micro_conductivity(k, moment(L, p, V));
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(250.0, 350.0);
  for (int p = 0; p < n; p++) T[p] = u(g);
  double bound = HUGE_VAL;
  for (int p = 0; p < n; p++) {
    double cs = 0.0;
    for (int b = L.first[p]; b < L.first[p + 1]; b++) {
      c[b] = bond_coefficient(kappa[p], kappa[L.j[b]], L.len[b], V, V);
      cs += c[b];
    }
    bound = std::min(bound, step_bound(rhoc * V, cs));
  }
  auto run = [&](double dt, int steps) {
    std::vector<double> Ts = T;
    double lo = 250.0, hi = 350.0, grow = 0.0;
    for (int s = 0; s < steps; s++) {
      exchange(L.first.data(), L.j.data(), c.data(), Ts.data(), 0, n, dE.data());
      double sum = 0.0, big = 0.0;
      for (int p = 0; p < n; p++) {
        sum += dE[p];
        big = std::max(big, std::fabs(dE[p]));
      }
      EXPECT_LE(std::fabs(sum), 1e-12 * big * n);
      for (int p = 0; p < n; p++) Ts[p] += dt * dE[p] / (rhoc * V);
      for (int p = 0; p < n; p++) grow = std::max({grow, Ts[p] - hi, lo - Ts[p]});
    }
    return grow;
  };
  EXPECT_LE(run(bound, 200), 1e-9);           // no new extremes at the bound
  EXPECT_GT(run(2.2 * bound, 400), 1.0);     // and the true limit is within 2x of it
}

TEST(Heat, ExposedFacesAddUpToTheSurface)
{
  for (int dim : {3, 2}) {
    const int n = 8;
    const double dx = 1.0;
    const Lattice L = lattice(dim, n, dx, 3.01 * dx);
    int faces = 0, layer_below = 0;
    for (size_t p = 0; p < L.x.size(); p++) {
      std::vector<std::array<double, 3>> xi;
      for (int b = L.first[p]; b < L.first[p + 1]; b++)
        xi.push_back({L.x[L.j[b]][0] - L.x[p][0], L.x[L.j[b]][1] - L.x[p][1],
                      L.x[L.j[b]][2] - L.x[p][2]});
      const int e = face_count(
          exposed_faces(reinterpret_cast<const double(*)[3]>(xi.data()), xi.size(), dx, dim));
      faces += e;
      const bool second = L.x[p][0] == dx && L.x[p][1] > 2 && L.x[p][1] < n - 3 &&
                          (dim == 2 || (L.x[p][2] > 2 && L.x[p][2] < n - 3));
      if (second) layer_below += e;
    }
    EXPECT_EQ(faces, dim == 3 ? 6 * n * n : 4 * n) << "dim " << dim;
    EXPECT_EQ(layer_below, 0);
  }
  EXPECT_DOUBLE_EQ(face_area(8.0, 3, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(face_area(2.0e-6 * 3.0, 2, 2.0e-3), std::sqrt(2.0e-6 * 3.0 * 2.0e-3));
}

TEST(Heat, DeformedFacesFollowNanson)
{
  // a corner point (+x, +y, +z faces), stretched 1.5 along x and sheared
  NOSPD::Mat3 F;
  F << 1.5, 0.2, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.8;
  const int faces = 1 | 4 | 16;
  const double A0 = 2.0;
  const double J = F.determinant();
  const NOSPD::Mat3 G = F.inverse().transpose();
  double expect = 0.0;
  for (int a = 0; a < 3; a++) expect += J * G.col(a).norm() * A0;
  EXPECT_NEAR(deformed_area(faces, A0, F), expect, 1e-14 * expect);
  // a pure stretch along x leaves the x face, widens the y and z faces
  NOSPD::Mat3 S = NOSPD::Mat3::Identity();
  S(0, 0) = 1.5;
  EXPECT_NEAR(deformed_area(1, A0, S), A0, 1e-14);
  EXPECT_NEAR(deformed_area(4, A0, S), 1.5 * A0, 1e-14);
  EXPECT_NEAR(deformed_area(1 | 2, A0, S), 2.0 * A0, 1e-14);    // both x faces (a slab)
  EXPECT_EQ(deformed_area(1, A0, -S), 0.0);                    // inverted: no area
}

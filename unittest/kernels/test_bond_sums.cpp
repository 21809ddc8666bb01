/* ----------------------------------------------------------------------
   PERI-NOSPD: unit tests of the classical style's bond sums
   (nospd_bond_sums.h), SIMD reductions over a point's bond list, on an
   irregular cloud with uneven weights, without LAMMPS.

   - Pass 1 under an affine displacement U = H xi: N = H K, sum w U =
     H sum w xi and sum w U (x) U = H K H^T (K = sum w xi (x) xi summed
     here bond by bond), to round-off.
   B and T are stored transposed (B^T row-major), B in the BREC records
   with the stabilization scalar, as the style keeps them.
   - Pass 2: the per-bond force with the i-terms (the virial path) equals
     the sum without them plus B_i sum w xi and the stabilization's
     i-term; both equal a bond-by-bond sum written out here; the hourglass
     term vanishes for an affine field and stays finite on a collapsed bond.
------------------------------------------------------------------------- */

#include "nospd_bond_sums.h"
#include "nospd_simd.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace NOSPD;

namespace {

// through the same per-target copies as the plugin's passes
template <bool MOMENTS>
NOSPD_KERNEL_CLONES void deformation(const Positions &p, const BondList &bl, int i, double *N,
                                     double *s, double *m)
{
  deformation_sums<MOMENTS>(p, bl, i, N, s, m);
}
template <StabPass STAB, int VIRIAL>
NOSPD_KERNEL_CLONES void forces(const Positions &p, const BondList &bl, const ForceTerms &ft,
                                int i, double *f, double *v)
{
  force_sums<STAB, VIRIAL>(p, bl, ft, i, f, v);
}

struct Cloud {
  std::vector<double> x, x0, w, B, T, Q;    // B: BREC records (B^T, c); Q: QREC per point
  std::vector<int> j;
  int n = 0;
};

// point 0 at the origin, n - 1 partners scattered in a ball of radius 3
Cloud make_cloud(int n, unsigned seed)
{
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.2, 1.5);
  Cloud c;
  c.n = n;
  c.x0.assign(3 * n, 0.0);
  for (int a = 1; a < n; a++) {
    double r2;
    do {
      for (int d = 0; d < 3; d++) c.x0[3 * a + d] = 3.0 * u(gen);
      r2 = c.x0[3 * a] * c.x0[3 * a] + c.x0[3 * a + 1] * c.x0[3 * a + 1] +
          c.x0[3 * a + 2] * c.x0[3 * a + 2];
    } while (r2 > 9.0 || r2 < 0.01);
    c.j.push_back(a);
    c.w.push_back(pos(gen));
  }
  // the layout the sums load: one readable double past the last atom
  // (NaN here: it must never reach a result)
  c.x0.push_back(std::nan(""));
  c.x = c.x0;
  c.B.resize(BREC * n);
  c.T.resize(9 * n + 1);
  for (auto &v : c.B) v = u(gen);
  for (auto &v : c.T) v = u(gen);
  c.T.back() = std::nan("");
  c.Q.resize(QREC * n + 1);
  for (auto &v : c.Q) v = u(gen);
  c.Q.back() = std::nan("");
  for (int a = 0; a < n; a++) c.B[BREC * a + 9] = pos(gen);
  return c;
}

double sc(const Cloud &c, int a)
{
  return c.B[BREC * a + 9];
}

double rel_diff(const double *a, const double *b, int n)
{
  double d = 0.0, s = 0.0;
  for (int k = 0; k < n; k++) {
    d = std::max(d, std::abs(a[k] - b[k]));
    s = std::max(s, std::abs(b[k]));
  }
  return d / std::max(s, 1.0e-300);
}

}    // namespace

TEST(BondSums, AffineDisplacementGivesHK)
{
  Cloud c = make_cloud(97, 7);
  const double H[9] = {0.01, -0.003, 0.002, 0.004, -0.02, 0.001, -0.005, 0.003, 0.015};
  // a rigid shift as well: U must not see it
  for (int a = 0; a < c.n; a++)
    for (int r = 0; r < 3; r++) {
      double hx = 0.0;
      for (int k = 0; k < 3; k++) hx += H[3 * r + k] * c.x0[3 * a + k];
      c.x[3 * a + r] = c.x0[3 * a + r] + hx + 0.7;
    }
  double K[9] = {0}, m0[3] = {0};
  for (size_t b = 0; b < c.j.size(); b++) {
    const double *e = &c.x0[3 * c.j[b]];
    for (int r = 0; r < 3; r++) {
      m0[r] += c.w[b] * e[r];
      for (int k = 0; k < 3; k++) K[3 * r + k] += c.w[b] * e[r] * e[k];
    }
  }
  double HK[9] = {0}, Hm[3] = {0}, HKHt[9] = {0};
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++) {
      Hm[r] += H[3 * r + k] * m0[k];
      for (int l = 0; l < 3; l++) HK[3 * r + k] += H[3 * r + l] * K[3 * l + k];
    }
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++)
      for (int l = 0; l < 3; l++) HKHt[3 * r + k] += HK[3 * r + l] * H[3 * k + l];

  const Positions p{c.x.data(), c.x0.data()};
  const BondList bl{c.j.data(), c.w.data(), 0, static_cast<int>(c.j.size())};
  double N[9], s[3], m[6];
  deformation<true>(p, bl, 0, N, s, m);
  EXPECT_LT(rel_diff(N, HK, 9), 1e-10);
  EXPECT_LT(rel_diff(s, Hm, 3), 1e-10);
  const double msym[6] = {HKHt[0], HKHt[4], HKHt[8], HKHt[1], HKHt[2], HKHt[5]};
  EXPECT_LT(rel_diff(m, msym, 6), 1e-10);

  // without the moments the same N and s, bit for bit
  double N2[9], s2[3];
  deformation<false>(p, bl, 0, N2, s2, nullptr);
  for (int k = 0; k < 9; k++) EXPECT_EQ(N2[k], N[k]);
  for (int k = 0; k < 3; k++) EXPECT_EQ(s2[k], s[k]);
}

namespace {

// the force on point 0 bond by bond, i-terms included, and its virial
template <StabPass STAB> void naive_force(const Cloud &c, double *f, double *v)
{
  for (int k = 0; k < 3; k++) f[k] = 0.0;
  for (int k = 0; k < 6; k++) v[k] = 0.0;
  for (size_t b = 0; b < c.j.size(); b++) {
    const int j = c.j[b];
    double e[3], y[3], uu[3];
    for (int d = 0; d < 3; d++) {
      e[d] = c.x0[3 * j + d] - c.x0[d];
      y[d] = c.x[3 * j + d] - c.x[d];
      uu[d] = y[d] - e[d];
    }
    double g[3];
    for (int r = 0; r < 3; r++) {
      g[r] = 0.0;
      for (int k = 0; k < 3; k++) g[r] += (c.B[BREC * j + 3 * k + r] + c.B[3 * k + r]) * e[k];
      if (has_springs(STAB)) g[r] += (sc(c, 0) + sc(c, j)) * uu[r];
      if (STAB == StabPass::SILLING_QUADRATIC) {
        // (alpha_j Q_j - alpha_i Q_i) phi_q(xi), Q's columns stored one after the other
        const double q[6] = {e[0] * e[0], e[1] * e[1], e[2] * e[2],
                             e[0] * e[1], e[0] * e[2], e[1] * e[2]};
        for (int k = 0; k < 6; k++) g[r] += (c.Q[QREC * j + 3 * k + r] - c.Q[3 * k + r]) * q[k];
      }
      if (STAB == StabPass::WAN)
        for (int k = 0; k < 3; k++) g[r] += (c.T[9 * j + 3 * k + r] + c.T[3 * k + r]) * uu[k];
    }
    if (STAB == StabPass::HOURGLASS) {
      double z[3], ry2 = 0.0, re = 0.0, zy = 0.0;
      for (int r = 0; r < 3; r++) {
        double hi = 0.0, hj = 0.0;
        for (int k = 0; k < 3; k++) {
          hi += c.T[3 * k + r] * e[k];
          hj += c.T[9 * j + 3 * k + r] * e[k];
        }
        // T holds c H: c_i (U - H_i xi) + c_j (U - H_j xi)
        z[r] = (sc(c, 0) + sc(c, j)) * uu[r] - hi - hj;
        ry2 += y[r] * y[r];
        re += e[r] * e[r];
      }
      for (int r = 0; r < 3; r++) zy += z[r] * y[r];
      if (ry2 > 0.0)
        for (int r = 0; r < 3; r++) g[r] += zy / (ry2 * std::sqrt(re)) * y[r];
    }
    const double w = c.w[b];
    for (int r = 0; r < 3; r++) f[r] += w * g[r];
    const int vr[6] = {0, 1, 2, 0, 0, 1}, vc[6] = {0, 1, 2, 1, 2, 2};
    for (int k = 0; k < 6; k++) v[k] += -0.5 * w * y[vr[k]] * g[vc[k]];
  }
}

template <StabPass STAB> void check_force_paths(unsigned seed)
{
  Cloud c = make_cloud(123, seed);
  std::mt19937 gen(seed + 1);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (auto &v : c.x) v += u(gen);
  const Positions p{c.x.data(), c.x0.data()};
  const BondList bl{c.j.data(), c.w.data(), 0, static_cast<int>(c.j.size())};
  const ForceTerms ft{c.B.data(), c.T.data(), c.Q.data()};

  double fv[3], v[6], f[3], fref[3], vref[6];
  forces<STAB, 1>(p, bl, ft, 0, fv, v);
  forces<STAB, 0>(p, bl, ft, 0, f, nullptr);
  naive_force<STAB>(c, fref, vref);
  EXPECT_LT(rel_diff(fv, fref, 3), 1e-12) << "STAB " << static_cast<int>(STAB);
  EXPECT_LT(rel_diff(v, vref, 6), 1e-12) << "STAB " << static_cast<int>(STAB);

  if (STAB == StabPass::HOURGLASS) return;    // the hourglass term has no factored i-term
  // the i-terms the caller adds from the moments
  double mx[3] = {0, 0, 0}, mu[3] = {0, 0, 0}, mq[6] = {0, 0, 0, 0, 0, 0};
  for (size_t b = 0; b < c.j.size(); b++) {
    double e[3];
    for (int d = 0; d < 3; d++) {
      e[d] = c.x0[3 * c.j[b] + d] - c.x0[d];
      mx[d] += c.w[b] * e[d];
      mu[d] += c.w[b] * ((c.x[3 * c.j[b] + d] - c.x[d]) - e[d]);
    }
    const double q[6] = {e[0] * e[0], e[1] * e[1], e[2] * e[2], e[0] * e[1], e[0] * e[2], e[1] * e[2]};
    for (int k = 0; k < 6; k++) mq[k] += c.w[b] * q[k];
  }
  for (int r = 0; r < 3; r++) {
    for (int k = 0; k < 3; k++) f[r] += c.B[3 * k + r] * mx[k];
    if (has_springs(STAB)) f[r] += sc(c, 0) * mu[r];
    if (STAB == StabPass::SILLING_QUADRATIC)
      for (int k = 0; k < 6; k++) f[r] -= c.Q[3 * k + r] * mq[k];
    if (STAB == StabPass::WAN)
      for (int k = 0; k < 3; k++) f[r] += c.T[3 * k + r] * mu[k];
  }
  EXPECT_LT(rel_diff(f, fref, 3), 1e-12) << "STAB " << static_cast<int>(STAB);
}

}    // namespace

TEST(BondSums, ForcePathsAgreeNone) { check_force_paths<StabPass::NONE>(11); }
TEST(BondSums, ForcePathsAgreeSilling) { check_force_paths<StabPass::SILLING>(12); }
TEST(BondSums, ForcePathsAgreeHourglass) { check_force_paths<StabPass::HOURGLASS>(13); }
TEST(BondSums, ForcePathsAgreeWan) { check_force_paths<StabPass::WAN>(14); }
TEST(BondSums, ForcePathsAgreeQuadraticFit) { check_force_paths<StabPass::SILLING_QUADRATIC>(15); }

namespace {
NOSPD_KERNEL_CLONES void quadratic(const Positions &p, const BondList &bl, int i, double *out)
{
  quadratic_sums(p, bl, i, out);
}
}    // namespace

// the quadratic fit's sums against a bond-by-bond sum: N2 = sum w U phi^T
// column by column, then sum w phi_q
TEST(BondSums, QuadraticSums)
{
  Cloud c = make_cloud(101, 31);
  std::mt19937 gen(32);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (size_t k = 0; k + 1 < c.x.size(); k++) c.x[k] += u(gen);
  const Positions p{c.x.data(), c.x0.data()};
  const BondList bl{c.j.data(), c.w.data(), 0, static_cast<int>(c.j.size())};
  double out[QSUMS], ref[QSUMS] = {};
  quadratic(p, bl, 0, out);
  for (size_t b = 0; b < c.j.size(); b++) {
    const int j = c.j[b];
    double e[3], uu[3];
    for (int d = 0; d < 3; d++) {
      e[d] = c.x0[3 * j + d] - c.x0[d];
      uu[d] = (c.x[3 * j + d] - c.x[d]) - e[d];
    }
    const double phi[9] = {e[0], e[1], e[2], e[0] * e[0], e[1] * e[1], e[2] * e[2],
                           e[0] * e[1], e[0] * e[2], e[1] * e[2]};
    for (int k = 0; k < 9; k++)
      for (int r = 0; r < 3; r++) ref[3 * k + r] += c.w[b] * uu[r] * phi[k];
    for (int k = 0; k < 6; k++) ref[27 + k] += c.w[b] * phi[3 + k];
  }
  EXPECT_LT(rel_diff(out, ref, 27), 1e-13);
  EXPECT_LT(rel_diff(out + 27, ref + 27, 6), 1e-13);
}

TEST(BondSums, HourglassVanishesOnAffineFieldAndCollapsedBond)
{
  // 62 bonds: the hourglass sums take 60 four at a time and the last two
  // one by one, so both paths meet the affine field and a collapsed bond
  Cloud c = make_cloud(63, 21);
  const double H[9] = {0.02, 0.01, 0.0, -0.01, 0.03, 0.005, 0.0, 0.002, -0.01};
  for (int a = 0; a < c.n; a++) {
    for (int r = 0; r < 3; r++) {
      double hx = 0.0;
      for (int k = 0; k < 3; k++) hx += H[3 * r + k] * c.x0[3 * a + k];
      c.x[3 * a + r] = c.x0[3 * a + r] + hx;
    }
    // T = c H (the hourglass pass's record) with each point's own c
    for (int r = 0; r < 3; r++)
      for (int k = 0; k < 3; k++) c.T[9 * a + 3 * k + r] = sc(c, a) * H[3 * r + k];
  }
  for (int a = 0; a < c.n; a++)
    for (int k = 0; k < 9; k++) c.B[BREC * a + k] = 0.0;
  const Positions p{c.x.data(), c.x0.data()};
  const BondList bl{c.j.data(), c.w.data(), 0, static_cast<int>(c.j.size())};
  const ForceTerms ft{c.B.data(), c.T.data()};
  double f[3], v[6], f0[3];
  forces<StabPass::HOURGLASS, 1>(p, bl, ft, 0, f, v);
  forces<StabPass::HOURGLASS, 0>(p, bl, ft, 0, f0, nullptr);
  for (int d = 0; d < 3; d++) EXPECT_LT(std::abs(f[d]), 1e-13);
  for (int d = 0; d < 3; d++) EXPECT_LT(std::abs(f0[d]), 1e-13);

  // partners 5 (a bond of the four-at-a-time path) and 62 (the last bond)
  // pushed onto point 0 and given another H: those bonds have no direction
  // and take no term, the rest stay affine, no NaN
  for (int a : {5, 62}) {
    for (int d = 0; d < 3; d++) c.x[3 * a + d] = c.x[d];
    for (int k = 0; k < 9; k++) c.T[9 * a + k] = 0.3;
  }
  forces<StabPass::HOURGLASS, 1>(p, bl, ft, 0, f, v);
  forces<StabPass::HOURGLASS, 0>(p, bl, ft, 0, f0, nullptr);
  for (int d = 0; d < 3; d++) {
    EXPECT_TRUE(std::isfinite(f[d]) && std::isfinite(f0[d]));
    EXPECT_LT(std::abs(f[d]), 1e-13);
    EXPECT_LT(std::abs(f0[d]), 1e-13);
  }
}

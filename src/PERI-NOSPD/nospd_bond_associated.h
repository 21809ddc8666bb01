/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Bond-associated ("horizon-stabilized") correspondence kernels.
   Knows nothing of LAMMPS.

   For the bond (i,j) the bond-associated family is
       h_ij = { k in H_i : |X_k - X_j| <= r },
   and with w_k = omega_ik V_k, b_k = xi_ik, U_k = Y_ik - xi_ik:
       K_j = sum_{k in h_ij} w_k b_k (x) b_k,
       F_j = I + (sum_{k in h_ij} w_k U_k (x) b_k) K_j^-1,   P_j = P(F_j).
   Membership is symmetric, k in h_ij <=> j in h_ik, so both forms are
   a state-based model with the force state
       T_i<xi_ik> = omega_ik Gbar_k b_k,
       Form I :  Gbar_k = (V_h(k)/V_H) P_k K_k^-1             (bond ik only)
       Form II:  Gbar_k = sum_{j in h_ik} beta_j P_j K_j^-1,   beta_j = V_h(j)/S
   and f_i = sum_k (T_i<xi_ik> - T_k<xi_ki>) V_k.  Form II is the exact
   gradient of E = sum_i V_i sum_j beta_j W(F_j).

   The two sums over a bond-associated family (for F_j and for Gbar_k)
   dominate the cost.  All the reference data of a family - member
   lists, K_j^-1, weights - depend only on the family's reference offsets
   and weights, so they live in a BondPattern that every family of the
   same shape shares (on a regular grid: one for the interior and a few
   hundred near surfaces).  The members of a pattern are ordered
   boustrophedon-wise (planes, rows, and alternating directions), so that
   on a grid each h_ij is a union of about 10 contiguous runs (3D, delta =
   3 dx, ratio 1) rather than 55 scattered members; a run costs one
   difference of prefix sums.  A pattern that many families share also
   gets a straight-line program of pairwise sums (about 13 row additions
   per h_ij).  For the linear small-strain law the bonds skip the general
   constitutive call.  Families of one pattern may be evaluated two at a
   time ("lanes"), which the compiler packs into vector registers.
------------------------------------------------------------------------- */

#ifndef NOSPD_BOND_ASSOCIATED_H
#define NOSPD_BOND_ASSOCIATED_H

#include "nospd_constitutive.h"
#include "nospd_simd.h"
#include "nospd_sum_program.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

namespace NOSPD {

enum class HSForm { I = 1, II = 2 };

/* Reference data of one family shape.  Slots are the members in
   boustrophedon order; per-slot tensors are dim x dim, row-major. */
struct BondPattern {
  int n = 0;                       // family size
  int dim = 3;
  double radius = 0.0;             // bond-associated horizon r = ratio * delta
  double tol = 0.0;                // the conditioning its K's were tested against
  std::vector<double> b;           // reference offsets xi_k, 3 per slot, one spare double
  std::vector<double> w;           // omega_k V_k
  std::vector<int> run_first;      // runs of slot j: run_first[j] .. run_first[j+1]
  std::vector<uint16_t> runs;      // (first, last + 1) slot pairs
  std::vector<double> kinv;        // K_j^-1 (zero where singular), and one spare double
  std::vector<double> cforce;      // c_j: beta_j (Form II) or V_h(j)/V_H (Form I)
  std::vector<double> beta;        // V_h(j)/S: weight of bond j in energy and stress
  std::vector<char> singular;      // K_j singular: bond falls back to the family's F
  int nsingular = 0;
  double kinv_full[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};    // K_i^-1 of the whole family
  bool atom_singular = false;
  long members = 0;                // sum_j |h_ij|, for the log

  // matching: quantized offsets in lexicographic (z, y, x) order and the
  // slot of each lexicographic position
  std::vector<int64_t> key;
  std::vector<int> lex_to_slot;
  uint64_t shape_hash = 0;    // of key and weights, for the stencil's keys (0: not yet)

  // bond sums by program, built for patterns that many families share
  SumProgram program;

  double bytes() const
  {
    return sizeof(BondPattern) + 8.0 * (b.size() + w.size() + kinv.size() +
        cforce.size() + beta.size() + key.size()) +
        4.0 * (run_first.size() + lex_to_slot.size()) + 2.0 * runs.size() + singular.size() +
        program.bytes();
  }
};

/* Boustrophedon order of members given in lexicographic (z, y, x) order
   of their quantized offsets key[3l..3l+2] = (qx, qy, qz): planes of
   equal z in turn, the rows of odd planes reversed, and every other row
   reversed.  Consecutive rows then meet end to end, which merges the runs
   of a sphere's section.  Returns lex position -> slot. */
inline std::vector<int> boustrophedon(const std::vector<int64_t> &key, int n)
{
  std::vector<std::vector<std::vector<int>>> planes;    // plane -> row -> lex positions
  for (int l = 0; l < n; ++l) {
    const int64_t *k = &key[3 * l];
    if (planes.empty() || key[3 * planes.back()[0][0] + 2] != k[2]) planes.push_back({{l}});
    else if (key[3 * planes.back().back()[0] + 1] != k[1]) planes.back().push_back({l});
    else planes.back().back().push_back(l);
  }
  std::vector<int> lex_to_slot(n);
  int slot = 0, row = 0;
  for (size_t p = 0; p < planes.size(); ++p) {
    auto &rows = planes[p];
    if (p % 2) std::reverse(rows.begin(), rows.end());
    for (auto &r : rows) {
      if (row++ % 2) std::reverse(r.begin(), r.end());
      for (int l : r) lex_to_slot[l] = slot++;
    }
  }
  return lex_to_slot;
}

/* Build a pattern from one family given in lexicographic order: offsets
   (3 per member), weights omega V, volumes V, quantized keys.  tol is the
   conditioning below which a shape tensor counts as singular. */
inline void build_pattern(BondPattern &p, int dim, int n, const double *b_lex,
                          const double *w_lex, const double *vol_lex,
                          const std::vector<int64_t> &key_lex, double radius, HSForm form,
                          double tol)
{
  p = BondPattern();
  p.n = n;
  p.dim = dim;
  p.radius = radius;
  p.tol = tol;
  p.key = key_lex;
  p.lex_to_slot = boustrophedon(key_lex, n);
  const int nc = dim * dim;
  p.b.assign(3 * n + 1, 0.0);    // + 1: an offset loads as 4 doubles
  p.w.assign(n, 0.0);
  std::vector<double> vol(n);
  for (int l = 0; l < n; ++l) {
    const int s = p.lex_to_slot[l];
    for (int c = 0; c < 3; ++c) p.b[3 * s + c] = b_lex[3 * l + c];
    if (dim == 2) p.b[3 * s + 2] = 0.0;
    p.w[s] = w_lex[l];
    vol[s] = vol_lex[l];
  }

  // the whole family: K_i, and its volume V_H
  auto shape = [&](const Mat3 &K, double *out) {
    Mat3 Kd = K, Ki;
    if (dim == 2) {
      Kd(0, 2) = Kd(1, 2) = Kd(2, 0) = Kd(2, 1) = 0.0;
      Kd(2, 2) = 1.0;
    }
    const bool ok = safe_inverse(Kd, dim, tol, Ki);
    for (int r = 0; r < dim; ++r)
      for (int c = 0; c < dim; ++c) out[r * dim + c] = Ki(r, c);
    return ok;
  };
  Mat3 K = Mat3::Zero();
  double vh_all = 0.0;
  for (int s = 0; s < n; ++s) {
    const Vec3 bs(p.b[3 * s], p.b[3 * s + 1], p.b[3 * s + 2]);
    K += p.w[s] * bs * bs.transpose();
    vh_all += vol[s];
  }
  p.atom_singular = (n == 0) || !shape(K, p.kinv_full);

  // bond-associated families: runs of members, K_j, V_h(j)
  const double r2 = radius * radius;
  p.run_first.assign(n + 1, 0);
  p.kinv.assign(nc * n + 1, 0.0);    // + 1: a row of K_j^-1 loads as 4 doubles
  p.cforce.assign(n, 0.0);
  p.beta.assign(n, 0.0);
  p.singular.assign(n, 1);
  std::vector<double> vh(n, 0.0);
  for (int j = 0; j < n; ++j) {
    p.run_first[j] = (int) p.runs.size() / 2;
    Mat3 Kj = Mat3::Zero();
    bool inside = false;
    for (int k = 0; k <= n; ++k) {
      bool member = false;
      if (k < n) {
        const double dx = p.b[3 * k] - p.b[3 * j], dy = p.b[3 * k + 1] - p.b[3 * j + 1],
                     dz = p.b[3 * k + 2] - p.b[3 * j + 2];
        member = dx * dx + dy * dy + dz * dz <= r2;
      }
      if (member) {
        const Vec3 bk(p.b[3 * k], p.b[3 * k + 1], p.b[3 * k + 2]);
        Kj += p.w[k] * bk * bk.transpose();
        vh[j] += vol[k];
        p.members++;
      }
      if (member && !inside) p.runs.push_back((uint16_t) k);
      if (!member && inside) p.runs.push_back((uint16_t) k);
      inside = member;
    }
    if (!p.atom_singular) p.singular[j] = shape(Kj, &p.kinv[nc * j]) ? 0 : 1;
    p.nsingular += p.singular[j];
  }
  p.run_first[n] = (int) p.runs.size() / 2;

  const double S = std::accumulate(vh.begin(), vh.end(), 0.0);
  for (int j = 0; j < n; ++j) {
    p.beta[j] = S > 0.0 ? vh[j] / S : 0.0;
    p.cforce[j] = (form == HSForm::II) ? p.beta[j] : vh[j] / vh_all;
  }
}

/* Several families of one pattern are evaluated together, L "lanes" (1
   or 2), stored innermost: every array below is [row][value][lane].  The
   lanes share the pattern's member lists and K_j^-1, so one program step
   or one 3x3 product serves them all, and the compiler packs the lanes
   into vector registers.

   Rows of dim*dim values.  Inside the sums a 3D row is split into its
   first 8 values (64 bytes per lane: whole packed registers) and a ninth
   kept in a side array; a 2D row is 4 values. */
template <int DIM, int L> struct RowLayout {
  static constexpr int NC = DIM * DIM;          // values per row
  static constexpr int NM = DIM == 3 ? 8 : 4;   // values in the main array
  static constexpr int NA = NC - NM;            // values in the side array (0 or 1)
  static constexpr int RM = NM * L;             // doubles per main row
};

/* Scratch of a family evaluation: the sums' work rows (main and side), the
   bond sums, and the bond tensors of Form I. */
struct StateScratch {
  std::vector<double> work, side, sums, g;
  void reserve(int n, int nrow, int lanes)
  {
    if ((int) sums.size() < 9 * lanes * n) {
      sums.assign(9 * lanes * n, 0.0);
      g.assign(9 * lanes * n, 0.0);
    }
    if ((int) side.size() < lanes * (nrow + 1)) {
      work.assign(8 * lanes * (nrow + 1) + 8, 0.0);
      side.assign(lanes * (nrow + 1), 0.0);
    }
  }
  // the main work rows, aligned to 64 bytes
  double *main_rows()
  {
    auto a = reinterpret_cast<std::uintptr_t>(work.data());
    return work.data() + ((64 - a % 64) % 64) / sizeof(double);
  }
};

// row kernels on distinct rows: plain loops that become packed arithmetic
template <int N>
inline void row_sum(double *__restrict c, const double *__restrict a, const double *__restrict b)
{
  for (int m = 0; m < N; ++m) c[m] = a[m] + b[m];
}

template <int N> inline void row_add(double *__restrict acc, const double *__restrict a)
{
  for (int m = 0; m < N; ++m) acc[m] += a[m];
}

template <int N>
inline void row_add_diff(double *__restrict acc, const double *__restrict hi,
                         const double *__restrict lo)
{
  for (int m = 0; m < N; ++m) acc[m] += hi[m] - lo[m];
}

/* S_j = sum_{k in h_ij} X_k for every slot j.  X is in the work rows
   0..n-1 (main and side), which the evaluation overwrites; S goes to out
   as [j][value][lane]. */
template <int DIM, int L>
inline void bond_sums(const BondPattern &p, StateScratch &s, double *__restrict out)
{
  using RL = RowLayout<DIM, L>;
  constexpr int NC = RL::NC, NA = RL::NA, RM = RL::RM;
  const int n = p.n;
  const SumProgram &pg = p.program;
  double *__restrict w = s.main_rows();
  double *__restrict side = s.side.data();

  auto emit = [&](int j, const double *acc, const double *acc_side) {
    double *o = out + NC * L * j;
    for (int q = 0; q < RM; ++q) o[q] = acc[q];
    if (NA)
      for (int l = 0; l < L; ++l) o[RM + l] = acc_side[l];
  };

  if (pg.ready()) {
    // index loads, not arithmetic, bound this loop: a record's fields
    // come in one load (the first field in the low bits)
    static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "records are read little-endian");
    const uint16_t *c = pg.code.data();
    const uint16_t *end = c + pg.code.size();
    while (c < end) {
      uint64_t rec;
      std::memcpy(&rec, c, sizeof(rec));
      const unsigned d = rec & 0xffff, a = (rec >> 16) & 0xffff, b = (rec >> 32) & 0xffff;
      c += 4;
      if (d != SumProgram::OUTPUT) {
        row_sum<RM>(w + RM * d, w + RM * a, w + RM * b);
        if (NA) row_sum<L>(side + L * d, side + L * a, side + L * b);
      } else {
        double acc[RM] = {}, acc_side[L] = {};
        for (unsigned q = 0; q < b; ++q) {
          row_add<RM>(acc, w + RM * c[q]);
          if (NA) row_add<L>(acc_side, side + L * c[q]);
        }
        emit(a, acc, acc_side);
        c += (b + 3) & ~3u;
      }
    }
    return;
  }

  // prefix sums in place, shifted by one row: row k = sum_{l < k} X_l
  double run[RM] = {}, run_side[L] = {};
  for (int k = 0; k <= n; ++k) {
    for (int q = 0; q < RM; ++q) {
      const double x = k < n ? w[RM * k + q] : 0.0;
      w[RM * k + q] = run[q];
      run[q] += x;
    }
    if (NA)
      for (int l = 0; l < L; ++l) {
        const double x = k < n ? side[L * k + l] : 0.0;
        side[L * k + l] = run_side[l];
        run_side[l] += x;
      }
  }
  for (int j = 0; j < n; ++j) {
    double acc[RM] = {}, acc_side[L] = {};
    const uint16_t *r = &p.runs[2 * p.run_first[j]];
    const int nrun = p.run_first[j + 1] - p.run_first[j];
    for (int q = 0; q < nrun; ++q) {
      const int hi = r[2 * q + 1], lo = r[2 * q];
      row_add_diff<RM>(acc, w + RM * hi, w + RM * lo);
      if (NA) row_add_diff<L>(acc_side, side + L * hi, side + L * lo);
    }
    emit(j, acc, acc_side);
  }
}

// 3x3 embedding of a dim x dim block plus the identity
template <int DIM> inline Mat3 identity_plus(const double *h)
{
  Mat3 F = Mat3::Identity();
  for (int r = 0; r < DIM; ++r)
    for (int c = 0; c < DIM; ++c) F(r, c) += h[r * DIM + c];
  return F;
}

// out = A (dim x dim) times B (dim x dim), row-major
template <int DIM> inline void block_mul(const double *a, const double *b, double *out)
{
  for (int r = 0; r < DIM; ++r)
    for (int c = 0; c < DIM; ++c) {
      double s = 0.0;
      for (int m = 0; m < DIM; ++m) s += a[r * DIM + m] * b[m * DIM + c];
      out[r * DIM + c] = s;
    }
}

template <int DIM> inline void block_of(const Mat3 &M, double *out)
{
  for (int r = 0; r < DIM; ++r)
    for (int c = 0; c < DIM; ++c) out[r * DIM + c] = M(r, c);
}

/* The small-strain law is linear: P(I + H) = lambda tr(e) I + 2 mu e on the
   in-plane (2D) or full (3D) block, e = sym(H).  Its two constants are read
   off first_piola itself and checked against it on a general H, so the law
   keeps its one definition; bonds then skip the general call, and sums of
   stresses become stresses of sums. */
struct LinearLaw {
  bool ok = false;
  double lam = 0.0, mu = 0.0;
};

inline LinearLaw probe_linear_law(Law law, Plane plane, const Lame &m, int dim)
{
  LinearLaw lin;
  if (law != Law::SMALL) return lin;
  const double s = 1.0e-3;
  Mat3 F = Mat3::Identity(), P;
  double W;
  F(0, 0) += s;
  if (!first_piola(law, plane, m, F, P, W)) return lin;
  lin.lam = P(1, 1) / s;
  lin.mu = 0.5 * (P(0, 0) / s - lin.lam);

  // check on a general H
  Mat3 H;
  H << 0.3e-3, -0.7e-3, 0.2e-3, 0.5e-3, -0.4e-3, 0.9e-3, -0.6e-3, 0.1e-3, 0.8e-3;
  if (dim == 2) H(0, 2) = H(1, 2) = H(2, 0) = H(2, 1) = H(2, 2) = 0.0;
  F = Mat3::Identity() + H;
  if (!first_piola(law, plane, m, F, P, W)) return lin;
  double tr = 0.0;
  for (int a = 0; a < dim; ++a) tr += H(a, a);
  double err = 0.0, wl = 0.0;
  for (int a = 0; a < dim; ++a)
    for (int c = 0; c < dim; ++c) {
      const double e = 0.5 * (H(a, c) + H(c, a));
      const double pl = 2.0 * lin.mu * e + (a == c ? lin.lam * tr : 0.0);
      err = std::max(err, std::abs(pl - P(a, c)));
      wl += 0.5 * pl * e;
    }
  lin.ok = err <= 1.0e-10 * P.norm() && std::abs(wl - W) <= 1.0e-10 * std::abs(W);
  return lin;
}

/* One regular bond of a 3D family under the linear law (the hot case):
   H = N K^-1, P = lambda tr(H) I + mu (H + H^T), G = c P K^-1, row by row
   on 4-lane vectors (a row of H is N's row times the rows of K^-1).  The
   rows' fourth lanes carry junk from the load past each row and are
   never used.  Adds beta H to the rows hm and, with energy, beta W to W;
   G goes to g (row-major). */
inline void linear_bond_3d(const double *N, const double *Ki, double lam, double mu, double c,
                           double beta, bool energy, simd::v4 hm[3], double &W, double *g)
{
  using namespace simd;
  const v4 k0 = load4(Ki), k1 = load4(Ki + 3), k2 = load4(Ki + 6);
  const v4 h0 = N[0] * k0 + N[1] * k1 + N[2] * k2;
  const v4 h1 = N[3] * k0 + N[4] * k1 + N[5] * k2;
  const v4 h2 = N[6] * k0 + N[7] * k1 + N[8] * k2;
  const double ltr = lam * (h0[0] + h1[1] + h2[2]);
  const v4 p0 = mu * (h0 + v4{h0[0], h1[0], h2[0], 0.0}) + v4{ltr, 0.0, 0.0, 0.0};
  const v4 p1 = mu * (h1 + v4{h0[1], h1[1], h2[1], 0.0}) + v4{0.0, ltr, 0.0, 0.0};
  const v4 p2 = mu * (h2 + v4{h0[2], h1[2], h2[2], 0.0}) + v4{0.0, 0.0, ltr, 0.0};
  if (energy) W += 0.5 * beta * (dot3(p0, h0) + dot3(p1, h1) + dot3(p2, h2));
  hm[0] += beta * h0;
  hm[1] += beta * h1;
  hm[2] += beta * h2;
  const v4 g0 = c * (p0[0] * k0 + p0[1] * k1 + p0[2] * k2);
  const v4 g1 = c * (p1[0] * k0 + p1[1] * k1 + p1[2] * k2);
  const v4 g2 = c * (p2[0] * k0 + p2[1] * k1 + p2[2] * k2);
  for (int b = 0; b < 3; ++b) {
    g[b] = g0[b];
    g[3 + b] = g1[b];
    g[6 + b] = g2[b];
  }
}

/* Outcome of one family evaluation. */
struct StateOutput {
  Mat3 F;              // deformation gradient of the whole family (output, fallback)
  Mat3 P;              // sum_j beta_j P_j: the family's mean stress
  double W = 0.0;      // sum_j beta_j W(F_j): stored-energy density
  int bad = -2;        // on failure: slot whose law is undefined (-1: the family's F)
  double bad_J = 0.0;  // on failure: det F of that slot (> 0: the law, not F, failed)
  int fallback = 0;    // bonds that used the family's F
};

/* A law whose stress depends on the bond as well as on its F: inelastic
   materials keep history per bond-associated family (nospd_bond_history.h).
   begin() sees the whole family's F before the bonds are evaluated;
   stress() is called for every slot whose K_j is regular, and with slot
   -1 for the state of the whole family that singular bond families fall
   back to.  F arrives with F(2,2) = 1 in 2D (plane stress solves it). */
class BondLaw {
 public:
  virtual ~BondLaw() = default;
  virtual void begin(const Mat3 &F_family) = 0;
  virtual bool stress(int slot, Mat3 &F, Mat3 &P, double &W) = 0;
};

/* What the evaluation of L families of one pattern needs per lane. */
struct LaneInput {
  const Lame *m = nullptr;
  const LinearLaw *lin = nullptr;
  BondLaw *bond_law = nullptr;  // if set, the stress of each bond (else law(F))
  const double *U = nullptr;    // displacement differences in slot order, 3 per slot
  double *t = nullptr;          // out: Gbar_k b_k, 3 per slot
};

/* The evaluation of L families of one pattern, step by step: the work
   rows X_k = w U (x) b and the family's F, each bond's F_j, P_j and
   G_j = c_j P_j K_j^-1, the whole family's state for singular bonds, and
   the force state t_k = Gbar_k b_k.  Form II writes G straight into the
   work rows of the second sum. */
template <int DIM, int L> struct FamilyPass {
  using RL = RowLayout<DIM, L>;
  static constexpr int NC = RL::NC, NM = RL::NM, RM = RL::RM;
  const BondPattern &p;
  HSForm form;
  Law law;
  Plane plane;
  const LaneInput *in;
  bool energy;
  StateOutput *out;
  int n;
  double *__restrict w, *__restrict side, *__restrict sums, *__restrict gI;
  bool linear = true;
  double lam[L], mu[L];
  double hfam[NC][L];
  double cs_force = 0.0, cs_beta = 0.0;
  double hmean[NC][L] = {};    // linear law: sum_j beta_j H_j
  double f33[L] = {};          // other laws: sum_j beta_j F_j,zz (2D: solved in plane stress)
  simd::v4 hm[3] = {};         // its rows, for the 3D one-lane linear bonds
  double gs[NC][L] = {};       // the whole family's G (singular bonds)

  FamilyPass(const BondPattern &p, HSForm form, Law law, Plane plane, const LaneInput *in,
             bool energy, StateScratch &s, StateOutput *out) :
      p(p), form(form), law(law), plane(plane), in(in), energy(energy), out(out), n(p.n),
      w(s.main_rows()), side(s.side.data()), sums(s.sums.data()), gI(s.g.data())
  {
    for (int l = 0; l < L; ++l) {
      linear = linear && in[l].lin && in[l].lin->ok && !in[l].bond_law;
      lam[l] = in[l].lin ? in[l].lin->lam : 0.0;
      mu[l] = in[l].lin ? in[l].lin->mu : 0.0;
    }
  }

  void put(int row, int c, int l, double v)
  {
    if (c < NM) w[RM * row + L * c + l] = v;
    else side[L * row + l] = v;
  }

  // X_k = w U (x) b into the work rows, and the whole family's F from their sum
  void family_rows()
  {
    double nall[NC][L] = {};
    if constexpr (DIM == 3 && L == 1) {
      // rows w U_a b^T on 4-lane vectors; each row's store spills one junk
      // value into the next row's first slot, which that row then overwrites
      using namespace simd;
      v4 n0{}, n1{}, n2{};
      const double *U = in[0].U;
      for (int k = 0; k < n; ++k) {
        const v4 wb = p.w[k] * load4(&p.b[3 * k]);
        const v4 x0 = U[3 * k] * wb, x1 = U[3 * k + 1] * wb, x2 = U[3 * k + 2] * wb;
        double *row = w + RM * k;
        std::memcpy(row, &x0, sizeof(x0));
        std::memcpy(row + 3, &x1, sizeof(x1));
        row[6] = x2[0];
        row[7] = x2[1];
        side[k] = x2[2];
        n0 += x0;
        n1 += x1;
        n2 += x2;
      }
      for (int c = 0; c < 3; ++c) {
        nall[c][0] = n0[c];
        nall[3 + c][0] = n1[c];
        nall[6 + c][0] = n2[c];
      }
    } else {
      for (int k = 0; k < n; ++k) {
        const double *bk = &p.b[3 * k];
        for (int a = 0; a < DIM; ++a)
          for (int l = 0; l < L; ++l) {
            const double wu = p.w[k] * in[l].U[3 * k + a];
            for (int c = 0; c < DIM; ++c) {
              const double x = wu * bk[c];
              put(k, a * DIM + c, l, x);
              nall[a * DIM + c][l] += x;
            }
          }
      }
    }
    for (int l = 0; l < L; ++l) {
      double nl[NC], hl[NC];
      for (int c = 0; c < NC; ++c) nl[c] = nall[c][l];
      block_mul<DIM>(nl, p.kinv_full, hl);
      for (int c = 0; c < NC; ++c) hfam[c][l] = hl[c];
      out[l].F = identity_plus<DIM>(hl);
      if (in[l].bond_law) in[l].bond_law->begin(out[l].F);
    }
  }

  // the linear law's P_j of H_j (pb), with its energy and the mean of H
  void linear_stress(int j, const double (&h)[NC][L], double (&pb)[NC][L])
  {
    double tr[L] = {};
    for (int a = 0; a < DIM; ++a)
      for (int l = 0; l < L; ++l) tr[l] += h[a * DIM + a][l];
    for (int a = 0; a < DIM; ++a)
      for (int c = 0; c < DIM; ++c)
        for (int l = 0; l < L; ++l)
          pb[a * DIM + c][l] =
              mu[l] * (h[a * DIM + c][l] + h[c * DIM + a][l]) + (a == c ? lam[l] * tr[l] : 0.0);
    if (energy)
      for (int l = 0; l < L; ++l) {
        double w2 = 0.0;
        for (int c = 0; c < NC; ++c) w2 += pb[c][l] * h[c][l];
        out[l].W += 0.5 * p.beta[j] * w2;
      }
    for (int c = 0; c < NC; ++c)
      for (int l = 0; l < L; ++l) hmean[c][l] += p.beta[j] * h[c][l];
  }

  // any other law's P_j (pb) through the lane's law; false where undefined
  bool law_stress(int j, const double (&h)[NC][L], double (&pb)[NC][L])
  {
    for (int l = 0; l < L; ++l) {
      double hl[NC];
      for (int c = 0; c < NC; ++c) hl[c] = h[c][l];
      Mat3 F = identity_plus<DIM>(hl), P;
      double W;
      if (!(in[l].bond_law ? in[l].bond_law->stress(j, F, P, W)
                           : first_piola(law, plane, *in[l].m, F, P, W))) {
        out[l].bad = j;
        out[l].bad_J = F.determinant();
        return false;
      }
      out[l].P += p.beta[j] * P;
      out[l].W += p.beta[j] * W;
      f33[l] += p.beta[j] * F(2, 2);
      for (int a = 0; a < DIM; ++a)
        for (int c = 0; c < DIM; ++c) pb[a * DIM + c][l] = P(a, c);
    }
    return true;
  }

  // bond j: F_j = I + N_j K_j^-1, P_j and G_j; false where the law is undefined
  bool bond(int j)
  {
    double g[NC][L];
    if (p.singular[j]) {
      for (int c = 0; c < NC; ++c)
        for (int l = 0; l < L; ++l) g[c][l] = 0.0;
      cs_force += p.cforce[j];
      cs_beta += p.beta[j];
      for (int l = 0; l < L; ++l) out[l].fallback++;
    } else if (DIM == 3 && L == 1 && linear) {
      linear_bond_3d(sums + NC * j, &p.kinv[NC * j], lam[0], mu[0], p.cforce[j], p.beta[j],
                     energy, hm, out[0].W, &g[0][0]);
    } else {
      const double *N = sums + NC * L * j;    // [c][l]
      const double *Ki = &p.kinv[NC * j];
      double h[NC][L], pb[NC][L];
      for (int a = 0; a < DIM; ++a)
        for (int b = 0; b < DIM; ++b)
          for (int l = 0; l < L; ++l) {
            double v = 0.0;
            for (int m = 0; m < DIM; ++m) v += N[L * (a * DIM + m) + l] * Ki[m * DIM + b];
            h[a * DIM + b][l] = v;
          }
      if (linear) linear_stress(j, h, pb);
      else if (!law_stress(j, h, pb)) return false;
      const double cj = p.cforce[j];
      for (int a = 0; a < DIM; ++a)
        for (int b = 0; b < DIM; ++b)
          for (int l = 0; l < L; ++l) {
            double v = 0.0;
            for (int m = 0; m < DIM; ++m) v += pb[a * DIM + m][l] * Ki[m * DIM + b];
            g[a * DIM + b][l] = cj * v;
          }
    }
    for (int c = 0; c < NC; ++c)
      for (int l = 0; l < L; ++l) {
        if (form == HSForm::II) put(j, c, l, g[c][l]);
        else gI[NC * L * j + L * c + l] = g[c][l];
      }
    return true;
  }

  // singular bond families: the family's F, P(F) K^-1 over the whole family
  bool fallback()
  {
    if constexpr (DIM == 3 && L == 1) {
      if (linear)    // the 3D one-lane linear bonds' H, first
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) hmean[3 * a + b][0] += hm[a][b];
    }
    if (!(cs_force > 0.0 || cs_beta > 0.0)) return true;
    for (int l = 0; l < L; ++l) {
      Mat3 F = out[l].F, P;
      double W;
      if (!(in[l].bond_law ? in[l].bond_law->stress(-1, F, P, W)
                           : first_piola(law, plane, *in[l].m, F, P, W))) {
        out[l].bad = -1;
        out[l].bad_J = F.determinant();
        return false;
      }
      out[l].F = F;
      if (linear)
        for (int c = 0; c < NC; ++c) hmean[c][l] += cs_beta * hfam[c][l];
      else
        out[l].P += cs_beta * P;
      f33[l] += cs_beta * F(2, 2);
      out[l].W += cs_beta * W;
      double pl[NC], gl[NC];
      block_of<DIM>(P, pl);
      block_mul<DIM>(pl, p.kinv_full, gl);
      for (int c = 0; c < NC; ++c) gs[c][l] = gl[c];
    }
    return true;
  }

  // the family's mean stress: under the linear law P of the bonds' mean H;
  // in 2D the out-of-plane stretch is the bonds' mean, as the stress is
  void mean_stress()
  {
    if (linear)
      for (int l = 0; l < L; ++l) {
        double hl[NC];
        for (int c = 0; c < NC; ++c) hl[c] = hmean[c][l];
        Mat3 F = identity_plus<DIM>(hl);
        double W;
        first_piola(law, plane, *in[l].m, F, out[l].P, W);
        f33[l] = F(2, 2);
      }
    if constexpr (DIM == 2)
      for (int l = 0; l < L; ++l) out[l].F(2, 2) = f33[l];
  }

  // force state: t_k = Gbar_k b_k (Form II: the second sum is in sums)
  void force_state()
  {
    for (int k = 0; k < n; ++k) {
      double gk[NC][L];
      if (form == HSForm::II) {
        const double *row = sums + NC * L * k;
        for (int c = 0; c < NC; ++c)
          for (int l = 0; l < L; ++l) gk[c][l] = row[L * c + l] + cs_force * gs[c][l];
      } else if (p.singular[k]) {
        for (int c = 0; c < NC; ++c)
          for (int l = 0; l < L; ++l) gk[c][l] = p.cforce[k] * gs[c][l];
      } else {
        const double *row = gI + NC * L * k;
        for (int c = 0; c < NC; ++c)
          for (int l = 0; l < L; ++l) gk[c][l] = row[L * c + l];
      }
      const double *bk = &p.b[3 * k];
      for (int l = 0; l < L; ++l) {
        double *tk = in[l].t + 3 * k;
        for (int a = 0; a < DIM; ++a) {
          double v = 0.0;
          for (int c = 0; c < DIM; ++c) v += gk[a * DIM + c][l] * bk[c];
          tk[a] = v;
        }
        if (DIM == 2) tk[2] = 0.0;
      }
    }
  }
};

/* Evaluate L families that share the pattern p.  The force state of each
   is T_i<xi_k> = omega_k t_k.  The energy is summed only if asked for.
   Returns false where the law is undefined (det F <= 0); out[l].bad names
   the bond of the lane that failed. */
template <int DIM, int L>
bool evaluate_families(const BondPattern &p, HSForm form, Law law, Plane plane,
                       const LaneInput *in, bool energy, StateScratch &s, StateOutput *out)
{
  const int n = p.n;
  for (int l = 0; l < L; ++l) {
    out[l].P.setZero();
    out[l].W = 0.0;
    out[l].fallback = 0;
    out[l].F = Mat3::Identity();
  }
  if (p.atom_singular) {
    for (int l = 0; l < L; ++l)
      for (int k = 0; k < 3 * n; ++k) in[l].t[k] = 0.0;
    return true;
  }
  s.reserve(n, std::max(n, p.program.nrow), L);
  FamilyPass<DIM, L> e(p, form, law, plane, in, energy, s, out);
  e.family_rows();
  bond_sums<DIM, L>(p, s, e.sums);
  for (int j = 0; j < n; ++j)
    if (!e.bond(j)) return false;
  if (!e.fallback()) return false;
  e.mean_stress();
  // Gbar_k: Form II sums G over the bond-associated family of k
  if (form == HSForm::II) bond_sums<DIM, L>(p, s, e.sums);
  e.force_state();
  return true;
}

/* One family: the single-lane case. */
template <int DIM>
bool evaluate_family(const BondPattern &p, HSForm form, Law law, Plane plane, const Lame &m,
                     const LinearLaw &lin, bool energy, const double *U, double *t,
                     StateScratch &s, StateOutput &out, BondLaw *bond_law = nullptr)
{
  LaneInput in;
  in.m = &m;
  in.lin = &lin;
  in.bond_law = bond_law;
  in.U = U;
  in.t = t;
  return evaluate_families<DIM, 1>(p, form, law, plane, &in, energy, s, &out);
}

/* The member lists of every bond-associated family of a pattern (input of
   build_sum_program). */
inline std::vector<std::vector<int>> member_sets(const BondPattern &p)
{
  std::vector<std::vector<int>> sets(p.n);
  for (int j = 0; j < p.n; ++j) {
    const uint16_t *r = &p.runs[2 * p.run_first[j]];
    for (int q = 0; q < p.run_first[j + 1] - p.run_first[j]; ++q)
      for (int k = r[2 * q]; k < r[2 * q + 1]; ++k) sets[j].push_back(k);
  }
  return sets;
}

/* F_j of one bond-associated family (output and tests): slot j of the
   pattern, U in slot order.  Returns false (F = family F) where K_j is
   singular. */
template <int DIM>
bool bond_defgrad(const BondPattern &p, int j, const double *U, Mat3 &F)
{
  constexpr int NC = DIM * DIM;
  double nsum[NC] = {}, h[NC];
  const bool own = !p.singular[j];
  for (int k = 0; k < p.n; ++k) {
    if (own) {
      const double dx = p.b[3 * k] - p.b[3 * j], dy = p.b[3 * k + 1] - p.b[3 * j + 1],
                   dz = p.b[3 * k + 2] - p.b[3 * j + 2];
      if (dx * dx + dy * dy + dz * dz > p.radius * p.radius) continue;
    }
    for (int a = 0; a < DIM; ++a)
      for (int c = 0; c < DIM; ++c) nsum[a * DIM + c] += p.w[k] * U[3 * k + a] * p.b[3 * k + c];
  }
  block_mul<DIM>(nsum, own ? &p.kinv[NC * j] : p.kinv_full, h);
  F = identity_plus<DIM>(h);
  return own;
}

/* Bounds on how fast a family's forces change with the displacements,
   linearized at the reference, for the stable time step (the bonds fix's
   stiffness bound).  With H_j = sum_{l in h_j} U_l (x) a_jl, a_jl = w_l
   K_j^-1 b_l, and U_l = u_l - u_i, H_j changes by at most
       D_j = sum_{l in h_j} |a_jl| + |m_j|,   m_j = sum_{l in h_j} a_jl,
   per unit displacement of every point of {i} and h_j (the whole family
   with K^-1 where K_j is singular: a_sl, m_s, D_s).  P changes by at most
   |C| as much.  The family's force on member k, w_k t_k, is
       Form II: sum_{j : k in h_j} c_j P_j a_jk + cs P_s a_sk,
       Form I:  c_k P_k a_kk  (c_k P_s a_sk where K_k is singular),
   (cs: the c_j of the singular bonds) and on the centre i the sum of
   those, which in Form II is sum_j c_j P_j m_j + cs P_s m_s.  rows[k]
   (k < n) bounds the sum over all points q of |d (w_k t_k) / d u_q| / |C|,
   rows[n] the same for the centre's force.  The pattern's reference data
   alone: one pass over the members, as one evaluation of the family. */
template <int DIM>
void family_row_bounds(const BondPattern &p, HSForm form, std::vector<double> &rows)
{
  constexpr int NC = DIM * DIM;
  const int n = p.n;
  rows.assign(n + 1, 0.0);
  // |K^-1 b_k| w_k: one slot's a for the inverse Ki
  auto a_of = [&](const double *Ki, int k, double *a) {
    for (int r = 0; r < 3; ++r) a[r] = 0.0;
    for (int r = 0; r < DIM; ++r)
      for (int c = 0; c < DIM; ++c) a[r] += p.w[k] * Ki[r * DIM + c] * p.b[3 * k + c];
  };
  auto norm = [](const double *a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); };
  // a slot list's D, and |m|
  auto spread = [&](const double *Ki, const std::vector<int> &members, double &D, double &mlen) {
    double m[3] = {0.0, 0.0, 0.0}, a[3];
    D = 0.0;
    for (int l : members) {
      a_of(Ki, l, a);
      D += norm(a);
      for (int r = 0; r < 3; ++r) m[r] += a[r];
    }
    mlen = norm(m);
    D += mlen;
  };
  if (p.atom_singular || n == 0) return;
  const std::vector<std::vector<int>> sets = member_sets(p);
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  double Ds, ms, cs = 0.0, a[3];
  spread(p.kinv_full, all, Ds, ms);
  for (int j = 0; j < n; ++j)
    if (p.singular[j]) cs += p.cforce[j];
  for (int j = 0; j < n; ++j) {
    if (p.singular[j]) {
      if (form == HSForm::I) {
        a_of(p.kinv_full, j, a);
        rows[j] = p.cforce[j] * norm(a) * Ds;
      }
      continue;
    }
    const double *Kj = &p.kinv[NC * j];
    double D, mlen;
    spread(Kj, sets[j], D, mlen);
    if (form == HSForm::I) {
      a_of(Kj, j, a);
      rows[j] = p.cforce[j] * norm(a) * D;
    } else {
      for (int l : sets[j]) {
        a_of(Kj, l, a);
        rows[l] += p.cforce[j] * norm(a) * D;
      }
      rows[n] += p.cforce[j] * mlen * D;
    }
  }
  if (form == HSForm::I) {
    for (int k = 0; k < n; ++k) rows[n] += rows[k];
    return;
  }
  if (cs > 0.0) {
    for (int k = 0; k < n; ++k) {
      a_of(p.kinv_full, k, a);
      rows[k] += cs * norm(a) * Ds;
    }
    rows[n] += cs * ms * Ds;
  }
}

}    // namespace NOSPD

#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The bond-associated force operator of a regular grid as a stencil.
   Knows nothing of LAMMPS.

   Under the linear (small-strain) law a family's force state is linear
   in its displacement differences, t_k = sum_m A_km U_m, U_m = u_{i+e_m}
   - u_i.  Where every family within delta of a point has one pattern (a
   grid away from surfaces and broken bonds), the force density on the
   point is therefore a fixed combination of the displacements within
   2 delta: its own family gives f_i += w_k t_k, and each family it is a
   member of (slot s of the family of i - e_s) gives f_i -= w_s t_s, so
       f_i = sum_d S_d u_{i+d},   sum_d S_d = 0 (translations are free).
   A grid pattern is centrosymmetric, S_d = S_-d, and
       f_i = sum_{d > 0} S_d (u_{i+d} + u_{i-d} - 2 u_i).
   The family's F and the mean of its bonds' H are linear too:
       F - I = sum_k U_k (x) aF_k,  aF_k = w_k K^-1 b_k,
       Hbar  = sum_k U_k (x) aH_k,  aH_k = w_k sum_{j in h_k} beta_j K_j^-1 b_k
   (singular bond families: K^-1 for K_j^-1), with aF_-k = -aF_k, so each
   is a sum over half the slots of (u_{i+e} - u_{i-e}) (x) a.

   The blocks A_km are read off the family evaluation itself, one call per
   unit displacement of a member, so the stencil is the model, not a
   second derivation of it: forces agree with the family path to round-off.
   On the benchmark grid (3D, delta = 3 dx, ratio 1) a point costs 414
   block products against two ~55-member sums per bond of its family.

   Near a surface the families within delta of a point have many patterns
   and the operator is not centrosymmetric; points that share their whole
   neighbourhood (the patterns of their own and their partners' families,
   at the same offsets) share a one-sided stencil, assembled from each
   family's blocks A_km (PointStencilBuilder), f_i = sum_d S_d (u_{i+d} -
   u_i) over every offset on its own.
------------------------------------------------------------------------- */

#ifndef NOSPD_STENCIL_H
#define NOSPD_STENCIL_H

#include "nospd_bond_associated.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

namespace NOSPD {

struct Stencil {
  bool ok = false;
  int dim = 3;
  double h[3] = {0.0, 0.0, 0.0};    // lattice spacing along x, y, z
  // centrosymmetric (a grid's inside): pairs (+d, -d), the integer offset
  // d (3 each) and S_d by columns, each column 4 doubles (12 per pair).
  // one_sided (a point near a surface, build_point_stencil): every offset
  // d != 0 on its own, f_i = sum_d S_d (u_{i+d} - u_i)
  bool one_sided = false;
  std::vector<int> pair_off;
  std::vector<double> pair_block;
  // family slots in pairs (+e, -e): e (3 each), aF and aH of +e (4 each);
  // one-sided: every slot e_k with its aF_k and aH_k
  std::vector<int> slot_off;
  std::vector<double> slot_aF, slot_aH;
  // the pattern has singular bond families: the family's F passes
  // through the law as the family path does (plane stress solves F_zz)
  bool family_fallback = false;

  int npairs() const { return (int) pair_off.size() / 3; }
  int nslots() const { return (int) slot_off.size() / 3; }
  double bytes() const
  {
    return sizeof(Stencil) + 4.0 * (pair_off.size() + slot_off.size()) +
        8.0 * (pair_block.size() + slot_aF.size() + slot_aH.size());
  }
};

namespace detail {
  using Offset = std::array<int, 3>;
  inline Offset neg(const Offset &a) { return {-a[0], -a[1], -a[2]}; }
  inline Offset sub(const Offset &a, const Offset &b)
  {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  }
  // first nonzero component positive
  inline bool positive(const Offset &a)
  {
    for (int c = 0; c < 3; ++c)
      if (a[c]) return a[c] > 0;
    return false;
  }
}    // namespace detail

/* The lattice of a pattern: the smallest offset along each axis (false
   where an axis has none) */
template <int DIM> bool pattern_lattice(const BondPattern &p, double *h)
{
  for (int c = 0; c < 3; ++c) h[c] = 0.0;
  for (int c = 0; c < DIM; ++c) {
    double hc = 0.0;
    for (int k = 0; k < p.n; ++k) {
      const double a = std::abs(p.b[3 * k + c]);
      if (a > 0.0 && (hc == 0.0 || a < hc)) hc = a;
    }
    if (hc == 0.0) return false;
    h[c] = hc;
  }
  return true;
}

/* The slots' offsets in whole spacings h; false where one is off the
   lattice */
template <int DIM>
bool lattice_offsets(const BondPattern &p, const double *h, std::vector<detail::Offset> &e)
{
  e.assign(p.n, {0, 0, 0});
  for (int k = 0; k < p.n; ++k)
    for (int c = 0; c < DIM; ++c) {
      const double q = p.b[3 * k + c] / h[c];
      e[k][c] = (int) std::lround(q);
      if (std::abs(q - e[k][c]) > 1.0e-8) return false;
    }
  return true;
}

/* The family's operator A_km, by columns (block (k, m) at 9 (k n + m),
   row-major): the force state t_k for a unit displacement of member m
   along each axis, read off the family evaluation itself, one call per
   unit displacement (the spacing `unit` keeps the probe's numbers
   ordinary).  False where the family has no evaluation (no shape tensor). */
template <int DIM>
bool family_operator(const BondPattern &p, HSForm form, Law law, Plane plane, const Lame &m,
                     const LinearLaw &lin, double unit, std::vector<double> &A)
{
  const int n = p.n;
  A.assign((size_t) 9 * n * n, 0.0);
  std::vector<double> U(3 * n + 1, 0.0), t(3 * n + 1, 0.0);
  StateScratch scratch;
  StateOutput out;
  for (int mm = 0; mm < n; ++mm)
    for (int a = 0; a < DIM; ++a) {
      U[3 * mm + a] = unit;
      if (!evaluate_family<DIM>(p, form, law, plane, m, lin, false, U.data(), t.data(), scratch,
                                out))
        return false;
      U[3 * mm + a] = 0.0;
      for (int k = 0; k < n; ++k)
        for (int r = 0; r < DIM; ++r) A[((size_t) k * n + mm) * 9 + 3 * r + a] = t[3 * k + r] / unit;
    }
  return true;
}

/* The slots' gradients: F - I = sum_k U_k (x) aF_k, Hbar = sum_k U_k (x) aH_k */
template <int DIM>
void slot_gradients(const BondPattern &p, std::vector<std::array<double, 3>> &aF,
                    std::vector<std::array<double, 3>> &aH)
{
  constexpr int NC = DIM * DIM;
  const int n = p.n;
  auto kinv_b = [&](const double *Ki, int k, double *out3) {
    for (int r = 0; r < 3; ++r) out3[r] = 0.0;
    for (int r = 0; r < DIM; ++r)
      for (int c = 0; c < DIM; ++c) out3[r] += Ki[r * DIM + c] * p.b[3 * k + c];
  };
  double cs_beta = 0.0;
  for (int j = 0; j < n; ++j)
    if (p.singular[j]) cs_beta += p.beta[j];
  aF.assign(n, {0.0, 0.0, 0.0});
  aH.assign(n, {0.0, 0.0, 0.0});
  for (int k = 0; k < n; ++k) {
    double v[3], acc[3] = {0.0, 0.0, 0.0};
    kinv_b(p.kinv_full, k, v);
    for (int r = 0; r < 3; ++r) {
      aF[k][r] = p.w[k] * v[r];
      acc[r] = cs_beta * v[r];
    }
    const uint16_t *runs = &p.runs[2 * p.run_first[k]];
    for (int q = 0; q < p.run_first[k + 1] - p.run_first[k]; ++q)
      for (int j = runs[2 * q]; j < runs[2 * q + 1]; ++j) {
        if (p.singular[j]) continue;
        kinv_b(&p.kinv[NC * j], k, v);
        for (int r = 0; r < 3; ++r) acc[r] += p.beta[j] * v[r];
      }
    for (int r = 0; r < 3; ++r) aH[k][r] = p.w[k] * acc[r];
  }
}

/* Offset d and its block S_d (row-major) appended, by columns padded to 4 */
inline void append_block(Stencil &st, const detail::Offset &d, const double *blk)
{
  for (int c = 0; c < 3; ++c) st.pair_off.push_back(d[c]);
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) st.pair_block.push_back(blk[3 * r + c]);
    st.pair_block.push_back(0.0);
  }
}

/* Blocks in memory order of a grid whose x runs fastest: consecutive
   blocks read neighbouring cells */
inline void sort_blocks_zyx(std::vector<int> &off, std::vector<double> &block)
{
  const int nb = (int) off.size() / 3;
  std::vector<int> order(nb);
  for (int q = 0; q < nb; ++q) order[q] = q;
  auto zyx = [&](int q) {
    const int *o = &off[3 * q];
    return std::array<int, 3>{o[2], o[1], o[0]};
  };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return zyx(a) < zyx(b); });
  std::vector<int> o2(3 * nb);
  std::vector<double> b2(12 * nb);
  for (int q = 0; q < nb; ++q) {
    std::copy_n(&off[3 * order[q]], 3, &o2[3 * q]);
    std::copy_n(&block[12 * order[q]], 12, &b2[12 * q]);
  }
  off.swap(o2);
  block.swap(b2);
}

/* The stencil of the families of pattern p under the linear law lin
   (form, law and plane as the family path takes them).  Not ok where the
   law is not linear, the family has no shape tensor, the offsets are not
   on a lattice of spacings h, or the operator is not centrosymmetric. */
template <int DIM>
Stencil build_stencil(const BondPattern &p, HSForm form, Law law, Plane plane, const Lame &m,
                      const LinearLaw &lin)
{
  using detail::Offset;
  Stencil st;
  st.dim = DIM;
  const int n = p.n;
  if (!lin.ok || p.atom_singular || n == 0) return st;

  // the lattice: the smallest offset along each axis, every offset a
  // whole multiple of it
  if (!pattern_lattice<DIM>(p, st.h)) return st;
  std::vector<Offset> e;
  if (!lattice_offsets<DIM>(p, st.h, e)) return st;
  std::map<Offset, int> slot_at;
  for (int k = 0; k < n; ++k) slot_at[e[k]] = k;
  std::vector<int> mirror(n);
  for (int k = 0; k < n; ++k) {
    auto it = slot_at.find(detail::neg(e[k]));
    if (it == slot_at.end()) return st;
    mirror[k] = it->second;
  }

  // A_km by columns: the force state for a unit displacement of member m
  std::vector<double> A;
  if (!family_operator<DIM>(p, form, law, plane, m, lin, st.h[0], A)) return st;

  // S_d from the point's own family and the families it belongs to
  std::map<Offset, std::array<double, 9>> S;
  auto add = [&](const Offset &d, const double *blk, double scale) {
    auto &s = S[d];
    for (int q = 0; q < 9; ++q) s[q] += scale * blk[q];
  };
  const Offset zero{0, 0, 0};
  for (int k = 0; k < n; ++k)
    for (int mm = 0; mm < n; ++mm) {
      const double *blk = &A[((size_t) k * n + mm) * 9];
      add(e[mm], blk, p.w[k]);
      add(zero, blk, -p.w[k]);
      add(detail::sub(e[mm], e[k]), blk, -p.w[k]);
      add(detail::neg(e[k]), blk, p.w[k]);
    }
  // (each term above adds to S_0 what it adds elsewhere, with the
  // opposite sign: sum_d S_d = 0 by construction)
  double scale = 0.0;
  for (auto &kv : S)
    for (int q = 0; q < 9; ++q) scale = std::max(scale, std::abs(kv.second[q]));
  if (scale == 0.0) return st;

  // pairs, each block the mean of S_d and S_-d (equal to round-off)
  for (auto &kv : S) {
    if (!detail::positive(kv.first)) continue;
    auto it = S.find(detail::neg(kv.first));
    double blk[9], big = 0.0;
    for (int q = 0; q < 9; ++q) {
      const double other = it == S.end() ? 0.0 : it->second[q];
      if (std::abs(kv.second[q] - other) > 1.0e-9 * scale) return Stencil();
      blk[q] = 0.5 * (kv.second[q] + other);
      big = std::max(big, std::abs(blk[q]));
    }
    if (big <= 1.0e-14 * scale) continue;
    append_block(st, kv.first, blk);
  }

  sort_blocks_zyx(st.pair_off, st.pair_block);

  // aF_k and aH_k
  std::vector<std::array<double, 3>> aF, aH;
  slot_gradients<DIM>(p, aF, aH);
  st.family_fallback = p.nsingular > 0;
  double ascale = 0.0;
  for (int k = 0; k < n; ++k)
    for (int r = 0; r < 3; ++r) ascale = std::max({ascale, std::abs(aF[k][r]), std::abs(aH[k][r])});
  for (int k = 0; k < n; ++k) {
    if (!detail::positive(e[k])) continue;
    const int km = mirror[k];
    for (int c = 0; c < 3; ++c) st.slot_off.push_back(e[k][c]);
    for (int r = 0; r < 3; ++r) {
      if (std::abs(aF[k][r] + aF[km][r]) > 1.0e-9 * ascale ||
          std::abs(aH[k][r] + aH[km][r]) > 1.0e-9 * ascale)
        return Stencil();
      st.slot_aF.push_back(0.5 * (aF[k][r] - aF[km][r]));
      st.slot_aH.push_back(0.5 * (aH[k][r] - aH[km][r]));
    }
    st.slot_aF.push_back(0.0);
    st.slot_aH.push_back(0.0);
  }
  st.ok = true;
  return st;
}

/* The one-sided stencil of a point whose neighbourhood is not one
   pattern (near a surface, an interface, broken bonds), assembled from
   the operators of the families that reach it: its own,
       f_i += sum_k w_k t_k,   t_k = sum_m A_km (u_{i+e_m} - u_i),
   and each family centred at i + a in which it is slot s,
       f_i -= (V_{i+a} / V_i) w_s t_s.
   The offsets d reach 2 delta: at most R lattice spacings along each
   axis. */
class PointStencilBuilder {
 public:
  PointStencilBuilder(int dim, int R) :
      dim_(dim), R_(R), side_(2 * R + 1), S_((size_t) 9 * side_ * side_ * (dim == 3 ? side_ : 1), 0.0)
  {
  }

  // the point's own family (e: its slots' offsets, w: its weights)
  bool add_own(const std::vector<detail::Offset> &e, const std::vector<double> &w,
               const std::vector<double> &A)
  {
    const int n = (int) e.size();
    const detail::Offset zero{0, 0, 0};
    for (int k = 0; k < n; ++k)
      for (int m = 0; m < n; ++m)
        if (!add(e[m], zero, &A[((size_t) k * n + m) * 9], w[k])) return false;
    return true;
  }

  // the family centred at offset a, of which the point is slot s; ws =
  // (V_{i+a} / V_i) w_s
  bool add_member(const detail::Offset &a, const std::vector<detail::Offset> &e,
                  const std::vector<double> &A, int s, double ws)
  {
    const int n = (int) e.size();
    for (int m = 0; m < n; ++m) {
      const detail::Offset d{a[0] + e[m][0], a[1] + e[m][1], a[2] + e[m][2]};
      if (!add(d, a, &A[((size_t) s * n + m) * 9], -ws)) return false;
    }
    return true;
  }

  // the stencil: the blocks d != 0 above round-off, and the own family's
  // slots for F and the mean bond H
  template <int DIM>
  Stencil finish(const BondPattern &own, const std::vector<detail::Offset> &e, const double *h)
  {
    Stencil st;
    st.dim = DIM;
    st.one_sided = true;
    for (int c = 0; c < 3; ++c) st.h[c] = h[c];
    double scale = 0.0;
    for (double v : S_) scale = std::max(scale, std::abs(v));
    if (scale == 0.0) return st;
    const int zside = DIM == 3 ? side_ : 1;
    for (int z = 0; z < zside; ++z)
      for (int y = 0; y < side_; ++y)
        for (int x = 0; x < side_; ++x) {
          const detail::Offset d{x - R_, y - R_, DIM == 3 ? z - R_ : 0};
          if (d[0] == 0 && d[1] == 0 && d[2] == 0) continue;
          const double *blk = &S_[9 * cell(d)];
          double big = 0.0;
          for (int q = 0; q < 9; ++q) big = std::max(big, std::abs(blk[q]));
          if (big > 1.0e-14 * scale) append_block(st, d, blk);
        }
    sort_blocks_zyx(st.pair_off, st.pair_block);
    std::vector<std::array<double, 3>> aF, aH;
    slot_gradients<DIM>(own, aF, aH);
    st.family_fallback = own.nsingular > 0;
    for (int k = 0; k < own.n; ++k) {
      for (int c = 0; c < 3; ++c) st.slot_off.push_back(e[k][c]);
      for (int r = 0; r < 3; ++r) {
        st.slot_aF.push_back(aF[k][r]);
        st.slot_aH.push_back(aH[k][r]);
      }
      st.slot_aF.push_back(0.0);
      st.slot_aH.push_back(0.0);
    }
    st.ok = true;
    return st;
  }

  double bytes() const { return 8.0 * S_.size(); }

 private:
  int dim_, R_, side_;
  std::vector<double> S_;    // S_d by cell of the cube |d_c| <= R, 9 each (row-major)

  size_t cell(const detail::Offset &d) const
  {
    const size_t z = dim_ == 3 ? (size_t) (d[2] + R_) : 0;
    return (size_t) (d[0] + R_) + side_ * ((size_t) (d[1] + R_) + side_ * z);
  }
  bool inside(const detail::Offset &d) const
  {
    for (int c = 0; c < dim_; ++c)
      if (d[c] < -R_ || d[c] > R_) return false;
    return dim_ == 3 || d[2] == 0;
  }
  // S_d += scale blk, S_o -= scale blk: each term leaves sum_d S_d = 0
  bool add(const detail::Offset &d, const detail::Offset &o, const double *blk, double scale)
  {
    if (!inside(d) || !inside(o)) return false;
    double *sd = &S_[9 * cell(d)], *so = &S_[9 * cell(o)];
    for (int q = 0; q < 9; ++q) {
      sd[q] += scale * blk[q];
      so[q] -= scale * blk[q];
    }
    return true;
  }
};

/* The force densities on the points in cells c[0..NP) (NP = 1, 2 or 4).
   u: displacements by cell, 4 per cell (the fourth unused), so that a
   point's neighbours are u[4 (c +- pair_lin[q])] without an atom lookup.
   The points share each block's loads; each point's sum runs on three
   accumulators (one per column), whose additions do not wait on each
   other across points.  A point's sum is the same bits whichever NP it
   is taken with (which depends on the ranks and threads). */
template <int DIM, int NP, bool ONE_SIDED = false>
inline void stencil_forces(const Stencil &st, const double *u, const long *c, const int *pair_lin,
                           double (*f)[3])
{
  using namespace simd;
  const double *uc[NP];
  v4 ui2[NP], a0[NP], a1[NP], a2[NP];    // ui2: 2 u_i (pairs) or u_i (one-sided)
  for (int p = 0; p < NP; ++p) {
    uc[p] = u + 4 * c[p];
    ui2[p] = ONE_SIDED ? load4(uc[p]) : 2.0 * load4(uc[p]);
    a0[p] = a1[p] = a2[p] = v4{};
  }
  const double *blk = st.pair_block.data();
  const int np = st.npairs();
  for (int q = 0; q < np; ++q) {
    const long l = 4L * pair_lin[q];
    const double *c0 = blk + 12 * q;
    const v4 k0 = load4(c0), k1 = load4(c0 + 4);
    for (int p = 0; p < NP; ++p) {
      const v4 d = ONE_SIDED ? load4(uc[p] + l) - ui2[p]
                             : (load4(uc[p] + l) + load4(uc[p] - l)) - ui2[p];
      a0[p] += k0 * d[0];
      a1[p] += k1 * d[1];
      if (DIM == 3) a2[p] += load4(c0 + 8) * d[2];
    }
  }
  for (int p = 0; p < NP; ++p) {
    const v4 acc = (a0[p] + a1[p]) + a2[p];
    f[p][0] = acc[0], f[p][1] = acc[1], f[p][2] = DIM == 3 ? acc[2] : 0.0;
  }
}

/* The family's H = F - I and the mean bond H of the point in cell c
   (row-major 3x3, rows and columns past DIM zero); slot_lin as pair_lin
   for the family's slots. */
template <int DIM, bool ONE_SIDED = false>
inline void stencil_family(const Stencil &st, const double *u, long c, const int *slot_lin,
                           double *H, double *Hbar)
{
  using namespace simd;
  const double *uc = u + 4 * c;
  v4 hf[3] = {}, hb[3] = {};
  const v4 ui = load4(uc);
  const int ns = st.nslots();
  for (int s = 0; s < ns; ++s) {
    const long l = 4L * slot_lin[s];
    const v4 d = ONE_SIDED ? load4(uc + l) - ui : load4(uc + l) - load4(uc - l);
    const v4 af = load4(&st.slot_aF[4 * s]), ah = load4(&st.slot_aH[4 * s]);
    for (int r = 0; r < DIM; ++r) {
      hf[r] += d[r] * af;
      hb[r] += d[r] * ah;
    }
  }
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      const bool in = r < DIM && k < DIM;
      H[3 * r + k] = in ? hf[r][k] : 0.0;
      Hbar[3 * r + k] = in ? hb[r][k] : 0.0;
    }
}

}    // namespace NOSPD

#endif

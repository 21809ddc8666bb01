/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The bond lists of the families, in one contiguous (CSR) layout.
   Knows nothing of LAMMPS.

   Point i's bonds are [first[i], first[i+1]): the local index j of the
   partner (its closest image), the partner slot (the index of the
   partner's ID in the family's ID list, where a broken bond is 0) and the
   weight omega V_j.  The owner (FixNospdBonds) fills the lists once per
   reneighboring (open/add/close, then order_for_pairs where the pair
   order is used) and drops broken bonds in place (compact), keeping the
   order a rebuild would give.

   Pair order (order_for_pairs): each point's bonds to owned points j < i
   first, then to owned j > i (from pair[i]), then to ghosts (from
   ghost[i]), each group in partner order.  A pass that visits each pair of
   owned points once takes bond i-j (j > i) for both ends, so it needs
   every such bond in both lists: symmetric() checks that by a hash of
   (i, j) summed over the first group and over the second, equal (mod 2^64)
   exactly when the owned pairs are symmetric.
------------------------------------------------------------------------- */

#ifndef NOSPD_FAMILY_STORE_H
#define NOSPD_FAMILY_STORE_H

#include <cstddef>
#include <cstdint>
#include <vector>

namespace NOSPD {

class FamilyStore {
 public:
  int *first = nullptr;    // [natoms + 1]
  int *j = nullptr;        // partner's local index
  int *slot = nullptr;     // partner slot
  double *w = nullptr;     // omega(|xi|) V_j
  int *pair = nullptr;     // [natoms], in pair order only
  int *ghost = nullptr;
  int natoms = -1;         // points the lists cover (-1: not built)
  int version = 0;         // changes whenever the lists change
  bool pair_order = false;    // lists kept in pair order

  int count(int i) const { return first[i + 1] - first[i]; }
  bool symmetric() const { return pair_order && sym; }

  // building: room for `points` points and `bonds` bonds, then for each
  // point i in turn open(i), add() its bonds, and close(n) at the end
  void reserve(int points, int64_t bonds)
  {
    if (points + 1 > (int) first_.size()) first_.resize(points + 1);
    if (bonds > (int64_t) j_.size()) {
      const std::size_t n = (size_t) (1.02 * (double) bonds) + 16;    // room for a few more
      j_.resize(n);
      slot_.resize(n);
      w_.resize(n);
    }
    point_to_data();
  }
  void open(int i) { first[i] = nb; }
  void add(int jj, int s, double ww)
  {
    j[nb] = jj;
    slot[nb] = s;
    w[nb] = ww;
    nb++;
  }
  void close(int n)
  {
    first[n] = nb;
    nb = 0;
    natoms = n;
    version++;
  }

  // the lists in pair order (owned j < i, owned j > i, ghosts); n points
  // owned, whose local indices are below n
  void order_for_pairs()
  {
    const int n = natoms;
    if (n > (int) pair_.size()) {
      pair_.resize(n);
      ghost_.resize(n);
      point_to_data();
    }
    uint64_t below = 0, above = 0;
    std::vector<int> js, slots, group;
    std::vector<double> ws;
    for (int i = 0; i < n; i++) {
      const int from = first[i], to = first[i + 1];
      js.assign(j + from, j + to);
      slots.assign(slot + from, slot + to);
      ws.assign(w + from, w + to);
      group.resize(to - from);
      int cnt[3] = {0, 0, 0};
      for (int k = 0; k < to - from; k++) {
        group[k] = (js[k] >= n || js[k] == i) ? 2 : (js[k] < i ? 0 : 1);
        cnt[group[k]]++;
      }
      int next[3] = {from, from + cnt[0], from + cnt[0] + cnt[1]};
      pair[i] = next[1];
      ghost[i] = next[2];
      for (int k = 0; k < to - from; k++) {
        const int b = next[group[k]]++;
        j[b] = js[k];
        slot[b] = slots[k];
        w[b] = ws[k];
        if (group[k] == 0) below += pair_hash(js[k], i);
        if (group[k] == 1) above += pair_hash(i, js[k]);
      }
    }
    sym = (below == above);
    pair_order = true;
    version++;
  }

  // drop, in place, the bonds for which broken(i, slot) holds, keeping the
  // order of the rest (and the pair-order groups)
  template <class Broken> void compact(Broken broken)
  {
    if (natoms < 0 || !first) return;
    uint64_t below = 0, above = 0;
    int b = 0;
    for (int i = 0; i < natoms; i++) {
      const int start = first[i], end = first[i + 1];
      const int pair_from = pair_order ? pair[i] : end;
      const int ghost_from = pair_order ? ghost[i] : end;
      first[i] = b;
      auto keep = [&](int from, int to, int grp) {
        for (int k = from; k < to; k++) {
          if (broken(i, slot[k])) continue;
          j[b] = j[k];
          slot[b] = slot[k];
          w[b] = w[k];
          if (grp == 0) below += pair_hash(j[b], i);
          if (grp == 1) above += pair_hash(i, j[b]);
          b++;
        }
      };
      if (!pair_order) {
        keep(start, end, 2);
        continue;
      }
      keep(start, pair_from, 0);
      pair[i] = b;
      keep(pair_from, ghost_from, 1);
      ghost[i] = b;
      keep(ghost_from, end, 2);
    }
    first[natoms] = b;
    version++;
    if (pair_order) sym = (below == above);
  }

  double bytes() const
  {
    return (double) (first_.size() + 2 * j_.size() + pair_.size() + ghost_.size()) * sizeof(int) +
        (double) w_.size() * sizeof(double);
  }

 private:
  std::vector<int> first_, j_, slot_, pair_, ghost_;
  std::vector<double> w_;
  int nb = 0;    // bonds added since the last close
  bool sym = false;

  void point_to_data()
  {
    first = first_.data();
    j = j_.data();
    slot = slot_.data();
    w = w_.data();
    pair = pair_.empty() ? nullptr : pair_.data();
    ghost = ghost_.empty() ? nullptr : ghost_.data();
  }
  static uint64_t pair_hash(uint64_t lo, uint64_t hi)
  {
    uint64_t z = (lo << 32 | hi) + 0x9e3779b97f4a7c15ULL;    // splitmix64
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
};

}    // namespace NOSPD

#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Contact rest distances remembered per point pair.  Knows nothing of
   LAMMPS.

   The contact force of fix nospd/damage pushes unbonded points apart below
   a rest distance d0 (0.9 of their reference distance, at most r_c).  A bond
   that breaks while its ends are closer than d0 (a compressed zone, a
   failed point) would switch on a loaded contact spring: energy created
   out of nothing.  Such a pair remembers its distance at the break as its
   rest distance d <= d0 instead; contact then resists only further
   approach.  When the pair opens past d (the spring unloaded, so no energy
   changes hands) d follows the distance back up to d0, and the pair is
   forgotten there or when it leaves the contact range.  Both ends keep
   their own copy and update it from the same distance, so the two forces
   stay equal and opposite.

   A record is RECORD doubles: the count n, then n pairs (partner ID,
   rest distance).  IDs are exact in a double up to 2^53.
------------------------------------------------------------------------- */

#ifndef NOSPD_CONTACT_MEMORY_H
#define NOSPD_CONTACT_MEMORY_H

#include <algorithm>

namespace NOSPD {

struct ContactMemory {
  static constexpr int CAPACITY = 32;
  static constexpr int RECORD = 1 + 2 * CAPACITY;

  static int count(const double *rec) { return static_cast<int>(rec[0]); }
  static void clear(double *rec) { rec[0] = 0.0; }
  // the used length of a record (what exchange and restart carry)
  static int used(const double *rec) { return 1 + 2 * count(rec); }

  // slot of partner `tag`, or -1
  static int find(const double *rec, double tag)
  {
    const int n = count(rec);
    for (int k = 0; k < n; k++)
      if (rec[1 + 2 * k] == tag) return k;
    return -1;
  }

  // a bond to `tag` broke at distance r below the nominal rest distance
  // d0: remember r; false when the record is full (the pair then gets d0)
  static bool remember(double *rec, double tag, double r, double d0)
  {
    if (!(r < d0)) return true;
    const int k = find(rec, tag);
    if (k >= 0) {
      rec[2 + 2 * k] = std::min(rec[2 + 2 * k], r);
      return true;
    }
    const int n = count(rec);
    if (n == CAPACITY) return false;
    rec[1 + 2 * n] = tag;
    rec[2 + 2 * n] = r;
    rec[0] = n + 1;
    return true;
  }

  // the rest distance of the pair (slot k of the record, -1: none) at
  // distance r: the remembered one, raised to r (at most d0) where the
  // pair has opened past it; keep[k] says whether the slot stays (in
  // range and still below d0)
  static double rest(double *rec, int k, double r, double d0, bool *keep)
  {
    if (k < 0) return d0;
    double &d = rec[2 + 2 * k];
    if (r > d) d = std::min(r, d0);
    keep[k] = d < d0;
    return d;
  }

  // drop the slots not kept in this evaluation (out of range, or back at
  // their nominal distance)
  static void prune(double *rec, const bool *keep)
  {
    const int n = count(rec);
    int m = 0;
    for (int k = 0; k < n; k++) {
      if (!keep[k]) continue;
      rec[1 + 2 * m] = rec[1 + 2 * k];
      rec[2 + 2 * m] = rec[2 + 2 * k];
      m++;
    }
    rec[0] = m;
  }
};

}    // namespace NOSPD

#endif

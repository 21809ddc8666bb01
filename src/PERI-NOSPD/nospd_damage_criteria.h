/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The bond-breaking criteria of fix nospd/damage as small functors, one per
   criterion: each turns one bond, seen from its lower-ID end a, into the
   value compared with the critical one (the plain stretch criterion has
   its own loop, FixNospdDamage::stretch_cuts).  Knows nothing of LAMMPS.
------------------------------------------------------------------------- */

#ifndef NOSPD_DAMAGE_CRITERIA_H
#define NOSPD_DAMAGE_CRITERIA_H

#include "nospd_damage.h"

#include <algorithm>

namespace NOSPD {

/* A bond from its lower-ID end a to its higher-ID end c: reference xi,
   current Y, U = Y - xi, |xi|, |Y|, stretch s, and the per-atom state
   rows that fix nospd/damage forwards (criterion-specific, see each). */
struct BondView {
  const double *xi, *U, *Y;
  double rxi, ry, s;
  const double *sa, *sc;
  double horizon;    // of the pair's types
};

/* Each criterion: bool operator()(v, val, limit) gives the bond's value
   (false: the bond is no candidate) and may lower the limit; TRACKS_SMIN
   marks the one that keeps each atom's smallest stretch. */

// stretch with Silling & Askari's (2005) s_0 = s_00 - alpha s_min per atom,
// the smaller s_0 of the two ends (state: s_min)
struct AlphaStretchCriterion {
  static constexpr bool TRACKS_SMIN = true;
  double alpha;
  bool operator()(const BondView &v, double &val, double &limit) const
  {
    limit -= alpha * std::max(v.sa[0], v.sc[0]);
    val = v.s;
    return true;
  }
};

// energy held by the bond, 1/2 omega ((A_a + A_c) xi).U, in tension only
// (state: A = P K^-1, row-major)
struct EnergyCriterion {
  static constexpr bool TRACKS_SMIN = false;
  bool inverse;    // omega = delta/|xi|, else 1
  bool operator()(const BondView &v, double &val, double &) const
  {
    if (!(v.s > 0.0)) return false;
    double Asum[9];
    for (int k = 0; k < 9; k++) Asum[k] = v.sa[k] + v.sc[k];
    const double omega = inverse ? v.horizon / v.rxi : 1.0;
    val = bond_energy(omega, Asum, v.xi, v.U);
    return true;
  }
};

// n.S n of the ends' mean tensor: stress along the current bond, strain
// along the reference bond (state: S as xx yy zz xy xz yz)
struct PrincipalCriterion {
  static constexpr bool TRACKS_SMIN = false;
  bool along_current;
  bool operator()(const BondView &v, double &val, double &) const
  {
    double S[6];
    for (int k = 0; k < 6; k++) S[k] = 0.5 * (v.sa[k] + v.sc[k]);
    const double *d = along_current ? v.Y : v.xi;
    const double r = along_current ? v.ry : v.rxi;
    if (!(r > 0.0)) return false;
    const double n[3] = {d[0] / r, d[1] / r, d[2] / r};
    val = normal_component(S, n);
    return true;
  }
};

// von Mises stress of the ends' mean, in tension only (state: sigma)
struct VonMisesCriterion {
  static constexpr bool TRACKS_SMIN = false;
  bool operator()(const BondView &v, double &val, double &) const
  {
    if (!(v.s > 0.0)) return false;
    double S[6];
    for (int k = 0; k < 6; k++) S[k] = 0.5 * (v.sa[k] + v.sc[k]);
    val = von_mises6(S);
    return true;
  }
};

// a failed point (equivalent plastic strain or Johnson-Cook damage past its
// limit) loses all its bonds (state: the point's measure)
struct PointFailureCriterion {
  static constexpr bool TRACKS_SMIN = false;
  bool operator()(const BondView &v, double &val, double &) const
  {
    val = std::max(v.sa[0], v.sc[0]);
    return true;
  }
};

}    // namespace NOSPD

#endif

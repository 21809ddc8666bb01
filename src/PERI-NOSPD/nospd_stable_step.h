/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The stable time step estimate of velocity Verlet, per atom type.
   Knows nothing of LAMMPS.

   Two values per type, each the smallest over the type's points:
   - the bond-based body's with the same P-wave modulus (Silling and Askari
     2005, Comput. Struct. 83:1526, eq. 31): dt = sqrt(2 rho / s),
     s = sum_j V_j c / |xi_j|;
   - from a row bound R of the linearized stiffness (the sum over points k
     of the norms of df_i/du_k, a block Gershgorin bound on the largest
     eigenvalue of M^-1 K): dt = 2 sqrt(rho / R).
   The estimate takes the smaller of the first and `margin` times the
   second (the bound's measured slack, style by style: doc
   fix_peri_neigh_nospd, "Stable time step").  StableStep keeps the values
   of the last setup, for the log, the warnings and the instability errors.
------------------------------------------------------------------------- */

#ifndef NOSPD_STABLE_STEP_H
#define NOSPD_STABLE_STEP_H

#include "nospd_tensor.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace NOSPD {

// how a stabilization's spring acts per bond: none; Silling's (w s z);
// the hourglass spring (w s/|xi| along the bond); Wan's (w S z with
// |S| <= |C| |K^-1|)
enum class SpringKind { NONE, PER_WEIGHT, PER_LENGTH, WAN };

// the stiffness of a bond of length len at an end with spring constant s,
// elasticity norm cn and |K^-1| = kappa (0 where K is singular: no spring)
inline double spring_stiffness(SpringKind kind, double s, double cn, double kappa, double len)
{
  if (kappa == 0.0) return 0.0;
  switch (kind) {
    case SpringKind::PER_WEIGHT: return s;
    case SpringKind::PER_LENGTH: return s / len;
    case SpringKind::WAN: return cn * kappa;
    default: return 0.0;
  }
}

// the largest eigenvalue of the symmetric K^-1 (in 2D of its in-plane
// block: the out-of-plane entry is a placeholder)
inline double spectral_norm(const Mat3 &Kinv, bool plane)
{
  if (plane) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(Kinv.topLeftCorner<2, 2>(),
                                                            Eigen::EigenvaluesOnly);
    return es.eigenvalues().cwiseAbs().maxCoeff();
  }
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(Kinv, Eigen::EigenvaluesOnly);
  return es.eigenvalues().cwiseAbs().maxCoeff();
}

class StableStep {
 public:
  static constexpr double NONE = 1.0e300;    // no estimate (no points, no modulus)

  // velocity Verlet's step from a bond-based sum s and from a row bound R
  static double bond_based(double rho, double s) { return s > 0.0 ? std::sqrt(2.0 * rho / s) : NONE; }
  static double from_row_bound(double rho, double R)
  {
    return R > 0.0 ? 2.0 * std::sqrt(rho / R) : NONE;
  }

  // take the per-type values (index 0 unused, NONE where absent) of this
  // setup; true when the estimate differs from the last one taken
  bool take(const std::vector<double> &bond_dt, const std::vector<double> &bound_dt, double margin)
  {
    bond = bond_dt;
    bound = bound_dt;
    std::vector<double> all(bond.size());
    for (size_t t = 0; t < bond.size(); t++)
      all[t] = bound[t] < NONE ? std::min(bond[t], margin * bound[t]) : bond[t];
    const bool changed = (all != reported);
    reported = all;
    return changed;
  }

  // the estimate of a type and its two parts (0: none)
  double of(int type) const { return part(reported, type); }
  double bond_part(int type) const { return part(bond, type); }
  double bound_part(int type) const { return part(bound, type); }
  int ntypes() const { return reported.empty() ? 0 : (int) reported.size() - 1; }
  // the smallest estimate over the types (0: none)
  double smallest() const
  {
    double est = 0.0;
    for (int t = 1; t <= ntypes(); t++)
      if (of(t) > 0.0 && (est == 0.0 || of(t) < est)) est = of(t);
    return est;
  }
  // the type of the smallest estimate (0: none)
  int smallest_type() const
  {
    int worst = 0;
    for (int t = 1; t <= ntypes(); t++)
      if (of(t) > 0.0 && (!worst || of(t) < of(worst))) worst = t;
    return worst;
  }

  double checked = -1.0;    // the time step last checked against the estimate

 private:
  std::vector<double> reported, bond, bound;
  static double part(const std::vector<double> &v, int type)
  {
    return (type >= 0 && type < (int) v.size() && v[type] < NONE) ? v[type] : 0.0;
  }
};

}    // namespace NOSPD

#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(peri/nospd/omp,PairPeriNospdOMP);
// clang-format on
#else

#ifndef LMP_PAIR_PERI_NOSPD_OMP_H
#define LMP_PAIR_PERI_NOSPD_OMP_H

#include "pair_peri_nospd.h"

namespace LAMMPS_NS {

/* peri/nospd with its passes (F, the constitutive pass, the forces) split
   over OpenMP threads: what `-sf omp` or `suffix omp` picks.  Every pass
   gathers over each atom's own bonds and writes that atom's rows only, so
   the threads share nothing but the energy and virial sums, which are
   kept per thread and added in thread order.  Forces are bitwise those of
   peri/nospd (but for the hourglass term, which peri/nospd sums over pairs
   of points: the same to rounding); the sums differ in their last bits. */
class PairPeriNospdOMP : public PairPeriNospd {
 public:
  PairPeriNospdOMP(class LAMMPS *);

 protected:
  void for_ranges(int n, bool thread_safe, const RangeFn &fn) override;
  // every pass split by atoms, the hourglass one too (no pair order)
  bool pair_order_usable() const override { return false; }
};

}    // namespace LAMMPS_NS

#endif
#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(peri/nospd/hs/omp,PairPeriNospdHSOMP);
// clang-format on
#else

#ifndef LMP_PAIR_PERI_NOSPD_HS_OMP_H
#define LMP_PAIR_PERI_NOSPD_HS_OMP_H

#include "pair_peri_nospd_hs.h"

namespace LAMMPS_NS {

/* peri/nospd/hs with its passes over OpenMP threads: what `-sf omp` or
   `suffix omp` picks.  The threads take contiguous ranges of the families;
   each thread scatters the partners' shares of its families' forces into
   its own buffer, and the buffers are added in thread order after the
   pass, so the forces equal those of peri/nospd/hs up to the order of
   those sums (last bits). */
class PairPeriNospdHSOMP : public PairPeriNospdHS {
 public:
  PairPeriNospdHSOMP(class LAMMPS *);

 protected:
  void for_ranges(int n, bool thread_safe, const RangeFn &fn) override;
};

}    // namespace LAMMPS_NS

#endif
#endif

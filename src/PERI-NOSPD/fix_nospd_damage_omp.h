/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(nospd/damage/omp,FixNospdDamageOMP);
// clang-format on
#else

#ifndef LMP_FIX_NOSPD_DAMAGE_OMP_H
#define LMP_FIX_NOSPD_DAMAGE_OMP_H

#include "fix_nospd_damage.h"

namespace LAMMPS_NS {

/* fix nospd/damage with its per-atom loops (the bond checks, the contact
   forces, the stored state) over OpenMP threads: what `-sf omp` picks.
   Each thread lists the bonds to cut of its own atoms; the lists are
   joined in thread order, so the same bonds break as with the plain fix. */
class FixNospdDamageOMP : public FixNospdDamage {
 public:
  FixNospdDamageOMP(class LAMMPS *, int, char **);
  void init() override;
};

}    // namespace LAMMPS_NS

#endif
#endif

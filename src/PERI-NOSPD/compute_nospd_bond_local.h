/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(nospd/bond/local,ComputeNospdBondLocal);
// clang-format on
#else

#ifndef LMP_COMPUTE_NOSPD_BOND_LOCAL_H
#define LMP_COMPUTE_NOSPD_BOND_LOCAL_H

#include "compute.h"

#include "nospd_tensor.h"

#include <vector>

namespace LAMMPS_NS {

/* Per-bond output for dump local: one row per intact bond (i, j) of each
   owned atom i in the group (both directions of a bond appear, on the
   owners of i and of j).  Under peri/nospd/hs the deformation gradient
   and stress are the bond-associated ones; under peri/nospd they are atom
   i's. */
class ComputeNospdBondLocal : public Compute {
 public:
  ComputeNospdBondLocal(class LAMMPS *, int, char **);
  ~ComputeNospdBondLocal() override;
  void init() override;
  void compute_local() override;
  double memory_usage() override;

 private:
  enum Quantity { ID, STRETCH, DEFGRAD, STRESS, OWN, EQPS };
  // the bond's inelastic state: the bond-associated entry (peri/nospd/hs),
  // else nullptr (the atom's state serves)
  const double *bond_state(int i, int b, int own) const;
  bool bond_stress(int i, int b, int own, NOSPD::Mat3 &F, NOSPD::Mat3 &s) const;
  std::vector<int> quantities;
  int nmax;
  double **out;
  class PairPeriNospdBase *pair;
  class PairPeriNospdHS *pair_hs;

  void find_pair();
  int count_rows();
};

}    // namespace LAMMPS_NS

#endif
#endif

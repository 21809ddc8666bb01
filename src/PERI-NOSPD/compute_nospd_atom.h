/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(nospd/atom,ComputeNospdAtom);
// clang-format on
#else

#ifndef LMP_COMPUTE_NOSPD_ATOM_H
#define LMP_COMPUTE_NOSPD_ATOM_H

#include "compute.h"

#include <vector>

namespace LAMMPS_NS {

/* Per-atom output of the correspondence state owned by the bonds fix:
   deformation gradient, strain, Cauchy stress, von Mises stress, stored
   energy density, zero-energy-mode indicator and singular-family flag;
   for inelastic materials the history (equivalent plastic strain, plastic
   strain tensor, back stress, temperature, yield flag, plastic work,
   Johnson-Cook damage); with fix nospd/heat the heat flux -k grad T.
   Everything but the indicator is read, not recomputed. */
class ComputeNospdAtom : public Compute {
 public:
  ComputeNospdAtom(class LAMMPS *, int, char **);
  ~ComputeNospdAtom() override;
  void init() override;
  void compute_peratom() override;
  double memory_usage() override;

 private:
  enum Quantity {
    DEFGRAD, STRAIN, STRESS, VONMISES, ENERGY, ZEM, SINGULAR,
    EQPS, PLASTIC_STRAIN, BACK_STRESS, TEMPERATURE, YIELDING, PLASTIC_WORK, JC_DAMAGE,
    STRAIN_RATE, HEAT_FLUX
  };
  std::vector<int> quantities;
  int nmax;
  double **out;
  class PairPeriNospdBase *pair;

  void find_pair();
  int history_columns(int i, int q, double *row, int c) const;
};

}    // namespace LAMMPS_NS

#endif
#endif

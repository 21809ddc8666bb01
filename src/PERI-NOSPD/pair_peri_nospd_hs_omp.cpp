/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The horizon-stabilized style's passes over OpenMP threads.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_hs_omp.h"

#include "comm.h"
#include "suffix.h"

using namespace LAMMPS_NS;

PairPeriNospdHSOMP::PairPeriNospdHSOMP(LAMMPS *lmp) : PairPeriNospdHS(lmp)
{
  suffix_flag |= Suffix::OMP;
  respa_enable = 0;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHSOMP::for_ranges(int n, bool thread_safe, const RangeFn &fn)
{
  threaded_ranges(thread_safe ? comm->nthreads : 1, n, fn);
}

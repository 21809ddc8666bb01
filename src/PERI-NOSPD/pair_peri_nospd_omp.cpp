/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The classical style's passes over OpenMP threads.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_omp.h"

#include "comm.h"
#include "suffix.h"

using namespace LAMMPS_NS;

PairPeriNospdOMP::PairPeriNospdOMP(LAMMPS *lmp) : PairPeriNospd(lmp)
{
  suffix_flag |= Suffix::OMP;
  respa_enable = 0;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdOMP::for_ranges(int n, bool thread_safe, const RangeFn &fn)
{
  threaded_ranges(thread_safe ? comm->nthreads : 1, n, fn);
}

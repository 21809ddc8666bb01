/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   fix nospd/damage over OpenMP threads.
------------------------------------------------------------------------- */

#include "fix_nospd_damage_omp.h"

#include "comm.h"

using namespace LAMMPS_NS;

FixNospdDamageOMP::FixNospdDamageOMP(LAMMPS *lmp, int narg, char **arg) :
    FixNospdDamage(lmp, narg, arg)
{
}

void FixNospdDamageOMP::init()
{
  FixNospdDamage::init();
  nthreads = comm->nthreads;
}

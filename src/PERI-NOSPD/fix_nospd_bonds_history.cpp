/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's use of its history store (NospdHistoryStore):
   its layout follows the families' partner slots, its records travel with
   the atoms, a minimization commits at its end, sums for output.
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "update.h"

#include "nospd_bond_sums.h"
#include "nospd_plasticity.h"
#include "nospd_tensor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

/* ----------------------------------------------------------------------
   inelastic history
------------------------------------------------------------------------- */

void FixNospdBonds::set_history_size(int n_atom, int n_bond)
{
  layout_history(MAX(n_atom, nhist_atom), MAX(n_bond, nhist_bond));
}

/* the pair style reads no history any more (its check let no plastic state
   go): drop it, so that the run goes on as a fresh one would */
void FixNospdBonds::drop_history()
{
  layout_history(0, 0);
}

/* ----------------------------------------------------------------------
   (re)lay the history rows out for n_atom values of the atom and n_bond
   per partner slot; values kept, new columns zero: the virgin state
------------------------------------------------------------------------- */

void FixNospdBonds::layout_history(int n_atom, int n_bond)
{
  hist.layout(n_atom, n_bond, n_bond ? maxpartner : 0, atom->nmax);
  maxexchange = max_exchange_size();
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::pack_history(int i, double *buf) const
{
  return hist.pack(i, buf, npartner[i], partner[i]);
}

int FixNospdBonds::unpack_history(int i, const double *buf, int n_atom, int n_bond)
{
  return hist.unpack(i, buf, n_atom, n_bond, npartner[i]);
}

/* ----------------------------------------------------------------------
   a minimization is one load step: its converged state is accepted
   (an MD run has accepted each of its steps at their end already)
------------------------------------------------------------------------- */

void FixNospdBonds::end_of_step()
{
  commit_history();
  if (update->ntimestep % ZEM_CHECK_EVERY == 0) check_zero_energy_modes();
}

void FixNospdBonds::post_run()
{
  if (update->whichflag == 2) {
    hist.commit();
    check_zero_energy_modes();    // a run is checked every ZEM_CHECK_EVERY steps
  }
  hist.trial_ready = false;
}

/* ---------------------------------------------------------------------- */

double **FixNospdBonds::current_history() const
{
  return hist.current(update->whichflag == 2);
}

/* ----------------------------------------------------------------------
   summed like pe and ke under PERI's conventions (rmass is the density,
   the pair energy the sum of energy densities), so that ke + pe + this is
   the conserved total
------------------------------------------------------------------------- */

double FixNospdBonds::history_sum(int k)
{
  const double sum = hist.local_sum(k, atom->nlocal, update->whichflag == 2);
  double all = 0.0;
  MPI_Allreduce(&sum, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's history store -- trial and accepted rows of
   the inelastic laws, laid out per atom and per partner slot, packed for
   migration, committed at the step's start, summed for output.
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
  const int slots = n_bond ? maxpartner : 0;
  if (n_atom == nhist_atom && n_bond == nhist_bond && slots == hist_slots) return;
  if (n_atom + n_bond == 0) {    // none: the state of a fix that never had any
    memory->destroy(history);
    memory->destroy(history_trial);
    history = history_trial = nullptr;
    nhistory = nhist_atom = nhist_bond = hist_slots = 0;
    maxexchange = maxpartner + 22 + quadratic_record();
    return;
  }
  const int n = n_atom + n_bond * slots;
  const int nmax = atom->nmax;
  double **h = nullptr, **t = nullptr;
  memory->create(h, nmax, n, "nospd/bonds:history");
  memory->create(t, nmax, n, "nospd/bonds:history_trial");
  const int keep_slots = MIN(slots, hist_slots);
  for (int i = 0; i < nmax; i++) {
    for (int k = 0; k < n; k++) h[i][k] = 0.0;
    for (int k = 0; k < nhist_atom; k++) h[i][k] = history[i][k];
    for (int s = 0; s < keep_slots; s++)
      for (int k = 0; k < nhist_bond; k++)
        h[i][n_atom + n_bond * s + k] = history[i][nhist_atom + nhist_bond * s + k];
    for (int k = 0; k < n; k++) t[i][k] = h[i][k];
  }
  memory->destroy(history);
  memory->destroy(history_trial);
  history = h;
  history_trial = t;
  nhistory = n;
  nhist_atom = n_atom;
  nhist_bond = n_bond;
  hist_slots = slots;
  maxexchange = maxpartner + 22 + quadratic_record() + nhistory;
}

/* ----------------------------------------------------------------------
   history of atom i in transit: the atom's values, then the entries of
   its intact partner slots in slot order (broken slots are dropped with
   their partners, see pack_exchange)
------------------------------------------------------------------------- */

int FixNospdBonds::pack_history(int i, double *buf) const
{
  int m = 0;
  for (int k = 0; k < nhist_atom; k++) buf[m++] = history[i][k];
  if (!nhist_bond) return m;
  for (int n = 0; n < npartner[i]; n++) {
    if (!partner[i][n]) continue;
    const double *b = bond_history(history[i], n);
    for (int k = 0; k < nhist_bond; k++) buf[m++] = b[k];
  }
  return m;
}

/* ----------------------------------------------------------------------
   the inverse for atom i, whose partners have arrived compacted; the
   record holds n_atom and n_bond values (its writer's layout)
------------------------------------------------------------------------- */

int FixNospdBonds::unpack_history(int i, const double *buf, int n_atom, int n_bond)
{
  int m = 0;
  double *h = history[i], *t = history_trial[i];
  for (int k = 0; k < nhistory; k++) h[k] = 0.0;
  for (int k = 0; k < n_atom; k++) {
    const double v = buf[m++];
    if (k < nhist_atom) h[k] = v;
  }
  if (n_bond) {
    for (int n = 0; n < npartner[i]; n++) {
      double *b = (n < hist_slots) ? bond_history(h, n) : nullptr;
      for (int k = 0; k < n_bond; k++) {
        const double v = buf[m++];
        if (b && k < nhist_bond) b[k] = v;
      }
    }
  }
  for (int k = 0; k < nhistory; k++) t[k] = h[k];
  return m;
}

/* ----------------------------------------------------------------------
   a minimization is one load step: its converged state is accepted
   (an MD run has accepted each of its steps at their end already)
------------------------------------------------------------------------- */

void FixNospdBonds::post_run()
{
  if (update->whichflag == 2) commit_history();
  trial_ready = 0;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::commit_history()
{
  if (!nhistory || !trial_ready) return;
  // the trial rows become the accepted ones by exchanging the two arrays
  // (same shape, grown together) rather than copying them: a bond-associated
  // family's history is ~900 values per point.  The rows now in
  // history_trial are stale until the next force evaluation, which writes
  // every owned row (the style copies the accepted row first where it
  // evaluates no return)
  std::swap(history, history_trial);
  trial_ready = 0;
}

/* ---------------------------------------------------------------------- */

double **FixNospdBonds::current_history() const
{
  return (update->whichflag == 2 && trial_ready) ? history_trial : history;
}

/* ---------------------------------------------------------------------- */

double FixNospdBonds::history_sum(int k)
{
  double sum = 0.0, all = 0.0;
  if (k < nhistory) {
    const int nlocal = atom->nlocal;
    // summed like pe and ke under PERI's conventions (rmass is the density,
    // the pair energy the sum of energy densities), so that
    // ke + pe + this is the conserved total
    double **h = current_history();
    for (int i = 0; i < nlocal; i++) sum += h[i][k];
  }
  MPI_Allreduce(&sum, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

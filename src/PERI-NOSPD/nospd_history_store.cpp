/* ----------------------------------------------------------------------
   PERI-NOSPD: the history store of the bonds fix (nospd_history_store.h).
------------------------------------------------------------------------- */

#include "nospd_history_store.h"

#include "memory.h"

#include <algorithm>
#include <utility>

using namespace LAMMPS_NS;

NospdHistoryStore::~NospdHistoryStore()
{
  memory->destroy(accepted);
  memory->destroy(trial);
}

/* ---------------------------------------------------------------------- */

void NospdHistoryStore::layout(int na, int nb, int nslots, int nmax)
{
  if (na == n_atom && nb == n_bond && nslots == slots) return;
  if (na + nb == 0) {    // none: the state of a fix that never had any
    memory->destroy(accepted);
    memory->destroy(trial);
    accepted = trial = nullptr;
    n = n_atom = n_bond = slots = 0;
    return;
  }
  const int nn = na + nb * nslots;
  double **h = nullptr, **t = nullptr;
  memory->create(h, nmax, nn, "nospd/bonds:history");
  memory->create(t, nmax, nn, "nospd/bonds:history_trial");
  const int keep_slots = std::min(nslots, slots);
  for (int i = 0; i < nmax; i++) {
    for (int k = 0; k < nn; k++) h[i][k] = 0.0;
    for (int k = 0; k < std::min(n_atom, na); k++) h[i][k] = accepted[i][k];
    for (int s = 0; s < keep_slots; s++)
      for (int k = 0; k < std::min(n_bond, nb); k++)
        h[i][na + nb * s + k] = accepted[i][n_atom + n_bond * s + k];
    for (int k = 0; k < nn; k++) t[i][k] = h[i][k];
  }
  memory->destroy(accepted);
  memory->destroy(trial);
  accepted = h;
  trial = t;
  n = nn;
  n_atom = na;
  n_bond = nb;
  slots = nslots;
}

/* ---------------------------------------------------------------------- */

void NospdHistoryStore::grow(int nmax)
{
  if (!n) return;
  memory->grow(accepted, nmax, n, "nospd/bonds:history");
  memory->grow(trial, nmax, n, "nospd/bonds:history_trial");
}

void NospdHistoryStore::copy(int i, int j)
{
  for (int k = 0; k < n; k++) {
    accepted[j][k] = accepted[i][k];
    trial[j][k] = trial[i][k];
  }
}

void NospdHistoryStore::clear(int i)
{
  for (int k = 0; k < n; k++) accepted[i][k] = trial[i][k] = 0.0;
}

/* ---------------------------------------------------------------------- */

int NospdHistoryStore::pack(int i, double *buf, int npartner, const tagint *partner) const
{
  int m = 0;
  for (int k = 0; k < n_atom; k++) buf[m++] = accepted[i][k];
  if (!n_bond) return m;
  for (int s = 0; s < npartner; s++) {
    if (!partner[s]) continue;
    const double *b = bond(accepted[i], s);
    for (int k = 0; k < n_bond; k++) buf[m++] = b[k];
  }
  return m;
}

int NospdHistoryStore::unpack(int i, const double *buf, int na, int nb, int npartner)
{
  int m = 0;
  double *h = accepted[i], *t = trial[i];
  for (int k = 0; k < n; k++) h[k] = 0.0;
  for (int k = 0; k < na; k++) {
    const double v = buf[m++];
    if (k < n_atom) h[k] = v;
  }
  if (nb) {
    for (int s = 0; s < npartner; s++) {
      double *b = (s < slots) ? bond(h, s) : nullptr;
      for (int k = 0; k < nb; k++) {
        const double v = buf[m++];
        if (b && k < n_bond) b[k] = v;
      }
    }
  }
  for (int k = 0; k < n; k++) t[k] = h[k];
  return m;
}

/* ----------------------------------------------------------------------
   the trial rows become the accepted ones by exchanging the two arrays
   (same shape, grown together) rather than copying them: a bond-associated
   family's history is ~900 values per point.  The rows then in `trial` are
   stale until the next force evaluation, which writes every owned row (the
   styles copy the accepted row first where they evaluate no return)
------------------------------------------------------------------------- */

void NospdHistoryStore::commit()
{
  if (!n || !trial_ready) return;
  std::swap(accepted, trial);
  trial_ready = false;
}

/* ---------------------------------------------------------------------- */

double NospdHistoryStore::local_sum(int k, int nlocal, bool minimizing) const
{
  double sum = 0.0;
  if (k >= n) return sum;
  double **h = current(minimizing);
  for (int i = 0; i < nlocal; i++) sum += h[i][k];
  return sum;
}

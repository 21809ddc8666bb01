/* ----------------------------------------------------------------------
   PERI-NOSPD: the per-atom arrays of fix nospd/damage: the criterion's
   state (migrates with atoms) and the remembered contacts (migrate and go
   into restart files).
------------------------------------------------------------------------- */

#include "fix_nospd_damage.h"

#include "atom.h"
#include "error.h"
#include "memory.h"

#include "nospd_contact_memory.h"

using namespace LAMMPS_NS;
using NOSPD::ContactMemory;

/* ---------------------------------------------------------------------- */

double FixNospdDamage::memory_usage()
{
  double bytes = (double) nmax_comm * ncomm * sizeof(double) + (double) atom->nmax * nstate * sizeof(double);
  if (contact) bytes += (double) atom->nmax * ContactMemory::RECORD * sizeof(double);
  return bytes;
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::grow_arrays(int nmax)
{
  if (nstate) memory->grow(state, nmax, nstate, "nospd/damage:state");
  if (contact) memory->grow(cmem, nmax, ContactMemory::RECORD, "nospd/damage:cmem");
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::copy_arrays(int i, int j, int /*delflag*/)
{
  for (int k = 0; k < nstate; k++) state[j][k] = state[i][k];
  if (contact)
    for (int k = 0; k < ContactMemory::used(cmem[i]); k++) cmem[j][k] = cmem[i][k];
}

/* ---------------------------------------------------------------------- */

int FixNospdDamage::pack_exchange(int i, double *buf)
{
  int m = 0;
  for (int k = 0; k < nstate; k++) buf[m++] = state[i][k];
  if (contact)
    for (int k = 0; k < ContactMemory::used(cmem[i]); k++) buf[m++] = cmem[i][k];
  return m;
}

/* ---------------------------------------------------------------------- */

int FixNospdDamage::unpack_exchange(int nlocal, double *buf)
{
  int m = 0;
  for (int k = 0; k < nstate; k++) state[nlocal][k] = buf[m++];
  if (contact) {
    const int n = 1 + 2 * static_cast<int>(buf[m]);
    for (int k = 0; k < n; k++) cmem[nlocal][k] = buf[m++];
  }
  return m;
}

/* ----------------------------------------------------------------------
   restart: the remembered contacts only (the criterion's state is
   recomputed by the first force evaluation)
------------------------------------------------------------------------- */

int FixNospdDamage::pack_restart(int i, double *buf)
{
  const int n = ContactMemory::used(cmem[i]);
  buf[0] = n + 1;
  for (int k = 0; k < n; k++) buf[1 + k] = cmem[i][k];
  return n + 1;
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  const double count = extra[nlocal][m];
  if (!(count >= 0.0 && count <= ContactMemory::CAPACITY && count == static_cast<int>(count)))
    error->one(FLERR, "Fix {}: restart file holds {} remembered contacts for an atom (0 to {}): "
               "the file is damaged or from another version", style, count, ContactMemory::CAPACITY);
  const int n = 1 + 2 * static_cast<int>(count);
  for (int k = 0; k < n; k++) cmem[nlocal][k] = extra[nlocal][m++];
}

/* ---------------------------------------------------------------------- */

int FixNospdDamage::size_restart(int nlocal)
{
  return 1 + ContactMemory::used(cmem[nlocal]);
}

/* ---------------------------------------------------------------------- */

int FixNospdDamage::maxsize_restart()
{
  return 1 + ContactMemory::RECORD;
}

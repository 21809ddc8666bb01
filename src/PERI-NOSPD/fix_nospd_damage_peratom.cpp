/* ----------------------------------------------------------------------
   PERI-NOSPD: the per-atom arrays of fix nospd/damage: the criterion's
   state (stored after each force computation, thermal strain included;
   migrates with atoms) and the remembered contacts (migrate and go into
   restart files).
------------------------------------------------------------------------- */

#include "fix_nospd_damage.h"

#include "atom.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "memory.h"
#include "pair_peri_nospd_base.h"

#include "nospd_constitutive.h"
#include "nospd_contact_memory.h"
#include "nospd_plasticity.h"
#include "nospd_tensor.h"
#include "nospd_threads.h"

using namespace LAMMPS_NS;
using NOSPD::ContactMemory;
using NOSPD::Mat3;

/* ----------------------------------------------------------------------
   the thermal column travels to the ghosts only where a type has a
   thermal strain (the plain stretch loop then takes its thermal variant)
------------------------------------------------------------------------- */

void FixNospdDamage::init_thermal()
{
  thermal = false;
  small_law = pair->law() == NOSPD::Law::SMALL;
  if (ecol >= 0)
    for (int i = 1; i <= atom->ntypes; i++)
      if (pair->has_thermal_strain(i)) thermal = true;
  const int n = 4 + nstate - ((ecol >= 0 && !thermal) ? 1 : 0);
  if (n != ncomm) {
    memory->destroy(cdata);
    cdata = nullptr;
    nmax_comm = 0;
    ncomm = n;
  }
}

/* ----------------------------------------------------------------------
   what the criteria need of each owned atom, from the force computation
   that just ended: A = P K^-1 (energy), the Cauchy stress or the strain
   (tensor criteria; xx yy zz xy xz yz); zero for a singular family
------------------------------------------------------------------------- */

void FixNospdDamage::store_state()
{
  if (!nstate || !bonds) return;
  const int nlocal = atom->nlocal;
  if (thermal)
    for (int i = 0; i < nlocal; i++) state[i][ecol] = pair->thermal_strain(i);
  if (criterion == STRETCH) return;
  const NOSPD::Law law = pair->law();
  if (criterion == EQPS || criterion == JC_DAMAGE) {
    // the point's history after this force computation (the trial state,
    // which the end of the step accepts)
    const int k = (criterion == EQPS) ? NOSPD::Hist::EQPS : NOSPD::Hist::DAMAGE;
    // only the built-in plastic types keep EQPS and DAMAGE there
    const bool has = bonds->nhistory > k;
    const int *type = atom->type;
    for (int i = 0; i < nlocal; i++)
      state[i][0] = (has && pair->has_history(type[i])) ? bonds->history_trial[i][k] : 0.0;
    return;
  }
  NOSPD::run_ranges(nthreads, nlocal,
                    [&](int from, int to, int) { store_state_range(law, from, to); });
}

void FixNospdDamage::store_state_range(NOSPD::Law law, int from, int to)
{
  for (int i = from; i < to; i++) {
    double *c = state[i];
    const bool sing = bonds->singular[i] != 0;
    if (sing) {
      for (int k = 0; k < nstate; k++)
        if (k != ecol) c[k] = 0.0;
      continue;
    }
    const Mat3 F = NOSPD::load(bonds->defgrad[i]);
    const Mat3 P = NOSPD::load(bonds->pk1[i]);
    if (criterion == ENERGY) {
      NOSPD::store(Mat3(P * NOSPD::load(bonds->kinv[i])), c);
      continue;
    }
    Mat3 S;
    if (criterion == STRAIN_PRINCIPAL) {
      // the mechanical strain: the thermal one removed as the law removes it
      const Mat3 I = Mat3::Identity();
      const double e = thermal ? c[ecol] : 0.0, l = 1.0 + e;
      S = NOSPD::small_kinematics(law) ? Mat3(0.5 * (F + F.transpose()) - (1.0 + e) * I)
                                     : Mat3(0.5 * (F.transpose() * F / (l * l) - I));
    } else
      S = NOSPD::cauchy_stress(law, F, P);
    c[0] = S(0, 0);
    c[1] = S(1, 1);
    c[2] = S(2, 2);
    c[3] = S(0, 1);
    c[4] = S(0, 2);
    c[5] = S(1, 2);
  }
}

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

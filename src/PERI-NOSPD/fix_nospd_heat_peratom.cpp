/* ----------------------------------------------------------------------
   PERI-NOSPD: fix nospd/heat's per-atom state -- the temperature and its
   companions (fix_nospd_heat.h: SEEN, KAPPA, AREA0, FACES, KCUR, MCAL)
   through forward communication, migration and restart files.
------------------------------------------------------------------------- */

#include "fix_nospd_heat.h"

#include "atom.h"
#include "comm.h"
#include "memory.h"

#include <limits>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

// mode 0: temperature and kappa (this frame's); mode 1: J (frame current)
int FixNospdHeat::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    if (comm_mode == 1) {
      buf[m++] = jcur[j];
      continue;
    }
    buf[m++] = tfield[j];
    buf[m++] = kappa_of(j);
  }
  return m;
}

void FixNospdHeat::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    if (comm_mode == 1) {
      jcur[i] = buf[m++];
      continue;
    }
    tfield[i] = buf[m++];
    (current_frame ? kcur[i] : aux[i][KAPPA]) = buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdHeat::grow_arrays(int nmax)
{
  memory->grow(tfield, nmax, "nospd/heat:tfield");
  memory->grow(aux, nmax, NAUX, "nospd/heat:aux");
  vector_atom = tfield;
}

void FixNospdHeat::copy_arrays(int i, int j, int /*delflag*/)
{
  tfield[j] = tfield[i];
  for (int k = 0; k < NAUX; k++) aux[j][k] = aux[i][k];
}

void FixNospdHeat::set_arrays(int i)
{
  tfield[i] = std::numeric_limits<double>::quiet_NaN();    // set at the next init
  aux[i][SEEN] = 0.0;
  aux[i][KAPPA] = -1.0;    // calibrated at the next setup
  for (int k = AREA0; k < NAUX; k++) aux[i][k] = 0.0;    // MCAL 0: taken at the first step
}

int FixNospdHeat::pack_exchange(int i, double *buf)
{
  buf[0] = tfield[i];
  for (int k = 0; k < NAUX; k++) buf[1 + k] = aux[i][k];
  return 1 + NAUX;
}

int FixNospdHeat::unpack_exchange(int i, double *buf)
{
  tfield[i] = buf[0];
  for (int k = 0; k < NAUX; k++) aux[i][k] = buf[1 + k];
  return 1 + NAUX;
}

/* ---------------------------------------------------------------------- */

void FixNospdHeat::write_restart(FILE *fp)
{
  double v[2] = {compute_vector(2), 0.0};
  MPI_Allreduce(&plastic_in, &v[1], 1, MPI_DOUBLE, MPI_SUM, world);
  if (comm->me == 0) {
    int size = 2 * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(v, sizeof(double), 2, fp);
  }
}

void FixNospdHeat::restart(char *buf)
{
  const auto *v = reinterpret_cast<const double *>(buf);
  inflow = comm->me == 0 ? v[0] : 0.0;
  plastic_in = comm->me == 0 ? v[1] : 0.0;
}

int FixNospdHeat::pack_restart(int i, double *buf)
{
  buf[0] = 2 + NAUX;
  return 1 + pack_exchange(i, buf + 1);
}

void FixNospdHeat::unpack_restart(int nlocal, int nth)
{
  double **extra_rec = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra_rec[nlocal][m]);
  unpack_exchange(nlocal, &extra_rec[nlocal][m + 1]);
}

int FixNospdHeat::size_restart(int /*i*/)
{
  return 2 + NAUX;
}

int FixNospdHeat::maxsize_restart()
{
  return 2 + NAUX;
}

double FixNospdHeat::memory_usage()
{
  return (double) atom->nmax * (1 + NAUX) * sizeof(double) + coef.capacity() * sizeof(double);
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's reference frame -- x0 in the periodic image
   of x (shifted by the reference box), the body's mean displacement, the
   reference box followed through flips, and the one reference bond
   geometry every consumer takes (reference_bond).
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "math_const.h"
#include "memory.h"
#include "update.h"

#include "nospd_bond_sums.h"
#include "nospd_plasticity.h"
#include "nospd_reference_box.h"
#include "nospd_tensor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

/* ----------------------------------------------------------------------
   x0 in the periodic image of x, for owned and ghost atoms.  Ghosts carry
   their owner's x0 unshifted, so x - x0 = u + (image shift); the minimum
   image of that difference, taken about the body's mean displacement
   u_m, is u - u_m (valid while |u - u_m| stays below half a box length:
   any rigid translation, a shear with remap up to nearly 100 %), and the
   rest counts whole box lengths.  u_m is the circular mean of the owned
   atoms' displacements in box fractions (their x wrapped by whole box
   lengths must not pull it), the same on every rank.  The
   image of the reference is shifted by the REFERENCE box length: a box
   deformed since the families were built (fix deform, change_box) must not
   stretch the reference bonds that cross its boundary.
------------------------------------------------------------------------- */

void FixNospdBonds::update_x0s()
{
  const int nall = atom->nlocal + atom->nghost;
  if (!(domain->xperiodic || domain->yperiodic || domain->zperiodic)) {
    x0s = atom->x0;
    return;
  }
  follow_box();
  // one row more than the atoms: the bond sums read a double past the last
  if (nall + 1 > nmax_x0s) {
    nmax_x0s = std::max(atom->nmax, nall + 1);
    memory->destroy(x0s_store);
    memory->create(x0s_store, nmax_x0s, 3, "nospd/bonds:x0s");
  }
  x0s_store[nall][0] = x0s_store[nall][1] = x0s_store[nall][2] = 0.0;
  double **x = atom->x;
  double **x0 = atom->x0;
  const double *h = domain->h;
  double um[3];
  mean_displacement(um);
  for (int i = 0; i < nall; i++) {
    const double d0[3] = {x[i][0] - x0[i][0] - um[0], x[i][1] - x0[i][1] - um[1],
                          x[i][2] - x0[i][2] - um[2]};
    double d[3] = {d0[0], d0[1], d0[2]};
    domain->minimum_image(FLERR, d);
    // shift = n0 a + n1 b + n2 c, the current box vectors (upper triangular)
    const double s0 = d0[0] - d[0], s1 = d0[1] - d[1], s2 = d0[2] - d[2];
    const double n2 = std::round(s2 / h[2]);
    const double n1 = std::round((s1 - n2 * h[3]) / h[1]);
    const double n0 = std::round((s0 - n1 * h[5] - n2 * h[4]) / h[0]);
    double shift[3];
    ref_box.image(n0, n1, n2, shift);
    for (int k = 0; k < 3; k++) x0s_store[i][k] = x0[i][k] + shift[k];
  }
  x0s = x0s_store;
}

/* ----------------------------------------------------------------------
   the circular mean of the owned atoms' displacements x - x0 along each
   periodic box vector (as fractions of it), in distance units: atoms that
   crossed a periodic boundary count as where they were
------------------------------------------------------------------------- */

void FixNospdBonds::mean_displacement(double *um) const
{
  const int nlocal = atom->nlocal;
  double **x = atom->x, **x0 = atom->x0;
  const int *type = atom->type;
  const double *hi = domain->h_inv, *h = domain->h;
  const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
  double cs[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, cs_all[6];
  for (int i = 0; i < nlocal; i++) {
    if (model.active && !model.active[type[i]]) continue;
    const double d[3] = {x[i][0] - x0[i][0], x[i][1] - x0[i][1], x[i][2] - x0[i][2]};
    const double lam[3] = {hi[0] * d[0] + hi[5] * d[1] + hi[4] * d[2], hi[1] * d[1] + hi[3] * d[2],
                           hi[2] * d[2]};
    for (int k = 0; k < 3; k++) {
      cs[k] += cos(MathConst::MY_2PI * lam[k]);
      cs[3 + k] += sin(MathConst::MY_2PI * lam[k]);
    }
  }
  MPI_Allreduce(cs, cs_all, 6, MPI_DOUBLE, MPI_SUM, world);
  double m[3];
  for (int k = 0; k < 3; k++) {
    const bool defined = periodic[k] && (cs_all[k] != 0.0 || cs_all[3 + k] != 0.0);
    m[k] = defined ? atan2(cs_all[3 + k], cs_all[k]) / (MathConst::MY_2PI) : 0.0;
  }
  um[0] = h[0] * m[0] + h[5] * m[1] + h[4] * m[2];
  um[1] = h[1] * m[1] + h[3] * m[2];
  um[2] = h[2] * m[2];
}

/* ----------------------------------------------------------------------
   the reference box follows the basis of the current one through flips
   (NOSPD::ReferenceBox::follow).  Called at every reneighboring and, for
   triclinic boxes, every step (post_integrate).
------------------------------------------------------------------------- */

void FixNospdBonds::follow_box()
{
  ref_box.follow(domain->h);
}
/* ---------------------------------------------------------------------- */

void FixNospdBonds::reference_bond(const double *x0i, const double *x0j, double *xi) const
{
  const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
  ref_box.bond(x0i, x0j, periodic, domain->h, xi);
}

void FixNospdBonds::bond_vector(int i, int b, double *xi) const
{
  reference_bond(atom->x0[i], atom->x0[bond_j[b]], xi);
}

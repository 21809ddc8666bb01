/* ----------------------------------------------------------------------
   PERI-NOSPD: the contact force of fix nospd/damage: a short-range repulsion
   between points that share no intact bond (its own neighbor list).
------------------------------------------------------------------------- */

#include "fix_nospd_damage.h"

#include "atom.h"
#include "domain.h"
#include "fix_nospd_bonds.h"
#include "neigh_list.h"

#include "nospd_contact_memory.h"
#include "nospd_damage_criteria.h"

#include "nospd_threads.h"

#include <cmath>

using namespace LAMMPS_NS;
using NOSPD::ContactMemory;
using NOSPD::Mat3;

/* ----------------------------------------------------------------------
   Short-range contact between points without an intact bond (crack
   faces, fragments, separate bodies), after the short-range force idea of
   Silling's EMU and LAMMPS's PERI styles, written as a repulsive spring:
     f_i += k_IJ V_j (r - d_ij)/delta_IJ (x_j - x_i)/r   for r < d_ij
     d_ij = min(0.9 |xi_ij|, r_c),  k_IJ = C c_IJ
   c_IJ the bond-based micromodulus of the materials (3D 18K/(pi delta^4),
   2D 9E/(pi t delta^3) plane stress, 48E/(5 pi t delta^3) plane strain),
   C = contact/stiffness (default 15), r_c = contact/radius (default 1.35
   times the point spacing).  Pairs V_i f_i + V_j f_j = 0: momentum is
   conserved.  Force density, like every force of the peri styles.  Its
   potential, in the styles' density convention (each end takes half):
     e_i += 1/4 k_IJ V_j (r - d_ij)^2/delta_IJ   per partner j in contact,
   and the virial 1/2 (x_i - x_j) (x) f_i, both tallied on i.
------------------------------------------------------------------------- */

void FixNospdDamage::contact_forces()
{
  econtact = econtact_volume = 0.0;
  if (!list) return;
  double **x = atom->x, **x0 = atom->x0, **f = atom->f;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  const double *vfrac = atom->vfrac;
  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  const double rc2 = contact_rc * contact_rc;

  // per thread: contacts, energy, global virial
  struct Sums {
    bigint nc = 0;
    double e = 0.0, ev = 0.0;    // density convention, and sum V_i e_i
    double v[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  };
  std::vector<Sums> sums(NOSPD::range_count(nthreads, inum));
  NOSPD::run_ranges(sums.size(), inum, [&](int from, int to, int tid) {
    bigint &nc = sums[tid].nc;
    double &e = sums[tid].e;
    double &ev = sums[tid].ev;
    // the energy audit's copy of the material's force
    double *fm = auditing ? fmat.data() : nullptr;
    double *vsum = sums[tid].v;
    for (int ii = from; ii < to; ii++) {
      const int i = ilist[ii];
      if (!(mask[i] & groupbit)) continue;
      const int *jlist = firstneigh[i];
      double *rec = cmem[i];
      const int nmem = ContactMemory::count(rec);
      bool keep[ContactMemory::CAPACITY] = {};
      for (int jj = 0; jj < numneigh[i]; jj++) {
        const int j = jlist[jj] & NEIGHMASK;
        if (!(mask[j] & groupbit)) continue;
        const double dx = x[j][0] - x[i][0], dy = x[j][1] - x[i][1], dz = x[j][2] - x[i][2];
        const double rsq = dx * dx + dy * dy + dz * dz;
        if (rsq >= rc2 || rsq == 0.0) continue;
        double d0[3];
        bonds->reference_bond(x0[i], x0[j], d0);
        const double r0 = sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]);
        const double dij = std::min(0.9 * r0, contact_rc);
        const double r = sqrt(rsq);
        const int k = nmem ? ContactMemory::find(rec, (double) tag[j]) : -1;
        if (k < 0 && r >= dij) continue;
        if (bonded(i, tag[j])) continue;    // bonded pairs interact through their bond
        const int it = type[i], jt = type[j];
        if (delta[it][jt] == 0.0) continue;    // another pair style's type
        const double d = ContactMemory::rest(rec, k, r, dij, keep);
        if (r >= d) continue;
        const double kv = kcontact[it][jt] * vfrac[j] / delta[it][jt];
        const double fpair = kv * (r - d) / r;
        f[i][0] += fpair * dx;
        f[i][1] += fpair * dy;
        f[i][2] += fpair * dz;
        if (fm) {
          fm[3 * i] += fpair * dx;
          fm[3 * i + 1] += fpair * dy;
          fm[3 * i + 2] += fpair * dz;
        }
        e += 0.25 * kv * (r - d) * (r - d);
        ev += vfrac[i] * 0.25 * kv * (r - d) * (r - d);
        if (vflag_either) contact_virial(i, fpair, dx, dy, dz, vsum);
        nc++;
      }
      if (nmem) ContactMemory::prune(rec, keep);
    }
  });
  bigint nc = 0;
  double e = 0.0, ev = 0.0;
  for (const Sums &t : sums) {
    nc += t.nc;
    e += t.e;
    ev += t.ev;
    if (vflag_global)
      for (int k = 0; k < 6; k++) virial[k] += t.v[k];
  }
  econtact = e;
  econtact_volume = ev;
  bigint all = 0;
  MPI_Allreduce(&nc, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  ncontact = all / 2;
}

/* ---------------------------------------------------------------------- */

bool FixNospdDamage::bonded(int i, tagint tj) const
{
  for (int n = 0; n < bonds->npartner[i]; n++)
    if (bonds->partner[i][n] == tj) return true;
  return false;
}

/* ----------------------------------------------------------------------
   the virial of one contact force on i: 1/2 (x_i - x_j) (x) f_i, with
   x_i - x_j = -(dx, dy, dz)
------------------------------------------------------------------------- */

void FixNospdDamage::contact_virial(int i, double fpair, double dx, double dy, double dz,
                                    double *vsum)
{
  const double v[6] = {-0.5 * fpair * dx * dx, -0.5 * fpair * dy * dy, -0.5 * fpair * dz * dz,
                       -0.5 * fpair * dx * dy, -0.5 * fpair * dx * dz, -0.5 * fpair * dy * dz};
  if (vflag_global)
    for (int k = 0; k < 6; k++) vsum[k] += v[k];
  if (vflag_atom)
    for (int k = 0; k < 6; k++) vatom[i][k] += v[k];
}

/* ----------------------------------------------------------------------
   bonds about to break (atom, slot): a pair already closer than its
   contact rest distance remembers its distance as the rest distance
   (NOSPD::ContactMemory), so that contact does not start loaded
------------------------------------------------------------------------- */

void FixNospdDamage::remember_contacts(const std::vector<std::pair<int, int>> &cut)
{
  double **x = atom->x, **x0 = atom->x0;
  const int *type = atom->type;
  const int *mask = atom->mask;
  for (const auto &c : cut) {
    const int i = c.first;
    const tagint tj = bonds->partner[i][c.second];
    int j = atom->map(tj);
    if (j < 0 || !(mask[i] & groupbit)) continue;
    j = domain->closest_image(i, j);
    if (!(mask[j] & groupbit) || delta[type[i]][type[j]] == 0.0) continue;
    const double dx = x[j][0] - x[i][0], dy = x[j][1] - x[i][1], dz = x[j][2] - x[i][2];
    const double r = sqrt(dx * dx + dy * dy + dz * dz);
    if (!(r < contact_rc)) continue;
    double d0[3];
    bonds->reference_bond(x0[i], x0[j], d0);
    const double r0 = sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]);
    if (!ContactMemory::remember(cmem[i], (double) tj, r, std::min(0.9 * r0, contact_rc))) cmem_full++;
  }
}

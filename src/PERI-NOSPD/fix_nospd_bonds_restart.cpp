/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's restart -- its global record (style, model,
   reference box), per-atom records, and the adoption of a restart written
   by the other pair style.
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "neigh_list.h"

#include "nospd_carry.h"

#include <cmath>
#include <vector>

using namespace LAMMPS_NS;

static constexpr int RESTART_V2 = 10;
static constexpr int RESTART_V3 = 20;
static constexpr int RESTART_V4 = 30;    // and whether atoms carry quadratic curvatures

/* ----------------------------------------------------------------------
   global restart data: FixPeriNeigh's two values, the reference box, and
   what the families were built with (periodicity, the writer's pair style,
   the horizons, the laws whose state the history holds), so that a restart
   is checked against a changed input as a continued session is
------------------------------------------------------------------------- */

void FixNospdBonds::write_restart(FILE *fp)
{
  // list[0] is `first` plus RESTART_V4 (V3 files end before the curvature
  // flag, V2 files hold seven values, older six)
  std::vector<double> list = {(double) (first + RESTART_V4), (double) maxpartner,
                              (double) ref_box.set, ref_box.ref[0], ref_box.ref[1], ref_box.ref[2],
                              (double) nbonds_vanished, ref_box.ref[3], ref_box.ref[4], ref_box.ref[5],
                              (double) built_periodic, (double) style_kind,
                              (double) family_horizon.size(), (double) history_law.size()};
  list.insert(list.end(), family_horizon.begin(), family_horizon.end());
  list.insert(list.end(), history_law.begin(), history_law.end());
  list.push_back(kinv2 ? 1.0 : 0.0);
  if (comm->me == 0) {
    int size = list.size() * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::restart(char *buf)
{
  auto *list = (double *) buf;
  const int head = static_cast<int>(list[0]);
  first = head % RESTART_V2;
  if (head >= RESTART_V2) nbonds_vanished = static_cast<bigint>(list[6]);
  maxpartner = static_cast<int>(list[1]);
  ref_box.set = list[2] != 0.0;
  for (int k = 0; k < 3; k++) ref_box.ref[k] = list[3 + k];
  // older files: the reference tilts are unknown, take the box's
  for (int k = 3; k < 6; k++) ref_box.ref[k] = domain->h[k];
  for (int k = 0; k < 6; k++) ref_box.last[k] = domain->h[k];
  if (head >= RESTART_V3) {
    for (int k = 3; k < 6; k++) ref_box.ref[k] = list[4 + k];
    built_periodic = static_cast<int>(list[10]);
    restart_kind = static_cast<int>(list[11]);
    const int nh = static_cast<int>(list[12]), nl = static_cast<int>(list[13]);
    family_horizon.assign(list + 14, list + 14 + nh);
    history_law.assign(list + 14 + nh, list + 14 + nh + nl);
    // the quadratic fit's arrays, to receive the curvatures the atoms carry
    // (nospd_quadratic_carry.h); the pair's set_model keeps or drops them
    if (head >= RESTART_V4 && list[14 + nh + nl] != 0.0) model.quadratic = true;
  }
  if (nhist_bond) layout_history(nhist_atom, nhist_bond);
  // partner arrays are 2D: size them now, before the per-atom data arrive
  grow_arrays(atom->nmax);
}

/* ---------------------------------------------------------------------- */

static const char *style_of_kind(int kind)
{
  return kind == 2 ? "peri/nospd/hs" : "peri/nospd";
}

void FixNospdBonds::adopt_style(int kind)
{
  if (restart_kind && restart_kind != kind) {
    if (comm->me == 0)
      error->warning(FLERR, "Fix {}: the restart file's bond families and state were written "
                     "under pair_style {}; pair_style {} builds new ones at the next run, as a "
                     "pair_style command between runs does (broken bonds and inelastic history "
                     "are not carried over)", id, style_of_kind(restart_kind), style_of_kind(kind));
    start_over();
  }
  restart_kind = 0;
  style_kind = kind;
}

/* ----------------------------------------------------------------------
   forget the families and the state: the next setup builds them anew
------------------------------------------------------------------------- */

void FixNospdBonds::start_over()
{
  for (int i = 0; i < atom->nlocal; i++) clear_atom(i);
  first = 1;
  nbonds_vanished = 0;
  // the x0 stay, and with them the box they are the reference of
  built_periodic = -1;
  family_horizon.clear();
  history_law.clear();
}

/* ----------------------------------------------------------------------
   restart: the families (intact partners only), the partner volume sum and
   the singular flag (kept for a family that lost bonds);
   K^-1 and the bond arrays are rebuilt from them at setup
------------------------------------------------------------------------- */

int FixNospdBonds::pack_restart(int i, double *buf)
{
  int m = 2;
  for (int n = 0; n < npartner[i]; n++)
    if (partner[i][n]) buf[m++] = partner[i][n];
  buf[1] = m - 2;
  buf[m++] = vinter[i];
  buf[m++] = family_size[i];
  // the history's layout: its size, or (with entries per partner slot)
  // minus the atom's part and the size of a slot's entry
  if (nhist_bond) {
    buf[m++] = -nhist_atom;
    buf[m++] = nhist_bond;
  } else {
    buf[m++] = nhistory;
  }
  m += pack_history(i, buf + m);
  buf[m++] = ubuf(own_tag[i]).d;
  buf[m++] = family_type[i];
  buf[m++] = singular[i] == 1;    // a damaged family's stays (update_shape_tensors)
  for (int k = 0; k < 9; k++) buf[m++] = fcarry[i][k];
  buf[m++] = kinv2 ? NOSPD::CarriedQuadratic::G_SIZE : 0;
  if (kinv2)
    for (int k = 0; k < NOSPD::CarriedQuadratic::G_SIZE; k++)
      buf[m++] = kinv2[i][NOSPD::CarriedQuadratic::G_AT + k];
  buf[0] = m;    // first value: size of this fix's record, as Atom expects
  return m;
}

/* ---------------------------------------------------------------------- */

void FixNospdBonds::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  const int end = m + static_cast<int>(extra[nlocal][m]);
  m++;
  npartner[nlocal] = static_cast<int>(extra[nlocal][m++]);
  for (int n = 0; n < npartner[nlocal]; n++)
    partner[nlocal][n] = static_cast<tagint>(extra[nlocal][m++]);
  vinter[nlocal] = extra[nlocal][m++];
  family_size[nlocal] = static_cast<int>(extra[nlocal][m++]);
  wvolume[nlocal] = 0.0;
  singular[nlocal] = 0;
  stale[nlocal] = 1;
  int n_atom = static_cast<int>(extra[nlocal][m++]), n_bond = 0;
  if (n_atom < 0) {
    n_atom = -n_atom;
    n_bond = static_cast<int>(extra[nlocal][m++]);
  }
  set_history_size(n_atom, n_bond);
  if (nhistory) m += unpack_history(nlocal, &extra[nlocal][m], n_atom, n_bond);
  // files written before IDs were tracked end here: the ID is the file's
  own_tag[nlocal] = (m < end) ? (tagint) ubuf(extra[nlocal][m++]).i : 0;
  // and before the type of the families was kept: unknown (not checked)
  family_type[nlocal] = (m < end) ? static_cast<int>(extra[nlocal][m++]) : 0;
  // and before a damaged family's singularity was kept: found anew
  if (m < end) singular[nlocal] = static_cast<int>(extra[nlocal][m++]);
  // and before families carried F_c (nospd_carry.h): none carried
  for (int k = 0; k < 9; k++) fcarry[nlocal][k] = (k % 4 == 0) ? 1.0 : 0.0;
  if (m + 9 <= end) {
    NOSPD::Mat3 Fc = NOSPD::load(&extra[nlocal][m]);
    m += 9;
    if (!NOSPD::carried_deformation_valid(Fc))
      error->one(FLERR, "Fix {}: the restart file's carried deformation of atom {} is {}: the file "
                 "is damaged", id, atom->tag[nlocal], (Fc - NOSPD::Mat3::Identity()).norm());
    NOSPD::store(Fc, fcarry[nlocal]);
  }
  // and before families carried quadratic curvatures: none carried
  if (kinv2)
    for (int k = 0; k < NOSPD::CarriedQuadratic::ATOM_RECORD; k++) kinv2[nlocal][k] = 0.0;
  const int ng = (m < end) ? static_cast<int>(extra[nlocal][m++]) : 0;
  if (ng != 0 && ng != NOSPD::CarriedQuadratic::G_SIZE)
    error->one(FLERR, "Fix {}: the restart file's record of atom {} holds {} curvature values "
               "(expected 0 or {}): the file is damaged", id, atom->tag[nlocal], ng,
               NOSPD::CarriedQuadratic::G_SIZE);
  for (int k = 0; k < ng; k++) {
    const double g = extra[nlocal][m++];
    if (!std::isfinite(g))
      error->one(FLERR, "Fix {}: the restart file's carried curvature of atom {} is {}: the "
                 "file is damaged", id, atom->tag[nlocal], g);
    if (kinv2) kinv2[nlocal][NOSPD::CarriedQuadratic::G_AT + k] = g;
  }
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::maxsize_restart()
{
  return maxpartner + 19 + NOSPD::CarriedQuadratic::G_SIZE + nhistory;
}

/* ---------------------------------------------------------------------- */

int FixNospdBonds::size_restart(int nlocal)
{
  int n = 0;
  for (int k = 0; k < npartner[nlocal]; k++)
    if (partner[nlocal][k]) n++;
  return n + 18 + (kinv2 ? NOSPD::CarriedQuadratic::G_SIZE : 0) + (nhist_bond ? 1 : 0) +
      nhist_atom + n * nhist_bond;
}

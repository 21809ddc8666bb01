/* ----------------------------------------------------------------------
   PERI-NOSPD: fix nospd/damage's energy audit (nospd_energy_audit.h): the
   work the material's own forces do on it against the energy it stores
   and dissipates; a warning, once, when it creates energy.
------------------------------------------------------------------------- */

#include "fix_nospd_damage.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "modify.h"
#include "pair_peri_nospd_base.h"
#include "update.h"

#include <cstring>

using namespace LAMMPS_NS;

namespace {
// energy created beyond this fraction of the dissipated warns (issue 44's
// bound on the suite's fragmentation and perforation scenes)
constexpr double CREATED_FRACTION = 0.01;
// ... and above this fraction of the energy in motion (kinetic and stored,
// or moved since the start): the time integration's wander stays below it
// (measured: 1e-4 in a crushed block's fragments flying apart)
constexpr double NOISE_FLOOR = 1.0e-3;
}    // namespace

/* ----------------------------------------------------------------------
   the audit needs dynamics (velocity Verlet: a step moves x by dt v at the
   half step), the forces of a potential and no other pair style adding to
   the same atoms, and a temperature that holds (fix nospd/heat or the
   user's changes the stored energy where nothing moves)
------------------------------------------------------------------------- */

void FixNospdDamage::audit_init()
{
  auditing = audit_wanted && update->whichflag == 1 && force->pair == pair &&
      pair->potential_cause().empty() && modify->get_fix_by_style("^nospd/heat").empty() &&
      !pair->temperature_given() && update->integrate_style &&
      std::strcmp(update->integrate_style, "verlet") == 0;
  audit.restart();
  work_local = 0.0;
}

/* ----------------------------------------------------------------------
   the material's force of this evaluation: the pair style's, before any
   fix adds to atom->f (pre_reverse); contact_forces adds its own
------------------------------------------------------------------------- */

void FixNospdDamage::audit_forces()
{
  const int nlocal = atom->nlocal;
  fmat.resize(3 * static_cast<size_t>(nlocal));
  if (nlocal) std::memcpy(fmat.data(), atom->f[0], sizeof(double) * 3 * nlocal);
}

/* ----------------------------------------------------------------------
   half of a step's work on the material: -1/2 dt sum V f . v, v the half
   step's velocity (after initial_integrate, before final_integrate) and f
   the material's force at either end of the step
------------------------------------------------------------------------- */

void FixNospdDamage::audit_half_step()
{
  const int nlocal = atom->nlocal;
  if ((int) fmat.size() < 3 * nlocal) return;    // no force of this evaluation yet
  double **v = atom->v;
  const double *vfrac = atom->vfrac;
  double w = 0.0;
  for (int i = 0; i < nlocal; i++)
    w += vfrac[i] * (fmat[3 * i] * v[i][0] + fmat[3 * i + 1] * v[i][1] + fmat[3 * i + 2] * v[i][2]);
  work_local -= 0.5 * update->dt * w;
}

/* ----------------------------------------------------------------------
   on steps whose energies were tallied: the balance, and a warning once
------------------------------------------------------------------------- */

void FixNospdDamage::audit_observe()
{
  if (update->eflag_global != update->ntimestep) return;
  const int nlocal = atom->nlocal;
  const double *vfrac = atom->vfrac;
  const int *type = atom->type;
  const double *wdens = bonds->energy_density;
  double local[4] = {work_local, econtact_volume, 0.0, 0.0}, all[4];
  double **v = atom->v;
  const double *rho = atom->rmass;
  const int nhist = bonds->nhistory;
  double **hist = bonds->history_trial;
  for (int i = 0; i < nlocal; i++) {
    local[1] += vfrac[i] * wdens[i];
    local[3] += 0.5 * vfrac[i] * rho[i] * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    if (nhist > NOSPD::Hist::WORK && pair->material_law(type[i]).history_size() > 0)
      local[2] += vfrac[i] * hist[i][NOSPD::Hist::WORK];
  }
  MPI_Allreduce(local, all, 4, MPI_DOUBLE, MPI_SUM, world);
  audit.observe(all[0], all[1], all[2], all[3]);
  // (before any bond breaks the material is elastic: nothing to audit)
  if (audit_warned || nbroken_total == 0 || !audit.creates(CREATED_FRACTION, NOISE_FLOOR)) return;
  audit_warned = true;
  const double dis = audit.dissipated();
  const std::string share = dis > 0.0
      ? fmt::format("{:.3g} % of the {:.4g} it dissipated (bound {:.3g} %)",
                    100.0 * audit.created() / dis, dis, 100.0 * CREATED_FRACTION)
      : fmt::format("while it dissipated {:.4g}: it gained energy", dis);
  if (comm->me == 0)
    error->warning(FLERR, "fix {} {}: step {}: the material created energy: {:.4g} (the work "
                   "of its own forces less its stored and plastic energy fell by that), {}; "
                   "broken bonds should only release energy. Some stabilizations and "
                   "damaged_state settings do this in some scenes (doc Howto_choose_model: "
                   "stabilization silling 0.5 and damaged_state carry are the defaults that "
                   "pass the suite); a smaller time step rules out the integration",
                   style, id, update->ntimestep, audit.created(), share);
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::setup_pre_reverse(int, int)
{
  if (auditing) audit_forces();
}

void FixNospdDamage::pre_reverse(int, int)
{
  if (auditing) audit_forces();
}

void FixNospdDamage::post_integrate()
{
  if (auditing) audit_half_step();
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The bond-associated style's inelastic families: their history rows
   (begin_history, finish_history), their failures, and the linearization
   for the Newton minimizer's probes (PairPeriNospdBase::begin_linearization):
   every bond of an inelastic family has its own F and its own return, so
   the point it is linearized about is each bond's F there, recorded by one
   force pass.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_hs.h"

#include "atom.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "update.h"

#include "nospd_simd.h"

using namespace LAMMPS_NS;
using NOSPD::BondPattern;
using NOSPD::Mat3;

namespace {
// one bond's plastic return (point_core, the return mapping, the log and
// exp series inlined), built for the CPU like the bond sums
NOSPD_KERNEL_CLONES NOSPD::ReturnStatus bond_return_kernel(
    NOSPD::Law law, NOSPD::Plane plane, const NOSPD::Lame &m, const NOSPD::FlowLaw &fl,
    const NOSPD::ThermalLaw &th, const NOSPD::PointEnv &env, NOSPD::Mat3 &F, const double *pn,
    double *p1, NOSPD::Mat3 &P, double &W)
{
  return NOSPD::detail::bond_return(law, plane, m, fl, th, env, F, pn, p1, P, W);
}

}    // namespace

/* ----------------------------------------------------------------------
   Start owned atom i's history: its trial row is the accepted one until
   its bonds are evaluated (a family without history, or without a regular
   shape tensor, keeps it), and an inelastic family gets its law.
------------------------------------------------------------------------- */

void PairPeriNospdHS::begin_history(int i, const BondPattern &p, FamilyWork &w, int lane,
                                    LaneLaws &laws)
{
  const double *hn = fix_bonds->history[i];
  double *h1 = fix_bonds->history_trial[i];
  std::copy(hn, hn + fix_bonds->nhistory, h1);
  const int itype = atom->type[i];
  if (!fix_bonds->nhist_bond) return;
  NOSPD::FamilyRows *rows = nullptr;
  if (bond_material(itype)) {
    NOSPD::FamilyMaterial &law = laws.material;
    law.mat = materials[itype].get();
    law.env.dt = update->whichflag == 2 ? 0.0 : update->dt;    // minimize: quasi-static
    law.env.T = temperature_base[i];
    law.env.rho = atom->rmass[i];
    if (law.mat->wants_point_data()) {
      laws.point_data = umat_env(i);
      law.env.umat = &laws.point_data;
    }
    rows = &law;
    laws.active = &law;
  } else if (has_history(itype)) {
    NOSPD::FamilyPlasticity &law = laws.plastic;
    law.law = strain_law;
    law.plane = plane_mode;
    law.m = &lame[itype];
    law.fl = &flow[itype];
    law.th = &thermal[itype];
    law.env.dt = update->whichflag == 2 ? 0.0 : update->dt;    // minimize: quasi-static
    law.env.T_base = temperature_base[i];
    law.env.rho = atom->rmass[i];
    law.bond_return = bond_return_kernel;
    rows = &law;
    laws.active = &law;
  } else {
    return;
  }
  rows->pattern = &p;
  rows->hn = hn;
  rows->h1 = h1;
  rows->slot_of = w.sbuf[lane].data();
  rows->bond_offset = fix_bonds->nhist_atom;
  rows->bond_stride = fix_bonds->nhist_bond;
  rows->record = nullptr;
  rows->about = nullptr;
  if (lin_mode != LinMode::OFF && lin_first[i + 1] > lin_first[i]) {
    double *row = lin_F.data() + lin_first[i];
    if (lin_mode == LinMode::RECORD) rows->record = row;
    else rows->about = row;
  }
}

/* ----------------------------------------------------------------------
   the family row of owned atom i after its bonds; during minimize the
   energy of a plastic point is the step's incremental potential, as in
   the classical style
------------------------------------------------------------------------- */

void PairPeriNospdHS::finish_history(int i, LaneLaws &laws, int eflag, bool minimizing, Tally &t)
{
  if (laws.active == &laws.material) laws.material.finish();
  else laws.plastic.finish();
  if (eflag && minimizing)
    tally_energy(i, fix_bonds->history_trial[i][NOSPD::Hist::WORK] -
                 fix_bonds->history[i][NOSPD::Hist::WORK], t);
}

/* ----------------------------------------------------------------------
   a bond's law (not a bond history law) undefined at owned atom i: a
   formula non-finite at a det F > 0 is the formula's doing
------------------------------------------------------------------------- */

void PairPeriNospdHS::bond_failure(int i, const NOSPD::StateOutput &out, tagint partner) const
{
  const std::string family = out.bad >= 0 ? "bond-associated family" : "whole family";
  if (strain_law == NOSPD::Law::USER && out.bad_J > 0.0)
    error->one(FLERR, "pair_style {}: the energy formula of type {} (W = '{}') gives a "
               "non-finite stress at atom {} on step {} for the {} of its bond to atom {} "
               "(det F = {:.6g}){}", force->pair_style, atom->type[i],
               user_materials->spec(atom->type[i]).energy, atom->tag[i], update->ntimestep,
               family, partner, out.bad_J, fix_bonds->user_law_cause("formula"));
  error->one(FLERR, "pair_style {}: atom {} on step {}: the finite-strain law is undefined "
             "(det F <= 0) for the {} of its bond to atom {}{}", force->pair_style, atom->tag[i],
             update->ntimestep, family, partner, fix_bonds->unstable_cause());
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::family_failure(int i, const LaneLaws &laws, const Mat3 &F) const
{
  if (laws.active == &laws.material) {
    if (!laws.material.status.ok()) material_failure(i, laws.material.status, F);
    return;
  }
  const NOSPD::ReturnStatus st = laws.plastic.status;
  if (st == NOSPD::ReturnStatus::OK) return;
  if (st == NOSPD::ReturnStatus::BAD_DEFORMATION)
    error->one(FLERR, "pair_style {}: atom {} on step {}: the finite-strain law is undefined "
               "(det F <= 0) in its family (det F of the whole family {:.6g}){}",
               force->pair_style, atom->tag[i], update->ntimestep, F.determinant(),
               fix_bonds->unstable_cause());
  inelastic_failure(i, st, F);
}

/* ----------------------------------------------------------------------
   record every inelastic family's F and its bonds' (9 values each, in
   FamilyRows::lin_entry's order) at the current positions, which the
   last force evaluation saw; the probes then linearize about them.
   Returns the number of such families on this rank.
------------------------------------------------------------------------- */

int PairPeriNospdHS::begin_linearization()
{
  end_linearization();
  if (!fix_bonds || !fix_bonds->nhist_bond || !fix_bonds->bond_arrays_current()) return 0;
  if (mapped_version != fix_bonds->bond_version || (int) state_pattern.size() != atom->nlocal)
    map_families();
  const int nlocal = atom->nlocal;
  lin_first.assign(nlocal + 1, 0);
  int families = 0;
  for (int i = 0; i < nlocal; i++) {
    const int itype = atom->type[i];
    const bool law = bond_material(itype) || has_history(itype);
    const size_t n = law ? 9 * static_cast<size_t>(patterns[state_pattern[i]].n + 2) : 0;
    families += law ? 1 : 0;
    lin_first[i + 1] = lin_first[i] + n;
  }
  lin_F.assign(lin_first[nlocal], 0.0);
  // the forces of this pass are not used: the next evaluation clears them
  lin_mode = LinMode::RECORD;
  compute(0, 0);
  lin_mode = LinMode::PROBE;
  return families;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::end_linearization()
{
  lin_mode = LinMode::OFF;
  std::vector<double>().swap(lin_F);
  std::vector<size_t>().swap(lin_first);
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: the material table of both styles (build_materials), the
   temperature a law sees, and the failure messages of a point's law.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_base.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "fix_nospd_heat.h"
#include "force.h"
#include "input.h"
#include "update.h"
#include "variable.h"

#include "nospd_input.h"

#include <cmath>

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;
using NOSPD::Stab;

/* ----------------------------------------------------------------------
   each active type's law behind the material-point interface
   (nospd_material.h): the one place a law is chosen
------------------------------------------------------------------------- */

void PairPeriNospdBase::build_materials()
{
  materials.clear();
  materials.resize(atom->ntypes + 1);
  for (int i = 1; i <= atom->ntypes; i++) {
    if (!active[i]) continue;
    if (inelastic[i] == POINT_UMAT)
      materials[i] = std::make_unique<NOSPD::UmatPointMaterial>(user_materials->umat(i));
    else if (drucker_prager[i].active)
      materials[i] = std::make_unique<NOSPD::DruckerPragerMaterial>(strain_law, plane_mode,
                                                                    lame[i], drucker_prager[i]);
    else if (inelastic[i] == POINT_PLASTIC)
      materials[i] = std::make_unique<NOSPD::J2Material>(strain_law, plane_mode, lame[i],
                                                         flow[i], thermal[i]);
    else
      materials[i] = std::make_unique<NOSPD::ElasticMaterial>(strain_law, plane_mode, lame[i]);
  }
}

// the message of a law that failed at owned atom i
void PairPeriNospdBase::material_failure(int i, NOSPD::PointStatus st, const Mat3 &F) const
{
  if (st.family == NOSPD::PointStatus::UMAT) umat_failure(i, static_cast<NOSPD::UmatStatus>(st.code), F);
  if (st.family == NOSPD::PointStatus::RETURN)
    inelastic_failure(i, static_cast<NOSPD::ReturnStatus>(st.code), F);
  law_failure(i, F);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::law_failure(int i, const Mat3 &F) const
{
  const double J = F.determinant();
  if (strain_law == Law::USER && J > 0.0)
    error->one(FLERR, "pair_style {}: the energy formula of type {} (W = '{}') gives a "
               "non-finite stress at atom {} on step {} (det F = {:.6g}){}", force->pair_style,
               atom->type[i], user_materials->spec(atom->type[i]).energy, atom->tag[i],
               update->ntimestep, J, fix_bonds->user_law_cause("formula"));
  error->one(FLERR, "pair_style {}: atom {} on step {} has det F = {:.6g}: the "
             "finite-strain law is undefined for an inverted or collapsed family{}",
             force->pair_style, atom->tag[i], update->ntimestep, J, fix_bonds->unstable_cause());
}

/* ----------------------------------------------------------------------
   one UMAT increment of owned atom i from its accepted history
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   what a UMAT's material point at owned atom i needs besides F
------------------------------------------------------------------------- */

NOSPD::UmatPoint PairPeriNospdBase::umat_env(int i) const
{
  NOSPD::UmatPoint pt;
  pt.dt = update->dt;
  // TIME at the start of the increment, as Abaqus passes it (the setup's
  // evaluation of the accepted state takes no increment: its own time)
  const double t_now = update->atime + (update->ntimestep - update->atimestep) * update->dt;
  pt.time = update->setupflag ? t_now : t_now - update->dt;
  pt.temperature = temperature_base[i];
  for (int d = 0; d < 3; d++) pt.coords[d] = atom->x[i][d];
  pt.celent = (domain->dimension == 3) ? cbrt(atom->vfrac[i]) : sqrt(atom->vfrac[i] / thickness);
  pt.noel = static_cast<int>(atom->tag[i]);
  pt.kinc = static_cast<int>(update->ntimestep);
  return pt;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::umat_failure(int i, NOSPD::UmatStatus st, const Mat3 &F) const
{
  const int itype = atom->type[i];
  const std::string lib = user_materials->library(itype);
  if (st == NOSPD::UmatStatus::ABORT)
    error->one(FLERR, "pair_style {}: the UMAT of type {} ({}) stopped at atom {} on step {}: {}",
               force->pair_style, itype, lib, atom->tag[i], update->ntimestep,
               NOSPD::umat_report().message);
  if (st == NOSPD::UmatStatus::STATEV_OVERFLOW)
    error->one(FLERR, "pair_style {}: the UMAT of type {} ({}, symbol {}) wrote past its NSTATV "
               "= {} state variables (statev {}) at atom {} on step {}: declare as many as it "
               "writes with 'statev N'", force->pair_style, itype, lib,
               user_materials->symbol(itype), user_materials->umat(itype).nstatev,
               user_materials->umat(itype).nstatev, atom->tag[i], update->ntimestep);
  if (st == NOSPD::UmatStatus::NONFINITE)
    error->one(FLERR, "pair_style {}: the UMAT of type {} ({}) returned a non-finite stress, "
               "energy or state variable at atom {} on step {}{}", force->pair_style, itype, lib,
               atom->tag[i], update->ntimestep, fix_bonds->user_law_cause("UMAT"));
  law_failure(i, F);
}

/* ----------------------------------------------------------------------
   the user's temperature of each owned atom (before adiabatic heating)
------------------------------------------------------------------------- */

void PairPeriNospdBase::fill_base_temperature()
{
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  if (temperature_kind == TEMP_VARIABLE) {
    NOSPD_INPUT::variable_in_range(error, fmt::format("pair_style {}: temperature", force->pair_style),
                                   temperature_name, [&]() {
      input->variable->compute_atom(temperature_index, 0, temperature_base, 1, 0);
    });
  } else if (temperature_kind == TEMP_PROPERTY) {
    const double *t = atom->dvector[temperature_index];
    for (int i = 0; i < nlocal; i++) temperature_base[i] = t[i];
  } else if (heat_field) {
    for (int i = 0; i < nlocal; i++) temperature_base[i] = heat_field->base_temperature(i, type[i]);
  } else {
    for (int i = 0; i < nlocal; i++) temperature_base[i] = thermal[type[i]].T_ref;
  }
  // the plastic and thermal laws read an absolute temperature (T_ref > 0 is
  // already required); a UMAT may take any scale, but not a non-finite one
  for (int i = 0; i < nlocal; i++) {
    const double T = temperature_base[i];
    const bool absolute = inelastic[type[i]] == POINT_PLASTIC;
    if (inelastic[type[i]] && !(std::isfinite(T) && (T > 0.0 || !absolute)))
      error->one(FLERR, "pair_style {}: step {}: atom {} has temperature {} from {}{}{}",
                 force->pair_style, update->ntimestep, atom->tag[i], T,
                 temperature_kind == TEMP_VARIABLE ? "v_" : heat_field ? "fix nospd/heat" : "d_",
                 temperature_name,
                 std::isfinite(T) ? " (the temperature of a plastic or thermal law is absolute: "
                                    "it must be > 0)" : "");
  }
}

/* ---------------------------------------------------------------------- */

double PairPeriNospdBase::temperature(int i) const
{
  const int nhist = fix_bonds ? fix_bonds->nhistory : 0;
  const int itype = atom->type[i];
  if (heat_field && (!nhist || !temperature_base || i >= nmax_work))
    return heat_field->base_temperature(i, itype) + adiabatic_heat(i);
  if (!nhist || !temperature_base || i >= nmax_work) return thermal[itype].T_ref;
  return temperature_base[i] + adiabatic_heat(i);
}

/* ---------------------------------------------------------------------- */

double PairPeriNospdBase::thermal_strain(int i) const
{
  const int itype = atom->type[i];
  if (!has_thermal_strain(itype)) return 0.0;
  return thermal[itype].alpha * (temperature(i) - thermal[itype].T_ref);
}

/* ----------------------------------------------------------------------
   the heating in the accepted state's history: J2/Johnson-Cook with heat
   cp chi only (other laws keep other things at that index)
------------------------------------------------------------------------- */

double PairPeriNospdBase::adiabatic_heat(int i, bool newest) const
{
  const int itype = atom->type[i];
  if (!fix_bonds || !fix_bonds->nhistory || !has_history(itype)) return 0.0;
  if (!flow[itype].active || !(thermal[itype].cp > 0.0)) return 0.0;
  double **rows = newest && fix_bonds->hist.trial_ready ? fix_bonds->history_trial : fix_bonds->history;
  return rows[i][NOSPD::Hist::HEAT];
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::inelastic_failure(int i, NOSPD::ReturnStatus st, const Mat3 &F) const
{
  if (st == NOSPD::ReturnStatus::BAD_TEMPERATURE) {
    const NOSPD::ThermalLaw &th = thermal[atom->type[i]];
    const double T = temperature(i), eth = th.alpha * (T - th.T_ref);
    error->one(FLERR, "pair_style {}: atom {} on step {} has temperature {:.6g}, where the "
               "thermal {} of type {} (thermal {:.6g} {:.6g}) is {:.6g}: the law is undefined "
               "there; check the temperature (its variable or property) and the thermal law",
               force->pair_style, atom->tag[i], update->ntimestep, T,
               strain_law == NOSPD::Law::SMALL ? "strain alpha (T - T_ref)"
                                               : "stretch 1 + alpha (T - T_ref)",
               atom->type[i], th.alpha, th.T_ref,
               strain_law == NOSPD::Law::SMALL ? eth : 1.0 + eth);
  }
  if (st == NOSPD::ReturnStatus::BAD_DEFORMATION)
    error->one(FLERR, "pair_style {}: atom {} on step {} has det F = {:.6g}: the finite-strain "
               "law is undefined for an inverted or collapsed family{}",
               force->pair_style, atom->tag[i], update->ntimestep, F.determinant(),
               fix_bonds->unstable_cause());
  if (drucker_prager[atom->type[i]].active)
    error->one(FLERR, "pair_style {}: atom {} on step {}: a Drucker-Prager state beyond the "
               "cone's apex (hydrostatic tension above its strength) cannot return without "
               "dilatancy: give the type a dilatancy angle psi > 0", force->pair_style,
               atom->tag[i], update->ntimestep);
  error->one(FLERR, "pair_style {}: the plastic return mapping did not converge at atom {} on "
             "step {} (equivalent plastic strain {:.6g}, temperature {:.6g}); the strain "
             "increment may be too large (time step) or the flow law ill-posed",
             force->pair_style, atom->tag[i], update->ntimestep,
             fix_bonds->history[i][NOSPD::Hist::EQPS], temperature_base[i]);
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#include "compute_nospd_atom.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "fix_nospd_heat.h"
#include "force.h"
#include "memory.h"
#include "pair.h"
#include "pair_peri_nospd_base.h"
#include "update.h"

#include "nospd_constitutive.h"
#include "nospd_plasticity.h"
#include "nospd_umat.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using NOSPD::Mat3;

static int ncolumns(int q)
{
  switch (q) {
    case 0: return 9;    // F
    case 1: return 6;    // strain
    case 2: return 6;    // stress
    case 8: return 6;    // plastic strain
    case 9: return 6;    // back stress
    case 15: return 3;   // heat flux
    default: return 1;
  }
}

/* ---------------------------------------------------------------------- */

ComputeNospdAtom::ComputeNospdAtom(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), out(nullptr), pair(nullptr)
{
  for (int iarg = 3; iarg < narg; iarg++) {
    const std::string k = arg[iarg];
    if (k == "F") quantities.push_back(DEFGRAD);
    else if (k == "strain") quantities.push_back(STRAIN);
    else if (k == "stress") quantities.push_back(STRESS);
    else if (k == "vonmises") quantities.push_back(VONMISES);
    else if (k == "energy") quantities.push_back(ENERGY);
    else if (k == "zem") quantities.push_back(ZEM);
    else if (k == "singular") quantities.push_back(SINGULAR);
    else if (k == "eqps") quantities.push_back(EQPS);
    else if (k == "plastic_strain") quantities.push_back(PLASTIC_STRAIN);
    else if (k == "back_stress") quantities.push_back(BACK_STRESS);
    else if (k == "temperature") quantities.push_back(TEMPERATURE);
    else if (k == "yield") quantities.push_back(YIELDING);
    else if (k == "plastic_work") quantities.push_back(PLASTIC_WORK);
    else if (k == "jc_damage") quantities.push_back(JC_DAMAGE);
    else if (k == "strain_rate") quantities.push_back(STRAIN_RATE);
    else if (k == "heat_flux") quantities.push_back(HEAT_FLUX);
    else
      error->all(FLERR, "compute {}: unknown quantity '{}' (F, strain, stress, vonmises, energy, "
                 "zem, singular, eqps, plastic_strain, back_stress, temperature, yield, "
                 "plastic_work, jc_damage, strain_rate, heat_flux)", style, k);
  }
  if (quantities.empty()) quantities = {DEFGRAD, STRAIN, STRESS, VONMISES, ENERGY, ZEM, SINGULAR};

  int n = 0;
  for (int q : quantities) n += ncolumns(q);
  peratom_flag = 1;
  size_peratom_cols = n;
}

/* ---------------------------------------------------------------------- */

ComputeNospdAtom::~ComputeNospdAtom()
{
  memory->destroy(out);
}

/* ---------------------------------------------------------------------- */

void ComputeNospdAtom::init()
{
  find_pair();
}

/* ----------------------------------------------------------------------
   the pair style is looked up at every invocation, not only at init: a
   pair_style command between runs replaces it, and output (write_dump,
   Python's extract_compute) may ask before the next init
------------------------------------------------------------------------- */

void ComputeNospdAtom::find_pair()
{
  pair = PairPeriNospdBase::find(force);
  if (!pair) error->all(FLERR, "compute {} requires a peri/nospd pair style", style);
}

/* ---------------------------------------------------------------------- */

void ComputeNospdAtom::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    memory->destroy(out);
    nmax = atom->nmax;
    memory->create(out, nmax, size_peratom_cols, "nospd/atom:out");
    array_atom = out;
  }

  find_pair();
  FixNospdBonds *bonds = pair->bonds();
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const int *type = atom->type;
  // the per-atom state travels with the atoms; the bond arrays (zem) are
  // those of the last rebuild, stale once atoms were added or deleted
  const bool ready = bonds && bonds->bond_first;
  const bool bonds_current = ready && bonds->bond_arrays_current();
  // the flux needs the ghosts' temperatures (a collective forward comm)
  FixNospdHeat *heat = pair->attached_heat();
  const bool want_flux =
      std::find(quantities.begin(), quantities.end(), (int) HEAT_FLUX) != quantities.end();
  if (want_flux && heat) heat->prepare_flux();

  for (int i = 0; i < nlocal; i++) {
    double *row = out[i];
    if (!(mask[i] & groupbit) || !ready || !pair->owns_type(type[i])) {
      for (int k = 0; k < size_peratom_cols; k++) row[k] = 0.0;
      continue;
    }
    const Mat3 F = NOSPD::load(bonds->defgrad[i]);
    const Mat3 P = NOSPD::load(bonds->pk1[i]);
    Mat3 sigma = Mat3::Zero();
    if (!bonds->singular[i]) sigma = NOSPD::cauchy_stress(pair->law(), F, P);
    int c = 0;
    for (int q : quantities) {
      switch (q) {
        case DEFGRAD:
          for (int k = 0; k < 9; k++) row[c++] = bonds->defgrad[i][k];
          break;
        case STRAIN: {
          const Mat3 I = Mat3::Identity();
          const Mat3 e = NOSPD::small_kinematics(pair->law()) ? Mat3(0.5 * (F + F.transpose()) - I)
                                                             : Mat3(0.5 * (F.transpose() * F - I));
          row[c++] = e(0, 0); row[c++] = e(1, 1); row[c++] = e(2, 2);
          row[c++] = e(0, 1); row[c++] = e(0, 2); row[c++] = e(1, 2);
          break;
        }
        case STRESS:
          row[c++] = sigma(0, 0); row[c++] = sigma(1, 1); row[c++] = sigma(2, 2);
          row[c++] = sigma(0, 1); row[c++] = sigma(0, 2); row[c++] = sigma(1, 2);
          break;
        case VONMISES: row[c++] = NOSPD::von_mises(sigma); break;
        case ENERGY: row[c++] = bonds->energy_density[i]; break;
        case ZEM: row[c++] = bonds_current ? bonds->zem_indicator(i) : 0.0; break;
        case SINGULAR: row[c++] = bonds->singular[i]; break;
        case HEAT_FLUX:
          if (heat && bonds_current) heat->heat_flux(i, row + c);
          else row[c] = row[c + 1] = row[c + 2] = 0.0;
          c += 3;
          break;
        default: c = history_columns(i, q, row, c); break;
      }
    }
  }
}

/* ----------------------------------------------------------------------
   inelastic history of atom i (zeros where the material has none).
   Plastic strain: eps_p (strain small); the plastic Green-Lagrange
   strain (C_p - I)/2 (strain hencky, C_p from the stored C_p^-1).
------------------------------------------------------------------------- */

int ComputeNospdAtom::history_columns(int i, int q, double *row, int c) const
{
  namespace H = NOSPD::Hist;
  FixNospdBonds *bonds = pair->bonds();
  const int n = ncolumns(q);
  // a UMAT's row keeps its SPD + SCD where the plastic laws keep their work
  // (UmatHist::WORK == Hist::WORK), the column the bonds fix sums
  static_assert(NOSPD::UmatHist::WORK == H::WORK, "UMAT dissipation not in the work column");
  const int itype = atom->type[i];
  const bool has = bonds->nhistory > 0 &&
      (pair->has_history(itype) || (q == PLASTIC_WORK && pair->is_umat(itype)));
  if (!has && q != TEMPERATURE) {
    for (int k = 0; k < n; k++) row[c + k] = 0.0;
    return c + n;
  }
  const double *h = has ? bonds->current_history()[i] : nullptr;
  switch (q) {
    case EQPS: row[c] = h[H::EQPS]; break;
    case YIELDING: row[c] = h[H::YIELDING]; break;
    case PLASTIC_WORK: row[c] = h[H::WORK]; break;
    case JC_DAMAGE: row[c] = h[H::DAMAGE]; break;
    case STRAIN_RATE: row[c] = h[H::RATE]; break;
    case TEMPERATURE: row[c] = pair->temperature(i); break;
    case BACK_STRESS:
      for (int k = 0; k < 6; k++) row[c + k] = h[H::BACK + k];
      break;
    case PLASTIC_STRAIN: {
      const double *p = h + H::PLASTIC;
      if (NOSPD::small_kinematics(pair->law())) {
        for (int k = 0; k < 6; k++) row[c + k] = p[k];
      } else {
        const Mat3 Cpinv = Mat3::Identity() + NOSPD::load_sym(p);
        NOSPD::store_sym(0.5 * (Cpinv.inverse() - Mat3::Identity()), row + c);
      }
      break;
    }
  }
  return c + n;
}

/* ---------------------------------------------------------------------- */

double ComputeNospdAtom::memory_usage()
{
  return (double) nmax * size_peratom_cols * sizeof(double);
}

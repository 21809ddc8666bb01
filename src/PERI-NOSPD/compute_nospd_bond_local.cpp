/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#include "compute_nospd_bond_local.h"

#include "atom.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "memory.h"
#include "pair_peri_nospd_base.h"
#include "pair_peri_nospd_hs.h"
#include "update.h"

#include "nospd_constitutive.h"

#include <cmath>

using namespace LAMMPS_NS;
using NOSPD::Mat3;

static int ncolumns(int q)
{
  switch (q) {
    case 0: return 2;    // id of i and j
    case 2: return 9;    // F
    case 3: return 6;    // Cauchy stress
    default: return 1;
  }
}

/* ---------------------------------------------------------------------- */

ComputeNospdBondLocal::ComputeNospdBondLocal(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), out(nullptr), pair(nullptr), pair_hs(nullptr)
{
  for (int iarg = 3; iarg < narg; iarg++) {
    const std::string k = arg[iarg];
    if (k == "id") quantities.push_back(ID);
    else if (k == "stretch") quantities.push_back(STRETCH);
    else if (k == "F") quantities.push_back(DEFGRAD);
    else if (k == "stress") quantities.push_back(STRESS);
    else if (k == "own") quantities.push_back(OWN);
    else if (k == "eqps") quantities.push_back(EQPS);
    else
      error->all(FLERR, "compute {}: unknown quantity '{}' (id, stretch, F, stress, own, eqps)",
                 style, k);
  }
  if (quantities.empty()) quantities = {ID, STRETCH, DEFGRAD, STRESS};
  int n = 0;
  for (int q : quantities) n += ncolumns(q);
  local_flag = 1;
  size_local_cols = n;
  size_local_rows = 0;
}

/* ---------------------------------------------------------------------- */

ComputeNospdBondLocal::~ComputeNospdBondLocal()
{
  memory->destroy(out);
}

/* ---------------------------------------------------------------------- */

void ComputeNospdBondLocal::init()
{
  find_pair();
}

/* ----------------------------------------------------------------------
   looked up at every invocation: a pair_style command between runs
   replaces the pair style, and output may ask before the next init
------------------------------------------------------------------------- */

void ComputeNospdBondLocal::find_pair()
{
  pair = PairPeriNospdBase::find(force);
  if (!pair) error->all(FLERR, "compute {} requires a peri/nospd or peri/nospd/hs pair style", style);
  pair_hs = dynamic_cast<PairPeriNospdHS *>(pair);
}

/* ---------------------------------------------------------------------- */

int ComputeNospdBondLocal::count_rows()
{
  find_pair();
  FixNospdBonds *bonds = pair->bonds();
  // no rows before the first run, nor after atoms were added or deleted
  // since (the bond arrays are rebuilt at the next run's setup)
  if (!bonds || !bonds->bond_arrays_current()) return 0;
  int n = 0;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit) n += bonds->bond_first[i + 1] - bonds->bond_first[i];
  return n;
}

/* ---------------------------------------------------------------------- */

void ComputeNospdBondLocal::compute_local()
{
  invoked_local = update->ntimestep;
  const int nrows = count_rows();
  if (nrows > nmax) {
    memory->destroy(out);
    nmax = nrows;
    memory->create(out, nmax, size_local_cols, "nospd/bond/local:out");
  }
  size_local_rows = nrows;
  array_local = out;
  if (!nrows) return;

  FixNospdBonds *bonds = pair->bonds();
  const bool plane_stress = pair->plane() == NOSPD::Plane::STRESS;
  double **x = atom->x;
  const int *type = atom->type;
  int row = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    for (int b = bonds->bond_first[i]; b < bonds->bond_first[i + 1]; b++) {
      const int j = bonds->bond_j[b];
      double Fb[9];
      int own = 0;
      if (pair_hs) own = pair_hs->bond_defgrad(i, b, Fb);
      if (!pair_hs || own < 0) {
        for (int k = 0; k < 9; k++) Fb[k] = bonds->defgrad[i][k];
        own = 0;
      }
      if (own && plane_stress && bonds->singular[i] == 0) {
        // the bond's out-of-plane stretch is solved by its law, with its stress
        Mat3 F = NOSPD::load(Fb), s;
        if (bond_stress(i, b, own, F, s)) Fb[8] = F(2, 2);
      }
      double *r = out[row++];
      int c = 0;
      for (int q : quantities) {
        switch (q) {
          case ID:
            r[c++] = atom->tag[i];
            r[c++] = atom->tag[j];
            break;
          case STRETCH: {
            double xi[3], l0 = 0.0, l = 0.0;
            bonds->bond_vector(i, b, xi);
            for (int k = 0; k < 3; k++) {
              l0 += xi[k] * xi[k];
              l += (x[j][k] - x[i][k]) * (x[j][k] - x[i][k]);
            }
            r[c++] = std::sqrt(l / l0) - 1.0;
            break;
          }
          case DEFGRAD:
            for (int k = 0; k < 9; k++) r[c++] = Fb[k];
            break;
          case STRESS: {
            Mat3 F = NOSPD::load(Fb), s = Mat3::Zero();
            if (bonds->singular[i] == 0 && !bond_stress(i, b, own, F, s)) s.setZero();
            r[c++] = s(0, 0); r[c++] = s(1, 1); r[c++] = s(2, 2);
            r[c++] = s(0, 1); r[c++] = s(0, 2); r[c++] = s(1, 2);
            break;
          }
          case OWN: r[c++] = own; break;
          case EQPS: {
            const double *bs = bond_state(i, b, own);
            if (bs) r[c++] = bs[pair->bond_material(type[i]) ? NOSPD::Hist::EQPS : NOSPD::BondHist::EQPS];
            else if (pair->has_history(type[i]))
              r[c++] = bonds->current_history()[i][NOSPD::Hist::EQPS];
            else r[c++] = 0.0;
            break;
          }
        }
      }
    }
  }
}

/* ---------------------------------------------------------------------- */

const double *ComputeNospdBondLocal::bond_state(int i, int b, int own) const
{
  FixNospdBonds *bonds = pair->bonds();
  if (!pair_hs || !bonds->nhist_bond || !pair->has_history(atom->type[i])) return nullptr;
  double *row = bonds->current_history()[i];
  if (!own)
    return row + (pair->bond_material(atom->type[i]) ? pair->material_law(atom->type[i]).history_size()
                                                     : NOSPD::FamilyHist::FALLBACK);
  return bonds->bond_history(row, bonds->bond_slot[b]);
}

/* ----------------------------------------------------------------------
   Cauchy stress of bond b of atom i at its F: the law's, or for an
   inelastic type that of its state (FixNospdBonds::current_history: the
   accepted one, or a minimization's latest; the bond's own under
   peri/nospd/hs, else atom i's stress)
------------------------------------------------------------------------- */

bool ComputeNospdBondLocal::bond_stress(int i, int b, int own, Mat3 &F, Mat3 &s) const
{
  const int itype = atom->type[i];
  FixNospdBonds *bonds = pair->bonds();
  Mat3 P;
  double W;
  if (pair->has_history(itype) || pair->is_umat(itype)) {
    const double *bs = bond_state(i, b, own);
    if (!bs) {
      F = NOSPD::load(bonds->defgrad[i]);
      P = NOSPD::load(bonds->pk1[i]);
    } else if (pair->bond_material(itype)) {
      // the law from the bond's accepted state: elastic back to it at its F
      const NOSPD::Material &law = pair->material_law(itype);
      std::vector<double> h1(law.history_size());
      NOSPD::MaterialEnv env;
      env.T = pair->temperature(i);
      env.rho = atom->rmass[i];
      if (!law.stress(F, bs, h1.data(), env, P, W).ok()) return false;
    } else if (!NOSPD::accepted_bond_stress(pair->law(), pair->plane(), pair->material(itype),
                                            pair->flow_law(itype), pair->thermal_law(itype),
                                            pair->temperature(i), bs, F, P)) {
      return false;
    }
  } else if (!NOSPD::first_piola(pair->law(), pair->plane(), pair->material(itype), F, P, W)) {
    return false;
  }
  s = NOSPD::cauchy_stress(pair->law(), F, P);
  return true;
}

/* ---------------------------------------------------------------------- */

double ComputeNospdBondLocal::memory_usage()
{
  return (double) nmax * size_local_cols * sizeof(double);
}

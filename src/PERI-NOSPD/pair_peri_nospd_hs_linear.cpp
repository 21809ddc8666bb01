/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The bond-associated style's linearization for the Newton minimizer's
   probes (PairPeriNospdBase::begin_linearization): every bond of an
   inelastic family has its own F and its own return, so the point it is
   linearized about is each bond's F there, recorded by one force pass.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_hs.h"

#include "atom.h"
#include "fix_nospd_bonds.h"

using namespace LAMMPS_NS;

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

/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Registration of every style of the package with LAMMPS's plugin loader.
------------------------------------------------------------------------- */

#include "lammpsplugin.h"

#include "error.h"
#include "lammps.h"
#include "version.h"

#include "compute_nospd_atom.h"
#include "compute_nospd_bond_local.h"
#include "fix_nospd_bonds.h"
#include "fix_nospd_damage.h"
#include "fix_nospd_damage_omp.h"
#include "fix_nospd_heat.h"
#include "min_nospd_newton.h"
#include "pair_peri_nospd.h"
#include "pair_peri_nospd_hs.h"
#include "pair_peri_nospd_hs_omp.h"
#include "pair_peri_nospd_omp.h"

#include <cstring>

using namespace LAMMPS_NS;

namespace {

// A plugin compiled against one LAMMPS version and loaded into another
// would read class layouts that differ: refuse at style creation with the
// two versions named, instead of crashing somewhere later.
bool version_ok(LAMMPS *lmp, const char *style)
{
  if (strcmp(lmp->version, LAMMPS_VERSION) == 0) return true;
  lmp->error->all(FLERR,
                  "PERI-NOSPD style {} was compiled for LAMMPS {} but is loaded into LAMMPS {}: "
                  "rebuild the plugin against this LAMMPS's source tree",
                  style, LAMMPS_VERSION, lmp->version);
  return false;
}

Pair *pair_nospd_creator(LAMMPS *lmp)
{
  version_ok(lmp, "pair peri/nospd");
  return new PairPeriNospd(lmp);
}

Pair *pair_nospd_omp_creator(LAMMPS *lmp)
{
  version_ok(lmp, "pair peri/nospd/omp");
  return new PairPeriNospdOMP(lmp);
}

Pair *pair_nospd_hs_creator(LAMMPS *lmp)
{
  version_ok(lmp, "pair peri/nospd/hs");
  return new PairPeriNospdHS(lmp);
}

Pair *pair_nospd_hs_omp_creator(LAMMPS *lmp)
{
  version_ok(lmp, "pair peri/nospd/hs/omp");
  return new PairPeriNospdHSOMP(lmp);
}

Fix *fix_bonds_creator(LAMMPS *lmp, int argc, char **argv)
{
  version_ok(lmp, "fix PERI_NEIGH/NOSPD");
  return new FixNospdBonds(lmp, argc, argv);
}

Fix *fix_damage_creator(LAMMPS *lmp, int argc, char **argv)
{
  version_ok(lmp, "fix nospd/damage");
  return new FixNospdDamage(lmp, argc, argv);
}

Fix *fix_heat_creator(LAMMPS *lmp, int argc, char **argv)
{
  version_ok(lmp, "fix nospd/heat");
  return new FixNospdHeat(lmp, argc, argv);
}

Fix *fix_damage_omp_creator(LAMMPS *lmp, int argc, char **argv)
{
  version_ok(lmp, "fix nospd/damage/omp");
  return new FixNospdDamageOMP(lmp, argc, argv);
}

Compute *compute_bond_local_creator(LAMMPS *lmp, int argc, char **argv)
{
  version_ok(lmp, "compute nospd/bond/local");
  return new ComputeNospdBondLocal(lmp, argc, argv);
}

Compute *compute_atom_creator(LAMMPS *lmp, int argc, char **argv)
{
  version_ok(lmp, "compute nospd/atom");
  return new ComputeNospdAtom(lmp, argc, argv);
}

Min *min_newton_creator(LAMMPS *lmp)
{
  version_ok(lmp, "min_style nospd/newton");
  return new MinNospdNewton(lmp);
}

}    // namespace

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  auto register_plugin = (lammpsplugin_regfunc) regfunc;
  lammpsplugin_t plugin;
  plugin.version = LAMMPS_VERSION;
  plugin.author = "PERI-NOSPD developers";
  plugin.handle = handle;

  plugin.style = "pair";
  plugin.name = "peri/nospd";
  plugin.info = "PERI-NOSPD classical correspondence peridynamics";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_nospd_creator;
  (*register_plugin)(&plugin, lmp);

  // the same style under a name without "peri": LAMMPS's PERI_NEIGH fix
  // (made by peri/lps, peri/pmb) finds its pair by matching "peri", which
  // fails when a second "peri" style sits in the same pair hybrid
  plugin.name = "nospd";
  plugin.info = "PERI-NOSPD classical correspondence peridynamics (alias of peri/nospd)";
  (*register_plugin)(&plugin, lmp);

  // the OpenMP variant, which `-sf omp` / `suffix omp` picks
  plugin.name = "peri/nospd/omp";
  plugin.info = "PERI-NOSPD classical correspondence peridynamics, OpenMP threads";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_nospd_omp_creator;
  (*register_plugin)(&plugin, lmp);
  plugin.name = "nospd/omp";
  plugin.info = "PERI-NOSPD classical correspondence, OpenMP threads (alias of peri/nospd/omp)";
  (*register_plugin)(&plugin, lmp);

  plugin.style = "pair";
  plugin.name = "peri/nospd/hs";
  plugin.info = "PERI-NOSPD horizon-stabilized (bond-associated) correspondence peridynamics";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_nospd_hs_creator;
  (*register_plugin)(&plugin, lmp);
  plugin.name = "nospd/hs";
  plugin.info = "PERI-NOSPD horizon-stabilized correspondence (alias of peri/nospd/hs)";
  (*register_plugin)(&plugin, lmp);
  plugin.name = "peri/nospd/hs/omp";
  plugin.info = "PERI-NOSPD horizon-stabilized correspondence peridynamics, OpenMP threads";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &pair_nospd_hs_omp_creator;
  (*register_plugin)(&plugin, lmp);
  plugin.name = "nospd/hs/omp";
  plugin.info = "PERI-NOSPD horizon-stabilized correspondence, OpenMP threads (alias)";
  (*register_plugin)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "PERI_NEIGH/NOSPD";
  plugin.info = "PERI-NOSPD bond families, reference and deformation state";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_bonds_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.style = "compute";
  plugin.name = "nospd/atom";
  plugin.info = "PERI-NOSPD per-atom F, strain, stress, von Mises, energy, zero-energy-mode indicator";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &compute_atom_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.style = "compute";
  plugin.name = "nospd/bond/local";
  plugin.info = "PERI-NOSPD per-bond output: ids, stretch, (bond-associated) F and stress";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &compute_bond_local_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "nospd/damage";
  plugin.info = "PERI-NOSPD bond breaking, pre-cracks and contact";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_damage_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "nospd/damage/omp";
  plugin.info = "PERI-NOSPD bond breaking, pre-cracks and contact, OpenMP threads";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_damage_omp_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "nospd/heat";
  plugin.info = "PERI-NOSPD peridynamic heat conduction and thermo-mechanical coupling";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &fix_heat_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.style = "min";
  plugin.name = "nospd/newton";
  plugin.info = "PERI-NOSPD Newton-Krylov minimizer for quasi-static load steps";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &min_newton_creator;
  (*register_plugin)(&plugin, lmp);
}

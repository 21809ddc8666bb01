/* ----------------------------------------------------------------------
   PERI-NOSPD: the arguments of fix nospd/damage: its criterion and keywords,
   every number through nospd_input.h; and the pair style's settings known
   to go wrong with them (warn_settings), and the tables they make per type
   pair (setup_tables).
------------------------------------------------------------------------- */

#include "fix_nospd_damage.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "memory.h"
#include "region.h"

#include "pair_peri_nospd_base.h"

#include "nospd_damage_criteria.h"
#include "nospd_input.h"
#include "nospd_stabilization.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using NOSPD::Mat3;

double FixNospdDamage::Args::number(int i) const
{
  return NOSPD_INPUT::real(error, cmd, key, arg[i]);
}

void FixNospdDamage::Args::need(int iarg, int n, const std::string &what) const
{
  if (iarg + n >= narg) error->all(FLERR, "{}: {} needs {} value(s)", cmd, what, n);
}

/* ----------------------------------------------------------------------
   the criterion (the first argument) and its value; returns the index of
   the first keyword
------------------------------------------------------------------------- */

int FixNospdDamage::parse_criterion(Args &args)
{
  const int narg = args.narg;
  char **arg = args.arg;
  const std::string &cmd = args.cmd;
  std::string &numkey = args.key;
  auto number = [&](int i) { return args.number(i); };
  auto need = [&](int iarg, int n, const std::string &key) { args.need(iarg, n, key); };
  int iarg = 3;
  const std::string c = arg[iarg];
  if (c == "none") {
    criterion = NONE;
    iarg += 1;
  } else if (c == "stretch" || c == "energy") {
    need(iarg, 1, c);
    criterion = (c == "stretch") ? STRETCH : ENERGY;
    if (strcmp(arg[iarg + 1], "g0") == 0) {
      from_g0 = true;
      iarg += 2;
      if (iarg < narg && NOSPD::parse_real(arg[iarg], value) != NOSPD::Parsed::NOT_A_NUMBER) {
        numkey = c + " g0";
        value = number(iarg);
        g0_given = true;
        if (!(value > 0.0)) error->all(FLERR, "{}: fracture energy G0 must be > 0, got {}", cmd, arg[iarg]);
        iarg++;
      }
    } else {
      numkey = c;
      value = number(iarg + 1);
      if (!(value > 0.0))
        error->all(FLERR, "{}: critical {} must be > 0, got {}", cmd,
                   criterion == STRETCH ? "stretch" : "bond energy", arg[iarg + 1]);
      iarg += 2;
    }
  } else if (c == "stress" || c == "strain") {
    need(iarg, 2, c);
    const std::string kind = arg[iarg + 1];
    if (c == "stress" && kind == "principal") criterion = STRESS_PRINCIPAL;
    else if (c == "stress" && kind == "vonmises") criterion = STRESS_VONMISES;
    else if (c == "strain" && kind == "principal") criterion = STRAIN_PRINCIPAL;
    else
      error->all(FLERR, "{}: unknown criterion '{} {}' (stress principal, stress vonmises, "
                 "strain principal)", cmd, c, kind);
    numkey = c + " " + kind;
    value = number(iarg + 2);
    if (!(value > 0.0)) error->all(FLERR, "{}: critical {} must be > 0, got {}", cmd, c, arg[iarg + 2]);
    iarg += 3;
  } else if (c == "eqps") {
    need(iarg, 1, c);
    criterion = EQPS;
    numkey = c;
    value = number(iarg + 1);
    if (!(value > 0.0))
      error->all(FLERR, "{}: critical equivalent plastic strain must be > 0, got {}", cmd, arg[iarg + 1]);
    iarg += 2;
  } else if (c == "johnson_cook") {
    criterion = JC_DAMAGE;
    value = 1.0;
    iarg += 1;
  } else
    error->all(FLERR, "{}: unknown criterion '{}' (stretch, energy, stress, strain, eqps, "
               "johnson_cook, none)", cmd, c);

  return iarg;
}

/* ----------------------------------------------------------------------
   one keyword and its values at arg[iarg]; returns the index after them
------------------------------------------------------------------------- */

int FixNospdDamage::parse_keyword(Args &args, int iarg, const char *&contact_keyword_given)
{
  char **arg = args.arg;
  const std::string &cmd = args.cmd;
  auto number = [&](int i) { return args.number(i); };
  auto need = [&](int iarg, int n, const std::string &key) { args.need(iarg, n, key); };
  const std::string key = arg[iarg];
  args.key = key;
  if (key == "scatter") {
    need(iarg, 2, key);
    scatter_width = number(iarg + 1);
    scatter_seed = NOSPD_INPUT::integer(error, cmd, "scatter seed", arg[iarg + 2], -INT_MAX, INT_MAX);
    if (!(scatter_width >= 0.0 && scatter_width < 1.0))
      error->all(FLERR, "{}: scatter width must be in [0,1), got {}", cmd, arg[iarg + 1]);
    if (scatter_seed <= 0) error->all(FLERR, "{}: scatter seed must be > 0, got {}", cmd, arg[iarg + 2]);
    iarg += 3;
  } else if (key == "nofail") {
    need(iarg, 2, key);
    const std::string kind = arg[iarg + 1];
    if (kind == "group") {
      const int ig = group->find(arg[iarg + 2]);
      if (ig < 0) error->all(FLERR, "{}: nofail group {} does not exist", cmd, arg[iarg + 2]);
      nofail_groupbit = group->bitmask[ig];
    } else if (kind == "region") {
      if (!domain->get_region_by_id(arg[iarg + 2]))
        error->all(FLERR, "{}: nofail region {} does not exist", cmd, arg[iarg + 2]);
      delete[] nofail_region_id;
      nofail_region_id = utils::strdup(arg[iarg + 2]);
    } else
      error->all(FLERR, "{}: nofail takes 'group ID' or 'region ID', got '{}'", cmd, kind);
    iarg += 3;
  } else if (key == "singular") {
    need(iarg, 1, key);
    const std::string v = arg[iarg + 1];
    if (v == "keep") detach_singular = false;
    else if (v == "detach") detach_singular = true;
    else error->all(FLERR, "{}: singular takes keep or detach, got '{}'", cmd, v);
    iarg += 2;
  } else if (key == "precrack") {
    iarg = add_precrack(args, iarg);
  } else if (key == "contact") {
    need(iarg, 1, key);
    contact = utils::logical(FLERR, arg[iarg + 1], false, lmp) == 1;
    iarg += 2;
  } else if (key == "contact/stiffness") {
    need(iarg, 1, key);
    contact_scale = number(iarg + 1);
    contact_keyword_given = "contact/stiffness";
    if (!(contact_scale > 0.0)) error->all(FLERR, "{}: contact/stiffness must be > 0, got {}", cmd, arg[iarg + 1]);
    iarg += 2;
  } else if (key == "contact/radius") {
    need(iarg, 1, key);
    contact_radius = number(iarg + 1);
    contact_keyword_given = "contact/radius";
    if (!(contact_radius > 0.0)) error->all(FLERR, "{}: contact/radius must be > 0, got {}", cmd, arg[iarg + 1]);
    iarg += 2;
  } else if (key == "alpha") {
    need(iarg, 1, key);
    alpha = number(iarg + 1);
    if (!(alpha >= 0.0)) error->all(FLERR, "{}: alpha must be >= 0, got {}", cmd, arg[iarg + 1]);
    if (criterion != STRETCH) error->all(FLERR, "{}: alpha applies to the stretch criterion only", cmd);
    iarg += 2;
  } else if (key == "audit") {
    need(iarg, 1, key);
    audit_wanted = utils::logical(FLERR, arg[iarg + 1], false, lmp) == 1;
    iarg += 2;
  } else if (key == "every") {
    need(iarg, 1, key);
    nevery = NOSPD_INPUT::integer(error, cmd, key, arg[iarg + 1], -INT_MAX, INT_MAX);
    if (nevery <= 0) error->all(FLERR, "{}: every must be > 0, got {}", cmd, arg[iarg + 1]);
    iarg += 2;
  } else {
    for (const char *c : {"none", "stretch", "energy", "stress", "strain", "eqps", "johnson_cook"})
      if (key == c)
        error->all(FLERR, "{}: a second criterion '{}': one fix has one criterion (the first "
                   "argument); define another fix nospd/damage for another", cmd, key);
    error->all(FLERR, "{}: unknown keyword '{}'", cmd, key);
  }
  return iarg;
}

/* ----------------------------------------------------------------------
   precrack x1 y1 x2 y2 (2D) | x1 y1 z1 x2 y2 z2 x3 y3 z3 (3D), every corner
   inside the box; returns the index after it
------------------------------------------------------------------------- */

int FixNospdDamage::add_precrack(Args &args, int iarg)
{
  char **arg = args.arg;
  const std::string &cmd = args.cmd;
  const std::string key = arg[iarg];
  const int dim = domain->dimension;
  auto number = [&](int i) { return args.number(i); };
  auto need = [&](int iarg, int n, const std::string &key) { args.need(iarg, n, key); };
  const int n = (dim == 2) ? 4 : 9;
  need(iarg, n, key + (dim == 2 ? " (2D: x1 y1 x2 y2)" : " (3D: x1 y1 z1 x2 y2 z2 x3 y3 z3)"));
  for (int k = 1; k <= n; k++)
    if (!utils::is_double(arg[iarg + k]) && !utils::strmatch(arg[iarg + k], "^[-+]?(inf|nan)"))
      error->all(FLERR, "{}: precrack needs {} numbers in {}D, got '{}'", cmd, n, dim, arg[iarg + k]);
  std::array<double, 9> p{};
  for (int k = 0; k < n; k++) p[k] = number(iarg + 1 + k);
  // every corner inside the box
  const int npts = (dim == 2) ? 2 : 3;
  for (int q = 0; q < npts; q++)
    for (int d = 0; d < dim; d++) {
      const double v = p[q * dim + d];
      if (v < domain->boxlo[d] || v > domain->boxhi[d])
        error->all(FLERR, "{}: precrack point {} lies outside the box in {} ({} not in "
                   "[{}, {}])", cmd, q + 1, "xyz"[d], v, domain->boxlo[d], domain->boxhi[d]);
    }
  if (dim == 3) {
    const NOSPD::Vec3 p1(p[0], p[1], p[2]), p2(p[3], p[4], p[5]), p3(p[6], p[7], p[8]);
    if (!((p2 - p1).cross(p3 - p1).norm() > 0.0))
      error->all(FLERR, "{}: precrack corners are collinear", cmd);
    // the fourth corner too
    for (int d = 0; d < 3; d++) {
      const double v = p[3 + d] + p[6 + d] - p[d];
      if (v < domain->boxlo[d] || v > domain->boxhi[d])
        error->all(FLERR, "{}: precrack corner P2+P3-P1 lies outside the box in {}", cmd, "xyz"[d]);
    }
  } else if (p[0] == p[2] && p[1] == p[3])
    error->all(FLERR, "{}: precrack segment has zero length", cmd);
  precracks.push_back(p);
  return iarg + 1 + n;
}

/* ----------------------------------------------------------------------
   settings of the pair style known to go wrong once bonds break, each
   measured in a scene of bench/scenes/run_suite.py: one warning each,
   with what to do instead
------------------------------------------------------------------------- */

void FixNospdDamage::warn_settings(const std::string &cmd)
{
  if (comm->me != 0) return;
  const int kind = pair->stabilization_kind();
  const bool brittle = criterion != EQPS && criterion != JC_DAMAGE;
  struct Known {
    bool applies;
    const char *what;
  };
  const Known known[] = {
      {pair->bond_associated() && kind == static_cast<int>(NOSPD::Stab::NONE),
       "the bond-associated style without a stabilization term lets damaged families run "
       "away (the body shatters where peri/pmb cracks); add `stabilization silling 0.5` to "
       "pair_style peri/nospd/hs (doc Howto_choose_model, \"Warnings\")"},
      {pair->quadratic_active() && !pair->carries_deformation(),
       "with stabilization/fit quadratic and damaged_state refit a family that loses bonds "
       "falls back to the linear fit, whose springs start loaded: breaking bonds adds energy "
       "(measured: 25-117 % of the dissipated in a ductile perforation); keep damaged_state "
       "carry, which carries the fit's curvature (doc pair_peri_nospd, \"Families that lose "
       "bonds\")"},
      {kind == static_cast<int>(NOSPD::Stab::WAN),
       "stabilization wan's springs follow K^-1, which grows when a family loses bonds: "
       "breaking bonds adds energy (measured: 23 % of the dissipated in a ductile "
       "perforation); for fracture use stabilization silling (doc pair_peri_nospd, "
       "\"Families that lose bonds\")"},
  };
  for (const Known &k : known)
    if (k.applies) error->warning(FLERR, "{} {}: {}", cmd, id, k.what);
  // the soda-lime glass plate of examples/crack_branching branches with
  // silling 0.05-0.1 and hourglass 0.2-0.5, not with silling 0.2-0.5
  if (brittle && kind == static_cast<int>(NOSPD::Stab::SILLING) &&
      pair->stabilization_parameter() > 0.15)
    error->warning(FLERR, "{} {}: Silling's springs at G = {:g} hold a running crack from "
                   "branching (measured: the soda-lime glass plate of examples/crack_branching "
                   "keeps one crack with G >= 0.2, branches with G <= 0.1 or hourglass 0.2-0.5); "
                   "where cracks may branch use stabilization silling 0.05 or hourglass 0.5, "
                   "which turn the Kalthoff-Winkler cracks to 62-64 deg instead of 72 at dx 1 mm "
                   "(doc Howto_choose_model, \"Warnings\")", cmd, id,
                   pair->stabilization_parameter());
}

/* ----------------------------------------------------------------------
   critical values and contact stiffness per type pair; a bond between
   types I and J uses the smaller of the two types' critical values
------------------------------------------------------------------------- */

void FixNospdDamage::setup_tables()
{
  const std::string cmd = std::string("fix ") + style;
  const int ntypes = atom->ntypes;
  const int dim = domain->dimension;
  const NOSPD::Plane plane = pair->plane();
  const double t = pair->plate_thickness();

  memory->destroy(crit);
  memory->destroy(kcontact);
  memory->destroy(delta);
  memory->create(crit, ntypes + 1, ntypes + 1, "nospd/damage:crit");
  memory->create(kcontact, ntypes + 1, ntypes + 1, "nospd/damage:kcontact");
  memory->create(delta, ntypes + 1, ntypes + 1, "nospd/damage:delta");

  if (from_g0 && !g0_given)
    for (int i = 1; i <= ntypes; i++)
      if (pair->owns_type(i) && !(pair->fracture_energy(i) > 0.0))
        error->all(FLERR, "{}: atom type {} has no fracture energy G0: read its material from a "
                   "material file with a G0, or give G0 after 'g0'", cmd, i);

  auto type_value = [&](int i, double d) {
    if (!from_g0) return value;
    const double G0 = g0_given ? value : pair->fracture_energy(i);
    if (criterion == STRETCH)
      return NOSPD::critical_stretch_from_g0(dim, plane, pair->youngs_modulus(i),
                                             pair->poisson_ratio(i), d, G0);
    return NOSPD::critical_energy_from_g0(dim, d, t, G0);
  };

  // types of other pair styles (pair hybrid) have no bonds and no contact here
  for (int i = 1; i <= ntypes; i++)
    for (int j = 1; j <= ntypes; j++) {
      delta[i][j] = crit[i][j] = kcontact[i][j] = 0.0;
      if (!pair->owns_type(i) || !pair->owns_type(j)) continue;
      const double d = pair->horizon(i, j);
      delta[i][j] = d;
      crit[i][j] = std::min(type_value(i, d), type_value(j, d));
      const double ci = NOSPD::micromodulus(dim, plane, pair->youngs_modulus(i),
                                            pair->poisson_ratio(i), d, t);
      const double cj = NOSPD::micromodulus(dim, plane, pair->youngs_modulus(j),
                                            pair->poisson_ratio(j), d, t);
      kcontact[i][j] = contact_scale * 0.5 * (ci + cj);
    }

  // contact radius: given, or 1.35 times the largest point spacing, the
  // spacing taken from the volume (2D: V = dx^2 t)
  if (contact) {
    if (contact_radius > 0.0) contact_rc = contact_radius;
    else {
      double vmax = 0.0;
      for (int i = 0; i < atom->nlocal; i++) vmax = std::max(vmax, atom->vfrac[i]);
      double all;
      MPI_Allreduce(&vmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
      const double dx = (dim == 3) ? std::cbrt(all) : std::sqrt(all / t);
      contact_rc = 1.35 * dx;
    }
    double dmin = 1e300;
    int imin = 0, jmin = 0;
    for (int i = 1; i <= ntypes; i++)
      for (int j = 1; j <= ntypes; j++)
        if (pair->owns_type(i) && pair->owns_type(j) && delta[i][j] < dmin) {
          dmin = delta[i][j];
          imin = i, jmin = j;
        }
    if (imin && !(contact_rc < dmin))
      error->all(FLERR, "{}: contact radius {} must be smaller than the horizon {} of types {} {}",
                 cmd, contact_rc, dmin, imin, jmin);
  }

  if (comm->me == 0 && criterion != NONE) {
    std::string msg = fmt::format("{} {}: critical value per type pair:", cmd, id);
    for (int i = 1; i <= ntypes; i++)
      for (int j = i; j <= ntypes; j++)
        if (pair->owns_type(i) && pair->owns_type(j))
          msg += fmt::format(" {}-{} {:.6g}", i, j, crit[i][j]);
    utils::logmesg(lmp, msg + "\n");
  }
}

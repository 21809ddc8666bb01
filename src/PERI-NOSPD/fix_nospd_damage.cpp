/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Damage: bond-breaking criteria, pre-cracks, singular families, contact.

   Symmetry of breaking.  A bond (i,j) lives in the partner lists of both
   i and j, which may be owned by different MPI ranks; each owner decides
   for its own slot.  The two decisions agree bit for bit because every
   number that enters them is the same on both ranks:
     - reference bond vectors come from x0, which ghosts carry unshifted,
       imaged in the reference box by the bonds fix (reference_bond; an
       operation symmetric under negation), the reference the forces use
       however the box has changed since the families were built;
     - displacements u = x - x0 are computed by each atom's owner and
       forward-communicated unchanged; the current bond is the current
       box's minimum image of (x0_j - x0_i) + (u_j - u_i), in which whole
       box lengths cancel, symmetric under negation too;
     - per-atom tensors (A = P K^-1, stress, strain) and flags are
       forward-communicated from their owners;
     - every bond is evaluated in the order (lower ID, higher ID), and the
       scatter factor is a hash of the two reference positions.
   The total number of slots broken in a step is checked to be even.

   Timing.  The state of each atom (A, stress or strain) is stored after
   the force computation of a step (post_force); the criteria are
   evaluated at the start of the next force computation (pre_force) from
   the current positions and that state, and broken bonds leave K and F
   before the forces are computed.  The forces of a step therefore belong
   to the bond state a restart file written after that step holds, and a
   run continued from it breaks the same bonds as an uninterrupted one.
------------------------------------------------------------------------- */

#include "fix_nospd_damage.h"

#include "atom.h"
#include "citeme.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "input.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair_peri_nospd_base.h"
#include "region.h"
#include "update.h"

#include "nospd_contact_memory.h"
#include "nospd_damage_criteria.h"
#include "nospd_input.h"
#include "nospd_plasticity.h"

#include "nospd_threads.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;
using NOSPD::Mat3;

static const char cite_damage[] =
    "fix nospd/damage: doi:10.1016/j.compstruc.2004.11.026\n\n"
    "@Article{SillingAskari05,\n"
    " author = {S. A. Silling and E. Askari},\n"
    " title = {A Meshfree Method Based on the Peridynamic Model of Solid Mechanics},\n"
    " journal = {Comput.\\ Struct.},\n"
    " year =    2005,\n"
    " volume =  83,\n"
    " pages =   {1526--1535}\n"
    "}\n\n";

namespace {
/* Minimum image of a difference vector, without the per-call overhead of
   Domain::minimum_image (orthogonal boxes; triclinic boxes use it).  Like
   it, symmetric under negation: mi(-d) = -mi(d) bit for bit. */
inline void min_image(const Domain *domain, double *d)
{
  if (domain->triclinic) {
    domain->minimum_image(FLERR, d);
    return;
  }
  if (domain->xperiodic)
    while (fabs(d[0]) > domain->xprd_half) d[0] += (d[0] < 0.0) ? domain->xprd : -domain->xprd;
  if (domain->yperiodic)
    while (fabs(d[1]) > domain->yprd_half) d[1] += (d[1] < 0.0) ? domain->yprd : -domain->yprd;
  if (domain->zperiodic)
    while (fabs(d[2]) > domain->zprd_half) d[2] += (d[2] < 0.0) ? domain->zprd : -domain->zprd;
}

}    // namespace

/* ----------------------------------------------------------------------
   The reference bond xi from end a to end c (the bonds fix's reference
   geometry), the current bond Y (the minimum image, in the current box, of
   the raw reference difference plus the raw displacement difference: exact
   through any box change, since whole box lengths cancel) and U = Y - xi
   (in a box without periodic dimensions: the displacement difference).
   Every term is antisymmetric in (a, c) bit for bit.
------------------------------------------------------------------------- */

void FixNospdDamage::bond_geometry(const double *x0a, const double *x0c, const double *ua,
                                   const double *uc, bool periodic, double *xi, double *U,
                                   double *Y) const
{
  for (int k = 0; k < 3; k++) {
    xi[k] = x0c[k] - x0a[k];
    U[k] = uc[k] - ua[k];
    Y[k] = xi[k] + U[k];
  }
  if (!periodic) return;
  min_image(domain, Y);
  bonds->reference_bond(x0a, x0c, xi);
  for (int k = 0; k < 3; k++) U[k] = Y[k] - xi[k];
}

namespace {

constexpr int FLAG_NOFAIL = 1;
constexpr int FLAG_SINGULAR = 2;
constexpr int FLAG_INGROUP = 4;
}    // namespace


/* ---------------------------------------------------------------------- */

FixNospdDamage::FixNospdDamage(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), nthreads(1), criterion(NONE), from_g0(false), value(0.0), g0_given(false),
    scatter_width(0.0), alpha(0.0), scatter_seed(0), nevery(1), nofail_groupbit(0),
    nofail_region_id(nullptr), nofail_region(nullptr), detach_singular(false), contact(false),
    contact_scale(15.0), contact_radius(0.0), contact_rc(0.0), list(nullptr), pair(nullptr),
    bonds(nullptr), crit(nullptr), kcontact(nullptr), delta(nullptr), nstate(0), state(nullptr), ncomm(4), nmax_comm(0),
    cdata(nullptr), precracks_done(false), nbroken_total(0), nbroken_step(0), ncontact(0),
    econtact(0.0)
{
  if (lmp->citeme) lmp->citeme->add(cite_damage);
  const std::string cmd = std::string("fix ") + style;
  if (narg < 4) error->all(FLERR, "Illegal {} command: missing criterion", cmd);

  vector_flag = 1;
  size_vector = 7;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;

  Args args{error, cmd, narg, arg, ""};
  const char *contact_keyword_given = nullptr;    // the last contact/... keyword
  for (int iarg = parse_criterion(args); iarg < narg;)
    iarg = parse_keyword(args, iarg, contact_keyword_given);
  if (!contact && contact_keyword_given)
    error->all(FLERR, "{}: {} given without contact yes: it sets the contact force, which is "
               "off", cmd, contact_keyword_given);
  if (contact) {
    // the contact force is an interaction like the pair style's: its energy
    // (global scalar) and virial enter thermo pe and pressure by default
    scalar_flag = 1;
    extscalar = 1;
    energy_global_flag = 1;
    virial_global_flag = virial_peratom_flag = 1;
    thermo_energy = thermo_virial = 1;
  }
  if (criterion == NONE && precracks.empty() && !contact)
    error->all(FLERR, "{}: criterion none with neither precrack nor contact does nothing", cmd);

  switch (criterion) {
    case ENERGY: nstate = 9; break;
    case STRESS_PRINCIPAL:
    case STRAIN_PRINCIPAL:
    case STRESS_VONMISES: nstate = 6; break;
    case STRETCH: nstate = (alpha > 0.0) ? 1 : 0; break;
    case EQPS:
    case JC_DAMAGE: nstate = 1; break;
    default: nstate = 0;
  }
  // criteria of the bond's length or displacement see its mechanical part
  // only: a freely expanding body breaks nothing (the stress ones need none)
  if (criterion == STRETCH || criterion == ENERGY || criterion == STRAIN_PRINCIPAL ||
      criterion == STRESS_VONMISES)
    ecol = nstate++;
  ncomm = 4 + nstate;    // init leaves the thermal column out where no type has one
  comm_forward = ncomm;
  if (peratom()) {
    FixNospdDamage::grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    for (int i = 0; i < atom->nlocal; i++) {
      for (int k = 0; k < nstate; k++) state[i][k] = 0.0;
      if (contact) NOSPD::ContactMemory::clear(cmem[i]);
    }
  }
  if (contact) {
    // the remembered contacts go into restart files with their atoms
    restart_peratom = 1;
    atom->add_callback(Atom::RESTART);
  }
}

/* ---------------------------------------------------------------------- */

FixNospdDamage::~FixNospdDamage()
{
  if (peratom() && modify->get_fix_by_id(id)) atom->delete_callback(id, Atom::GROW);
  if (contact && modify->get_fix_by_id(id)) atom->delete_callback(id, Atom::RESTART);
  memory->destroy(state);
  memory->destroy(cmem);
  delete[] nofail_region_id;
  memory->destroy(crit);
  memory->destroy(kcontact);
  memory->destroy(delta);
  memory->destroy(cdata);
}

/* ---------------------------------------------------------------------- */

int FixNospdDamage::setmask()
{
  int mask = 0;
  mask |= PRE_FORCE;         // breaking; setup_pre_force: pre-cracks
  mask |= MIN_PRE_FORCE;     // pre-cracks before minimize (no breaking there)
  mask |= POST_FORCE;
  mask |= PRE_REVERSE;       // the energy audit: the pair style's forces
  mask |= POST_INTEGRATE;    // and the work they do over a step
  return mask;
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::init()
{
  const std::string cmd = std::string("fix ") + style;
  econtact = 0.0;    // minimize adds no contact force: no stale energy either
  pair = PairPeriNospdBase::find(force);
  if (!pair)
    error->all(FLERR, "{} requires a peri/nospd pair style (it acts on that style's bond "
               "families)", cmd);
  bonds = pair->bonds();
  if (!bonds) error->all(FLERR, "{}: the pair style has no bond families yet", cmd);
  // rerun evaluates forces of stored snapshots without time steps: no
  // pre_force, so no bond breaks (pre-cracks still apply)
  const bool rerun = input->command && utils::strmatch(input->command, "^rerun");
  if (comm->me == 0 && criterion != NONE && rerun && !rerun_warned)
    error->warning(FLERR, "{} {}: rerun breaks no bonds (it takes no time steps): its energies "
                   "and forces are those of the body with the bonds intact at the start of the "
                   "rerun", cmd, id);
  rerun_warned = rerun;    // once per rerun command (it initializes per snapshot)
  if (!settings_warned && criterion != NONE) warn_settings(cmd);
  settings_warned = true;
  if (criterion == EQPS || criterion == JC_DAMAGE) {
    bool any = false;
    for (int i = 1; i <= atom->ntypes; i++)
      if (pair->has_history(i) &&
          (criterion == EQPS ? pair->flow_law(i).active : pair->thermal_law(i).failure))
        any = true;
    if (!any)
      error->all(FLERR, "{}: criterion {} needs a type with {} in its pair_coeff", cmd,
                 criterion == EQPS ? "eqps" : "johnson_cook",
                 criterion == EQPS ? "plasticity (yield or johnson_cook)" : "jc_failure D1..D5");
  }

  if (nofail_region_id) {
    nofail_region = domain->get_region_by_id(nofail_region_id);
    if (!nofail_region) error->all(FLERR, "{}: nofail region {} does not exist", cmd, nofail_region_id);
  }
  setup_tables();
  init_thermal();
  audit_init();

  if (contact) {
    auto *req = neighbor->add_request(this, NeighConst::REQ_FULL);
    req->set_cutoff(contact_rc);
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::init_list(int /*id*/, NeighList *ptr)
{
  list = ptr;
}

/* ----------------------------------------------------------------------
   pre-cracks: before the first force evaluation of the first run
------------------------------------------------------------------------- */

void FixNospdDamage::setup_pre_force(int /*vflag*/)
{
  // families built anew (the first run, a pair_style command between runs,
  // a restart read under the other style): the count of broken bonds
  // starts over and the pre-cracks are cut into the new families
  if (bonds->families_serial != families_seen) {
    families_seen = bonds->families_serial;
    nbroken_total = 0;
    precracks_done = false;
  }
  if (!precracks_done) {
    if (!precracks.empty()) apply_precracks();
    precracks_done = true;
  }
}

/* ----------------------------------------------------------------------
   after the setup force computation: contact, and the state for the first
   evaluation.  Nothing breaks here, so that a run split in two (or
   continued from a restart) breaks the same bonds as one uninterrupted
   run: the restart holds the bonds of the last step, whose forces were
   computed with exactly those bonds.
------------------------------------------------------------------------- */

void FixNospdDamage::setup(int vflag)
{
  v_init(vflag);
  if (contact) contact_forces();
  else ncontact = 0;
  if (auditing) audit_observe();
  store_state();
  // the smallest stretch of each family, for the first evaluation
  if (criterion == STRETCH && alpha > 0.0) evaluate_and_break(false);
}

/* ----------------------------------------------------------------------
   start of the force computation: evaluate and break, so that this step's
   forces (and K^-1, F) use the new bond state
------------------------------------------------------------------------- */

void FixNospdDamage::pre_force(int /*vflag*/)
{
  nbroken_step = 0;
  nbroken_total += bonds->take_far_broken();    // at a rebuild of the ghosts
  if (criterion != NONE && update->ntimestep % nevery == 0) evaluate_and_break();
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::post_force(int vflag)
{
  v_init(vflag);
  if (contact) contact_forces();
  if (auditing) {
    audit_half_step();
    audit_observe();
  }
  store_state();
}

/* ----------------------------------------------------------------------
   per owned atom: displacement u = x - x0 (minimum image) now, flags now,
   and the state of the last force computation; then forward
   communication to the ghosts
------------------------------------------------------------------------- */

void FixNospdDamage::fill_comm_data()
{
  if (atom->nmax > nmax_comm) {
    nmax_comm = atom->nmax;
    memory->destroy(cdata);
    memory->create(cdata, nmax_comm, ncomm, "nospd/damage:cdata");
  }
  const int nlocal = atom->nlocal;
  double **x = atom->x, **x0 = atom->x0;
  const int *mask = atom->mask;

  for (int i = 0; i < nlocal; i++) {
    double *c = cdata[i];
    // raw: whole box lengths of a wrapped atom cancel in the bond's
    // current vector, imaged in the current box (bond_geometry)
    c[0] = x[i][0] - x0[i][0];
    c[1] = x[i][1] - x0[i][1];
    c[2] = x[i][2] - x0[i][2];
    int flags = 0;
    if (mask[i] & groupbit) flags |= FLAG_INGROUP;
    if ((nofail_groupbit && (mask[i] & nofail_groupbit)) ||
        (nofail_region && nofail_region->match(x[i][0], x[i][1], x[i][2])))
      flags |= FLAG_NOFAIL;
    if (bonds->singular[i]) flags |= FLAG_SINGULAR;
    c[3] = flags;
    for (int k = 0; k < ncomm - 4; k++) c[4 + k] = state[i][k];
  }
  comm->forward_comm(this);
}

/* ---------------------------------------------------------------------- */

int FixNospdDamage::pack_forward_comm(int n, int *list_, double *buf, int /*pbc_flag*/,
                                      int * /*pbc*/)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const double *c = cdata[list_[ii]];
    for (int k = 0; k < ncomm; k++) buf[m++] = c[k];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  const int last = first + n;
  for (int i = first; i < last; i++)
    for (int k = 0; k < ncomm; k++) cdata[i][k] = buf[m++];
}

/* ----------------------------------------------------------------------
   Evaluate every intact bond of every owned atom and break those that
   meet the criterion.  Bond values (a = lower ID end, b = higher):
     xi = minimum image of x0_b - x0_a,  U = u_b - u_a,  Y = xi + U
     stretch           s = (|Y| - |xi|)/|xi|                  >= s_c
     energy            w = 1/2 omega ((A_a + A_b) xi).U       >= w_c, s > 0
     stress principal  n.sigma_ab n,  n = Y/|Y|               >= sigma_c
     strain principal  n.eps_ab n,    n = xi/|xi|             >= eps_c
     stress vonmises   vm(sigma_ab)                           >= sigma_c, s > 0
   with sigma_ab = (sigma_a + sigma_b)/2 (likewise eps), positions of now
   and atom state of the last force computation.  Only bonds with both
   ends in the fix group and neither end "nofail" can break.
------------------------------------------------------------------------- */

void FixNospdDamage::evaluate_and_break(bool apply)
{
  fill_comm_data();
  // a bond longer than the ghost cutoff breaks in the step that takes it
  // there, whatever the criterion and whenever the ghosts are rebuilt (so
  // that a run split by a restart breaks it in the same step)
  const double rc = comm->get_comm_cutoff();
  far2 = rc * rc;
  std::vector<std::pair<int, int>> cut;
  switch (criterion) {
    case STRETCH:
      if (alpha > 0.0) cut = scan_bonds(NOSPD::AlphaStretchCriterion{alpha}, apply);
      else if (apply && thermal) stretch_cuts<true>(cut);
      else if (apply) stretch_cuts<false>(cut);
      break;
    case ENERGY:
      cut = scan_bonds(
          NOSPD::EnergyCriterion{bonds->get_model().influence == NospdBondModel::INVERSE}, apply);
      break;
    case STRESS_PRINCIPAL: cut = scan_bonds(NOSPD::PrincipalCriterion{true}, apply); break;
    case STRAIN_PRINCIPAL: cut = scan_bonds(NOSPD::PrincipalCriterion{false}, apply); break;
    case STRESS_VONMISES: cut = scan_bonds(NOSPD::VonMisesCriterion{}, apply); break;
    case EQPS:
    case JC_DAMAGE: cut = scan_bonds(NOSPD::PointFailureCriterion{}, apply); break;
  }
  if (!apply) return;
  nbroken_step = break_list(cut);
  nbroken_total += nbroken_step;
}

/* ----------------------------------------------------------------------
   Every intact bond of every owned atom through one criterion: the bonds
   to cut, as (atom, slot), in the serial order (one list per thread,
   joined in thread order).  The state rows are the forwarded cdata[.][4..].
------------------------------------------------------------------------- */

template <class Crit>
std::vector<std::pair<int, int>> FixNospdDamage::scan_bonds(const Crit &crit_of, bool apply)
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  const int *type = atom->type;
  double **x0 = atom->x0;
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  const int *bfirst = bonds->bond_first;
  const int *bj = bonds->bond_j;
  const int *bslot = bonds->bond_slot;
  std::vector<std::vector<std::pair<int, int>>> cuts(NOSPD::range_count(nthreads, nlocal));
  NOSPD::run_ranges(cuts.size(), nlocal, [&](int from, int to, int tid) {
    std::vector<std::pair<int, int>> &cut = cuts[tid];
    for (int i = from; i < to; i++) {
      const int fi = static_cast<int>(cdata[i][3]);
      double smin = 0.0;
      bool first = true;
      if (Crit::TRACKS_SMIN) state[i][0] = 0.0;
      if (!(fi & FLAG_INGROUP)) continue;
      for (int b = bfirst[i]; b < bfirst[i + 1]; b++) {
        const int j = bj[b];
        const int fj = static_cast<int>(cdata[j][3]);
        if (!(fj & FLAG_INGROUP)) continue;
        if ((fi | fj) & FLAG_NOFAIL) continue;
        const bool i_lo = tag[i] < tag[j];
        const int a = i_lo ? i : j, c = i_lo ? j : i;
        if (detach_singular && ((fi | fj) & FLAG_SINGULAR)) {
          cut.emplace_back(i, bslot[b]);
          continue;
        }
        double xi[3], U[3], Y[3];
        bond_geometry(x0[a], x0[c], cdata[a], cdata[c], periodic, xi, U, Y);
        NOSPD::BondView v{xi, U, Y, 0.0, 0.0, 0.0, cdata[a] + 4, cdata[c] + 4,
                          delta[type[a]][type[c]]};
        const double ry2 = Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2];
        if (ry2 > far2 && (apply || !Crit::TRACKS_SMIN)) {
          cut.emplace_back(i, bslot[b]);
          continue;
        }
        v.rxi = sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
        v.ry = sqrt(ry2);
        v.s = (v.ry - v.rxi) / v.rxi;
        if (thermal) {
          const double e = 0.5 * (cdata[a][4 + ecol] + cdata[c][4 + ecol]);
          v.s = NOSPD::mechanical_stretch(small_law, e, v.s);
          NOSPD::mechanical_displacement(small_law, e, xi, Y, U);
        }
        double limit = crit[type[a]][type[c]], val = 0.0;
        if (scatter_width > 0.0)
          limit *= NOSPD::scatter_factor((uint64_t) scatter_seed, NOSPD::position_key(x0[a]),
                                         NOSPD::position_key(x0[c]), scatter_width);
        if (!crit_of(v, val, limit)) continue;
        const bool breaks = val >= limit || std::isnan(val);
        if (!Crit::TRACKS_SMIN) {
          if (breaks) cut.emplace_back(i, bslot[b]);
        } else if (apply && breaks) {
          cut.emplace_back(i, bslot[b]);
        } else if (first || val < smin) {
          smin = val;
          first = false;
        }
      }
      if (Crit::TRACKS_SMIN) state[i][0] = smin;
    }
  });
  std::vector<std::pair<int, int>> cut;
  for (auto &c : cuts) cut.insert(cut.end(), c.begin(), c.end());
  return cut;
}

/* ----------------------------------------------------------------------
   The plain stretch criterion, the common case, as a tight loop over the
   flat arrays.  Each end evaluates the bond from its own side: with
   xi = x0_j - x0_i (minimum image) and U = u_j - u_i, the other end's
   values are the exact negatives (IEEE subtraction is antisymmetric, the
   minimum image too), so |Y|^2 and |xi|^2 and the decision agree bit for
   bit on both ends, on any rank, without ordering the ends by ID.
------------------------------------------------------------------------- */

template <bool THERMAL>
void FixNospdDamage::stretch_cuts(std::vector<std::pair<int, int>> &cut)
{
  const int nlocal = atom->nlocal;
  const int nc = ncomm;
  const double *_noalias const cd = cdata[0];
  const double *_noalias const x0f = atom->x0[0];
  double **x0 = atom->x0;
  const int *_noalias const bfirst = bonds->bond_first;
  const int *_noalias const bj = bonds->bond_j;
  const int *_noalias const bslot = bonds->bond_slot;
  const int *type = atom->type;
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  const bool one_type = (atom->ntypes == 1);
  const double limit1 = crit[1][1];

  std::vector<std::vector<std::pair<int, int>>> cuts(NOSPD::range_count(nthreads, nlocal));
  NOSPD::run_ranges(cuts.size(), nlocal, [&](int from, int to, int tid) {
    std::vector<std::pair<int, int>> &mine = cuts[tid];
    for (int i = from; i < to; i++) {
      const double *ci = cd + (bigint) nc * i;
      const int fi = static_cast<int>(ci[3]);
      if (!(fi & FLAG_INGROUP)) continue;
      const double xi0 = x0f[3 * i], yi0 = x0f[3 * i + 1], zi0 = x0f[3 * i + 2];
      const double uxi = ci[0], uyi = ci[1], uzi = ci[2];
      const int bend = bfirst[i + 1];
      for (int b = bfirst[i]; b < bend; b++) {
        const int j = bj[b];
        const double *cj = cd + (bigint) nc * j;
        const int fj = static_cast<int>(cj[3]);
        if (!(fj & FLAG_INGROUP)) continue;
        if ((fi | fj) & FLAG_NOFAIL) continue;
        if (detach_singular && ((fi | fj) & FLAG_SINGULAR)) {
          mine.emplace_back(i, bslot[b]);
          continue;
        }
        double xi[3] = {x0f[3 * j] - xi0, x0f[3 * j + 1] - yi0, x0f[3 * j + 2] - zi0};
        double Yx = xi[0] + (cj[0] - uxi), Yy = xi[1] + (cj[1] - uyi), Yz = xi[2] + (cj[2] - uzi);
        if (periodic) {
          double Y[3] = {Yx, Yy, Yz};
          min_image(domain, Y);
          Yx = Y[0];
          Yy = Y[1];
          Yz = Y[2];
          bonds->bond_vector(i, b, xi);
        }
        const double rxi2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
        const double ry2 = Yx * Yx + Yy * Yy + Yz * Yz;
        double limit = one_type ? limit1 : crit[type[i]][type[j]];
        if (scatter_width > 0.0)
          limit *= NOSPD::scatter_factor((uint64_t) scatter_seed, NOSPD::position_key(x0[i]),
                                         NOSPD::position_key(x0[j]), scatter_width);
        // s >= s_c  <=>  |Y|^2 >= (1 + s_c)^2 |xi|^2, without square roots;
        // the bond's thermal strain e moves the bound (mechanical_stretch)
        double f = 1.0 + limit;
        if (THERMAL) {
          const double e = 0.5 * (ci[4 + ecol] + cj[4 + ecol]);
          f = small_law ? f + e : f * (1.0 + e);
        }
        if (ry2 >= f * f * rxi2 || ry2 > far2 || std::isnan(ry2)) mine.emplace_back(i, bslot[b]);
      }
    }
  });
  for (auto &c : cuts) cut.insert(cut.end(), c.begin(), c.end());
}

/* ----------------------------------------------------------------------
   break the listed (atom, slot) pairs on this rank; collective: every
   rank calls it.  Returns the number of bonds (pairs) broken in total.
------------------------------------------------------------------------- */

int FixNospdDamage::break_list(std::vector<std::pair<int, int>> &cut)
{
  if (contact) remember_contacts(cut);
  for (auto &p : cut) bonds->break_bond(p.first, p.second);
  bigint mine[2] = {(bigint) cut.size(), cmem_full}, sums[2] = {0, 0};
  MPI_Allreduce(mine, sums, 2, MPI_LMP_BIGINT, MPI_SUM, world);
  const bigint all = sums[0];
  if (sums[1] && !cmem_warned && comm->me == 0)
    error->warning(FLERR, "Fix {}: {} bonds broke below the contact rest distance with no room "
                   "left to remember them ({} per atom): their contact starts loaded, which adds "
                   "energy; check the energy balance", style, sums[1], NOSPD::ContactMemory::CAPACITY);
  if (sums[1]) cmem_warned = true;
  if (all % 2)
    error->all(FLERR, "Fix {}: bonds broken on one end only ({} slots): bond evaluation is not "
               "symmetric; please report this", style, all);
  if (all) bonds->bonds_changed();
  return (int) (all / 2);
}

/* ----------------------------------------------------------------------
   cut every bond of the fix group whose reference segment crosses a
   pre-crack; the segment is built from its lower-ID end (and, for
   periodic boxes, also from its higher-ID end, the other image)
------------------------------------------------------------------------- */

void FixNospdDamage::apply_precracks()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  const int *mask = atom->mask;
  double **x0 = atom->x0;
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  const int dim = domain->dimension;
  const int *bfirst = bonds->bond_first;
  const int *bj = bonds->bond_j;
  const int *bslot = bonds->bond_slot;

  auto crosses = [&](const double *A, const double *B) {
    for (const auto &p : precracks) {
      if (dim == 2) {
        if (NOSPD::crosses_segment_2d(A, B, &p[0], &p[2])) return true;
      } else if (NOSPD::crosses_parallelogram_3d(A, B, &p[0], &p[3], &p[6]))
        return true;
    }
    return false;
  };

  std::vector<std::pair<int, int>> cut;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    for (int b = bfirst[i]; b < bfirst[i + 1]; b++) {
      const int j = bj[b];
      if (!(mask[j] & groupbit)) continue;
      const bool i_lo = tag[i] < tag[j];
      const int a = i_lo ? i : j, c = i_lo ? j : i;
      double d[3];
      bonds->bond_vector(i, b, d);    // from i: the lower ID's end is a
      if (!i_lo)
        for (double &v : d) v = -v;
      const double A[3] = {x0[a][0], x0[a][1], x0[a][2]};
      const double B[3] = {A[0] + d[0], A[1] + d[1], A[2] + d[2]};
      bool hit = crosses(A, B);
      if (!hit && periodic) {
        const double B2[3] = {x0[c][0], x0[c][1], x0[c][2]};
        const double A2[3] = {B2[0] - d[0], B2[1] - d[1], B2[2] - d[2]};
        hit = crosses(A2, B2);
      }
      if (hit) cut.emplace_back(i, bslot[b]);
    }
  }
  const int n = break_list(cut);
  nbroken_total += n;
  nbroken_step = n;
  if (comm->me == 0)
    utils::logmesg(lmp, "Fix {} {}: {} pre-crack(s) cut {} bonds\n", style, id,
                   precracks.size(), n);
}

/* ---------------------------------------------------------------------- */

double FixNospdDamage::compute_scalar()
{
  double all = 0.0;
  MPI_Allreduce(&econtact, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

/* ---------------------------------------------------------------------- */

double FixNospdDamage::compute_vector(int n)
{
  switch (n) {
    case 0: return (double) nbroken_total;
    case 1: return (double) nbroken_step;
    case 2: return bonds ? (double) bonds->nsingular : 0.0;
    case 3: return bonds ? 0.5 * (double) bonds->nbonds_total : 0.0;
    case 4: return (double) ncontact;
    case 5: return audit.created();
    default: return audit.dissipated();
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    double list_[2] = {(double) nbroken_total, (double) precracks.size()};
    int size = 2 * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list_, sizeof(double), 2, fp);
  }
}

/* ---------------------------------------------------------------------- */

void FixNospdDamage::restart(char *buf)
{
  auto *list_ = (double *) buf;
  nbroken_total = (bigint) list_[0];
  // the families in the restart file already carry the pre-cracks; cutting
  // them again finds no bond to cut, so nothing is skipped here
}

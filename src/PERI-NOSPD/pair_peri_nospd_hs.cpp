/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Horizon-stabilized (bond-associated) correspondence pair style.
------------------------------------------------------------------------- */

#include "pair_peri_nospd_hs.h"

#include "atom.h"
#include "citeme.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "memory.h"
#include "neighbor.h"
#include "update.h"

#include "nospd_input.h"
#include "nospd_simd.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <numeric>

using namespace LAMMPS_NS;
using NOSPD::BondPattern;
using NOSPD::HSForm;
using NOSPD::Mat3;

static const char cite_nospd_hs[] =
    "pair peri/nospd/hs: Chen and Spencer, IJNME 117 (2019) 713\n\n"
    "@Article{ChenSpencer19,\n"
    " author = {H. Chen and B. W. Spencer},\n"
    " title = {Peridynamic bond-associated correspondence model: Stability and convergence "
    "properties},\n"
    " journal = {Int.~J.~Numer.~Meth.~Engng.},\n"
    " year =    2019,\n"
    " volume =  117,\n"
    " number =  6,\n"
    " pages =   {713--727}\n"
    "}\n\n";

// offsets are matched to patterns after rounding to this fraction of the
// horizon: far below any spacing, far above the round-off of x0 differences
static constexpr double KEY_QUANTUM = 1.0e-10;
// weights of two families of one pattern agree to this relative tolerance
static constexpr double WEIGHT_TOL = 1.0e-12;
// patterns shared by at least this many families get a sum program (its
// construction costs about as much as evaluating a few hundred families)
static constexpr int PROGRAM_USERS = 64;
// a neighbourhood shared by at least this many points gets a one-sided
// stencil (its assembly costs about as much as evaluating a hundred
// families, besides the operators of the families it reads)
static constexpr int POINT_STENCIL_USERS = 4;
// the one-sided stencils' assembly holds a dense cube of blocks per
// neighbourhood: at most this many bytes of them at once
static constexpr double POINT_STENCIL_BATCH_BYTES = 256.0e6;
// the stencil pass takes points in blocks of this many (its kernel's loop
// over them is its own)
static constexpr int STENCIL_BLOCK = 64;

/* the evaluation kernel is built for the generic target and, where the
   compiler can, for AVX2 and AVX-512 (nospd_simd.h): its row sums and 3x3
   products are plain loops that widen with the target, about 10% faster
   on CPUs that have the wider units */

namespace {

// FNV-1a over a pattern's quantized offsets
uint64_t key_hash(const std::vector<int64_t> &key)
{
  uint64_t h = 1469598103934665603ULL;
  for (int64_t v : key) h = (h ^ (uint64_t) v) * 1099511628211ULL;
  return h;
}

template <int DIM, int L>
NOSPD_KERNEL_CLONES bool evaluate(const BondPattern &p, HSForm form, NOSPD::Law law,
                                  NOSPD::Plane plane, const NOSPD::LaneInput *in, bool energy,
                                  NOSPD::StateScratch &s, NOSPD::StateOutput *out)
{
  return NOSPD::evaluate_families<DIM, L>(p, form, law, plane, in, energy, s, out);
}
// one bond's plastic return (point_core, the return mapping, the log and
// exp series inlined), built for the CPU like the bond sums
NOSPD_KERNEL_CLONES NOSPD::ReturnStatus bond_return_kernel(
    NOSPD::Law law, NOSPD::Plane plane, const NOSPD::Lame &m, const NOSPD::FlowLaw &fl,
    const NOSPD::ThermalLaw &th, const NOSPD::PointEnv &env, NOSPD::Mat3 &F, const double *pn,
    double *p1, NOSPD::Mat3 &P, double &W)
{
  return NOSPD::detail::bond_return(law, plane, m, fl, th, env, F, pn, p1, P, W);
}

// the stencil's points [from, to) of a run: forces four at a time (the
// last ones two or one at a time: the same bits), then each point's F and
// mean bond H
template <int DIM, bool ONE>
NOSPD_KERNEL_CLONES void stencil_kernel(const NOSPD::Stencil &st, const double *u,
                                        const int *cells, const int *pair_lin,
                                        const int *slot_lin, int from, int to, double (*f)[3],
                                        double (*H)[9], double (*Hbar)[9])
{
  int q = from;
  for (; q + 4 <= to; q += 4) {
    const long c[4] = {cells[q], cells[q + 1], cells[q + 2], cells[q + 3]};
    NOSPD::stencil_forces<DIM, 4, ONE>(st, u, c, pair_lin, f + (q - from));
  }
  for (; q + 2 <= to; q += 2) {
    const long c[2] = {cells[q], cells[q + 1]};
    NOSPD::stencil_forces<DIM, 2, ONE>(st, u, c, pair_lin, f + (q - from));
  }
  if (q < to) {
    const long c[1] = {cells[q]};
    NOSPD::stencil_forces<DIM, 1, ONE>(st, u, c, pair_lin, f + (q - from));
  }
  for (q = from; q < to; q++)
    NOSPD::stencil_family<DIM, ONE>(st, u, cells[q], slot_lin, H[q - from], Hbar[q - from]);
}
}    // namespace

/* ---------------------------------------------------------------------- */

PairPeriNospdHS::PairPeriNospdHS(LAMMPS *lmp) :
    PairPeriNospd(lmp), hs_form(HSForm::II), hs_ratio(1.0), mapped_version(-1),
    nsingular_bonds(0), nfallback_states(0), reported(false), nmax_ghost(0), fghost(nullptr),
    vghost(nullptr), reverse_virial(0), nbig(0), stencil_on(true), nstencil_all(0),
    comm_mode(0), stencils_stale(false), first_point_mapping(true), stab_on(false)
{
  if (lmp->citeme) lmp->citeme->add(cite_nospd_hs);
  stab = NOSPD::Stab::NONE;
  comm_forward = 0;
  comm_reverse = 9;    // force, and the per-atom virial when it is wanted
  // compute pair: bond families on the singular-K fallback, points on the
  // stencil
  nextra = 2;
  pvector = new double[nextra];
  pvector[0] = pvector[1] = 0.0;
}

/* ---------------------------------------------------------------------- */

PairPeriNospdHS::~PairPeriNospdHS()
{
  restore_ghost_cutoff();    // comm outlives the pair style (LAMMPS::destroy)
  delete[] pvector;
  memory->destroy(fghost);
  memory->destroy(vghost);
}

/* ----------------------------------------------------------------------
   pair_style peri/nospd/hs keyword value ...
   form I|II and ratio r here; the classical style's keywords pass on.
   The bond-associated forces resist zero-energy modes by themselves, so
   the default is no stabilization; "stabilization silling G" (or
   "hourglass C") adds the classical style's term on the families' F (for
   damaged bodies, whose sparse bond-associated families lose that
   resistance); "wan" is an error.
------------------------------------------------------------------------- */

void PairPeriNospdHS::settings(int narg, char **arg)
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  std::vector<char *> rest;
  bool stabilized = false;    // silling or hourglass given
  // defaults again for a repeated pair_style command (see the base class)
  hs_form = HSForm::II;
  hs_ratio = 1.0;
  stencil_on = true;
  int iarg = 0;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg) {
      rest.push_back(arg[iarg++]);    // the classical parser reports the missing value
      continue;
    }
    const std::string val = arg[iarg + 1];
    if (key == "form") {
      if (val == "I" || val == "1") hs_form = HSForm::I;
      else if (val == "II" || val == "2") hs_form = HSForm::II;
      else error->all(FLERR, "{}: unknown form '{}' (I, II)", cmd, val);
    } else if (key == "stencil") {
      if (val != "yes" && val != "no")
        error->all(FLERR, "{}: stencil must be yes or no, got '{}'", cmd, val);
      stencil_on = val == "yes";
    } else if (key == "ratio") {
      hs_ratio = NOSPD_INPUT::real(error, cmd, key, val);
      if (!(hs_ratio > 0.0))
        error->all(FLERR, "{}: ratio must be > 0, got {}", cmd, val);
    } else if (key == "stabilization") {
      if (val == "silling" || val == "hourglass") {
        // the classical parser reads G (and reports a missing value)
        rest.push_back(arg[iarg]);
        rest.push_back(arg[iarg + 1]);
        if (iarg + 2 < narg) rest.push_back(arg[iarg + 2]);
        stabilized = true;
        iarg += 3;
        continue;
      }
      if (val != "none")
        error->all(FLERR, "{}: the bond-associated model controls zero-energy modes by itself; "
                   "stabilization must be none, silling G or hourglass C, got '{}'", cmd, val);
      stabilized = false;
    } else if (key == "stabilization/fit") {
      // even "linear": the keyword means nothing here, and a deck moved
      // over from peri/nospd should learn that rather than keep it silently
      error->all(FLERR, "{}: stabilization/fit is a keyword of peri/nospd (the "
                 "bond-associated deformation gradients need no springs)", cmd);
    } else {
      rest.push_back(arg[iarg]);
      rest.push_back(arg[iarg + 1]);
    }
    iarg += 2;
  }
  PairPeriNospd::settings((int) rest.size(), rest.data());
  stab_on = stabilized;
  if (!stab_on) stab = NOSPD::Stab::NONE;
  // new settings may change every pattern (and with them the stencils)
  patterns.clear();
  pattern_lookup.clear();
  mapped_version = -1;
  stencil_law.clear();
}

/* ---------------------------------------------------------------------- */

std::string PairPeriNospdHS::not_a_potential() const
{
  if (hs_form == NOSPD::HSForm::I) return "form I is not a potential";
  return PairPeriNospd::not_a_potential();
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::init_style()
{
  PairPeriNospd::init_style();
  // the bond-associated families take their plastic state per bond through
  // nospd_bond_history.h, which knows J2 and Johnson-Cook only so far
  for (int i = 1; i <= atom->ntypes; i++)
    if (active[i] && drucker_prager[i].active)
      error->all(FLERR, "pair_style {}: type {} has drucker_prager, which the bond-associated "
                 "style does not offer yet (its per-bond plastic state is J2's); use pair_style "
                 "peri/nospd", force->pair_style, i);
  // inelastic materials: a point history per family and a state per bond
  // (nospd_bond_history.h); a UMAT's family row is a UmatHist entry of
  // sums and means, then that of the whole family's F
  const int umat_size = user_materials->history_size();
  for (int i = 1; i <= atom->ntypes; i++) {
    if (has_history(i))
      fix_bonds->set_history_size(NOSPD::FamilyHist::SIZE, NOSPD::BondHist::SIZE);
    if (is_umat(i)) fix_bonds->set_history_size(2 * umat_size, umat_size);
  }
  // the classical B (H) and s travel with a stabilization; the stencil's
  // keys and flags at least
  if (!stab_on) comm_forward = 0;
  comm_forward = MAX(comm_forward, 1);
  raise_hybrid_comm_forward();
  mapped_version = -1;
  reported = false;
  linear_law.assign(atom->ntypes + 1, NOSPD::LinearLaw());
  for (int i = 1; i <= atom->ntypes; i++)
    linear_law[i] = NOSPD::probe_linear_law(strain_law, plane_mode, lame[i], domain->dimension);
  // the stencils anew where the law they were built for changed (a
  // pair_coeff, new settings); else kept, so that each run command does not
  // build them again (seconds on a large grid)
  const std::vector<double> law = stencil_law_signature();
  if (law != stencil_law) {
    pattern_stencils.clear();
    point_stencils.clear();
    first_point_mapping = true;
    stencil_law = law;
  }
  ghosts_for_stencil();
}

/* what the stencils of a pattern and type are a function of, besides the
   pattern: the form, the strain law and plane, and each type's material */

std::vector<double> PairPeriNospdHS::stencil_law_signature() const
{
  std::vector<double> sig = {(double) hs_form, hs_ratio, (double) strain_law,
                             (double) plane_mode, (double) domain->dimension};
  for (int i = 1; i <= atom->ntypes; i++) {
    const NOSPD::Lame &m = lame[i];
    const NOSPD::LinearLaw &l = linear_law[i];
    sig.insert(sig.end(), {(double) active[i], m.lambda, m.mu, m.lambda_ps, (double) l.ok, l.lam,
                           l.mu, cut[i][i]});
  }
  return sig;
}

/* ----------------------------------------------------------------------
   give back the user's communication cutoff where this style raised it
   and nobody changed it since (a later run without the stencil, another
   pair style)
------------------------------------------------------------------------- */

void PairPeriNospdHS::restore_ghost_cutoff()
{
  if (cutghost_raised < 0.0) return;
  if (comm->cutghostuser == cutghost_raised) comm->cutghostuser = cutghost_replaced;
  cutghost_raised = cutghost_replaced = -1.0;
}

/* ----------------------------------------------------------------------
   The stencil reads the displacements within 2 delta of a point.  Ghosts
   reach delta plus the skin by default: the points within 2 delta of a
   subdomain's edge, or a periodic box's, would then take their families,
   about eight times the cost (on 2 ranks, half the block).  Where the
   stencil can apply, raise the communication cutoff to 2 delta plus the
   skin, as LAMMPS's styles that need far ghosts do, and say so.
------------------------------------------------------------------------- */

void PairPeriNospdHS::ghosts_for_stencil()
{
  bool linear = false;
  double delta_max = 0.0;
  for (int i = 1; i <= atom->ntypes; i++) {
    linear = linear || linear_law[i].ok;
    for (int j = i; j <= atom->ntypes; j++) delta_max = MAX(delta_max, cut[i][j]);
  }
  const bool edges =
      comm->nprocs > 1 || domain->xperiodic || domain->yperiodic || domain->zperiodic;
  restore_ghost_cutoff();    // decided anew each run: the settings may have changed
  if (!stencil_on || !linear || !edges || user_law() || fix_bonds->nhistory > 0) return;
  const double need = 2.0 * delta_max + neighbor->skin;
  if (comm->get_comm_cutoff() >= need) return;
  cutghost_replaced = comm->cutghostuser;
  cutghost_raised = need;
  comm->cutghostuser = need;
  if (comm->me == 0)
    error->warning(FLERR,
                   "pair_style {}: increasing the communication cutoff to {:.8} (2 delta plus "
                   "the skin), so that points near subdomain edges take the linear law's "
                   "stencil; 'stencil no' keeps the default cutoff",
                   force->pair_style, need);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (mapped_version != fix_bonds->bond_version || (int) state_pattern.size() != atom->nlocal)
    map_families();

  // forces and per-atom virial landing on ghosts; the virial buffer only
  // when a per-atom virial is wanted
  const int nall = atom->nlocal + atom->nghost;
  reverse_virial = vflag_atom ? 1 : 0;
  grow_ghost_buffers();
  if (nall && reverse_virial) memset(&vghost[0][0], 0, sizeof(double) * 6 * nall);

  // the stabilization first: it needs the families' F, which the
  // bond-associated pass then overwrites with its own output
  if (stab_on) stabilization_pass(eflag);

  if (fix_bonds->nhistory) {
    grow_work();
    fill_base_temperature();
  }
  const bool virial = vflag_either;
  // the stencil knows no energy and no virial: steps that want them take
  // the families of every point
  if (stencils_stale && !eflag && !virial) map_stencils();
  const bool on_stencil_step = nstencil_all > 0 && !eflag && !virial;
  if (domain->dimension == 2)
    virial ? force_pass<2, 1>(eflag, false) : force_pass<2, 0>(eflag, on_stencil_step);
  else virial ? force_pass<3, 1>(eflag, false) : force_pass<3, 0>(eflag, on_stencil_step);
  if (on_stencil_step) stencil_pass();
  if (fix_bonds->nhistory) fix_bonds->trial_history_ready();
  if (stab == NOSPD::Stab::SILLING && eflag)
    for (int i = 0; i < atom->nlocal; i++) fix_bonds->energy_density[i] += stab_energy[i];

  // forces (and virial) scattered onto ghosts go home
  comm->reverse_comm(this);
  double **f = atom->f;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) f[i][k] += fghost[i][k];
  if (reverse_virial)
    for (int i = 0; i < nlocal; i++)
      for (int k = 0; k < 6; k++) vatom[i][k] += vghost[i][k];
}

/* fghost (and vghost where wanted) for every owned and ghost atom, zeroed */

void PairPeriNospdHS::grow_ghost_buffers()
{
  if (atom->nmax > nmax_ghost) {
    nmax_ghost = atom->nmax;
    memory->destroy(fghost);
    memory->destroy(vghost);
    memory->create(fghost, nmax_ghost, 3, "pair:fghost");
  }
  if (reverse_virial && !vghost) memory->create(vghost, nmax_ghost, 6, "pair:vghost");
  const int nall = atom->nlocal + atom->nghost;
  if (nall) memset(&fghost[0][0], 0, sizeof(double) * 3 * nall);
}

/* ----------------------------------------------------------------------
   The rows of the stable time step's stiffness bound (the bonds fix's
   bound_stable_timesteps, which adds the stabilization's springs): each
   family adds |C| rows[n] of its pattern (NOSPD::family_row_bounds) to its
   centre and (V_i / V_k) |C| rows[k] to member k, ghosts included; the
   ghosts' shares go home as the forces do.  Linearized at the reference:
   the families of the current mapping, elastic.
------------------------------------------------------------------------- */

void PairPeriNospdHS::bound_family_rows(std::vector<double> &rows)
{
  if (mapped_version != fix_bonds->bond_version || (int) state_pattern.size() != atom->nlocal)
    map_families();
  reverse_virial = 0;
  grow_ghost_buffers();
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  const double *vfrac = atom->vfrac;
  std::vector<std::vector<double>> pattern_rows(patterns.size());
  for (int i = 0; i < nlocal; i++) {
    const int pat = state_pattern[i];
    const double cn = stress_norm[type[i]];
    if (pat < 0 || !(cn > 0.0)) continue;
    const BondPattern &p = patterns[pat];
    std::vector<double> &r = pattern_rows[pat];
    if (r.empty()) {
      if (domain->dimension == 2) NOSPD::family_row_bounds<2>(p, hs_form, r);
      else NOSPD::family_row_bounds<3>(p, hs_form, r);
    }
    fghost[i][0] += cn * r[p.n];
    const int *bj = fix_bonds->bond_j + fix_bonds->bond_first[i];
    const uint16_t *perm = &state_perm[state_first[i]];
    for (int s = 0; s < p.n; s++) {
      const int j = bj[perm[s]];
      fghost[j][0] += cn * r[s] * vfrac[i] / vfrac[j];
    }
  }
  comm->reverse_comm(this);
  rows.resize(nlocal);
  for (int i = 0; i < nlocal; i++) rows[i] = fghost[i][0];
}

/* ----------------------------------------------------------------------
   Gather the displacement differences U of i's family in pattern order
   into ubuf[lane], and the partners' local indices into jbuf[lane].
------------------------------------------------------------------------- */

void PairPeriNospdHS::gather_family(int i, const BondPattern &p, const uint16_t *perm,
                                    FamilyWork &w, int lane)
{
  const double *const xf = atom->x[0];
  const double *const x0f = fix_bonds->x0s[0];
  const int *bj = fix_bonds->bond_j + fix_bonds->bond_first[i];
  const double xi = xf[3 * i], yi = xf[3 * i + 1], zi = xf[3 * i + 2];
  const double Xi = x0f[3 * i], Yi = x0f[3 * i + 1], Zi = x0f[3 * i + 2];
  double *u = w.ubuf[lane].data();
  int *jl = w.jbuf[lane].data();
  if (fix_bonds->nhist_bond) {
    const int *bs = fix_bonds->bond_slot + fix_bonds->bond_first[i];
    int *sl = w.sbuf[lane].data();
    for (int s = 0; s < p.n; s++) sl[s] = bs[perm[s]];
  }
  for (int s = 0; s < p.n; s++) {
    const int j = bj[perm[s]];
    jl[s] = j;
    u[3 * s] = (xf[3 * j] - xi) - (x0f[3 * j] - Xi);
    u[3 * s + 1] = (xf[3 * j + 1] - yi) - (x0f[3 * j + 1] - Yi);
    u[3 * s + 2] = (xf[3 * j + 2] - zi) - (x0f[3 * j + 2] - Zi);
  }
}

/* ----------------------------------------------------------------------
   Families are evaluated two at a time where two atoms share a pattern
   (the lanes of evaluate_families), else one at a time.
------------------------------------------------------------------------- */

template <int DIM, int VIRIAL> void PairPeriNospdHS::force_pass(int eflag, bool stencil_step)
{
  // a formula law keeps scratch space: one thread
  const int nlocal = atom->nlocal;
  prepare_work(comm->nthreads, nlocal + atom->nghost);
  const std::vector<int> &order = stencil_step ? family_order : state_order;
  if (stencil_step) {
    // (stencil steps have no virial: no masked pass with one is built)
    if (!VIRIAL)
      for_ranges((int) order.size(), !user_law(), [&](int from, int to, int tid, Tally &t) {
        force_range<DIM, 0, true>(order.data(), from, to, tid, eflag, t);
      });
  } else {
    for_ranges((int) order.size(), !user_law(), [&](int from, int to, int tid, Tally &t) {
      force_range<DIM, VIRIAL, false>(order.data(), from, to, tid, eflag, t);
    });
  }
  // the other threads' scatter, added in thread order
  double *fg = fghost[0];
  const int nall = nlocal + atom->nghost;
  for (size_t tid = 1; tid < work.size(); tid++) {
    if (!work[tid].used) continue;
    const double *g = work[tid].fg.data();
    for (int k = 0; k < 3 * nall; k++) fg[k] += g[k];
    if (VIRIAL && vflag_atom) {
      const double *gv = work[tid].vg.data();
      double *vg = vghost[0];
      for (int k = 0; k < 6 * nall; k++) vg[k] += gv[k];
    }
  }
}

/* ----------------------------------------------------------------------
   the families of order[from..to) by thread tid; MASKED: no force onto
   the points on the stencil
------------------------------------------------------------------------- */

template <int DIM, int VIRIAL, bool MASKED>
void PairPeriNospdHS::force_range(const int *order, int from, int to, int tid, int eflag,
                                  Tally &t)
{
  // two lanes pay in 2D, where a family's rows are short; in 3D the rows
  // of two families no longer fit the L1 cache and one lane is faster
  constexpr int LANES = DIM == 2 ? 2 : 1;
  const int *type = atom->type;
  FamilyWork &w = work[tid];
  w.used = true;
  const int nall = atom->nlocal + atom->nghost;
  double *fg = fghost[0];
  double *vg = (VIRIAL && vflag_atom) ? vghost[0] : nullptr;
  if (tid > 0) {
    std::fill(w.fg.begin(), w.fg.begin() + 3 * nall, 0.0);
    fg = w.fg.data();
    if (vg) {
      std::fill(w.vg.begin(), w.vg.begin() + 6 * nall, 0.0);
      vg = w.vg.data();
    }
  }
  NOSPD::StateOutput out[2];
  NOSPD::LaneInput in[2];
  LaneLaws laws[2];
  const int nhist = fix_bonds->nhistory;
  const bool minimizing = (update->whichflag == 2);
  for (int q = from; q < to;) {
    const int i0 = order[q];
    const BondPattern &p = patterns[state_pattern[i0]];
    const int lanes = (LANES == 2 && q + 1 < to &&
                       state_pattern[order[q + 1]] == state_pattern[i0]) ? 2 : 1;
    int atoms[2] = {i0, lanes == 2 ? order[q + 1] : -1};
    for (int l = 0; l < lanes; l++) {
      const int i = atoms[l];
      gather_family(i, p, &state_perm[state_first[i]], w, l);
      in[l].m = &lame[type[i]];
      in[l].lin = &linear_law[type[i]];
      in[l].U = w.ubuf[l].data();
      in[l].t = w.tbuf[l].data();
      laws[l].active = nullptr;
      if (nhist) begin_history(i, p, w, l, laws[l]);
      in[l].bond_law = laws[l].active;
    }
    const bool ok = lanes == 2
        ? evaluate<DIM, 2>(p, hs_form, strain_law, plane_mode, in, eflag != 0, w.scratch, out)
        : evaluate<DIM, 1>(p, hs_form, strain_law, plane_mode, in, eflag != 0, w.scratch, out);
    for (int l = 0; l < lanes; l++) {
      if (!ok && laws[l].active) family_failure(atoms[l], laws[l], out[l].F);
      if (!ok && out[l].bad != -2)
        bond_failure(atoms[l], out[l], out[l].bad >= 0 ? atom->tag[w.jbuf[l][out[l].bad]] : 0);
      apply_family<VIRIAL, MASKED>(atoms[l], p, w, l, fg, vg, out[l], eflag, t);
      if (laws[l].active && !p.atom_singular) finish_history(atoms[l], laws[l], eflag, minimizing, t);
    }
    q += lanes;
  }
}

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
  if (has_history(itype)) {
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
  } else if (is_umat(itype)) {
    NOSPD::FamilyUmat &law = laws.umat;
    law.mat = &user_materials->umat(itype);
    law.pt = umat_env(i);
    law.fallback = user_materials->history_size();
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
}

/* ----------------------------------------------------------------------
   the family row of owned atom i after its bonds; during minimize the
   energy of a plastic point is the step's incremental potential, as in
   the classical style
------------------------------------------------------------------------- */

void PairPeriNospdHS::finish_history(int i, LaneLaws &laws, int eflag, bool minimizing, Tally &t)
{
  if (laws.active == &laws.umat) {
    laws.umat.finish();
    return;
  }
  laws.plastic.finish();
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
  if (laws.active == &laws.umat) {
    if (laws.umat.status != NOSPD::UmatStatus::OK) umat_failure(i, laws.umat.status, F);
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
   per-thread work spaces: scratch and lanes for the largest family, and
   scatter buffers for the threads after the first
------------------------------------------------------------------------- */

void PairPeriNospdHS::prepare_work(int nthreads, int nall)
{
  if ((int) work.size() < std::max(1, nthreads)) work.resize(std::max(1, nthreads));
  for (size_t tid = 0; tid < work.size(); tid++) {
    FamilyWork &w = work[tid];
    w.used = false;
    for (int l = 0; l < 2; l++)
      if ((int) w.ubuf[l].size() < 3 * nbig) {
        w.ubuf[l].assign(3 * nbig, 0.0);
        w.tbuf[l].assign(3 * nbig, 0.0);
        w.jbuf[l].assign(nbig, 0);
        w.sbuf[l].assign(nbig, 0);
      }
    if (tid == 0) continue;
    if ((int) w.fg.size() < 3 * nall) w.fg.resize(3 * nall);
    if (reverse_virial && (int) w.vg.size() < 6 * nall) w.vg.resize(6 * nall);
  }
}

/* ----------------------------------------------------------------------
   The classical style's stabilization on the families' F, H = F - I:
   silling:   f_i += sum_j w (-(s_i H_i + s_j H_j) xi + (s_i + s_j) U),
              energy 1/2 s sum_j w |U - H xi|^2 per atom;
   hourglass: the force along each bond against its non-affine part (no
              energy).
   It acts on what the bond-associated forces leave free in sparse,
   damaged families; on a homogeneous deformation it vanishes
   (U = H xi), so the patch test and the bulk stress are those of the
   bond-associated model.
------------------------------------------------------------------------- */

void PairPeriNospdHS::stabilization_pass(int eflag)
{
  const bool silling = (stab == NOSPD::Stab::SILLING);
  grow_work();
  double **mom = eflag ? moments : nullptr;
  positions = fix_bonds->padded_positions();
  for_ranges(atom->nlocal, true, [&](int from, int to, int, Tally &) {
    fix_bonds->compute_deformation(positions, mom, from, to);
  });
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  if (eflag) stab_energy.assign(nlocal, 0.0);
  for (int i = 0; i < nlocal; i++) {
    if (fix_bonds->singular[i]) {
      for (int k = 0; k < NOSPD::BREC; k++) bmat[i][k] = 0.0;
      continue;
    }
    const double s = stab_scalar[type[i]];
    const Mat3 H = NOSPD::load(fix_bonds->defgrad[i]) - Mat3::Identity();
    bmat[i][STAB_SCALAR] = s;
    if (!silling) {
      NOSPD::store(Mat3::Zero(), bmat[i]);
      store_transposed(Mat3(s * H), tmat[i]);    // the hourglass pass reads c H
      continue;
    }
    store_transposed(Mat3(-s * H), bmat[i]);
    if (eflag) {
      // 1/2 s sum_j w |z|^2
      stab_energy[i] = 0.5 * s * nonaffine_moment(i, H, NOSPD::load(fix_bonds->kinv[i])).trace();
      tally_energy(i, stab_energy[i]);
    }
  }
  comm->forward_comm(this);
  if (silling) vflag_either ? PairPeriNospd::force_pass<NOSPD::StabPass::SILLING, 1>(eflag)
                            : PairPeriNospd::force_pass<NOSPD::StabPass::SILLING, 0>(eflag);
  else vflag_either ? PairPeriNospd::force_pass<NOSPD::StabPass::HOURGLASS, 1>(eflag)
                    : PairPeriNospd::force_pass<NOSPD::StabPass::HOURGLASS, 0>(eflag);
}

/* ----------------------------------------------------------------------
   Store one family's state for output and apply its force state:
     f_i += w_k t_k,   f_k -= (V_i/V_k) w_k t_k,   T_i<xi_k> = omega_k t_k
   (force densities: the true forces V_i w_k t_k are equal and opposite).
   Per-atom virial: half of each pair's r (x) f to either end.
------------------------------------------------------------------------- */

template <int VIRIAL, bool MASKED>
void PairPeriNospdHS::apply_family(int i, const BondPattern &p, FamilyWork &wk, int lane,
                                   double *fg, double *vg, const NOSPD::StateOutput &out,
                                   int eflag, Tally &tally)
{
  double **x = atom->x;
  const double *const vfrac = atom->vfrac;
  const double *const inv_vol = inv_vfrac.data();
  if (p.atom_singular) {
    // no force state of its own, as in the classical style
    NOSPD::store(Mat3::Identity(), fix_bonds->defgrad[i]);
    NOSPD::store(Mat3::Zero(), fix_bonds->pk1[i]);
    fix_bonds->energy_density[i] = 0.0;
    return;
  }
  NOSPD::store(out.F, fix_bonds->defgrad[i]);
  NOSPD::store(out.P, fix_bonds->pk1[i]);
  if (eflag) {
    fix_bonds->energy_density[i] = out.W;
    tally_energy(i, out.W, tally);
  }

  const int n = p.n;
  const double vi = vfrac[i];
  const double *t = wk.tbuf[lane].data();
  const int *jl = wk.jbuf[lane].data();
  const double *w = p.w.data();
  const char *skip = on_stencil.data();
  double fx = 0.0, fy = 0.0, fz = 0.0;
  double v[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int s = 0; s < n; s++) {
    const int j = jl[s];
    const double gx = w[s] * t[3 * s], gy = w[s] * t[3 * s + 1], gz = w[s] * t[3 * s + 2];
    fx += gx;
    fy += gy;
    fz += gz;
    if (MASKED && skip[j]) continue;
    const double r = vi * inv_vol[j];
    fg[3 * j] -= r * gx;
    fg[3 * j + 1] -= r * gy;
    fg[3 * j + 2] -= r * gz;
    if (VIRIAL) {
      // r (x) F with r = x_i - x_j, half to each end
      const double hx = 0.5 * (x[i][0] - x[j][0]), hy = 0.5 * (x[i][1] - x[j][1]),
                   hz = 0.5 * (x[i][2] - x[j][2]);
      const double vij[6] = {hx * gx, hy * gy, hz * gz, hx * gy, hx * gz, hy * gz};
      for (int k = 0; k < 6; k++) v[k] += vij[k];
      if (vflag_global)
        for (int k = 0; k < 6; k++) tally.virial[k] += r * vij[k];
      if (vflag_atom)
        for (int k = 0; k < 6; k++) vg[6 * j + k] += r * vij[k];
    }
  }
  if (MASKED && skip[i]) return;
  add_force_virial(i, fx, fy, fz, v, VIRIAL, tally);
}

/* ----------------------------------------------------------------------
   Assign every owned atom's family to a pattern, after the bonds fix
   rebuilt its arrays (reneighboring, broken bonds).  The order of an
   atom's bonds in those arrays is fixed while no bond of it breaks, so
   an atom found at the same index with as many bonds as before keeps its
   pattern and slot order, once the weights still match; the others are
   matched afresh.  Patterns nobody uses any more are dropped.
------------------------------------------------------------------------- */

void PairPeriNospdHS::map_families()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  const int *bfirst = fix_bonds->bond_first;
  const double *bw = fix_bonds->bond_w;
  const int *type = atom->type;

  std::vector<int> npat(nlocal), nfirst(nlocal + 1), ncount(nlocal);
  std::vector<tagint> ntag(nlocal);
  std::vector<uint16_t> nperm;
  nperm.reserve(bfirst[nlocal]);
  std::vector<uint16_t> perm;
  const int nold = (int) state_pattern.size();
  for (int i = 0; i < nlocal; i++) {
    const int cnt = bfirst[i + 1] - bfirst[i];
    nfirst[i] = (int) nperm.size();
    ncount[i] = cnt;
    ntag[i] = tag[i];
    bool keep = mapped_version >= 0 && i < nold && state_tag[i] == tag[i] &&
        state_count[i] == cnt && state_pattern[i] >= 0;
    if (keep) {
      const BondPattern &p = patterns[state_pattern[i]];
      keep = p.radius == hs_ratio * cut[type[i]][type[i]];
      const uint16_t *op = &state_perm[state_first[i]];
      for (int s = 0; keep && s < cnt; s++)
        keep = std::abs(bw[bfirst[i] + op[s]] - p.w[s]) <= WEIGHT_TOL * p.w[s];
      if (keep) {
        npat[i] = state_pattern[i];
        nperm.insert(nperm.end(), op, op + cnt);
        continue;
      }
    }
    npat[i] = match_pattern(i, perm);
    nperm.insert(nperm.end(), perm.begin(), perm.end());
  }
  nfirst[nlocal] = (int) nperm.size();

  // drop unused patterns and renumber
  std::vector<int> users(patterns.size(), 0), renum(patterns.size(), -1);
  for (int i = 0; i < nlocal; i++) users[npat[i]]++;
  std::vector<BondPattern> kept;
  std::vector<std::map<int, NOSPD::Stencil>> kept_stencils;
  pattern_stencils.resize(patterns.size());
  pattern_lookup.clear();
  for (size_t k = 0; k < patterns.size(); k++) {
    if (!users[k]) continue;
    renum[k] = (int) kept.size();
    kept.push_back(std::move(patterns[k]));
    kept_stencils.push_back(std::move(pattern_stencils[k]));
  }
  patterns.swap(kept);
  pattern_stencils.swap(kept_stencils);
  for (size_t k = 0; k < patterns.size(); k++)
    pattern_lookup.emplace(key_hash(patterns[k].key), (int) k);
  for (int i = 0; i < nlocal; i++) npat[i] = renum[npat[i]];

  state_pattern.swap(npat);
  state_first.swap(nfirst);
  state_count.swap(ncount);
  state_tag.swap(ntag);
  state_perm.swap(nperm);
  mapped_version = fix_bonds->bond_version;

  // 1/V of owned and ghost atoms, for the partners' share of each force
  const int nall = nlocal + atom->nghost;
  inv_vfrac.resize(nall);
  for (int i = 0; i < nall; i++) inv_vfrac[i] = 1.0 / atom->vfrac[i];

  // evaluation order: atoms grouped by pattern, so that neighbours in the
  // order can share an evaluation
  std::vector<int> start(patterns.size() + 1, 0);
  for (int i = 0; i < nlocal; i++) start[state_pattern[i] + 1]++;
  for (size_t k = 0; k < patterns.size(); k++) start[k + 1] += start[k];
  state_order.assign(nlocal, 0);
  for (int i = 0; i < nlocal; i++) state_order[start[state_pattern[i]]++] = i;

  // scratch for the largest family (prepare_work sizes each thread's)
  nbig = 0;
  for (auto &p : patterns) nbig = std::max(nbig, p.n);
  prepare_work(1, 0);
  // sum programs for the patterns many families share
  for (size_t k = 0; k < users.size(); k++) {
    if (users[k] < PROGRAM_USERS) continue;
    BondPattern &p = patterns[renum[k]];
    if (!p.program.ready()) p.program = NOSPD::build_sum_program(NOSPD::member_sets(p), p.n);
  }

  // bond families that fall back to the family's F
  bigint nsing = 0, nfall = 0;
  for (int i = 0; i < nlocal; i++) {
    const BondPattern &p = patterns[state_pattern[i]];
    if (p.atom_singular) continue;
    nsing += p.nsingular;
    nfall += p.nsingular ? 1 : 0;
  }
  pvector[0] = (double) nsing;
  MPI_Allreduce(&nsing, &nsingular_bonds, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Allreduce(&nfall, &nfallback_states, 1, MPI_LMP_BIGINT, MPI_SUM, world);

  // the stencils: now on a run's first mapping (its log line counts
  // them), else before the next step that can use them (damage remaps
  // often, and some decks want energy or virial on every step)
  if (!reported) map_stencils();
  else {
    stencils_stale = true;
    nstencil_all = 0;
  }

  if (!reported) {
    report_patterns();
    reported = true;
  }
}

/* ----------------------------------------------------------------------
   The stencil of a pattern under a type's law, built on first use; null
   where the law or the pattern has none (nospd_stencil.h)
------------------------------------------------------------------------- */

const NOSPD::Stencil *PairPeriNospdHS::stencil_for(int pattern, int type)
{
  auto &byType = pattern_stencils[pattern];
  auto it = byType.find(type);
  if (it == byType.end()) {
    const BondPattern &p = patterns[pattern];
    NOSPD::Stencil st = domain->dimension == 2
        ? NOSPD::build_stencil<2>(p, hs_form, strain_law, plane_mode, lame[type], linear_law[type])
        : NOSPD::build_stencil<3>(p, hs_form, strain_law, plane_mode, lame[type], linear_law[type]);
    it = byType.emplace(type, std::move(st)).first;
    nstencils_built++;
  }
  return it->second.ok ? &it->second : nullptr;
}

/* ----------------------------------------------------------------------
   Owned and ghost atoms on a lattice of spacings h, by their reference
   positions: cell_grid maps a cell to its atom (-1 none, -2 two atoms).
   coords receives each atom's cell (INT_MIN off the lattice).  False if
   the grid would be much larger than the atoms (bodies far apart).
------------------------------------------------------------------------- */

bool PairPeriNospdHS::build_cell_grid(const double *h, std::vector<std::array<int, 3>> &coords,
                                      long stride[3])
{
  const int nall = atom->nlocal + atom->nghost;
  double **x0s = fix_bonds->x0s;
  const int dim = domain->dimension;
  coords.assign(nall, {INT_MIN, INT_MIN, INT_MIN});
  int lo[3] = {INT_MAX, INT_MAX, INT_MAX}, hi[3] = {INT_MIN, INT_MIN, INT_MIN};
  for (int a = 0; a < nall; a++) {
    std::array<int, 3> c = {0, 0, 0};
    bool on = true;
    for (int k = 0; k < dim && on; k++) {
      const double q = (x0s[a][k] - x0s[0][k]) / h[k];
      on = std::abs(q) < 1.0e9 && std::abs(q - std::nearbyint(q)) <= 1.0e-6;
      if (on) c[k] = (int) std::nearbyint(q);
    }
    if (!on) continue;
    coords[a] = c;
    for (int k = 0; k < 3; k++) {
      lo[k] = MIN(lo[k], c[k]);
      hi[k] = MAX(hi[k], c[k]);
    }
  }
  if (lo[0] > hi[0]) return false;
  double cells = 1.0;
  for (int k = 0; k < 3; k++) cells *= (double) (hi[k] - lo[k] + 1);
  if (cells > 8.0 * nall + 4096.0) return false;
  stride[0] = 1;
  stride[1] = hi[0] - lo[0] + 1;
  stride[2] = stride[1] * (hi[1] - lo[1] + 1);
  cell_grid.assign((size_t) cells, -1);
  cell_of.assign(nall, -1);
  for (int a = 0; a < nall; a++) {
    if (coords[a][0] == INT_MIN) continue;
    for (int k = 0; k < 3; k++) coords[a][k] -= lo[k];
    cell_of[a] = coords[a][0] + stride[1] * coords[a][1] + stride[2] * coords[a][2];
    int &cell = cell_grid[cell_of[a]];
    cell = cell == -1 ? a : -2;
  }
  return true;
}

/* ----------------------------------------------------------------------
   Which owned atoms take the stencil, after the families were mapped: an
   atom whose pattern (shared by >= PROGRAM_USERS families) has a stencil,
   whose every partner has the same pattern, type and volume (a key that
   travels to ghosts), and whose cells within 2 delta are all there.  The
   families that only feed such atoms are not evaluated on stencil steps.
------------------------------------------------------------------------- */

void PairPeriNospdHS::map_stencils()
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  stencils_stale = false;
  std::vector<int> users(patterns.size(), 0);
  for (int i = 0; i < nlocal; i++) users[state_pattern[i]]++;
  const int *type = atom->type;
  const double *vfrac = atom->vfrac;
  stencil_runs.clear();
  stencil_blocks.clear();
  cell_grid.clear();
  cell_of.clear();
  on_stencil.assign(nall, 0);
  family_order = state_order;
  bigint nlocal_on = 0;
  const bool possible = stencil_on && fix_bonds->nhistory == 0 && !user_law();
  if (!possible) {
    nstencil_all = 0;
    pvector[1] = 0.0;
    return;
  }

  // every owned atom's family key, and its inside stencil; the keys go to
  // the ghosts.  A key hashes the pattern's shape and weights and the type
  // into 52 bits, so that a double holds it exactly.  family_of: key ->
  // (pattern, type) of the families owned here ((-1, -1) for two that
  // share a key).  A collision of keys between ranks would go unseen; at
  // 52 bits over a few thousand patterns its chance is below 1e-8.
  std::vector<const NOSPD::Stencil *> st_of(nlocal, nullptr);
  stencil_key.assign(nall, 0.0);
  std::map<std::pair<int, int>, double> key_of;
  std::map<double, std::pair<int, int>> family_of;
  for (int i = 0; i < nlocal; i++) {
    const int k = state_pattern[i];
    auto it = key_of.find({k, type[i]});
    if (it == key_of.end()) {
      BondPattern &p = patterns[k];
      if (!p.shape_hash) {
        std::vector<int64_t> key = p.key;
        for (double w : p.w) key.push_back(std::llround(std::log(w) * 1.0e9));
        // (a family kept singular for good has tol infinity)
        key.push_back(std::isfinite(p.tol) ? std::llround(std::log(p.tol) * 1.0e9) : INT64_MAX);
        p.shape_hash = key_hash(key) | 1;
      }
      const uint64_t h = key_hash({(int64_t) p.shape_hash, (int64_t) type[i]});
      it = key_of.emplace(std::make_pair(k, type[i]), (double) ((h >> 12) | 1)).first;
      auto ins = family_of.emplace(it->second, std::make_pair(k, type[i]));
      if (!ins.second) ins.first->second = {-1, -1};
    }
    stencil_key[i] = it->second;
    if (users[k] >= PROGRAM_USERS) st_of[i] = stencil_for(k, type[i]);
  }
  comm_mode = 1;
  comm->forward_comm(this);

  // the cell grid on the lattice of the first stencil, else of the most
  // common pattern (a body thinner than 4 delta has no inside)
  const NOSPD::Stencil *first = nullptr;
  for (int i = 0; i < nlocal && !first; i++) first = st_of[i];
  double h[3] = {0.0, 0.0, 0.0};
  bool lattice = first != nullptr;
  if (first) std::copy_n(first->h, 3, h);
  else if (!patterns.empty()) {
    const int k = (int) (std::max_element(users.begin(), users.end()) - users.begin());
    lattice = domain->dimension == 2 ? NOSPD::pattern_lattice<2>(patterns[k], h)
                                     : NOSPD::pattern_lattice<3>(patterns[k], h);
  }
  std::vector<std::array<int, 3>> coords;
  long stride[3] = {0, 0, 0};
  bool grid = lattice && build_cell_grid(h, coords, stride);
  bool collisions = false;
  if (grid)
    for (int c : cell_grid) collisions = collisions || c == -2;

  std::map<const NOSPD::Stencil *, int> run_of;
  for (int i = 0; grid && i < nlocal; i++) {
    const NOSPD::Stencil *st = st_of[i];
    if (!st || coords[i][0] == INT_MIN || st->h[0] != h[0] || st->h[1] != h[1] ||
        st->h[2] != h[2])
      continue;
    bool ok = true, all_owned = true;
    for (int b = fix_bonds->bond_first[i]; ok && b < fix_bonds->bond_first[i + 1]; b++) {
      const int j = fix_bonds->bond_j[b];
      ok = stencil_key[j] == stencil_key[i] && type[j] == type[i] && vfrac[j] == vfrac[i];
      if (j < nlocal) ok = ok && state_pattern[j] == state_pattern[i];
      else all_owned = false;
    }
    // owned partners of one pattern have their partners here: their cells
    // exist, unless two atoms share one
    if (ok && (!all_owned || collisions)) ok = stencil_cells_present(*st, coords[i], stride);
    if (!ok) continue;
    join_stencil_run(i, st, stride, run_of);
    nlocal_on++;
  }
  // the points near surfaces, interfaces and broken bonds
  if (grid) nlocal_on += map_point_stencils(coords, stride, h, family_of, run_of);
  // each run in cell order: consecutive points share most of their
  // neighbourhoods in the cache
  for (StencilRun &run : stencil_runs) {
    std::vector<int> order(run.atoms.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return run.cells[a] < run.cells[b]; });
    std::vector<int> atoms(order.size()), cells(order.size());
    for (size_t q = 0; q < order.size(); q++) {
      atoms[q] = run.atoms[order[q]];
      cells[q] = run.cells[order[q]];
    }
    run.atoms.swap(atoms);
    run.cells.swap(cells);
  }
  // the runs cut into blocks of points, the stencil pass's work items, in
  // the order of their first cells: threads that split them in contiguous
  // ranges get slabs of the body, each with its share of the one-sided
  // stencils (which cost about twice the grid's)
  stencil_blocks.clear();
  for (int r = 0; r < (int) stencil_runs.size(); r++)
    for (int q0 = 0; q0 < (int) stencil_runs[r].atoms.size(); q0 += STENCIL_BLOCK)
      stencil_blocks.push_back(
          {r, q0, std::min((int) stencil_runs[r].atoms.size(), q0 + STENCIL_BLOCK)});
  std::sort(stencil_blocks.begin(), stencil_blocks.end(),
            [&](const std::array<int, 3> &a, const std::array<int, 3> &b) {
              return stencil_runs[a[0]].cells[a[1]] < stencil_runs[b[0]].cells[b[1]];
            });
  // the flags go to the ghosts, whose families then leave them out
  comm_mode = 2;
  comm->forward_comm(this);
  comm_mode = 0;

  // families with a target off the stencil
  family_order.clear();
  for (int i : state_order) {
    bool needed = !on_stencil[i];
    for (int b = fix_bonds->bond_first[i]; !needed && b < fix_bonds->bond_first[i + 1]; b++)
      needed = !on_stencil[fix_bonds->bond_j[b]];
    if (needed) family_order.push_back(i);
  }
  pvector[1] = (double) nlocal_on;
  MPI_Allreduce(&nlocal_on, &nstencil_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
}

/* ----------------------------------------------------------------------
   Whether every cell a stencil reads around a point's cell holds one atom
------------------------------------------------------------------------- */

bool PairPeriNospdHS::stencil_cells_present(const NOSPD::Stencil &st,
                                            const std::array<int, 3> &at, const long *stride) const
{
  auto there = [&](const int *off) {
    for (int sgn = st.one_sided ? 1 : -1; sgn <= 1; sgn += 2) {
      long c = 0;
      for (int k = 0; k < 3; k++) {
        const long ck = at[k] + sgn * off[k];
        const long nk = k == 2 ? (long) cell_grid.size() / stride[2] : stride[k + 1] / stride[k];
        if (ck < 0 || ck >= nk) return false;
        c += ck * stride[k];
      }
      if (cell_grid[c] < 0) return false;
    }
    return true;
  };
  // the point's own cell too (its displacement is read from there)
  const int zero[3] = {0, 0, 0};
  if (!there(zero)) return false;
  for (int q = 0; q < st.npairs(); q++)
    if (!there(&st.pair_off[3 * q])) return false;
  for (int q = 0; q < st.nslots(); q++)
    if (!there(&st.slot_off[3 * q])) return false;
  return true;
}

/* ----------------------------------------------------------------------
   Owned atom i takes stencil st: its run (one per stencil) gains it
------------------------------------------------------------------------- */

void PairPeriNospdHS::join_stencil_run(int i, const NOSPD::Stencil *st, const long *stride,
                                       std::map<const NOSPD::Stencil *, int> &run_of)
{
  auto it = run_of.find(st);
  if (it == run_of.end()) {
    it = run_of.emplace(st, (int) stencil_runs.size()).first;
    StencilRun run;
    run.st = st;
    auto lin = [&](const int *off) {
      return (int) (off[0] * stride[0] + off[1] * stride[1] + off[2] * stride[2]);
    };
    for (int q = 0; q < st->npairs(); q++) run.pair_lin.push_back(lin(&st->pair_off[3 * q]));
    for (int q = 0; q < st->nslots(); q++) run.slot_lin.push_back(lin(&st->slot_off[3 * q]));
    stencil_runs.push_back(std::move(run));
  }
  StencilRun &run = stencil_runs[it->second];
  run.atoms.push_back(i);
  run.cells.push_back(cell_of[i]);
  on_stencil[i] = 1;
}

/* ----------------------------------------------------------------------
   The neighbourhood of owned atom i: its family key and volume, then, slot
   by slot of its pattern, each partner's family key and volume (bit
   patterns).  Points with one neighbourhood have one force operator.
------------------------------------------------------------------------- */

void PairPeriNospdHS::neighbourhood_key(int i, std::vector<int64_t> &key) const
{
  auto bits = [](double v) {
    int64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  const double *vfrac = atom->vfrac;
  const int n = state_count[i];
  const uint16_t *perm = &state_perm[state_first[i]];
  const int *bj = fix_bonds->bond_j + fix_bonds->bond_first[i];
  key.resize(2 * n + 2);
  key[0] = bits(stencil_key[i]);
  key[1] = bits(vfrac[i]);
  for (int s = 0; s < n; s++) {
    const int j = bj[perm[s]];
    key[2 * s + 2] = bits(stencil_key[j]);
    key[2 * s + 3] = bits(vfrac[j]);
  }
}

/* ----------------------------------------------------------------------
   One-sided stencils (nospd_stencil.h) for the owned atoms the grid's
   stencil left out, where at least POINT_STENCIL_USERS of them share a
   neighbourhood, every family of it is known here (owned, or a ghost
   whose key an owned family has) and has a linear law, and every cell it
   reads holds an atom.  Stencils are kept by neighbourhood between
   mappings; those no atom uses any more are dropped.  Returns the number
   of atoms that joined.
------------------------------------------------------------------------- */

int PairPeriNospdHS::map_point_stencils(const std::vector<std::array<int, 3>> &coords,
                                        const long *stride, const double *h,
                                        const std::map<double, std::pair<int, int>> &family_of,
                                        std::map<const NOSPD::Stencil *, int> &run_of)
{
  const int nlocal = atom->nlocal;
  const int *type = atom->type;

  // candidates: enough points of their own family's pattern and material
  // (a cheap first cut where damage has made most families unique), then
  // grouped by neighbourhood
  std::vector<int> candidates;
  std::unordered_map<double, int> own_count;
  for (int i = 0; i < nlocal; i++) {
    if (on_stencil[i] || coords[i][0] == INT_MIN) continue;
    if (patterns[state_pattern[i]].atom_singular || !linear_law[type[i]].ok) continue;
    candidates.push_back(i);
    own_count[stencil_key[i]]++;
  }
  std::unordered_map<uint64_t, std::vector<int>> by_hash;
  std::vector<int64_t> key, other;
  for (int i : candidates) {
    if (own_count[stencil_key[i]] < POINT_STENCIL_USERS) continue;
    neighbourhood_key(i, key);
    by_hash[key_hash(key)].push_back(i);
  }
  struct Group {
    std::vector<int64_t> key;
    std::vector<int> atoms;
    NOSPD::Stencil *st = nullptr;
  };
  std::vector<Group> groups;
  for (auto &kv : by_hash) {
    if ((int) kv.second.size() < POINT_STENCIL_USERS) continue;
    Group g;
    neighbourhood_key(kv.second[0], g.key);
    for (int i : kv.second) {
      neighbourhood_key(i, other);
      if (other == g.key) g.atoms.push_back(i);
    }
    if ((int) g.atoms.size() >= POINT_STENCIL_USERS) groups.push_back(std::move(g));
  }

  // the stencils kept from earlier mappings, and those to build
  std::map<std::vector<int64_t>, NOSPD::Stencil> kept;
  // After the first mapping of a run, new neighbourhoods come from bonds
  // breaking (or atoms migrating): a crack front's are many, short-lived
  // and shared by few points, and evaluating their families' operators
  // would cost more steps than they save; only those of many points are
  // built then.
  std::vector<int> to_build;
  for (int q = 0; q < (int) groups.size(); q++) {
    auto it = point_stencils.find(groups[q].key);
    if (it != point_stencils.end()) {
      groups[q].st = &kept.emplace(it->first, std::move(it->second)).first->second;
    } else if (first_point_mapping || (int) groups[q].atoms.size() >= PROGRAM_USERS)
      to_build.push_back(q);
  }
  point_stencils.swap(kept);
  first_point_mapping = false;
  std::vector<std::pair<const std::vector<int64_t> *, int>> needs;
  for (int q : to_build) needs.emplace_back(&groups[q].key, groups[q].atoms[0]);
  build_point_stencils(needs, h, family_of);

  int joined = 0;
  for (Group &g : groups) {
    if (!g.st) {
      auto it = point_stencils.find(g.key);
      if (it == point_stencils.end()) continue;
      g.st = &it->second;
    }
    if (!g.st->ok) continue;
    for (int i : g.atoms) {
      if (!stencil_cells_present(*g.st, coords[i], stride)) continue;
      join_stencil_run(i, g.st, stride, run_of);
      joined++;
    }
  }
  return joined;
}

/* ----------------------------------------------------------------------
   Build the one-sided stencils of neighbourhoods (key, an atom that has
   it) into point_stencils (not ok where a family is unknown here, has no
   linear law or no shape tensor, or is off the lattice).  Each family
   operator (pattern and type) is evaluated once per batch and added into
   every neighbourhood that reads it.
------------------------------------------------------------------------- */

void PairPeriNospdHS::build_point_stencils(
    const std::vector<std::pair<const std::vector<int64_t> *, int>> &needs, const double *h,
    const std::map<double, std::pair<int, int>> &family_of)
{
  using NOSPD::detail::Offset;
  if (needs.empty()) return;
  const int nlocal = atom->nlocal, dim = domain->dimension;
  const int *type = atom->type;
  const double *vfrac = atom->vfrac;

  struct Operator {
    int pattern, type;
    bool ok;
    std::vector<Offset> e;
    std::map<Offset, int> slot_at;
  };
  struct Ref {
    int need, slot;    // slot -1: the need's own family
    Offset at;         // the family's centre relative to the point
    double ws;         // (V_centre / V_point) w_slot
  };
  std::vector<Operator> ops;
  std::vector<std::vector<Ref>> refs;    // by operator
  std::map<std::pair<int, int>, int> op_of;
  int emax = 0;
  auto op_index = [&](int k, int t) {
    auto it = op_of.find({k, t});
    if (it != op_of.end()) return it->second;
    Operator op{k, t, false, {}, {}};
    const BondPattern &p = patterns[k];
    op.ok = !p.atom_singular && linear_law[t].ok &&
        (dim == 2 ? NOSPD::lattice_offsets<2>(p, h, op.e) : NOSPD::lattice_offsets<3>(p, h, op.e));
    for (int s = 0; op.ok && s < p.n; s++) {
      op.slot_at[op.e[s]] = s;
      for (int c = 0; c < 3; c++) emax = MAX(emax, std::abs(op.e[s][c]));
    }
    ops.push_back(std::move(op));
    refs.emplace_back();
    op_of.emplace(std::make_pair(k, t), (int) ops.size() - 1);
    return (int) ops.size() - 1;
  };

  const int nneed = (int) needs.size();
  std::vector<char> ok(nneed, 1);
  std::vector<int> own(nneed);
  for (int q = 0; q < nneed; q++) {
    const int i = needs[q].second;
    const int oi = op_index(state_pattern[i], type[i]);
    own[q] = oi;
    if (!ops[oi].ok) {
      ok[q] = 0;
      continue;
    }
    refs[oi].push_back({q, -1, {0, 0, 0}, 1.0});
    const int n = state_count[i];
    const uint16_t *perm = &state_perm[state_first[i]];
    const int *bj = fix_bonds->bond_j + fix_bonds->bond_first[i];
    for (int s = 0; ok[q] && s < n; s++) {
      const int j = bj[perm[s]];
      int pj = -1;
      if (j < nlocal) pj = state_pattern[j];
      else {
        auto f = family_of.find(stencil_key[j]);
        if (f != family_of.end() && f->second.second == type[j]) pj = f->second.first;
      }
      if (pj < 0) {
        ok[q] = 0;
        break;
      }
      const int oj = op_index(pj, type[j]);
      const Offset a = ops[oi].e[s];
      auto slot = ops[oj].slot_at.find(NOSPD::detail::neg(a));
      if (!ops[oj].ok || slot == ops[oj].slot_at.end()) {
        ok[q] = 0;
        break;
      }
      const double ws = vfrac[j] / vfrac[i] * patterns[pj].w[slot->second];
      refs[oj].push_back({q, slot->second, a, ws});
    }
  }

  // batches of neighbourhoods, each assembled on a dense cube of blocks
  const int R = 2 * emax;
  const double cube = 72.0 * (2 * R + 1) * (2 * R + 1) * (dim == 3 ? 2 * R + 1 : 1);
  const int batch = MAX(1, (int) (POINT_STENCIL_BATCH_BYTES / cube));
  std::vector<double> A;
  for (int q0 = 0; q0 < nneed; q0 += batch) {
    const int q1 = MIN(nneed, q0 + batch);
    std::vector<NOSPD::PointStencilBuilder> builders(q1 - q0, NOSPD::PointStencilBuilder(dim, R));
    for (size_t o = 0; o < ops.size(); o++) {
      bool used = false;
      for (const Ref &r : refs[o]) used = used || (r.need >= q0 && r.need < q1 && ok[r.need]);
      if (!used) continue;
      const Operator &op = ops[o];
      const BondPattern &p = patterns[op.pattern];
      const bool have = dim == 2
          ? NOSPD::family_operator<2>(p, hs_form, strain_law, plane_mode, lame[op.type],
                                      linear_law[op.type], h[0], A)
          : NOSPD::family_operator<3>(p, hs_form, strain_law, plane_mode, lame[op.type],
                                      linear_law[op.type], h[0], A);
      for (const Ref &r : refs[o]) {
        if (r.need < q0 || r.need >= q1 || !ok[r.need]) continue;
        NOSPD::PointStencilBuilder &b = builders[r.need - q0];
        const bool added = have &&
            (r.slot < 0 ? b.add_own(op.e, p.w, A) : b.add_member(r.at, op.e, A, r.slot, r.ws));
        if (!added) ok[r.need] = 0;
      }
    }
    for (int q = q0; q < q1; q++) {
      NOSPD::Stencil &st = point_stencils[*needs[q].first];
      if (!ok[q]) continue;
      const Operator &op = ops[own[q]];
      st = dim == 2 ? builders[q - q0].finish<2>(patterns[op.pattern], op.e, h)
                    : builders[q - q0].finish<3>(patterns[op.pattern], op.e, h);
      nstencils_built++;
    }
  }
}

/* ----------------------------------------------------------------------
   Forces, F and stress of the points on the stencil
------------------------------------------------------------------------- */

void PairPeriNospdHS::stencil_pass()
{
  // displacements by lattice cell: a point's neighbours without lookups
  // (cells that hold no atom, or two, are never read)
  const int nall = atom->nlocal + atom->nghost;
  double **x = atom->x;
  double **x0s = fix_bonds->x0s;
  ustencil.resize(4 * cell_grid.size() + 4);
  double *u = ustencil.data();
  for (int a = 0; a < nall; a++) {
    const long c = cell_of[a];
    if (c < 0) continue;
    for (int k = 0; k < 3; k++) u[4 * c + k] = x[a][k] - x0s[a][k];
    u[4 * c + 3] = 0.0;
  }
  double **f = atom->f;
  const bool two = domain->dimension == 2;
  // one range over the blocks of every run: threads share the many short
  // runs of one-sided stencils as well as the long one of the grid's
  for_ranges((int) stencil_blocks.size(), true, [&](int from, int to, int, Tally &) {
    double fb[STENCIL_BLOCK][3], Hb[STENCIL_BLOCK][9], Hbarb[STENCIL_BLOCK][9];
    for (int b = from; b < to; b++) {
      const StencilRun &run = stencil_runs[stencil_blocks[b][0]];
      const int q0 = stencil_blocks[b][1], q1 = stencil_blocks[b][2];
      const int *cells = run.cells.data(), *pl = run.pair_lin.data(), *sl = run.slot_lin.data();
      const bool one = run.st->one_sided;
      if (two && one) stencil_kernel<2, true>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      else if (two) stencil_kernel<2, false>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      else if (one) stencil_kernel<3, true>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      else stencil_kernel<3, false>(*run.st, u, cells, pl, sl, q0, q1, fb, Hb, Hbarb);
      for (int q = q0; q < q1; q++) {
        const int i = run.atoms[q];
        for (int k = 0; k < 3; k++) f[i][k] += fb[q - q0][k];
        store_stencil_state(i, *run.st, Hb[q - q0], Hbarb[q - q0]);
      }
    }
  });
}

/* ----------------------------------------------------------------------
   F and stress of a point on the stencil, as the family path stores them:
   P of the bonds' mean H (the law is linear), the family's F through the
   law where singular bond families use it (plane stress solves F_zz)
------------------------------------------------------------------------- */

void PairPeriNospdHS::store_stencil_state(int i, const NOSPD::Stencil &st, const double *H,
                                          const double *Hbar)
{
  const int itype = atom->type[i];
  Mat3 F = NOSPD::load(H) + Mat3::Identity(), Fbar = NOSPD::load(Hbar) + Mat3::Identity();
  Mat3 P, Pf;
  double W;
  NOSPD::first_piola(strain_law, plane_mode, lame[itype], Fbar, P, W);
  if (st.family_fallback) NOSPD::first_piola(strain_law, plane_mode, lame[itype], F, Pf, W);
  // plane stress: the bonds' mean out-of-plane stretch, as the family path
  if (plane_mode == NOSPD::Plane::STRESS) F(2, 2) = Fbar(2, 2);
  NOSPD::store(F, fix_bonds->defgrad[i]);
  NOSPD::store(P, fix_bonds->pk1[i]);
}

/* ----------------------------------------------------------------------
   Find (or build) the pattern of atom i's family; perm receives, for each
   slot of the pattern, the bond's offset within i's part of the fix's
   arrays.  The key is the family's offsets rounded to KEY_QUANTUM*delta,
   in lexicographic (z, y, x) order.
------------------------------------------------------------------------- */

int PairPeriNospdHS::match_pattern(int i, std::vector<uint16_t> &perm)
{
  const int bf = fix_bonds->bond_first[i];
  const int n = fix_bonds->bond_first[i + 1] - bf;
  if (n > 65535)
    error->one(FLERR, "pair_style {}: atom {} has {} bonds; at most 65535 are supported",
               force->pair_style, atom->tag[i], n);
  const int *bj = fix_bonds->bond_j + bf;
  const double *bw = fix_bonds->bond_w + bf;
  double **x0s = fix_bonds->x0s;
  const double delta = cut[atom->type[i]][atom->type[i]];
  const double radius = hs_ratio * delta;
  const double q = KEY_QUANTUM * delta;
  const double tol = fix_bonds->conditioning_tolerance(i);    // stricter once damaged

  struct Item {
    int64_t k[3];    // z, y, x
    int off;
  };
  std::vector<Item> items(n);
  for (int s = 0; s < n; s++) {
    const int j = bj[s];
    for (int c = 0; c < 3; c++)
      items[s].k[2 - c] = (int64_t) std::llround((x0s[j][c] - x0s[i][c]) / q);
    items[s].off = s;
  }
  std::sort(items.begin(), items.end(), [](const Item &a, const Item &b) {
    return std::lexicographical_compare(a.k, a.k + 3, b.k, b.k + 3);
  });
  std::vector<int64_t> key(3 * n);
  for (int l = 0; l < n; l++)
    for (int c = 0; c < 3; c++) key[3 * l + c] = items[l].k[2 - c];    // x, y, z
  const uint64_t h = key_hash(key);

  int found = -1;
  auto range = pattern_lookup.equal_range(h);
  for (auto it = range.first; it != range.second && found < 0; ++it) {
    const BondPattern &p = patterns[it->second];
    if (p.n != n || p.radius != radius || p.tol != tol || p.key != key) continue;
    bool same = true;
    for (int l = 0; same && l < n; l++) {
      const double wp = p.w[p.lex_to_slot[l]];
      same = std::abs(bw[items[l].off] - wp) <= WEIGHT_TOL * wp;
    }
    if (same) found = it->second;
  }

  if (found < 0) {
    std::vector<double> b(3 * n), w(n), vol(n);
    const double *vfrac = atom->vfrac;
    for (int l = 0; l < n; l++) {
      const int j = bj[items[l].off];
      for (int c = 0; c < 3; c++) b[3 * l + c] = x0s[j][c] - x0s[i][c];
      w[l] = bw[items[l].off];
      vol[l] = vfrac[j];
    }
    patterns.emplace_back();
    NOSPD::build_pattern(patterns.back(), domain->dimension, n, b.data(), w.data(), vol.data(),
                         key, radius, hs_form, tol);
    found = (int) patterns.size() - 1;
    pattern_lookup.emplace(h, found);
  }

  const BondPattern &p = patterns[found];
  perm.assign(n, 0);
  for (int l = 0; l < n; l++) perm[p.lex_to_slot[l]] = (uint16_t) items[l].off;
  return found;
}

/* ----------------------------------------------------------------------
   Once per run: the bond-associated families in numbers.  A ratio that
   leaves most bond-associated families degenerate is an input error.
------------------------------------------------------------------------- */

void PairPeriNospdHS::report_patterns()
{
  double loc[5] = {0.0, 0.0, 0.0, (double) patterns.size(), 0.0}, all[5];
  for (int i = 0; i < atom->nlocal; i++) {
    const BondPattern &p = patterns[state_pattern[i]];
    loc[0] += p.n;
    loc[1] += (double) p.members;
    loc[2] += (double) p.runs.size() / 2.0;
  }
  for (auto &p : patterns) loc[4] += p.bytes();
  for (auto &byType : pattern_stencils)
    for (auto &kv : byType) loc[4] += kv.second.bytes();
  for (auto &kv : point_stencils) loc[4] += kv.second.bytes() + 8.0 * kv.first.size();
  loc[4] += (double) (cell_grid.size() + cell_of.size() + family_order.size()) * sizeof(int) +
      (double) on_stencil.size() + 8.0 * stencil_key.size();
  for (auto &run : stencil_runs)
    loc[4] += (double) (run.pair_lin.size() + run.slot_lin.size() + 2 * run.atoms.size()) *
        sizeof(int);
  loc[4] += (double) state_perm.size() * sizeof(uint16_t) +
      (double) state_pattern.size() * (3 * sizeof(int) + sizeof(tagint));
  // the one-sided stencils and their points
  double one[2] = {0.0, 0.0}, one_all[2];
  for (auto &kv : point_stencils) one[0] += kv.second.ok ? 1.0 : 0.0;
  for (auto &run : stencil_runs)
    if (run.st->one_sided) one[1] += (double) run.atoms.size();
  MPI_Allreduce(loc, all, 5, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(one, one_all, 2, MPI_DOUBLE, MPI_SUM, world);
  const double natoms = (double) MAX(atom->natoms, 1);
  const double nbonds = MAX(all[0], 1.0);
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "PERI-NOSPD bond-associated families (pair {}, form {}, ratio {}):\n"
                   "  bond families = {:.0f}, mean members = {:.4g}, mean runs = {:.4g}\n"
                   "  singular bond families (family F used) = {}, in {} atoms\n"
                   "  patterns = {:.0f} (summed over ranks), pattern and mapping state = "
                   "{:.0f} bytes/point\n"
                   "  points on the linear law's stencil = {} of {} ({:.0f} of them on "
                   "{:.0f} one-sided stencils, summed over ranks)\n",
                   force->pair_style, hs_form == HSForm::I ? "I" : "II", hs_ratio, all[0],
                   all[1] / nbonds, all[2] / nbonds, nsingular_bonds, nfallback_states, all[3],
                   all[4] / natoms, nstencil_all, atom->natoms, one_all[1], one_all[0]);
  if (fix_bonds->nbonds_broken == 0 && all[0] > 0.0 && nsingular_bonds > 0.5 * all[0])
    error->all(FLERR, "pair_style {}: ratio {} is too small for singular_tol {:.4g}: {} of "
               "{:.0f} bond-associated families are degenerate (fewer than {} non-coplanar "
               "members, or shape tensors below singular_tol); use a larger ratio{}",
               force->pair_style, hs_ratio, singular_tol, nsingular_bonds, all[0],
               domain->dimension, singular_tol > 1.0e-4 ? " or a smaller singular_tol" : "");
}

/* ----------------------------------------------------------------------
   F of one bond-associated family, for output and tests
------------------------------------------------------------------------- */

int PairPeriNospdHS::bond_defgrad(int i, int b, double *F)
{
  if (mapped_version != fix_bonds->bond_version || i < 0 || i >= (int) state_pattern.size())
    return -1;
  const BondPattern &p = patterns[state_pattern[i]];
  const uint16_t *perm = &state_perm[state_first[i]];
  const int off = b - fix_bonds->bond_first[i];
  int slot = -1;
  for (int s = 0; s < p.n && slot < 0; s++)
    if (perm[s] == off) slot = s;
  if (slot < 0) return -1;
  FamilyWork &w = work[0];
  gather_family(i, p, perm, w, 0);
  Mat3 Fm;
  const bool own = domain->dimension == 2 ? NOSPD::bond_defgrad<2>(p, slot, w.ubuf[0].data(), Fm)
                                          : NOSPD::bond_defgrad<3>(p, slot, w.ubuf[0].data(), Fm);
  NOSPD::store(Fm, F);
  return own ? 1 : 0;
}

/* ----------------------------------------------------------------------
   forward: the classical B (H) and s for a stabilization, or the
   stencil's keys (comm_mode 1) and flags (2)
------------------------------------------------------------------------- */

int PairPeriNospdHS::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  if (comm_mode == 0) return PairPeriNospd::pack_forward_comm(n, list, buf, pbc_flag, pbc);
  for (int ii = 0; ii < n; ii++)
    buf[ii] = comm_mode == 1 ? stencil_key[list[ii]] : (double) on_stencil[list[ii]];
  return n;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::unpack_forward_comm(int n, int first, double *buf)
{
  if (comm_mode == 0) return PairPeriNospd::unpack_forward_comm(n, first, buf);
  for (int ii = 0; ii < n; ii++) {
    if (comm_mode == 1) stencil_key[first + ii] = buf[ii];
    else on_stencil[first + ii] = buf[ii] != 0.0 ? 1 : 0;
  }
}

/* ---------------------------------------------------------------------- */

int PairPeriNospdHS::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  const int last = first + n;
  for (int i = first; i < last; i++) {
    for (int k = 0; k < 3; k++) buf[m++] = fghost[i][k];
    if (reverse_virial)
      for (int k = 0; k < 6; k++) buf[m++] = vghost[i][k];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int j = list[ii];
    for (int k = 0; k < 3; k++) fghost[j][k] += buf[m++];
    if (reverse_virial)
      for (int k = 0; k < 6; k++) vghost[j][k] += buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::write_restart_settings(FILE *fp)
{
  PairPeriNospd::write_restart_settings(fp);
  const int iv = static_cast<int>(hs_form);
  fwrite(&iv, sizeof(int), 1, fp);
  fwrite(&hs_ratio, sizeof(double), 1, fp);
  const int st = stencil_on ? 1 : 0;
  fwrite(&st, sizeof(int), 1, fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::read_restart_settings(FILE *fp)
{
  PairPeriNospd::read_restart_settings(fp);
  int iv = 2, st = 1;
  if (comm->me == 0) {
    utils::sfread(FLERR, &iv, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &hs_ratio, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &st, sizeof(int), 1, fp, nullptr, error);
  }
  MPI_Bcast(&iv, 1, MPI_INT, 0, world);
  MPI_Bcast(&st, 1, MPI_INT, 0, world);
  stencil_on = st != 0;
  MPI_Bcast(&hs_ratio, 1, MPI_DOUBLE, 0, world);
  hs_form = static_cast<HSForm>(iv);
  // the classical settings hold the stabilization
  stab_on = (stab == NOSPD::Stab::SILLING || stab == NOSPD::Stab::HOURGLASS);
  if (!stab_on) stab = NOSPD::Stab::NONE;
}

/* ---------------------------------------------------------------------- */

double PairPeriNospdHS::memory_usage()
{
  double bytes = (double) nmax_ghost * (vghost ? 9 : 3) * sizeof(double);
  for (auto &p : patterns) bytes += p.bytes();
  bytes += (double) state_perm.capacity() * sizeof(uint16_t);
  bytes += (double) state_pattern.capacity() * (3 * sizeof(int) + sizeof(tagint));
  bytes += (double) (state_order.capacity() + family_order.capacity() + cell_grid.capacity() +
                     cell_of.capacity()) * sizeof(int);
  for (auto &byType : pattern_stencils)
    for (auto &kv : byType) bytes += kv.second.bytes();
  for (auto &kv : point_stencils) bytes += kv.second.bytes() + 8.0 * kv.first.size();
  for (auto &run : stencil_runs)
    bytes += (double) (run.pair_lin.size() + run.slot_lin.size() + run.atoms.size() +
                       run.cells.size()) * sizeof(int);
  bytes += (double) on_stencil.capacity() + 8.0 * (stencil_key.capacity() + ustencil.capacity());
  for (const FamilyWork &w : work)
    bytes += (double) (w.scratch.work.size() + w.scratch.side.size() + w.scratch.sums.size() +
                       w.scratch.g.size() + 2 * w.ubuf[0].size() + 2 * w.tbuf[0].size() +
                       w.fg.size() + w.vg.size()) *
      sizeof(double);
  return bytes;
}

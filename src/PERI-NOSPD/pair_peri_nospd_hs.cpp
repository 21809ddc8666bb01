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

/* the evaluation kernel is built for the generic target and, where the
   compiler can, for AVX2 and AVX-512 (nospd_simd.h): its row sums and 3x3
   products are plain loops that widen with the target, about 10% faster
   on CPUs that have the wider units */

namespace {

template <int DIM, int L>
NOSPD_KERNEL_CLONES bool evaluate(const BondPattern &p, HSForm form, NOSPD::Law law,
                                  NOSPD::Plane plane, const NOSPD::LaneInput *in, bool energy,
                                  NOSPD::StateScratch &s, NOSPD::StateOutput *out)
{
  return NOSPD::evaluate_families<DIM, L>(p, form, law, plane, in, energy, s, out);
}
}    // namespace

/* ---------------------------------------------------------------------- */

PairPeriNospdHS::PairPeriNospdHS(LAMMPS *lmp) :
    PairPeriNospdBase(lmp), hs_form(HSForm::II), hs_ratio(1.0), mapped_version(-1),
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
  PairPeriNospdBase::settings((int) rest.size(), rest.data());
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
  return PairPeriNospdBase::not_a_potential();
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::init_style()
{
  PairPeriNospdBase::init_style();
  // inelastic materials: a point history per family and a state per bond
  // (nospd_bond_history.h): J2/Johnson-Cook's compact per-bond state, a
  // UMAT's family row a UmatHist entry of sums and means then that of the
  // whole family's F, any other law its own history per bond
  for (int i = 1; i <= atom->ntypes; i++) {
    if (!active[i]) continue;
    if (bond_material(i))
      fix_bonds->set_history_size(NOSPD::FamilyMaterial::family_size(*materials[i]),
                                  materials[i]->history_size());
    else if (has_history(i))
      fix_bonds->set_history_size(NOSPD::FamilyHist::SIZE, NOSPD::BondHist::SIZE);
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
  if (silling) vflag_either ? PairPeriNospdBase::force_pass<NOSPD::StabPass::SILLING, 1>(eflag)
                            : PairPeriNospdBase::force_pass<NOSPD::StabPass::SILLING, 0>(eflag);
  else vflag_either ? PairPeriNospdBase::force_pass<NOSPD::StabPass::HOURGLASS, 1>(eflag)
                    : PairPeriNospdBase::force_pass<NOSPD::StabPass::HOURGLASS, 0>(eflag);
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
  if (comm_mode == 0) return PairPeriNospdBase::pack_forward_comm(n, list, buf, pbc_flag, pbc);
  for (int ii = 0; ii < n; ii++)
    buf[ii] = comm_mode == 1 ? stencil_key[list[ii]] : (double) on_stencil[list[ii]];
  return n;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::unpack_forward_comm(int n, int first, double *buf)
{
  if (comm_mode == 0) return PairPeriNospdBase::unpack_forward_comm(n, first, buf);
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
  PairPeriNospdBase::write_restart_settings(fp);
  const int iv = static_cast<int>(hs_form);
  fwrite(&iv, sizeof(int), 1, fp);
  fwrite(&hs_ratio, sizeof(double), 1, fp);
  const int st = stencil_on ? 1 : 0;
  fwrite(&st, sizeof(int), 1, fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdHS::read_restart_settings(FILE *fp)
{
  PairPeriNospdBase::read_restart_settings(fp);
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

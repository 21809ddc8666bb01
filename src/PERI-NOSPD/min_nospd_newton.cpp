/* ----------------------------------------------------------------------
   PERI-NOSPD: min_style nospd/newton (see the header and
   doc/min_nospd_newton.rst)
------------------------------------------------------------------------- */

#include "min_nospd_newton.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "angle.h"
#include "bond.h"
#include "dihedral.h"
#include "error.h"
#include "improper.h"
#include "kspace.h"
#include "fix_minimize.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "modify.h"
#include "nospd_krylov.h"
#include "nospd_input.h"
#include "output.h"
#include "pair.h"
#include "pair_peri_nospd_base.h"
#include "timer.h"
#include "update.h"
#include "utils.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdint>
#include <cstring>

using namespace LAMMPS_NS;

namespace {
constexpr const char *CMD = "min_style nospd/newton";
constexpr double EPS_ENERGY = 1.0e-8;    // as LAMMPS's line searches
constexpr double ARMIJO = 1.0e-4;
constexpr int MAX_BACKTRACK = 30;
// the forcing of the retry when a loose solve's direction does not descend
constexpr double RETRY_FORCING = 1.0e-4;
// |r| below this fraction of its start is near the rounding of the forces
// (positions carry ~1e-16 of the box; differences of them ~1e-10 of a
// load): a step that lowered it by less than STALL there ends the solve
constexpr double ROUNDING_FLOOR = 1.0e-7;
constexpr double STALL = 0.5;
// a rigid mode whose stiffness is below this fraction of a random
// direction's is taken as free (directional differences resolve ~1e-8)
constexpr double SINGULAR_RATIO = 1.0e-6;
// the surrogate keeps the bonds up to this fraction of the horizon (at
// three spacings: a lattice's nearest and diagonal neighbours): nearly as
// good a preconditioner as the whole family at a fraction of the fill
constexpr double SURROGATE_REACH = 0.5;
// owned dofs up to which the surrogate is factored exactly (beyond: an
// incomplete factor, whose Krylov counts grow with the resolution)
constexpr int DIRECT_DOFS = 600000;

// a reproducible number in [-1, 1) from an atom's tag and a component: the
// same perturbation on any rank count
double hashed(tagint tag, int k)
{
  uint64_t z = static_cast<uint64_t>(tag) * 3 + static_cast<uint64_t>(k) + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}
}    // namespace

/* ---------------------------------------------------------------------- */

MinNospdNewton::MinNospdNewton(LAMMPS *lmp) : Min(lmp)
{
  searchflag = 1;
}

/* ---------------------------------------------------------------------- */

bool MinNospdNewton::selected(const Update *update)
{
  return dynamic_cast<const MinNospdNewton *>(update->minimize) != nullptr;
}

/* ---------------------------------------------------------------------- */

int MinNospdNewton::modify_param(int narg, char **arg)
{
  const std::string key = arg[0];
  auto need = [&](int n) {
    if (narg < n + 1) error->all(FLERR, "min_modify {}: expected {} value(s)", key, n);
  };
  auto real_in = [&](const std::string &what, const char *word, double lo, double hi) {
    const double v = NOSPD_INPUT::real(error, "min_modify", what, word);
    if (!(v >= lo && v <= hi))
      error->all(FLERR, "min_modify {}: {} must be in [{:g}, {:g}], got {}", key, what, lo, hi,
                 word);
    return v;
  };
  if (key == "krylov") {
    need(1);
    const std::string v = arg[1];
    if (v == "auto") krylov = Krylov::AUTO;
    else if (v == "cg") krylov = Krylov::CG;
    else if (v == "gmres") krylov = Krylov::GMRES;
    else error->all(FLERR, "min_modify krylov: expected auto, cg or gmres, not {}", v);
    return 2;
  }
  if (key == "restart") {
    need(1);
    restart = NOSPD_INPUT::integer(error, "min_modify", "restart", arg[1], 1, 1000);
    return 2;
  }
  if (key == "krylov_max") {
    need(1);
    max_krylov = NOSPD_INPUT::integer(error, "min_modify", "krylov_max", arg[1], 1, 100000000);
    return 2;
  }
  if (key == "forcing") {
    need(2);
    eta_min = real_in("forcing (smallest)", arg[1], 1.0e-14, 0.9);
    eta_max = real_in("forcing (largest)", arg[2], eta_min, 0.9);
    return 3;
  }
  if (key == "precondition") {
    need(1);
    const std::string v = arg[1];
    if (v == "surrogate") precond = Precondition::SURROGATE;
    else if (v == "jacobi") precond = Precondition::JACOBI;
    else error->all(FLERR, "min_modify precondition: expected surrogate or jacobi, not {}", v);
    return 2;
  }
  if (key == "tangent_check") {
    need(1);
    tangent_check = utils::logical(FLERR, arg[1], false, lmp) == 1;
    return 2;
  }
  if (key == "fd_step") {
    need(1);
    fd_step = real_in("fd_step", arg[1], 0.0, 1.0e300);
    return 2;
  }
  return 0;
}

/* ---------------------------------------------------------------------- */

void MinNospdNewton::init()
{
  Min::init();
}

/* ---------------------------------------------------------------------- */

void MinNospdNewton::setup_style()
{
  if (nextra_global)
    error->all(FLERR, "{} does not support fixes that add global degrees of freedom "
               "(fix box/relax): use min_style cg", CMD);
  if (nextra_atom)
    error->all(FLERR, "{} does not support extra per-atom degrees of freedom: use min_style cg",
               CMD);
  // the pair styles are initialized by now (not yet at init())
  auto *pair = PairPeriNospdBase::find(force);
  auto *bonds = pair ? pair->bonds() : nullptr;
  // CG needs a symmetric tangent: forces that are an energy's gradient and
  // no inelastic state whose directional differences cross a yield surface
  const bool potential = !pair || pair->potential_cause().empty();
  const bool history = bonds && bonds->nhistory > 0;
  use_cg = krylov == Krylov::CG || (krylov == Krylov::AUTO && potential && !history);
  this->potential = potential;
  if (krylov == Krylov::CG && !potential && comm->me == 0)
    error->warning(FLERR, "{}: min_modify krylov cg with forces that are not an energy's "
                   "gradient ({}): the tangent is not symmetric; use krylov gmres",
                   CMD, pair->potential_cause());
  fix_minimize->add_vector(3);    // x0
  fix_minimize->add_vector(3);    // du
  fix_minimize->add_vector(3);    // mask: 1 free, 0 held
}

void MinNospdNewton::reset_vectors()
{
  nvec = 3 * atom->nlocal;
  if (nvec) xvec = atom->x[0];
  if (nvec) fvec = atom->f[0];
  x0 = fix_minimize->request_vector(0);
  du = fix_minimize->request_vector(1);
  double *m = fix_minimize->request_vector(2);
  mask.assign(m, m + nvec);
}

/* ---------------------------------------------------------------------- */

double MinNospdNewton::global_dot(const double *a, const double *b) const
{
  double s = 0.0, all = 0.0;
  for (int i = 0; i < nvec; i++) s += a[i] * b[i];
  MPI_Allreduce(&s, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

// r = V f on the free degrees of freedom (the gradient of the total energy)
void MinNospdNewton::residual(std::vector<double> &r)
{
  r.resize(nvec);
  const double *vfrac = atom->vfrac;
  for (int i = 0; i < nvec; i++) r[i] = mask[i] * (vfrac ? vfrac[i / 3] : 1.0) * fvec[i];
}

/* ----------------------------------------------------------------------
   forces at positions within the neighbor skin of the last build: the
   same calls as Min::energy_force without the reneighboring branch and
   without energies, so that the local order of the atoms (and every
   Krylov vector) stays valid
------------------------------------------------------------------------- */

void MinNospdNewton::force_no_reneighbor()
{
  timer->stamp();
  comm->forward_comm();
  timer->stamp(Timer::COMM);
  ev_set(update->ntimestep);
  eflag = vflag = 0;
  force_clear();
  if (modify->n_min_pre_force) modify->min_pre_force(vflag);
  if (pair_compute_flag) force->pair->compute(eflag, vflag);
  if (atom->molecular != Atom::ATOMIC) {
    if (force->bond) force->bond->compute(eflag, vflag);
    if (force->angle) force->angle->compute(eflag, vflag);
    if (force->dihedral) force->dihedral->compute(eflag, vflag);
    if (force->improper) force->improper->compute(eflag, vflag);
  }
  if (kspace_compute_flag) force->kspace->compute(eflag, vflag);
  if (modify->n_min_pre_reverse) modify->min_pre_reverse(eflag, vflag);
  if (force->newton) comm->reverse_comm();
  if (modify->n_min_post_force) modify->min_post_force(vflag);
  timer->stamp(Timer::PAIR);
  neval++;
}

/* ----------------------------------------------------------------------
   A v = -(r(x0 + h v) - r(x0)) / h, h scaled so that the move is `delta`
   (root mean square over the free dofs): a forward directional difference
------------------------------------------------------------------------- */

double MinNospdNewton::probe(const double *v, double *Av)
{
  const double vv = global_dot(v, v);
  if (!(vv > 0.0)) {
    for (int i = 0; i < nvec; i++) Av[i] = 0.0;
    return 0.0;
  }
  double nfree = 0.0;
  for (int i = 0; i < nvec; i++) nfree += mask[i];
  double all = 0.0;
  MPI_Allreduce(&nfree, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  const double h = delta * std::sqrt(all / vv);
  for (int i = 0; i < nvec; i++) xvec[i] = x0[i] + h * mask[i] * v[i];
  force_no_reneighbor();
  const double *vfrac = atom->vfrac;
  for (int i = 0; i < nvec; i++)
    Av[i] = -(mask[i] * (vfrac ? vfrac[i / 3] : 1.0) * fvec[i] - r0[i]) / h;
  for (int i = 0; i < nvec; i++) xvec[i] = x0[i];
  return h;
}

/* ----------------------------------------------------------------------
   held degrees of freedom (fix setforce, 2D's z, points with no partner):
   those whose force does not move at all when every position is moved
   by a random amount; the Newton correction leaves them where they are
------------------------------------------------------------------------- */

void MinNospdNewton::find_free_dofs()
{
  double *m = fix_minimize->request_vector(2);
  const int dim = domain->dimension;
  const tagint *tag = atom->tag;
  std::vector<double> f0(fvec, fvec + nvec);
  for (int i = 0; i < nvec; i++) {
    x0[i] = xvec[i];
    xvec[i] += (i % 3 < dim) ? delta * hashed(tag[i / 3], i % 3) : 0.0;
  }
  force_no_reneighbor();
  for (int i = 0; i < nvec; i++) m[i] = (i % 3 < dim && fvec[i] != f0[i]) ? 1.0 : 0.0;
  for (int i = 0; i < nvec; i++) {
    xvec[i] = x0[i];
    fvec[i] = f0[i];
  }
  mask.assign(m, m + nvec);
  // a force that does not move with the positions and is not zero (a
  // loaded point without partners, a fix setting a nonzero force): no
  // equilibrium exists
  double worst = 0.0, most = 0.0;
  for (int i = 0; i < nvec; i++)
    if (m[i] == 0.0 && i % 3 < dim) worst = std::max(worst, std::fabs(fvec[i]));
  MPI_Allreduce(&worst, &most, 1, MPI_DOUBLE, MPI_MAX, world);
  if (!(most > 0.0)) return;
  bigint who = -1, first = -1;
  for (int i = 0; i < nvec && who < 0; i++)
    if (m[i] == 0.0 && i % 3 < dim && std::fabs(fvec[i]) == most) who = tag[i / 3];
  if (who < 0) who = MAXBIGINT;
  MPI_Allreduce(&who, &first, 1, MPI_LMP_BIGINT, MPI_MIN, world);
  error->all(FLERR, "{}: atom {} carries a force ({:.6g}) that no stiffness resists (a point "
             "without partners under a load, a fix setting a nonzero force, or a load so large "
             "that the stiffness is lost in its rounding): the force balance has no solution; "
             "remove the load or hold the point", CMD, first, most);
}

/* ----------------------------------------------------------------------
   what would make the solve meaningless: non-finite forces, a probe step
   below the positions' rounding or beyond a derivative's reach, dmax <= 0
------------------------------------------------------------------------- */

void MinNospdNewton::check_settings()
{
  double big = 0.0, all = 0.0;
  for (int i = 0; i < nvec; i++)
    if (!std::isfinite(fvec[i])) big = 1.0;
  MPI_Allreduce(&big, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (all > 0.0)
    error->all(FLERR, "{}: the forces at the start are not finite (inf or nan): check the "
               "loads (fix addforce values) and the positions", CMD);
  const double L = std::max(domain->prd[0], std::max(domain->prd[1], domain->prd[2]));
  if (fd_step > 0.0 && (fd_step < 1.0e-12 * L || fd_step > 1.0e-4 * L))
    error->all(FLERR, "{}: min_modify fd_step {:.6g} is outside [{:.3g}, {:.3g}] (1e-12 to "
               "1e-4 of the largest box length): below it the positions' rounding swamps the "
               "difference, above it the difference is no derivative; 0 picks 1.5e-8 of it",
               CMD, fd_step, 1.0e-12 * L, 1.0e-4 * L);
  if (!(dmax > 0.0))
    error->all(FLERR, "{}: min_modify dmax {} must be positive (it caps each Newton step)",
               CMD, dmax);
}

/* ----------------------------------------------------------------------
   an unconstrained body: a rigid translation or rotation of the free
   points that the forces do not resist makes the tangent singular
------------------------------------------------------------------------- */

void MinNospdNewton::check_singular()
{
  const int dim = domain->dimension;
  const tagint *tag = atom->tag;
  residual(r0);
  std::vector<double> v(nvec), Av(nvec);
  for (int i = 0; i < nvec; i++) v[i] = mask[i] * hashed(tag[i / 3], i % 3);
  probe(v.data(), Av.data());
  const double vv = global_dot(v.data(), v.data());
  if (!(vv > 0.0)) return;    // nothing free: nothing to solve
  const double ref = global_dot(Av.data(), Av.data()) / vv;
  // the rigid modes restricted to the free dofs: translations, rotations
  // about the centroid; their span holds the rotation about any held point
  double c[4] = {0.0, 0.0, 0.0, 0.0}, call[4];
  for (int i = 0; i < nvec; i += 3)
    if (mask[i] + mask[i + 1] + mask[i + 2] > 0.0) {
      for (int d = 0; d < 3; d++) c[d] += xvec[i + d];
      c[3] += 1.0;
    }
  MPI_Allreduce(c, call, 4, MPI_DOUBLE, MPI_SUM, world);
  for (int d = 0; d < 3; d++) call[d] /= call[3];
  std::vector<int> modes;
  std::vector<std::vector<double>> T, AT;
  for (int mode = 0; mode < 6; mode++) {
    const bool rotation = mode >= 3;
    const int d = mode % 3;
    if ((!rotation && d >= dim) || (rotation && dim == 2 && d != 2)) continue;
    for (int i = 0; i < nvec; i += 3) {
      const double p[3] = {xvec[i] - call[0], xvec[i + 1] - call[1], xvec[i + 2] - call[2]};
      double t[3] = {0.0, 0.0, 0.0};
      if (!rotation) t[d] = 1.0;
      else {    // e_d x p
        t[(d + 1) % 3] = -p[(d + 2) % 3];
        t[(d + 2) % 3] = p[(d + 1) % 3];
      }
      for (int k = 0; k < 3; k++) v[i + k] = mask[i + k] * t[k];
    }
    if (!(global_dot(v.data(), v.data()) > 0.0)) continue;
    probe(v.data(), Av.data());
    modes.push_back(mode);
    T.push_back(v);
    AT.push_back(Av);
  }
  // the least stiff combination: min |A T c|^2 / |T c|^2
  const int m = static_cast<int>(modes.size());
  if (m == 0) return;
  Eigen::MatrixXd GA(m, m), GT(m, m);
  for (int a = 0; a < m; a++)
    for (int b = 0; b < m; b++) {
      GA(a, b) = global_dot(AT[a].data(), AT[b].data());
      GT(a, b) = global_dot(T[a].data(), T[b].data());
    }
  GT += 1.0e-14 * GT.trace() * Eigen::MatrixXd::Identity(m, m);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(GA, GT);
  const double s = std::sqrt(std::max(0.0, eig.eigenvalues()(0)) / ref);
  if (!(s < SINGULAR_RATIO)) return;
  const Eigen::VectorXd w = eig.eigenvectors().col(0);
  double big = 0.0;
  for (int a = 0; a < m; a++) big = std::max(big, std::fabs(w(a)) * std::sqrt(GT(a, a)));
  std::string which;
  const char *axis = "xyz";
  for (int a = 0; a < m; a++)
    if (std::fabs(w(a)) * std::sqrt(GT(a, a)) >= 0.3 * big)
      which += fmt::format("{}{} {}", which.empty() ? "" : ", ",
                           modes[a] >= 3 ? "rotation about" : "translation along",
                           axis[modes[a] % 3]);
  error->all(FLERR, "{}: the tangent is singular: nothing holds the body against a rigid "
             "motion combining {} (or only a stiffness {:.2g} of a random direction's, below "
             "{:g}); hold points with fix setforce 0.0 0.0 0.0, a stiffer fix spring or a "
             "wall, or use min_style fire", CMD, which, s, SINGULAR_RATIO);
}

/* ----------------------------------------------------------------------
   block Jacobi: per point the 3x3 diagonal block of a bond-based body
   with each type's P-wave micromodulus, V_i c sum_j w_j xi (x) xi / |xi|^3,
   inverted on the point's free components
------------------------------------------------------------------------- */

void MinNospdNewton::build_preconditioner()
{
  const int nlocal = atom->nlocal;
  pinv.assign(9 * static_cast<size_t>(nlocal), 0.0);
  auto *pair = PairPeriNospdBase::find(force);
  FixNospdBonds *bonds = pair ? pair->bonds() : nullptr;
  const bool lists = bonds && bonds->bond_arrays_current() && bonds->bond_first;
  const double *cmod = bonds ? bonds->get_model().wave_micromodulus : nullptr;
  const double *vfrac = atom->vfrac;
  const int *type = atom->type;
  std::vector<double> B(9 * static_cast<size_t>(nlocal), 0.0);
  std::vector<char> have(nlocal, 0);
  double trace_sum = 0.0, count = 0.0;
  for (int i = 0; lists && i < nlocal && i < bonds->nbond_atoms; i++) {
    const double c = (cmod && cmod[type[i]] > 0.0 ? cmod[type[i]] : 1.0) * (vfrac ? vfrac[i] : 1.0);
    double *b = &B[9 * static_cast<size_t>(i)];
    for (int k = bonds->bond_first[i]; k < bonds->bond_first[i + 1]; k++) {
      double xi[3];
      bonds->bond_vector(i, k, xi);
      const double l2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
      if (!(l2 > 0.0)) continue;
      const double s = c * bonds->bond_w[k] / (l2 * std::sqrt(l2));
      for (int a = 0; a < 3; a++)
        for (int e = 0; e < 3; e++) b[3 * a + e] += s * xi[a] * xi[e];
    }
    const double tr = b[0] + b[4] + b[8];
    if (tr > 0.0) {
      have[i] = 1;
      trace_sum += tr / 3.0;
      count += 1.0;
    }
  }
  double sums[2] = {trace_sum, count}, all[2];
  MPI_Allreduce(sums, all, 2, MPI_DOUBLE, MPI_SUM, world);
  const double fallback = all[1] > 0.0 ? all[0] / all[1] : 1.0;
  for (int i = 0; i < nlocal; i++) {
    double b[9];
    for (int k = 0; k < 9; k++) b[k] = have[i] ? B[9 * static_cast<size_t>(i) + k] : 0.0;
    if (!have[i]) b[0] = b[4] = b[8] = fallback;
    // held components: identity rows and columns, zeroed after inversion
    const double *m = &mask[3 * static_cast<size_t>(i)];
    for (int a = 0; a < 3; a++)
      if (m[a] == 0.0)
        for (int e = 0; e < 3; e++) b[3 * a + e] = b[3 * e + a] = (a == e) ? 1.0 : 0.0;
    const double det = b[0] * (b[4] * b[8] - b[5] * b[7]) - b[1] * (b[3] * b[8] - b[5] * b[6]) +
        b[2] * (b[3] * b[7] - b[4] * b[6]);
    const double tr = b[0] + b[4] + b[8];
    double *p = &pinv[9 * static_cast<size_t>(i)];
    if (std::fabs(det) > 1.0e-12 * tr * tr * tr) {
      p[0] = (b[4] * b[8] - b[5] * b[7]) / det;
      p[1] = (b[2] * b[7] - b[1] * b[8]) / det;
      p[2] = (b[1] * b[5] - b[2] * b[4]) / det;
      p[3] = (b[5] * b[6] - b[3] * b[8]) / det;
      p[4] = (b[0] * b[8] - b[2] * b[6]) / det;
      p[5] = (b[2] * b[3] - b[0] * b[5]) / det;
      p[6] = (b[3] * b[7] - b[4] * b[6]) / det;
      p[7] = (b[1] * b[6] - b[0] * b[7]) / det;
      p[8] = (b[0] * b[4] - b[1] * b[3]) / det;
    } else {    // a family in a line or a plane: the diagonal alone
      for (int a = 0; a < 3; a++) p[4 * a] = b[4 * a] > 0.0 ? 1.0 / b[4 * a] : 1.0 / fallback;
    }
    for (int a = 0; a < 3; a++)
      for (int e = 0; e < 3; e++) p[3 * a + e] *= m[a] * m[e];
  }
}

/* ----------------------------------------------------------------------
   the surrogate's factor is kept from one minimize (load step) to the
   next while the families, the intact bonds and the held dofs are the
   same: its rows follow the atoms by tag, whatever order they have now
------------------------------------------------------------------------- */

void MinNospdNewton::prepare_surrogate()
{
  const int nlocal = atom->nlocal;
  auto *pair = PairPeriNospdBase::find(force);
  FixNospdBonds *bonds = pair ? pair->bonds() : nullptr;
  const bool lists = bonds && bonds->bond_arrays_current() && bonds->bond_first;
  // what the factor depends on
  double key[3] = {0.0, 0.0, 0.0}, all[3];
  const tagint *tag = atom->tag;
  for (int i = 0; i < nvec; i++) key[0] += mask[i] * hashed(tag[i / 3], i % 3);
  if (lists) key[1] = bonds->bond_first[std::min(nlocal, bonds->nbond_atoms)];
  key[2] = bonds ? static_cast<double>(bonds->families_serial) : -1.0;
  MPI_Allreduce(key, all, 3, MPI_DOUBLE, MPI_SUM, world);
  bool same = surrogate_factored && all[0] == surrogate_key[0] && all[1] == surrogate_key[1] &&
      all[2] == surrogate_key[2] && static_cast<int>(surrogate_tags.size()) == nlocal;
  // this order's row of each cached row
  surrogate_row.assign(nlocal, -1);
  for (int k = 0; same && k < nlocal; k++) {
    const int i = atom->map(surrogate_tags[k]);
    if (i < 0 || i >= nlocal || surrogate_row[i] >= 0) same = false;
    else surrogate_row[i] = k;
  }
  int ok = same ? 1 : 0, every = 0;
  MPI_Allreduce(&ok, &every, 1, MPI_INT, MPI_MIN, world);
  if (every) return;
  for (int k = 0; k < 3; k++) surrogate_key[k] = all[k];
  surrogate_tags.assign(tag, tag + nlocal);
  for (int i = 0; i < nlocal; i++) surrogate_row[i] = i;
  surrogate_factored = build_surrogate(bonds, lists);
  if (!surrogate_factored && comm->me == 0)
    error->warning(FLERR, "{}: the bond-based surrogate could not be factored; block Jacobi "
                   "instead", CMD);
}

bool MinNospdNewton::build_surrogate(FixNospdBonds *bonds, bool lists)
{
  const int nlocal = atom->nlocal;
  const double *cmod = bonds ? bonds->get_model().wave_micromodulus : nullptr;
  const double *vfrac = atom->vfrac;
  const int *type = atom->type;
  std::vector<NOSPD::SurrogatePreconditioner::Bond> list;
  auto modulus = [&](int i) { return cmod && cmod[type[i]] > 0.0 ? cmod[type[i]] : 1.0; };
  auto length = [](const double *v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  double **horizon = bonds ? bonds->get_model().horizon : nullptr;
  for (int i = 0; lists && horizon && i < nlocal && i < bonds->nbond_atoms; i++)
    for (int k = bonds->bond_first[i]; k < bonds->bond_first[i + 1]; k++) {
      NOSPD::SurrogatePreconditioner::Bond b;
      bonds->bond_vector(i, k, b.xi);
      const int j = bonds->bond_j[k];
      if (length(b.xi) > SURROGATE_REACH * horizon[type[i]][type[j]]) continue;
      b.i = i;
      b.j = j < nlocal ? j : nlocal;
      const double cij = j < nlocal ? 0.5 * (modulus(i) + modulus(j)) : modulus(i);
      b.c = cij * (vfrac ? vfrac[i] : 1.0) * bonds->bond_w[k];
      list.push_back(b);
    }
  const auto kind = nvec <= DIRECT_DOFS ? NOSPD::SurrogatePreconditioner::Kind::DIRECT
                                        : NOSPD::SurrogatePreconditioner::Kind::INCOMPLETE;
  int ok = surrogate.build(nlocal, list, mask.data(), kind) ? 1 : 0, all = 0;
  MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, world);
  return all == 1;
}

void MinNospdNewton::precondition(const double *r, double *z)
{
  if (precond == Precondition::SURROGATE && surrogate_factored) {
    const int n = nvec / 3;
    gather.resize(nvec);
    scatter.resize(nvec);
    for (int i = 0; i < n; i++)
      for (int a = 0; a < 3; a++) gather[3 * surrogate_row[i] + a] = r[3 * i + a];
    surrogate.apply(gather.data(), scatter.data());
    for (int i = 0; i < n; i++)
      for (int a = 0; a < 3; a++) z[3 * i + a] = scatter[3 * surrogate_row[i] + a];
    return;
  }
  for (int i = 0; i < nvec; i += 3) {
    const double *p = &pinv[3 * static_cast<size_t>(i)];
    for (int a = 0; a < 3; a++)
      z[i + a] = p[3 * a] * r[i] + p[3 * a + 1] * r[i + 1] + p[3 * a + 2] * r[i + 2];
  }
}

/* ----------------------------------------------------------------------
   the largest step fraction that moves no atom by more than min_modify
   dmax (LAMMPS's meaning: the most an atom moves in one iteration)
------------------------------------------------------------------------- */

double MinNospdNewton::step_cap() const
{
  double big = 0.0, all = 0.0;
  for (int i = 0; i < nvec; i++) big = std::max(big, std::fabs(du[i]));
  MPI_Allreduce(&big, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  return all > dmax ? dmax / all : 1.0;
}

/* ----------------------------------------------------------------------
   backtracking (Armijo): x = x0 + alpha du, alpha halved until the
   residual falls by the fraction ARMIJO alpha or, where the forces are an
   energy's gradient (the load step's incremental potential under
   plasticity), the energy falls by ARMIJO alpha of its slope: the energy
   guides a step across a yield surface, the residual the rounding-limited
   tail; 0 when accepted.  On failure x is x0 again, with its forces.
------------------------------------------------------------------------- */

int MinNospdNewton::line_search(double rnorm, double &alpha)
{
  alpha = step_cap();
  // slope of the energy along du: -f . du (pe and f as LAMMPS sums them)
  const double *vfrac = atom->vfrac;
  double slope = 0.0;
  for (int i = 0; i < nvec; i++) slope -= r0[i] / (vfrac ? vfrac[i / 3] : 1.0) * du[i];
  double all = 0.0;
  MPI_Allreduce(&slope, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  const bool by_energy = potential && all < 0.0;
  const double e0 = ecurrent;
  std::vector<double> r;
  for (int trial = 0; trial < MAX_BACKTRACK; trial++) {
    for (int i = 0; i < nvec; i++) xvec[i] = x0[i] + alpha * du[i];
    ecurrent = energy_force(1);
    neval++;
    residual(r);
    const double rn = std::sqrt(global_dot(r.data(), r.data()));
    if (std::isfinite(rn) && rn <= (1.0 - ARMIJO * alpha) * rnorm) return 0;
    if (by_energy && std::isfinite(rn) && ecurrent <= e0 + ARMIJO * alpha * all) return 0;
    alpha *= 0.5;
  }
  for (int i = 0; i < nvec; i++) xvec[i] = x0[i];
  ecurrent = energy_force(1);
  neval++;
  alpha = 0.0;
  // the atoms may have been sorted or exchanged: per-atom state anew
  residual(r0);
  if (precond == Precondition::SURROGATE) prepare_surrogate();
  if (precond == Precondition::JACOBI || !surrogate_factored) build_preconditioner();
  return 1;
}

/* ----------------------------------------------------------------------
   min_modify tangent_check: the operator the Krylov solves apply (laws'
   tangents where offered) against central differences of the forces
   themselves along a fixed random direction; relative difference
------------------------------------------------------------------------- */

double MinNospdNewton::check_tangent()
{
  const tagint *tag = atom->tag;
  std::vector<double> v(nvec), lin(nvec), plus(nvec);
  for (int i = 0; i < nvec; i++) v[i] = mask[i] * hashed(tag[i / 3], i % 3);
  auto *pair = PairPeriNospdBase::find(force);
  if (pair) pair->begin_linearization();
  const double h = probe(v.data(), lin.data());
  if (pair) pair->end_linearization();
  // central: r0 - r(x0 + h v) and r0 - r(x0 - h v), each over h
  probe(v.data(), plus.data());
  for (int i = 0; i < nvec; i++) v[i] = -v[i];
  std::vector<double> minus(nvec);
  probe(v.data(), minus.data());
  double d[2] = {0.0, 0.0}, all[2];
  for (int i = 0; i < nvec; i++) {
    const double central = 0.5 * (plus[i] - minus[i]);
    d[0] += (lin[i] - central) * (lin[i] - central);
    d[1] += central * central;
  }
  MPI_Allreduce(d, all, 2, MPI_DOUBLE, MPI_SUM, world);
  force_no_reneighbor();    // the state of x0 again, for the linearization
  (void) h;
  return all[1] > 0.0 ? std::sqrt(all[0] / all[1]) : 0.0;
}

/* ---------------------------------------------------------------------- */

NOSPD::KrylovResult MinNospdNewton::solve(double eta)
{
  // the probes see the laws' consistent tangents where they offer them
  auto *pair = PairPeriNospdBase::find(force);
  int nlin = pair ? pair->begin_linearization() : 0, all = 0;
  MPI_Allreduce(&nlin, &all, 1, MPI_INT, MPI_SUM, world);
  law_tangent_points = all;
  auto A = [&](const double *v, double *out) { probe(v, out); };
  auto M = [&](const double *r, double *z) { precondition(r, z); };
  auto dot = [&](const double *a, const double *b) { return global_dot(a, b); };
  NOSPD::KrylovResult kr = use_cg
      ? NOSPD::cg(nvec, r0.data(), du, A, M, dot, eta, max_krylov)
      : NOSPD::gmres(nvec, r0.data(), du, A, M, dot, eta, restart, max_krylov);
  // negative curvature at the start: GMRES needs no definiteness
  if (use_cg && kr.indefinite && kr.iterations <= 1)
    kr = NOSPD::gmres(nvec, r0.data(), du, A, M, dot, eta, restart, max_krylov);
  if (pair) pair->end_linearization();
  last_krylov += kr.iterations;
  krylov_total += kr.iterations;
  return kr;
}

/* ----------------------------------------------------------------------
   one Newton step from x0 with residual r0: the inexact solve, and when
   no step along it lowers the merit (a loose solve, or a directional
   difference across a yield surface) a tight solve, then the
   preconditioned residual itself; 0 when a step was taken
------------------------------------------------------------------------- */

int MinNospdNewton::newton_step(double rnorm, double eta)
{
  last_krylov = 0;
  NOSPD::KrylovResult kr = solve(eta);
  int fail = line_search(rnorm, alpha_final);
  const char *how = use_cg ? "cg" : "gmres";
  if (fail && eta > RETRY_FORCING) {
    kr = solve(RETRY_FORCING);
    fail = line_search(rnorm, alpha_final);
    how = "tight";
  }
  if (fail) {
    precondition(r0.data(), du);
    fail = line_search(rnorm, alpha_final);
    how = "residual";
  }
  if (comm->me == 0)
    utils::logmesg(lmp, "  nospd/newton {}: |V f| {:.6g}, {} iterations ({}, {:.2g} of {:.2g}), "
                   "step {:.4g}{}\n", niter, rnorm, last_krylov, how, kr.residual / kr.initial,
                   eta, alpha_final,
                   law_tangent_points ? fmt::format(", law tangent at {} points",
                                                    law_tangent_points) : "");
  if (fail && comm->me == 0 && rnorm > ROUNDING_FLOOR * residual_history.front())
    error->warning(FLERR, "{}: no step lowers the residual |V f| = {:.6g} ({:.2g} of its "
                   "start), neither along the Newton direction (Krylov {:.2g} of its start) "
                   "nor along the preconditioned residual: split the load into smaller steps, "
                   "raise min_modify krylov_max, or use min_style fire", CMD, rnorm,
                   rnorm / residual_history.front(), kr.residual / kr.initial);
  return fail;
}

/* ---------------------------------------------------------------------- */

int MinNospdNewton::iterate(int maxiter)
{
  const double dvalue = std::max(domain->prd[0], std::max(domain->prd[1], domain->prd[2]));
  delta = fd_step > 0.0 ? fd_step : 1.5e-8 * dvalue;
  newton_steps = krylov_total = last_krylov = 0;
  residual_history.clear();
  for (int i = 0; i < nvec; i++) x0[i] = xvec[i];
  fix_minimize->store_box();
  check_settings();
  find_free_dofs();
  check_singular();
  force_no_reneighbor();    // the state of x, not of the last probe
  if (neval >= update->max_eval) return MAXEVAL;

  auto fnorm_below = [&]() {
    if (!(update->ftol > 0.0)) return false;
    const double f2 = normstyle == MAX ? fnorm_max() : normstyle == INF ? fnorm_inf() : fnorm_sqr();
    return f2 < update->ftol * update->ftol;
  };
  double eta = eta_max, rprev = 0.0;
  int slow = 0;
  for (int iter = 0; iter < maxiter; iter++) {
    if (fnorm_below()) return FTOL;
    if (timer->check_timeout(niter)) return TIMEOUT;
    const bigint ntimestep = ++update->ntimestep;
    niter++;
    eprevious = ecurrent;
    for (int i = 0; i < nvec; i++) x0[i] = xvec[i];
    fix_minimize->store_box();    // x0's box, for reset_coords after a rebuild
    residual(r0);
    const double rnorm = std::sqrt(global_dot(r0.data(), r0.data()));
    residual_history.push_back(rnorm);
    if (rnorm == 0.0) return ZEROFORCE;
    // Eisenstat-Walker (choice 2, safeguarded): loosely far away, tightly near
    if (rprev > 0.0) {
      const double ew = 0.9 * (rnorm / rprev) * (rnorm / rprev);
      const double safe = 0.9 * eta * eta;
      eta = std::max(eta_min, std::min(eta_max, std::max(ew, safe > 0.1 ? safe : 0.0)));
      // at the rounding floor of the forces steps stall: stop there
      slow = rnorm > STALL * rprev ? slow + 1 : 0;
      if (slow >= 1 && rnorm < ROUNDING_FLOOR * residual_history.front()) {
        if (comm->me == 0)
          utils::logmesg(lmp, "  nospd/newton: |V f| {:.3g} is {:.2g} of its start, the "
                         "rounding of the forces: no smaller force tolerance can be met\n",
                         rnorm, rnorm / residual_history.front());
        return ZEROALPHA;
      }
    }
    rprev = rnorm;
    if (precond == Precondition::SURROGATE) prepare_surrogate();
    if (precond == Precondition::JACOBI || !surrogate_factored) build_preconditioner();
    if (tangent_check) {
      const double rel = check_tangent();
      if (comm->me == 0)
        utils::logmesg(lmp, "  nospd/newton {}: tangent check {:.3g}\n", niter, rel);
    }
    newton_steps++;
    if (newton_step(rnorm, eta)) return ZEROALPHA;
    if (neval >= update->max_eval) return MAXEVAL;
    if (std::fabs(ecurrent - eprevious) <
        update->etol * 0.5 * (std::fabs(ecurrent) + std::fabs(eprevious) + EPS_ENERGY))
      return ETOL;
    if (fnorm_below()) return FTOL;
    if (output->next == ntimestep) {
      timer->stamp();
      output->write(ntimestep);
      timer->stamp(Timer::OUTPUT);
    }
  }
  return MAXITER;
}

/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   What the classical and bond-associated styles share (PairPeriNospdBase).
------------------------------------------------------------------------- */

#include "pair_peri_nospd_base.h"

#include "atom.h"
#include "citeme.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "memory.h"
#include "modify.h"

#include "nospd_bond_sums.h"
#include "nospd_input.h"
#include "nospd_simd.h"
#include "nospd_threads.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;
using NOSPD::Stab;

static const char cite_nospd[] =
    "pair peri/nospd: doi:10.1007/s10659-007-9125-1\n\n"
    "@Article{Silling07,\n"
    " author = {S. A. Silling and M. Epton and O. Weckner and J. Xu and E. Askari},\n"
    " title = {Peridynamic States and Constitutive Modeling},\n"
    " journal = {J.~Elasticity},\n"
    " year =    2007,\n"
    " volume =  88,\n"
    " pages =   {151--184}\n"
    "}\n\n";

// first value of the settings in a restart file: the layout of what follows
// (files written before it existed start with the strain law, 0..8); the
// layout before damaged_leverage (0x4e530002) is read as without that limit,
// those before drucker_prager (up to 0x4e530003) without it
static constexpr int RESTART_LAYOUT = 0x4e530005;
static constexpr int RESTART_LAYOUT_V5 = 0x4e530005;    // ThermalLaw's conduction
static constexpr int RESTART_LAYOUT_V4 = 0x4e530004;
static constexpr int RESTART_LAYOUT_V3 = 0x4e530003;
static constexpr int RESTART_LAYOUT_V2 = 0x4e530002;

/* ---------------------------------------------------------------------- */

PairPeriNospdBase::PairPeriNospdBase(LAMMPS *lmp) :
    Pair(lmp), fix_bonds(nullptr), strain_law(Law::SMALL), plane_mode(Plane::NONE),
    stab(Stab::SILLING), stab_param(0.5), fit_quadratic(false),
    influence(NospdBondModel::CONSTANT), thickness(1.0), singular_tol(1.0e-4), damaged_tol(0.1),
    damaged_leverage(0.5),
    youngs(nullptr), poisson(nullptr), g0(nullptr), stab_scalar(nullptr), cut(nullptr),
    nmax_work(0), bmat(nullptr), tmat(nullptr), moments(nullptr), qmat(nullptr), qsums(nullptr),
    comm_tensors(1)
{
  user_materials = std::make_unique<NospdUserMaterials>(lmp);
  temperature_kind = TEMP_NONE;
  temperature_index = -1;
  temperature_base = nullptr;
  if (lmp->citeme) lmp->citeme->add(cite_nospd);
  single_enable = 0;
  restartinfo = 1;
  one_coeff = 0;
  manybody_flag = 1;
  no_virial_fdotr_compute = 1;
  comm_forward = NOSPD::BREC;
}

/* ---------------------------------------------------------------------- */

PairPeriNospdBase::~PairPeriNospdBase()
{
  if (fix_bonds && modify->get_fix_by_id(FixNospdBonds::ID)) modify->delete_fix(FixNospdBonds::ID);
  memory->destroy(bmat);
  memory->destroy(tmat);
  memory->destroy(moments);
  memory->destroy(temperature_base);
  memory->destroy(qmat);
  memory->destroy(qsums);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(cut);
    memory->destroy(youngs);
    memory->destroy(poisson);
    memory->destroy(g0);
    memory->destroy(stab_scalar);
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  memory->create(cutsq, n, n, "pair:cutsq");
  memory->create(cut, n, n, "pair:cut");
  memory->create(youngs, n, "pair:youngs");
  memory->create(poisson, n, "pair:poisson");
  memory->create(g0, n, "pair:g0");
  memory->create(stab_scalar, n, "pair:stab_scalar");
  for (int i = 0; i < n; i++) {
    youngs[i] = poisson[i] = g0[i] = stab_scalar[i] = 0.0;
    for (int j = 0; j < n; j++) {
      setflag[i][j] = 0;
      cut[i][j] = 0.0;
    }
  }
  lame.assign(n, NOSPD::Lame{0.0, 0.0, 0.0});
  material_name.assign(n, std::string());
  flow.assign(n, NOSPD::FlowLaw());
  thermal.assign(n, NOSPD::ThermalLaw());
  drucker_prager.assign(n, NOSPD::DruckerPrager());
  inelastic.assign(n, 0);
  user_materials->resize(atom->ntypes);
}

/* ----------------------------------------------------------------------
   pair_style peri/nospd keyword value ...
------------------------------------------------------------------------- */

void PairPeriNospdBase::settings(int narg, char **arg)
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  // a pair_style command naming the style in place calls settings() again on
  // the same instance: every keyword not given takes its default again, so
  // that a line means the same model whatever came before it
  strain_law = Law::SMALL;
  plane_mode = Plane::NONE;
  stab = Stab::SILLING;
  stab_param = 0.5;
  fit_quadratic = false;
  influence = NospdBondModel::CONSTANT;
  thickness = 1.0;
  singular_tol = 1.0e-4;
  damaged_tol = 0.1;
  damaged_leverage = 0.5;
  damaged_refit = false;
  temperature_kind = TEMP_NONE;
  temperature_name.clear();
  SettingsGiven given;
  for (int iarg = 0; iarg < narg;) {
    int next = model_keyword(cmd, narg, arg, iarg);
    if (next < 0) next = geometry_keyword(cmd, narg, arg, iarg, given);
    if (next < 0)
      error->all(FLERR, "{}: unknown keyword '{}'{}", cmd, arg[iarg],
                 (strcmp(arg[iarg], "form") == 0 || strcmp(arg[iarg], "ratio") == 0)
                     ? " (a keyword of peri/nospd/hs)" : "");
    iarg = next;
  }
  check_settings(cmd, given);
}

/* ----------------------------------------------------------------------
   one keyword of the law and its stabilization (strain, stabilization,
   stabilization/fit, influence) at arg[iarg]: the index after its values,
   -1 if the keyword is not one of these
------------------------------------------------------------------------- */

int PairPeriNospdBase::model_keyword(const std::string &cmd, int narg, char **arg, int iarg)
{
  const std::string key = arg[iarg];
  auto need = [&](int n) {
    if (iarg + n >= narg) error->all(FLERR, "{}: keyword {} needs {} value(s)", cmd, key, n);
  };
  if (key == "strain") {
    need(1);
    const std::string v = arg[iarg + 1];
    if (v == "small") strain_law = Law::SMALL;
    else if (v == "finite" || v == "corotational") strain_law = Law::COROTATIONAL;
    else if (v == "svk") strain_law = Law::SVK;
    else if (v == "neohookean") strain_law = Law::NEOHOOKE;
    else if (v == "hencky") strain_law = Law::HENCKY;
    else if (v == "formula") strain_law = Law::USER;
    else if (v == "umat") strain_law = Law::UMAT_SMALL;
    else if (v == "umat/finite") strain_law = Law::UMAT_FINITE;
    else error->all(FLERR, "{}: unknown strain '{}' (small, finite, svk, neohookean, hencky, "
                    "formula, umat, umat/finite)", cmd, v);
    iarg += 2;
  } else if (key == "stabilization") {
    need(1);
    const std::string v = arg[iarg + 1];
    iarg += 2;
    if (v == "none") stab = Stab::NONE;
    else if (v == "wan") stab = Stab::WAN;
    else if (v == "silling" || v == "hourglass") {
      if (iarg >= narg) error->all(FLERR, "{}: stabilization {} needs a value", cmd, v);
      stab = (v == "silling") ? Stab::SILLING : Stab::HOURGLASS;
      stab_param = NOSPD_INPUT::real(error, cmd, "stabilization " + v, arg[iarg]);
      if (!(stab_param > 0.0))
        error->all(FLERR, "{}: stabilization {} value must be > 0, got {}", cmd, v, arg[iarg]);
      iarg++;
    } else
      error->all(FLERR, "{}: unknown stabilization '{}' (none, silling G, hourglass C, wan)",
                 cmd, v);
  } else if (key == "stabilization/fit") {
    need(1);
    const std::string v = arg[iarg + 1];
    if (v == "linear") fit_quadratic = false;
    else if (v == "quadratic") fit_quadratic = true;
    else error->all(FLERR, "{}: unknown stabilization/fit '{}' (linear, quadratic)", cmd, v);
    iarg += 2;
  } else if (key == "influence") {
    need(1);
    const std::string v = arg[iarg + 1];
    if (v == "constant") influence = NospdBondModel::CONSTANT;
    else if (v == "inverse") influence = NospdBondModel::INVERSE;
    else error->all(FLERR, "{}: unknown influence '{}' (constant, inverse)", cmd, v);
    iarg += 2;
  } else {
    return -1;
  }
  return iarg;
}

/* ----------------------------------------------------------------------
   one keyword of the geometry, tolerances and temperature (plane,
   thickness, singular_tol, damaged_tol, damaged_leverage, damaged_state,
   temperature):
   the index after its values, -1 if the keyword is not one of these
------------------------------------------------------------------------- */

int PairPeriNospdBase::geometry_keyword(const std::string &cmd, int narg, char **arg, int iarg,
                                    SettingsGiven &given)
{
  const std::string key = arg[iarg];
  auto need = [&](int n) {
    if (iarg + n >= narg) error->all(FLERR, "{}: keyword {} needs {} value(s)", cmd, key, n);
  };
  if (key == "plane") {
    need(1);
    const std::string v = arg[iarg + 1];
    if (v == "strain") plane_mode = Plane::STRAIN;
    else if (v == "stress") plane_mode = Plane::STRESS;
    else error->all(FLERR, "{}: unknown plane '{}' (strain, stress)", cmd, v);
    given.plane = true;
    iarg += 2;
  } else if (key == "thickness") {
    need(1);
    thickness = NOSPD_INPUT::real(error, cmd, key, arg[iarg + 1]);
    if (!(thickness > 0.0)) error->all(FLERR, "{}: thickness must be > 0, got {}", cmd, arg[iarg + 1]);
    given.thickness = true;
    iarg += 2;
  } else if (key == "singular_tol" || key == "damaged_tol") {
    need(1);
    const double tol = NOSPD_INPUT::real(error, cmd, key, arg[iarg + 1]);
    if (!(tol > 0.0 && tol < 1.0))
      error->all(FLERR, "{}: {} must be in (0,1), got {}", cmd, key, arg[iarg + 1]);
    (key == "singular_tol" ? singular_tol : damaged_tol) = tol;
    (key == "singular_tol" ? given.singular : given.damaged) = true;
    iarg += 2;
  } else if (key == "damaged_leverage") {
    need(1);
    damaged_leverage = NOSPD_INPUT::real(error, cmd, key, arg[iarg + 1]);
    if (!(damaged_leverage > 0.0 && damaged_leverage <= 1.0))
      error->all(FLERR, "{}: damaged_leverage must be in (0,1] (1: no limit), got {}", cmd,
                 arg[iarg + 1]);
    iarg += 2;
  } else if (key == "damaged_state") {
    need(1);
    const std::string v = arg[iarg + 1];
    if (v == "carry") damaged_refit = false;
    else if (v == "refit") damaged_refit = true;
    else error->all(FLERR, "{}: damaged_state takes carry or refit, got '{}'", cmd, v);
    given.state = true;
    iarg += 2;
  } else if (key == "temperature") {
    need(1);
    const std::string v = arg[iarg + 1];
    if (v == "none") {
      temperature_kind = TEMP_NONE;
    } else if (utils::strmatch(v, "^d_.") && v.find(':') == std::string::npos) {
      temperature_kind = TEMP_PROPERTY;
    } else if (utils::strmatch(v, "^v_.")) {
      temperature_kind = TEMP_VARIABLE;
    } else
      error->all(FLERR, "{}: temperature needs d_name (a per-atom property of fix "
                 "property/atom), v_name (an atom-style variable) or none, got '{}'", cmd, v);
    temperature_name = (temperature_kind == TEMP_NONE) ? "" : v.substr(2);
    iarg += 2;
  } else {
    return -1;
  }
  return iarg;
}

/* ----------------------------------------------------------------------
   the settings together: tolerances, the quadratic fit's stabilization,
   2D-only keywords, the plane assumption's default
------------------------------------------------------------------------- */

void PairPeriNospdBase::check_settings(const std::string &cmd, const SettingsGiven &given)
{
  // a family that lost bonds is held to at least the intact families'
  // tolerance; singular_tol alone sets both (one tolerance, as given)
  if (!given.damaged && given.singular) damaged_tol = singular_tol;
  if (given.damaged && damaged_tol < singular_tol)
    error->all(FLERR, "{}: damaged_tol {} is below singular_tol {}: a family that lost bonds "
               "is held to at least the intact families' tolerance", cmd, damaged_tol,
               singular_tol);
  damaged_tol = std::max(damaged_tol, singular_tol);
  if (given.state && bond_associated())
    error->all(FLERR, "{}: damaged_state is a keyword of pair_style peri/nospd (the point's F "
               "F_c); the bond-associated style refits its bonds' families", cmd);
  if (fit_quadratic && stab != Stab::SILLING)
    error->all(FLERR, "{}: stabilization/fit quadratic applies to stabilization silling (its "
               "springs), not to stabilization {}", cmd,
               stab == Stab::NONE ? "none" : (stab == Stab::WAN ? "wan" : "hourglass"));
  // a 3D point volume is a volume: a thickness would be ignored without a word
  for (const auto &kw : {std::make_pair("plane", given.plane),
                        std::make_pair("thickness", given.thickness)})
    if (domain->dimension == 3 && kw.second)
      error->all(FLERR, "{}: keyword {} applies to 2D only (dimension 2)", cmd, kw.first);
  if (domain->dimension == 2 && !given.plane) plane_mode = Plane::STRAIN;
  if (domain->dimension == 3) plane_mode = Plane::NONE;
}

/* ---------------------------------------------------------------------- */

std::string PairPeriNospdBase::not_a_potential() const
{
  return stab == Stab::HOURGLASS ? "stabilization hourglass is not a potential" : "";
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::grow_work()
{
  // the quadratic fit's arrays come with the setting, grown with the rest
  if (atom->nmax <= nmax_work && (qmat != nullptr) == quadratic_active()) return;
  nmax_work = atom->nmax;
  memory->destroy(bmat);
  memory->destroy(tmat);
  memory->destroy(moments);
  memory->destroy(temperature_base);
  memory->create(temperature_base, nmax_work, "pair:temperature_base");
  // T^T with a spare row: the bond sums read a double past the last atom
  memory->create(bmat, nmax_work, NOSPD::BREC, "pair:bmat");
  memory->create(tmat, nmax_work + 1, 9, "pair:tmat");
  memset(bmat[0], 0, sizeof(double) * NOSPD::BREC * nmax_work);
  memset(tmat[0], 0, sizeof(double) * 9 * (nmax_work + 1));
  memory->create(moments, nmax_work, 6, "pair:moments");
  memory->destroy(qmat);
  memory->destroy(qsums);
  qmat = qsums = nullptr;
  if (quadratic_active()) {
    // Q's loads read a double past the last atom: a spare row
    memory->create(qmat, nmax_work + 1, NOSPD::QREC, "pair:qmat");
    memset(qmat[0], 0, sizeof(double) * NOSPD::QREC * (nmax_work + 1));
    memory->create(qsums, nmax_work, NOSPD::QSUMS, "pair:qsums");
  }
}

/* ----------------------------------------------------------------------
   Z = sum_j w z (x) z with z = U - H xi, from the moments of pass 1:
   Z = M_UU - H K H^T, since sum_j w U (x) xi = H K
------------------------------------------------------------------------- */

NOSPD::Mat3 PairPeriNospdBase::nonaffine_moment(int i, const Mat3 &H, const Mat3 &Ki) const
{
  const Mat3 M = NOSPD::load_sym(moments[i]);
  Mat3 K = Ki.inverse();
  if (domain->dimension == 2) K(2, 2) = 0.0;
  return M - H * K * H.transpose();
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::threaded_ranges(int nthreads, int n, const RangeFn &fn)
{
  const int nranges = NOSPD::range_count(nthreads, n);
  std::vector<Tally> tally(nranges);
  NOSPD::run_ranges(nranges, n, [&](int from, int to, int tid) { fn(from, to, tid, tally[tid]); });
  for (const Tally &t : tally) add_tally(t);
}

void PairPeriNospdBase::add_tally(const Tally &t)
{
  eng_vdwl += t.eng;
  for (int k = 0; k < 6; k++) virial[k] += t.virial[k];
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::tally_energy(int i, double e)
{
  if (eflag_global) eng_vdwl += e;
  if (eflag_atom) eatom[i] += e;
}

namespace {

// what pass 2 adds up per point, besides the bond lists
struct ForceOut {
  double *f;                 // 3 per atom (atom->f, flat)
  double *v;                 // 6 per atom in range order, with VIRIAL
};

// the hourglass pass over pairs (lists in pair order), points [from, to)
template <int VIRIAL>
NOSPD_KERNEL_CLONES void hourglass_pairs_kernel(const NOSPD::Positions &p,
                                                const NOSPD::PairOrder &po, const int *bj,
                                                const double *bw, const NOSPD::ForceTerms &ft,
                                                const double *vol, const double *inv_vol,
                                                int from, int to, double *f, double *v)
{
  NOSPD::hourglass_pair_sums<VIRIAL>(p, po, bj, bw, ft, vol, inv_vol, from, to, f, v);
}

/* forces of points [from, to); without VIRIAL the i-terms B_i sum_j w xi
   and S_i sum_j w U come from the moments rather than from every bond */
template <NOSPD::StabPass STAB, int VIRIAL>
NOSPD_KERNEL_CLONES void force_range_kernel(const NOSPD::Positions &p, const int *first,
                                            const int *bj, const double *bw,
                                            const NOSPD::ForceTerms &ft, const double *ximom,
                                            const double *umom, const double *qsums, int from,
                                            int to, const ForceOut &out)
{
  for (int i = from; i < to; i++) {
    double f[3], v[6];
    NOSPD::force_sums<STAB, VIRIAL>(p, {bj, bw, first[i], first[i + 1]}, ft, i, f, v);
    if (!VIRIAL) {
      // B and T are stored transposed: B(r, k) = Bt[3 k + r]
      const double *Bt = ft.B + NOSPD::BREC * i;
      const double *m = ximom + 3 * i;
      for (int r = 0; r < 3; r++) f[r] += Bt[r] * m[0] + Bt[3 + r] * m[1] + Bt[6 + r] * m[2];
      const double *u = umom + 3 * i;
      if (NOSPD::has_springs(STAB)) {
        const double si = Bt[9];    // the stabilization scalar
        for (int r = 0; r < 3; r++) f[r] += si * u[r];
      }
      if (STAB == NOSPD::StabPass::SILLING_QUADRATIC) {
        // - alpha_i Q_i sum_j w phi_q(xi)
        const double *Qi = ft.Q + NOSPD::QREC * i, *q = qsums + NOSPD::QSUMS * i + 27;
        for (int r = 0; r < 3; r++)
          for (int k = 0; k < 6; k++) f[r] -= Qi[3 * k + r] * q[k];
      } else if (STAB == NOSPD::StabPass::WAN) {
        const double *Tt = ft.T + 9 * i;
        for (int r = 0; r < 3; r++) f[r] += Tt[r] * u[0] + Tt[3 + r] * u[1] + Tt[6 + r] * u[2];
      }
    }
    for (int d = 0; d < 3; d++) out.f[3 * i + d] += f[d];
    if (VIRIAL)
      for (int k = 0; k < 6; k++) out.v[6 * (i - from) + k] = v[k];
  }
}

}    // namespace

/* ----------------------------------------------------------------------
   pass 2: f_i = sum_j w ((B_i + B_j) xi + (S_i + S_j) U)  [+ hourglass]
   (the bond sums: nospd_bond_sums.h)
------------------------------------------------------------------------- */

template <NOSPD::StabPass STAB, int VIRIAL> void PairPeriNospdBase::force_pass(int /*eflag*/)
{
  if (STAB == NOSPD::StabPass::HOURGLASS && fix_bonds->pairs_ordered()) return hourglass_pair_pass<VIRIAL>();
  for_ranges(atom->nlocal, true,
             [&](int from, int to, int, Tally &t) { force_range<STAB, VIRIAL>(from, to, t); });
}

template <NOSPD::StabPass STAB, int VIRIAL> void PairPeriNospdBase::force_range(int from, int to, Tally &t)
{
  if (to <= from) return;
  const NOSPD::ForceTerms ft{bmat[0], tmat[0], STAB == NOSPD::StabPass::SILLING_QUADRATIC ? qmat[0] : nullptr};
  std::vector<double> v(VIRIAL ? 6 * (to - from) : 0);
  force_range_kernel<STAB, VIRIAL>(positions, fix_bonds->bond_first, fix_bonds->bond_j,
                                   fix_bonds->bond_w, ft, fix_bonds->xi_moment[0],
                                   fix_bonds->u_moment[0], STAB == NOSPD::StabPass::SILLING_QUADRATIC ? qsums[0] : nullptr, from,
                                   to, {atom->f[0], v.data()});
  if (!VIRIAL) return;
  for (int i = from; i < to; i++) {
    const double *vi = v.data() + 6 * (i - from);
    if (vflag_global)
      for (int k = 0; k < 6; k++) t.virial[k] += vi[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom[i][k] += vi[k];
  }
}

/* ----------------------------------------------------------------------
   the hourglass pass visiting each pair of owned points once (one thread:
   the partner's force is a scatter); the lists are in the bonds fix's pair
   order, which this style asks for where it runs the hourglass on one
   thread (pair_order_usable)
------------------------------------------------------------------------- */

template <int VIRIAL> void PairPeriNospdBase::hourglass_pair_pass()
{
  const int nlocal = atom->nlocal;
  const double *vfrac = atom->vfrac;
  inv_volume.resize(nlocal);
  for (int i = 0; i < nlocal; i++) inv_volume[i] = vfrac[i] > 0.0 ? 1.0 / vfrac[i] : 0.0;
  std::vector<double> v(VIRIAL ? 6 * nlocal : 0, 0.0);
  const NOSPD::PairOrder po{fix_bonds->bond_first, fix_bonds->bond_pair, fix_bonds->bond_ghost};
  hourglass_pairs_kernel<VIRIAL>(positions, po, fix_bonds->bond_j, fix_bonds->bond_w,
                                 {bmat[0], tmat[0]}, vfrac, inv_volume.data(), 0, nlocal,
                                 atom->f[0], v.data());
  if (!VIRIAL) return;
  for (int i = 0; i < nlocal; i++) {
    const double *vi = v.data() + 6 * i;
    if (vflag_global)
      for (int k = 0; k < 6; k++) virial[k] += vi[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom[i][k] += vi[k];
  }
}

/* ---------------------------------------------------------------------- */

int PairPeriNospdBase::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                     int * /*pbc*/)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int i = list[ii];
    for (int k = 0; k < NOSPD::BREC; k++) buf[m++] = bmat[i][k];
    if (comm_tensors == 2)
      for (int k = 0; k < 9; k++) buf[m++] = tmat[i][k];
    if (qmat)
      for (int k = 0; k < NOSPD::QREC; k++) buf[m++] = qmat[i][k];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  const int last = first + n;
  for (int i = first; i < last; i++) {
    for (int k = 0; k < NOSPD::BREC; k++) bmat[i][k] = buf[m++];
    if (comm_tensors == 2)
      for (int k = 0; k < 9; k++) tmat[i][k] = buf[m++];
    if (qmat)
      for (int k = 0; k < NOSPD::QREC; k++) qmat[i][k] = buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    fwrite(&youngs[i], sizeof(double), 1, fp);
    fwrite(&poisson[i], sizeof(double), 1, fp);
    fwrite(&g0[i], sizeof(double), 1, fp);
    fwrite(&flow[i], sizeof(NOSPD::FlowLaw), 1, fp);
    fwrite(&thermal[i], sizeof(NOSPD::ThermalLaw), 1, fp);
    fwrite(&drucker_prager[i], sizeof(NOSPD::DruckerPrager), 1, fp);
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) fwrite(&cut[i][j], sizeof(double), 1, fp);
    }
  }
  // user materials only where the law needs them: older restarts stay readable
  if (user_law()) user_materials->write_restart(fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    if (me == 0) {
      utils::sfread(FLERR, &youngs[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &poisson[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &g0[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &flow[i], sizeof(NOSPD::FlowLaw), 1, fp, nullptr, error);
      const size_t bytes = restart_layout >= RESTART_LAYOUT_V5 ? sizeof(NOSPD::ThermalLaw)
                                                                : offsetof(NOSPD::ThermalLaw, k);
      utils::sfread(FLERR, &thermal[i], bytes, 1, fp, nullptr, error);
      if (restart_layout >= RESTART_LAYOUT_V4)
        utils::sfread(FLERR, &drucker_prager[i], sizeof(NOSPD::DruckerPrager), 1, fp, nullptr,
                      error);
    }
    MPI_Bcast(&drucker_prager[i], sizeof(NOSPD::DruckerPrager), MPI_BYTE, 0, world);
    MPI_Bcast(&flow[i], sizeof(NOSPD::FlowLaw), MPI_BYTE, 0, world);
    MPI_Bcast(&thermal[i], sizeof(NOSPD::ThermalLaw), MPI_BYTE, 0, world);
    MPI_Bcast(&youngs[i], 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&poisson[i], 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&g0[i], 1, MPI_DOUBLE, 0, world);
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        if (me == 0) utils::sfread(FLERR, &cut[i][j], sizeof(double), 1, fp, nullptr, error);
        MPI_Bcast(&cut[i][j], 1, MPI_DOUBLE, 0, world);
      }
    }
  }
  if (user_law()) user_materials->read_restart(fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::write_restart_settings(FILE *fp)
{
  const int layout = RESTART_LAYOUT;
  fwrite(&layout, sizeof(int), 1, fp);
  int iv[4] = {static_cast<int>(strain_law), static_cast<int>(plane_mode),
               static_cast<int>(stab), influence};
  // the quadratic fit in a bit of its own: files without it read as before
  if (fit_quadratic) iv[2] |= 32;
  if (damaged_refit) iv[2] |= 64;
  double dv[5] = {stab_param, thickness, singular_tol, damaged_tol, damaged_leverage};
  fwrite(iv, sizeof(int), 4, fp);
  fwrite(dv, sizeof(double), 5, fp);
  int tv[2] = {static_cast<int>(temperature_kind), static_cast<int>(temperature_name.size())};
  fwrite(tv, sizeof(int), 2, fp);
  fwrite(temperature_name.data(), 1, tv[1], fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospdBase::read_restart_settings(FILE *fp)
{
  int layout = 0;
  if (comm->me == 0) utils::sfread(FLERR, &layout, sizeof(int), 1, fp, nullptr, error);
  MPI_Bcast(&layout, 1, MPI_INT, 0, world);
  if (layout != RESTART_LAYOUT && layout != RESTART_LAYOUT_V4 && layout != RESTART_LAYOUT_V3 &&
      layout != RESTART_LAYOUT_V2)
    error->all(FLERR, "read_restart: the {} settings in this file were written by an older "
               "PERI-NOSPD plugin, whose layout this one cannot read: write the file again "
               "with this plugin", force->pair_style);
  int iv[4];
  double dv[5] = {0.0, 0.0, 0.0, 0.0, 1.0};
  restart_layout = layout;
  const int ndv = (layout == RESTART_LAYOUT_V2) ? 4 : 5;
  if (comm->me == 0) {
    utils::sfread(FLERR, iv, sizeof(int), 4, fp, nullptr, error);
    utils::sfread(FLERR, dv, sizeof(double), ndv, fp, nullptr, error);
  }
  MPI_Bcast(iv, 4, MPI_INT, 0, world);
  MPI_Bcast(dv, 5, MPI_DOUBLE, 0, world);
  int tv[2] = {0, 0};
  if (comm->me == 0) utils::sfread(FLERR, tv, sizeof(int), 2, fp, nullptr, error);
  MPI_Bcast(tv, 2, MPI_INT, 0, world);
  std::string tname(tv[1], ' ');
  if (comm->me == 0 && tv[1] > 0) utils::sfread(FLERR, &tname[0], 1, tv[1], fp, nullptr, error);
  if (tv[1] > 0) MPI_Bcast(&tname[0], tv[1], MPI_CHAR, 0, world);
  temperature_kind = static_cast<decltype(temperature_kind)>(tv[0]);
  temperature_name = tname;
  strain_law = static_cast<Law>(iv[0]);
  plane_mode = static_cast<Plane>(iv[1]);
  stab = static_cast<Stab>(iv[2] & 31);
  fit_quadratic = (iv[2] & 32) != 0;
  damaged_refit = (iv[2] & 64) != 0;
  influence = iv[3];
  stab_param = dv[0];
  thickness = dv[1];
  singular_tol = dv[2];
  damaged_tol = dv[3];
  damaged_leverage = dv[4];
}

/* ---------------------------------------------------------------------- */

double PairPeriNospdBase::memory_usage()
{
  // bmat (B^T and the stabilization scalar), tmat (with its spare row),
  // moments, temperature_base
  return ((double) nmax_work * (NOSPD::BREC + 9 + 6 + 1) + 9 + inv_volume.capacity()) *
      sizeof(double);
}

/* ---------------------------------------------------------------------- */

void *PairPeriNospdBase::extract(const char *name, int &dim)
{
  dim = 2;
  if (strcmp(name, "delta") == 0 || strcmp(name, "cut") == 0) return (void *) cut;
  return nullptr;
}

// pass 2 of the classical style; the Silling and hourglass passes also run on
// top of the bond-associated style's forces
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::NONE, 0>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::NONE, 1>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::SILLING, 0>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::SILLING, 1>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::HOURGLASS, 0>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::HOURGLASS, 1>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::WAN, 0>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::WAN, 1>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::SILLING_QUADRATIC, 0>(int);
template void LAMMPS_NS::PairPeriNospdBase::force_pass<NOSPD::StabPass::SILLING_QUADRATIC, 1>(int);

/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   pair_style peri/nospd, the classical correspondence step: F of every
   family (pass 1, the bonds fix), P through the material table (the
   constitutive pass), the bond forces with the stabilization (pass 2, the
   shared force pass of PairPeriNospdBase).
------------------------------------------------------------------------- */

#include "pair_peri_nospd.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "fix_nospd_bonds.h"
#include "update.h"

#include "nospd_bond_sums.h"
#include "nospd_simd.h"

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;
using NOSPD::Stab;

/* ---------------------------------------------------------------------- */

PairPeriNospd::PairPeriNospd(LAMMPS *lmp) : PairPeriNospdBase(lmp) {}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  grow_work();

  const bool linear_stab = (stab == Stab::SILLING || stab == Stab::WAN);
  double **mom = (eflag && linear_stab) ? moments : nullptr;
  positions = fix_bonds->padded_positions();
  for_ranges(atom->nlocal, true, [&](int from, int to, int, Tally &) {
    fix_bonds->compute_deformation(positions, mom, from, to);
  });
  if (quadratic_active()) quadratic_pass();
  constitutive_pass(eflag);
  comm->forward_comm(this);

  const bool virial = vflag_either;
  switch (stab) {
    case Stab::NONE:
      virial ? force_pass<NOSPD::StabPass::NONE, 1>(eflag) : force_pass<NOSPD::StabPass::NONE, 0>(eflag);
      break;
    case Stab::SILLING:
      if (quadratic_active()) virial ? force_pass<NOSPD::StabPass::SILLING_QUADRATIC, 1>(eflag) : force_pass<NOSPD::StabPass::SILLING_QUADRATIC, 0>(eflag);
      else virial ? force_pass<NOSPD::StabPass::SILLING, 1>(eflag) : force_pass<NOSPD::StabPass::SILLING, 0>(eflag);
      break;
    case Stab::HOURGLASS:
      virial ? force_pass<NOSPD::StabPass::HOURGLASS, 1>(eflag) : force_pass<NOSPD::StabPass::HOURGLASS, 0>(eflag);
      break;
    case Stab::WAN:
      virial ? force_pass<NOSPD::StabPass::WAN, 1>(eflag) : force_pass<NOSPD::StabPass::WAN, 0>(eflag);
      break;
  }
}

/* ----------------------------------------------------------------------
   the quadratic fit (nospd_stabilization.h): its sums per owned atom
------------------------------------------------------------------------- */

namespace {
NOSPD_KERNEL_CLONES void quadratic_range_kernel(const NOSPD::Positions &p, const int *first,
                                                const int *bj, const double *bw, int from, int to,
                                                double *out)
{
  for (int i = from; i < to; i++)
    NOSPD::quadratic_sums(p, {bj, bw, first[i], first[i + 1]}, i, out + NOSPD::QSUMS * i);
}
}    // namespace

void PairPeriNospd::quadratic_pass()
{
  for_ranges(atom->nlocal, true, [&](int from, int to, int, Tally &) {
    quadratic_range_kernel(positions, fix_bonds->bond_first, fix_bonds->bond_j,
                           fix_bonds->bond_w, from, to, qsums[0]);
  });
}

/* atom i's fit A = [H2 | Q]: H2 for B, alpha Q into qmat (columns), and
   e2 = sum_j w |U - A phi|^2 = sum_j w |U|^2 - A : N2 (the moments of the
   energy pass, else 0).  A family that lost bonds: its carried curvature
   (nospd_quadratic_carry.h).  Where the family has no quadratic fit, the
   linear one: H2 = H, Q = 0, e2 = sum_j w |U - H xi|^2. */
void PairPeriNospd::quadratic_spring(int i, const Mat3 &H, Mat3 &H2, double &e2, bool energy)
{
  const double *rec = fix_bonds->kinv2[i];
  const double alpha = stab_scalar[atom->type[i]];
  double *q = qmat[i];
  if (rec[NOSPD::QuadraticFit::PACKED] == NOSPD::CarriedQuadratic::FLAG) {
    const Mat3 Ki = NOSPD::load(fix_bonds->kinv[i]);
    const Eigen::Map<const NOSPD::Mat36> G(rec + NOSPD::CarriedQuadratic::G_AT);
    const NOSPD::Mat36 FcG = NOSPD::load(fix_bonds->fcarry[i]) * G;
    const Eigen::Map<const Eigen::Matrix<double, 3, 9>> N2(qsums[i]);
    const double elin = energy ? nonaffine_moment(i, H, Ki).trace() : 0.0;
    NOSPD::Mat36 Q;
    NOSPD::carried_quadratic_spring(H, FcG, N2, rec, Ki, elin, energy, H2, Q, e2);
    for (int k = 0; k < 6; k++)
      for (int r = 0; r < 3; r++) q[3 * k + r] = alpha * Q(r, k);
    return;
  }
  if (rec[NOSPD::QuadraticFit::PACKED] == 0.0) {
    H2 = H;
    for (int k = 0; k < NOSPD::QREC; k++) q[k] = 0.0;
    e2 = energy ? nonaffine_moment(i, H, NOSPD::load(fix_bonds->kinv[i])).trace() : 0.0;
    return;
  }
  const Eigen::Map<const Eigen::Matrix<double, 3, 9>> N2(qsums[i]);
  const Eigen::Matrix<double, 3, 9> A = NOSPD::quadratic_fit(N2, rec);
  H2 = A.leftCols<3>();
  for (int k = 0; k < 6; k++)
    for (int r = 0; r < 3; r++) q[3 * k + r] = alpha * A(r, 3 + k);
  e2 = 0.0;
  if (energy) e2 = moments[i][0] + moments[i][1] + moments[i][2] - A.cwiseProduct(N2).sum();
}

/* ----------------------------------------------------------------------
   per owned atom: P(F), W(F), and what pass 2 needs of it and its partners:
   B = P K^-1 - S H, plus S (Wan) or H (hourglass)
------------------------------------------------------------------------- */

void PairPeriNospd::constitutive_pass(int eflag)
{
  if (fix_bonds->nhistory) fill_base_temperature();
  // user laws keep scratch space (formulas) or may not be reentrant (UMATs)
  for_ranges(atom->nlocal, !user_law(),
             [&](int from, int to, int, Tally &t) { constitutive_range(from, to, eflag, t); });
  if (fix_bonds->nhistory) fix_bonds->trial_history_ready();
}

void PairPeriNospd::constitutive_range(int from, int to, int eflag, Tally &t)
{
  const int *type = atom->type;
  const int *singular = fix_bonds->singular;
  double **defgrad = fix_bonds->defgrad;
  double **kinv = fix_bonds->kinv;
  double **pk1 = fix_bonds->pk1;
  double *wdens = fix_bonds->energy_density;
  const int nhist = fix_bonds->nhistory;
  double **hist = fix_bonds->history;
  double **hist_trial = fix_bonds->history_trial;
  const bool minimizing = (update->whichflag == 2);
  NOSPD::PointEnv env;
  env.dt = minimizing ? 0.0 : update->dt;    // a minimize step is quasi-static: no rate

  for (int i = from; i < to; i++) {
    const int itype = type[i];
    const bool history_point = nhist && inelastic[itype];
    if (nhist && (!history_point || singular[i]))
      for (int k = 0; k < nhist; k++) hist_trial[i][k] = hist[i][k];
    if (singular[i]) {
      // no force state of its own: no stress, no stabilization
      for (int k = 0; k < 9; k++) tmat[i][k] = pk1[i][k] = 0.0;
      for (int k = 0; k < NOSPD::BREC; k++) bmat[i][k] = 0.0;
      if (qmat)
        for (int k = 0; k < NOSPD::QREC; k++) qmat[i][k] = 0.0;
      wdens[i] = 0.0;
      continue;
    }
    Mat3 F = NOSPD::load(defgrad[i]);
    const Mat3 H = F - Mat3::Identity();
    const Mat3 Ki = NOSPD::load(kinv[i]);
    Mat3 P;
    double W = 0.0;
    // F_c is I until a family loses bonds (nospd_carry.h)
    if (fix_bonds->lost_bonds(i)) carried_stress(i, F, P, W, env);
    else point_stress(i, F, P, W, env);
    NOSPD::store(F, defgrad[i]);
    NOSPD::store(P, pk1[i]);
    const Mat3 A = P * Ki;

    Mat3 B = A;
    double e2 = 0.0;    // with the quadratic fit: sum_j w |z2|^2
    if (stab == Stab::SILLING && qmat) {
      Mat3 H2;
      quadratic_spring(i, H, H2, e2, eflag);
      B -= stab_scalar[itype] * H2;
    } else if (stab == Stab::SILLING) {
      B -= stab_scalar[itype] * H;
    } else if (stab == Stab::WAN) {
      const Mat3 S = NOSPD::wan_tensor(lame[itype], domain->dimension, plane_mode, Ki);
      B -= S * H;
      store_transposed(S, tmat[i]);
    } else if (stab == Stab::HOURGLASS) {
      // c H: pass 2 needs the two ends' H xi only scaled by their c
      store_transposed(Mat3(stab_scalar[itype] * H), tmat[i]);
    }
    store_transposed(B, bmat[i]);
    bmat[i][STAB_SCALAR] = stab_scalar[itype];

    if (eflag) {
      double e = W;
      if (stab == Stab::SILLING || stab == Stab::WAN) {
        // 1/2 sum_j w z.S z = 1/2 S : Z
        const Mat3 Z = nonaffine_moment(i, H, Ki);
        if (stab == Stab::SILLING && qmat) e += 0.5 * stab_scalar[itype] * e2;
        else if (stab == Stab::SILLING) e += 0.5 * stab_scalar[itype] * Z.trace();
        else e += 0.5 * NOSPD::load(tmat[i]).cwiseProduct(Z).sum();    // S^T : Z = S : Z, Z symmetric
      }
      wdens[i] = e;
      // minimize solves one load step of the plasticity: its energy is the
      // step's incremental potential, W_e plus the dissipation of the step,
      // whose gradient the returned stress is (nospd_plasticity.h)
      if (minimizing && inelastic[itype] == POINT_PLASTIC)
        e += hist_trial[i][NOSPD::Hist::WORK] - hist[i][NOSPD::Hist::WORK];
      tally_energy(i, e, t);
    }
  }
}

/* ----------------------------------------------------------------------
   P and W of owned atom i whose family lost bonds: the law sees F F_c, its stress
   acts as P F_c^T (nospd_carry.h); F_c is planar in 2D, so F33 is the law's
------------------------------------------------------------------------- */

void PairPeriNospd::carried_stress(int i, Mat3 &F, Mat3 &P, double &W, const NOSPD::PointEnv &env)
{
  const Mat3 Fc = NOSPD::load(fix_bonds->fcarry[i]);
  Mat3 Fe = F * Fc;
  point_stress(i, Fe, P, W, env);
  if (domain->dimension == 2) F(2, 2) = Fe(2, 2);
  P = P * Fc.transpose();
}

/* ----------------------------------------------------------------------
   P and W of owned atom i at F (F33 written back in plane stress): by the
   type's law alone, the built-in inelastic point or its UMAT
------------------------------------------------------------------------- */

void PairPeriNospd::point_stress(int i, Mat3 &F, Mat3 &P, double &W, const NOSPD::PointEnv &env0)
{
  if (linearized && lin_row[i] >= 0) {
    const double *r = &lin[static_cast<size_t>(LIN_RECORD) * lin_row[i]];
    P = NOSPD::load(r + 9) +
        NOSPD::linear_step(Eigen::Map<const NOSPD::Tangent9>(r + 18), F - NOSPD::load(r));
    W = 0.0;    // a probe carries no energy (eflag is off)
    return;
  }
  const NOSPD::Material &law = *materials[atom->type[i]];
  NOSPD::UmatPoint pt;
  const NOSPD::MaterialEnv env = law_env(i, env0.dt, pt);
  const bool history = fix_bonds->nhistory > 0;
  const NOSPD::PointStatus st =
      law.stress(F, history ? fix_bonds->history[i] : nullptr,
                 history ? fix_bonds->history_trial[i] : nullptr, env, P, W);
  if (!st.ok()) material_failure(i, st, F);
}

/* ----------------------------------------------------------------------
   what owned atom i's law sees besides F: the step, and where the style
   keeps history its temperature, density and (a UMAT's) point data in pt
------------------------------------------------------------------------- */

NOSPD::MaterialEnv PairPeriNospd::law_env(int i, double dt, NOSPD::UmatPoint &pt)
{
  NOSPD::MaterialEnv env;
  env.dt = dt;
  if (fix_bonds->nhistory > 0) {
    env.T = temperature_base[i];
    env.rho = atom->rmass[i];
  }
  if (materials[atom->type[i]]->wants_point_data()) {
    pt = umat_env(i);
    env.umat = &pt;
  }
  return env;
}

/* ----------------------------------------------------------------------
   the points with history whose law offers its consistent tangent, at the
   F, P and history of the last force evaluation (carried families and
   singular points keep their law: the directional difference takes them)
------------------------------------------------------------------------- */

int PairPeriNospd::begin_linearization()
{
  const int nlocal = atom->nlocal;
  lin_row.assign(nlocal, -1);
  lin.clear();
  linearized = false;
  if (!fix_bonds || fix_bonds->nhistory == 0 || !fix_bonds->bond_arrays_current()) return 0;
  int n = 0;
  for (int i = 0; i < nlocal; i++) {
    const int itype = atom->type[i];
    if (!inelastic[itype] || fix_bonds->singular[i] || fix_bonds->lost_bonds(i)) continue;
    const Mat3 F = NOSPD::load(fix_bonds->defgrad[i]);
    NOSPD::UmatPoint pt;
    const NOSPD::MaterialEnv env = law_env(i, update->whichflag == 2 ? 0.0 : update->dt, pt);
    NOSPD::Tangent9 D;
    if (!materials[itype]->tangent(F, fix_bonds->history[i], env, D)) continue;
    lin.resize(static_cast<size_t>(LIN_RECORD) * (n + 1));
    double *r = &lin[static_cast<size_t>(LIN_RECORD) * n];
    for (int k = 0; k < 9; k++) {
      r[k] = F(k / 3, k % 3);
      r[9 + k] = fix_bonds->pk1[i][k];
    }
    Eigen::Map<NOSPD::Tangent9>(r + 18) = D;
    lin_row[i] = n++;
  }
  linearized = n > 0;
  return n;
}

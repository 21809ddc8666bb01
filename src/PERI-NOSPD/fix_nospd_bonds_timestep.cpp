/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's stable time step -- the estimate per type
   (bond-based value, stiffness bound), its log line and warning, and the
   likely cause named by the instability errors.
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

#include "nospd_bond_sums.h"
#include "nospd_plasticity.h"
#include "nospd_tensor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

/* ----------------------------------------------------------------------
   Stable time step estimate per type (NOSPD::StableStep): the bond-based
   value and a multiple (model.bound_margin) of the bound on the
   correspondence stiffness below, which sees K^-1.  The bound is
   sufficient; the margin is its measured slack (doc: "Stable time step").
   Logged when it changes; a warning when the time step exceeds it.
------------------------------------------------------------------------- */

void FixNospdBonds::report_stable_timestep()
{
  const double *c = model.wave_micromodulus;
  if (!c) return;
  const int ntypes = atom->ntypes, nlocal = atom->nlocal;
  const int *type = atom->type;
  const double *vfrac = atom->vfrac, *rho = atom->rmass;
  std::vector<double> dtmin(ntypes + 1, NOSPD::StableStep::NONE), dtbound(ntypes + 1, NOSPD::StableStep::NONE);
  for (int i = 0; i < nlocal; i++) {
    const int it = type[i];
    if (!(c[it] > 0.0)) continue;
    double s = 0.0;
    for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
      const int j = bond_j[b];
      const double dx = x0s[j][0] - x0s[i][0], dy = x0s[j][1] - x0s[i][1],
                   dz = x0s[j][2] - x0s[i][2];
      s += vfrac[j] * std::max(c[it], c[type[j]]) / sqrt(dx * dx + dy * dy + dz * dz);
    }
    dtmin[it] = std::min(dtmin[it], NOSPD::StableStep::bond_based(rho[i], s));
  }
  bound_stable_timesteps(dtbound);
  std::vector<double> bond_all(ntypes + 1), bound_all(ntypes + 1);
  MPI_Allreduce(dtmin.data(), bond_all.data(), ntypes + 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(dtbound.data(), bound_all.data(), ntypes + 1, MPI_DOUBLE, MPI_MIN, world);
  const bool changed = dt_est.take(bond_all, bound_all, model.bound_margin);
  // a run with no integrator moves nothing (quasi-static staggered steps
  // take the thermal step there): no mechanical bound to keep, and the
  // time step is checked at the first run that moves the points
  bool moves = false;
  for (const auto *f : modify->get_fix_list()) moves = moves || f->time_integrate;
  if (!changed && (update->dt == dt_est.checked || !moves)) return;
  if (moves) dt_est.checked = update->dt;
  if (comm->me != 0) return;
  std::string line = "PERI-NOSPD stable time step estimate:";
  for (int t = 1; t <= ntypes; t++) {
    if (dt_est.of(t) == 0.0) continue;
    // the estimate is the smaller of its two parts: say how it is made
    line += fmt::format(" type {} {:.4g}", t, dt_est.of(t));
    line += dt_est.bound_part(t) > 0.0
        ? fmt::format(" = min(bond-based {:.4g}, {:g} x stiffness bound {:.4g})",
                      dt_est.bond_part(t), model.bound_margin, dt_est.bound_part(t))
        : fmt::format(" (bond-based)");
  }
  const int worst = dt_est.smallest_type();
  if (!worst) return;
  const double est = dt_est.of(worst);
  if (changed) utils::logmesg(lmp, line + "\n");
  if (update->dt > est && moves)
    error->warning(FLERR, "Fix {}: timestep {:.4g} exceeds the stable estimate {:.4g} of atom "
                   "type {}: the run may blow up; use timestep {:.3g} or less",
                   style, update->dt, est, worst, 0.8 * est);
}

/* ----------------------------------------------------------------------
   A bound on the classical style's stiffness, linearized at the reference.
   Pass 2's force,
     f_i = sum_j w_ij ((P_i K_i^-1 + P_j K_j^-1) xi + s_i z_i + s_j z_j),
     z_k = U - H_k xi,  H_k = sum_l w_kl (u_l - u_k) (x) K_k^-1 xi_kl,
   with P = C : H, changes by at most R_i per unit displacement of every
   point (the sum over k of the 2-norms of df_i/du_k):
     R_i = |C| |K_i^-1 m_i| D_i + sum_j w_ij |C| |K_j^-1| |xi| D_j
           + sum_j w_ij (s_i (2 + |xi| D_i) + s_j (2 + |xi| D_j)),
   m_i = sum_j w_ij xi, and D_k = sum_l w_kl |K_k^-1 xi_kl| + |K_k^-1 m_k|
   the most H_k changes per unit displacement.  max_i R_i / rho_i bounds
   the largest eigenvalue of M^-1 K (a block Gershgorin bound), and velocity
   Verlet is stable below 2 / omega_max: dt_i = 2 sqrt(rho_i / R_i).
   Unlike the bond-based estimate it sees K^-1, so families cut short or
   flattened (nearly singular K) count as stiff as they are.  The quadratic
   fit's spring is bounded as Silling's (its H is the linear fit's here).
   The bond-associated style bounds its own force (model.family_rows:
   NOSPD::family_row_bounds of each pattern); its stabilization's springs
   are the classical ones, on the family's H.
------------------------------------------------------------------------- */

void FixNospdBonds::bound_stable_timesteps(std::vector<double> &dtmin)
{
  using NOSPD::Mat3;
  using NOSPD::Vec3;
  const double *cn = model.stress_norm;
  if (!cn) return;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const int *type = atom->type;
  const double *rho = atom->rmass;
  const bool plane = (model.dim == 2);
  auto bounded = [&](int i) {
    return !(model.active && !model.active[type[i]]) && cn[type[i]] > 0.0;
  };
  // D_i and |K_i^-1| of owned points, then of ghosts
  op_point.assign(2 * (size_t) nall, 0.0);
  std::vector<double> mlen(nlocal, 0.0);
  for (int i = 0; i < nlocal; i++) {
    if (singular[i] || !bounded(i)) continue;
    const Mat3 Ki = NOSPD::load(kinv[i]);
    Vec3 m = Vec3::Zero();
    double d = 0.0;
    for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
      const int j = bond_j[b];
      const Vec3 xi(x0s[j][0] - x0s[i][0], x0s[j][1] - x0s[i][1], x0s[j][2] - x0s[i][2]);
      m += bond_w[b] * xi;
      d += bond_w[b] * (Ki * xi).norm();
    }
    mlen[i] = (Ki * m).norm();
    op_point[2 * i] = d + mlen[i];
    op_point[2 * i + 1] = NOSPD::spectral_norm(Ki, plane);
  }
  comm_mode = 1;
  comm->forward_comm(this);
  comm_mode = 0;

  // the stabilization's stiffness of bond (k, l) at end k; none where K_k is singular
  auto spring = [&](int k, double len) {
    const double s = model.spring ? model.spring[type[k]] : 0.0;
    return NOSPD::spring_stiffness(model.spring_kind, s, cn[type[k]], op_point[2 * k + 1], len);
  };
  // the bond-associated style bounds its own force (its families' rows)
  std::vector<double> own_rows;
  const bool classical = !model.family_rows;
  if (!classical) model.family_rows(own_rows);
  for (int i = 0; i < nlocal; i++) {
    if (!bounded(i)) continue;
    const double Di = op_point[2 * i];
    double r = classical ? cn[type[i]] * mlen[i] * Di : own_rows[i];
    for (int b = bond_first[i]; b < bond_first[i + 1]; b++) {
      const int j = bond_j[b];
      const double dx = x0s[j][0] - x0s[i][0], dy = x0s[j][1] - x0s[i][1],
                   dz = x0s[j][2] - x0s[i][2];
      const double len = sqrt(dx * dx + dy * dy + dz * dz);
      const double Dj = op_point[2 * j], kj = op_point[2 * j + 1];
      r += bond_w[b] * ((classical ? cn[type[j]] * kj * len * Dj : 0.0) +
                        spring(i, len) * (2.0 + len * Di) + spring(j, len) * (2.0 + len * Dj));
    }
    dtmin[type[i]] = std::min(dtmin[type[i]], NOSPD::StableStep::from_row_bound(rho[i], r));
  }
}

/* the likely cause, for the instability errors of the fix and the pair style */

std::string FixNospdBonds::unstable_cause() const
{
  const double est = smallest_stable_timestep();
  if (est > 0.0 && update->dt > est)
    return fmt::format(": timestep {:.4g} exceeds the stable estimate {:.4g} (see the log); "
                       "reduce it", update->dt, est);
  const bool periodic = domain->xperiodic || domain->yperiodic || domain->zperiodic;
  if (est > 0.0)
    return fmt::format(" although timestep {:.4g} is below the stable estimate {:.4g}: look "
                       "for a stiff contact, an overlapping body or a large applied velocity{}; "
                       "or reduce the time step: the estimate is linearized at the reference "
                       "and leaves out contact, a stiffer inelastic tangent and rotated "
                       "families", update->dt, est,
                       periodic ? ", for displacements beyond half the periodic box length "
                                  "(a large shear or rotation of a periodic body)" : "");
  return "";
}

/* a stable run hands a user law finite deformations: a contact or an
   overlap does not make its value non-finite, the law does at that F */

std::string FixNospdBonds::user_law_cause(const std::string &law) const
{
  const double est = smallest_stable_timestep();
  if (est > 0.0 && update->dt > est) return unstable_cause();
  return fmt::format(": the {} itself gives it at this finite deformation; look in it for a "
                     "division by zero, a logarithm, root or power of a negative or zero "
                     "argument, or an overflow", law);
}

/* ----------------------------------------------------------------------
   Instability caught where it starts, before LAMMPS meets its results
   (non-numeric coordinates, lost atoms, too many neighbor bins): after the
   drift, every owned point must have a finite position and velocity, and a
   point that still has bonds must not have moved half its horizon in one
   step.  Velocity Verlet's drift is v dt, so the check costs one pass over
   the atoms and none over the bonds.
------------------------------------------------------------------------- */

void FixNospdBonds::post_integrate()
{
  if (ref_box.set && domain->triclinic) follow_box();    // before a flip at this step's exchange
  const int nlocal = atom->nlocal;
  if (nbond_atoms != nlocal) return;    // the bond arrays are being rebuilt
  double **x = atom->x, **v = atom->v;
  const int *type = atom->type;
  const double dt = update->dt;
  int bad = -1;
  bool nonfinite = false;
  double moved = 0.0;
  for (int i = 0; i < nlocal; i++) {
    if (model.active && !model.active[type[i]]) continue;
    const double v2 = v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2];
    if (!std::isfinite(v2) || !std::isfinite(x[i][0] + x[i][1] + x[i][2])) {
      bad = i;
      nonfinite = true;
      break;
    }
    if (bond_first[i + 1] == bond_first[i]) continue;    // a free fragment may fly
    const double half = 0.5 * model.horizon[type[i]][type[i]];
    if (v2 * dt * dt > half * half) {
      bad = i;
      moved = sqrt(v2) * dt;
      break;
    }
  }
  int anybad = (bad >= 0), all = 0;
  MPI_Allreduce(&anybad, &all, 1, MPI_INT, MPI_MAX, world);
  if (!all) return;
  const std::string cause = unstable_cause();
  if (bad >= 0) {
    if (nonfinite)
      error->one(FLERR, "Fix {}: step {}: atom {} has a non-finite position or velocity: the "
                 "run became unstable{}", style, update->ntimestep, atom->tag[bad], cause);
    error->one(FLERR, "Fix {}: step {}: atom {}, still bonded, moved {:.4g} in one step, more "
               "than half its horizon {:.4g}: the run became unstable{}", style,
               update->ntimestep, atom->tag[bad], moved, model.horizon[type[bad]][type[bad]], cause);
  }
  error->all(FLERR, "Fix {}: step {}: the run became unstable on another rank", style,
             update->ntimestep);
}

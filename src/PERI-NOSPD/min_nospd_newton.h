/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: min_style nospd/newton, an inexact Newton-Krylov solver of
   the force balance f(x) = 0 for quasi-static load steps.

   Each iteration solves A du = r with A = -dr/dx, r = V f (the force
   densities times the volumes: the gradient of the total energy, so A is
   symmetric wherever the forces derive from one), by preconditioned CG or
   GMRES (nospd_krylov.h); A v is a directional difference of the forces
   (Jacobian-free), so every pair style, law, stabilization and fix that
   adds or sets forces is linearized as it is.  The preconditioner is block
   Jacobi from a bond-based surrogate of the 3x3 diagonal blocks.  A
   backtracking line search on |r| guards poor starts.
------------------------------------------------------------------------- */

#ifdef MINIMIZE_CLASS
// clang-format off
MinimizeStyle(nospd/newton,MinNospdNewton);
// clang-format on
#else

#ifndef LMP_MIN_NOSPD_NEWTON_H
#define LMP_MIN_NOSPD_NEWTON_H

#include "min.h"
#include "nospd_krylov.h"
#include "nospd_surrogate.h"

#include <vector>

namespace LAMMPS_NS {

class MinNospdNewton : public Min {
 public:
  MinNospdNewton(class LAMMPS *);
  void init() override;
  void setup_style() override;
  void reset_vectors() override;
  int iterate(int) override;
  int modify_param(int, char **) override;
  // whether `minimize` runs this style (the checks that guard CG and
  // damped dynamics skip it: it needs no potential and takes no dmax step)
  static bool selected(const class Update *update);

  // figures of the last minimize for tests and output (rank-independent)
  int newton_steps = 0, krylov_total = 0, last_krylov = 0;
  bigint law_tangent_points = 0;    // points whose probes took their law's tangent
  std::vector<double> residual_history;    // masked |V f| at each iterate

 protected:
  enum class Krylov { AUTO, CG, GMRES };
  Krylov krylov = Krylov::AUTO;
  bool use_cg = false;
  bool potential = true;    // the forces are an energy's gradient
  int restart = 50;           // GMRES(m)
  int max_krylov = 1000;      // operator applications per Newton step
  double eta_max = 0.1;       // Eisenstat-Walker forcing bounds
  double eta_min = 1.0e-8;
  double fd_step = 0.0;       // directional difference step (length); 0: automatic
  double delta = 0.0;         // the step in use for this minimize
  bool tangent_check = false;    // log the operator against central differences

  double *x0 = nullptr;    // positions at the start of the step (fix_minimize)
  double *du = nullptr;    // Newton correction (fix_minimize)
  std::vector<double> r0, mask, weight, pinv;
  enum class Precondition { JACOBI, SURROGATE };
  Precondition precond = Precondition::SURROGATE;
  // the factored surrogate, its rows' atoms by tag and what it was made of
  NOSPD::SurrogatePreconditioner surrogate;
  bool surrogate_factored = false;
  std::vector<tagint> surrogate_tags;
  std::vector<int> surrogate_row;    // [nlocal]: the row of each owned atom
  double surrogate_key[3] = {0.0, 0.0, 0.0};
  std::vector<double> gather, scatter;
  void prepare_surrogate();
  bool build_surrogate(class FixNospdBonds *, bool lists);

  double probe(const double *v, double *Av);
  void force_no_reneighbor();
  void residual(std::vector<double> &r);
  double global_dot(const double *a, const double *b) const;
  void check_settings();
  void find_free_dofs();
  void check_singular();
  void build_preconditioner();
  void precondition(const double *r, double *z);
  int line_search(double rnorm, double &alpha);
  NOSPD::KrylovResult solve(double eta);
  double check_tangent();
  int newton_step(double rnorm, double eta);
  double step_cap() const;
};

}    // namespace LAMMPS_NS

#endif
#endif

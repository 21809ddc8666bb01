/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(PERI_NEIGH/NOSPD,FixNospdBonds);
// clang-format on
#else

#ifndef LMP_FIX_NOSPD_BONDS_H
#define LMP_FIX_NOSPD_BONDS_H

#include "fix_peri_neigh.h"
#include "nospd_family_store.h"
#include "nospd_history_store.h"
#include "nospd_reference_box.h"
#include "nospd_quadratic_carry.h"
#include "nospd_stabilization.h"
#include "nospd_stable_step.h"

#include "nospd_bond_sums.h"

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace LAMMPS_NS {

// How the owning pair style weighs bonds: horizon per type pair and the
// influence function.  Set by the pair style before the first run.
struct NospdBondModel {
  enum Influence { CONSTANT, INVERSE };
  double **horizon = nullptr;    // [ntypes+1][ntypes+1]
  int influence = CONSTANT;
  int dim = 3;
  double singular_tol = 1.0e-4;    // det K / (tr K/dim)^dim below this: singular
  double damaged_tol = 0.1;        // the same for a family that lost bonds
  // a family that lost bonds is singular when one bond's leverage
  // w xi^T K^-1 xi exceeds this (1: never)
  double damaged_leverage = 0.5;
  // a family that loses bonds carries the refit's difference (F_c,
  // nospd_carry.h): the classical style, whose law sees F F_c
  bool carry = false;
  const int *active = nullptr;     // [ntypes+1]: 1 for the types the pair style owns
  double thickness = 1.0;          // 2D: the volumes are area x thickness
  // points closer than this fraction of their spacing (from the volume) are
  // an error: overlapping create_atoms, a lattice written twice
  double coincident_fraction = 0.01;
  // [ntypes+1]: bond-based micromodulus with the material's P-wave modulus,
  // for the stable time step estimate (0: not estimated)
  const double *wave_micromodulus = nullptr;
  // [ntypes+1], for the bound on the correspondence operator's stiffness
  // that the estimate also takes (classical style; null: not bounded):
  // the norm of the elasticity tensor, 3K in 3D (0: not bounded), and the
  // stabilization's bond stiffness
  const double *stress_norm = nullptr;
  const double *spring = nullptr;
  // how the spring acts per bond (nospd_stable_step.h)
  NOSPD::SpringKind spring_kind = NOSPD::SpringKind::NONE;
  // the bond-associated style's own rows in place of the classical force's:
  // fills R_i for every owned atom (sum over points of the norms of its
  // force density's change per unit displacement, linearized at the
  // reference; springs left out).  Empty for the classical style.
  std::function<void(std::vector<double> &)> family_rows;
  // the estimate takes this multiple of the bound where it is below the
  // bond-based value: the bound's measured slack, style by style (doc
  // fix_peri_neigh_nospd, "Stable time step")
  double bound_margin = 2.0;
  // keep each family's quadratic fit operator (kinv2): stabilization/fit quadratic
  bool quadratic = false;
  // the zero-energy-mode control as the user wrote it (for the warning of
  // check_zero_energy_modes); empty: the style has no zero-energy modes
  std::string zem_control;
};

/* Owner of the bond families and of the reference and deformation state.
   Builds on FixPeriNeigh (partner tags and the partner volume sum that
   compute damage/atom reads; its per-bond r0 is not kept) and adds:
     - families built from x0 (minimum-imaged) before the first force call;
     - contiguous per-owned-atom bond arrays (CSR): local partner index and
       weight omega*V_j, refreshed once per reneighboring;
     - x0 in the current periodic image for owned and ghost atoms;
     - K^-1 per atom (recomputed only where a bond breaks), singular flags;
     - F, P and the stored-energy density per atom, filled in by pass 1 of
       the pair style and read by computes and the damage fix. */
class FixNospdBonds : public FixPeriNeigh {
 public:
  static constexpr const char *ID = "NOSPD_BONDS";    // made by the pair style
  FixNospdBonds(class LAMMPS *, int, char **);
  ~FixNospdBonds() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  void setup_post_neighbor() override;
  void post_integrate() override;
  void post_neighbor() override;
  void min_post_neighbor() override { post_neighbor(); }
  void end_of_step() override;
  void post_run() override;
  double compute_vector(int) override;

  double memory_usage() override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;

  void set_model(const NospdBondModel &m);
  // doubles per atom of the quadratic fit operators (0 unless model.quadratic)
  int quadratic_record() const { return kinv2 ? NOSPD::CarriedQuadratic::ATOM_RECORD : 0; }
  // the largest migration record (pack_exchange): partners, 4 flags and
  // sums, K^-1, F_c, the moments, ID and type, and the count
  int max_exchange_size() const { return maxpartner + 31 + quadratic_record() + nhistory; }
  // called by the owning pair style at each init: 1 classical (peri/nospd),
  // 2 bond-associated (peri/nospd/hs).  Families and state from a restart
  // written under the other style are dropped, as a pair_style command
  // between runs drops them.
  void adopt_style(int kind);
  bigint families_serial = 0;    // changes whenever families are built anew
  // the likely cause of an instability, for error messages ("" if unknown)
  std::string unstable_cause() const;
  // the same for a non-finite value from a user law (formula, UMAT): the
  // law itself, unless the time step was past the stable estimate
  std::string user_law_cause(const std::string &law) const;
  // the smallest of those estimates over the types (0: none)
  double smallest_stable_timestep() const { return dt_est.smallest(); }
  // the stable time step estimate of a type at the last run setup (0: none)
  double stable_timestep(int type) const { return dt_est.of(type); }
  // its parts: the bond-based body's, and the bound on the correspondence
  // stiffness (0: none; the estimate takes the smaller of the first and
  // bound_margin times the second)
  double bond_based_timestep(int type) const { return dt_est.bond_part(type); }
  double stiffness_bound_timestep(int type) const { return dt_est.bound_part(type); }
  const NospdBondModel &get_model() const { return model; }

  // Pass 1: F = I + (sum_j w U (x) xi) K^-1 for every owned atom.  When
  // `moments` is given it also receives sum_j w U (x) U (6 values, xx yy zz
  // xy xz yz) per atom, which the stabilization energy needs.
  // F (and the moments) of the owned atoms [from, to); to < 0: all.
  // pos: padded_positions() of this step.
  void compute_deformation(const NOSPD::Positions &pos, double **moments = nullptr, int from = 0,
                           int to = -1);
  // Current and reference (x0s) positions of owned + ghost atoms, flat, as
  // the bond sums load them (nospd_bond_sums.h: one readable double past
  // the last atom): LAMMPS's own arrays where their allocation already has
  // that room, else a padded copy.  Call once per force evaluation, after
  // the positions' forward communication.
  NOSPD::Positions padded_positions();

  // Pair order (the classical style's hourglass pass visits each pair of
  // owned points once, nospd_bond_sums.h): every pair style that uses this
  // fix votes at init whether it can use it; the order is taken at the next
  // setup when one votes for it and none against (the bond-associated
  // style's patterns follow the partner order and vote against).
  void vote_pair_order(bool usable) { pair_votes[usable ? 1 : 0]++; }
  // the bond lists are in pair order and the owned pairs are known to be
  // symmetric (each bond i-j owned on both ends is in both lists)
  bool pairs_ordered() const { return fam.symmetric(); }

  // Breaking bonds (damage fix): zero the partner slot, mark K^-1 stale.
  // Call bonds_changed() once after a batch of breaks on all ranks.
  void break_bond(int i, int slot);
  void bonds_changed();
  // bonds (pairs) broken past the ghost cutoff at rebuilds since the last
  // call, for the damage fix's count (settle_far_bonds)
  bigint take_far_broken()
  {
    const bigint n = far_broken;
    far_broken = 0;
    return n;
  }

  // Inelastic history (nospd_plasticity.h), n values per atom: `history`
  // holds the state of the last accepted step, `history_trial` what the
  // latest force evaluation made of it.  The trial state becomes the
  // accepted one at the end of each MD step and at the end of a
  // minimization: run 0, the setup of a run and line searches never
  // accumulate plastic strain.
  //
  // The horizon-stabilized style keeps history per bond-associated family
  // too: each row is n_atom values of the atom, then n_bond values for
  // each partner slot (maxpartner of them), which travel with their
  // partner when broken slots are dropped (migration, restart).
  void set_history_size(int n_atom, int n_bond = 0);
  void drop_history();
  void trial_history_ready() { hist.trial_ready = true; }
  void commit_history() { hist.commit(); }
  // the n_bond values of partner slot `slot` in a history row
  double *bond_history(double *row, int slot) const { return hist.bond(row, slot); }
  NospdHistoryStore hist{memory};    // the rows, owned here (nospd_history_store.h)
  // its fields under the names the pair styles, computes and tests read
  int &nhistory = hist.n;                  // values per atom, 0 if no type has history
  int &nhist_atom = hist.n_atom;           // of which the atom's own
  int &nhist_bond = hist.n_bond;           // and per partner slot
  double **&history = hist.accepted;       // [nmax][nhistory], accepted
  double **&history_trial = hist.trial;    // [nmax][nhistory], latest force evaluation
  double history_sum(int k); // sum over atoms of current_history()[k] (global)
  // the rows to report (computes, sums): the accepted ones, except during
  // a minimization, which accepts its trial rows only at its end (post_run)
  // while its output shows the state of its latest force evaluation
  double **current_history() const;
  // per type, the law whose state the history holds (the pair style's
  // code; empty after a restart)
  std::vector<int> history_law;
  // set by the pair style around its add_fix: any other instance is an error
  static bool made_by_pair_style;
  // the type an atom had at the last setup, under whose law its history was
  // written (0: created since, no family)
  int type_of_history(int i) const { return family_type[i]; }

  // the zero-energy-mode indicator of owned point i at the last force
  // evaluation (NOSPD::ZemSum; 0 where K is singular)
  double zem_indicator(int i) const;
  // the same after a quadratic fit (NOSPD::QuadraticZemSum; -1: no fit)
  double zem_quadratic(int i) const;
  // the threshold of its zem_ratio above which a point counts as held by
  // no stabilization, and the steps between checks during a run
  static constexpr double ZEM_RATIO_LIMIT = 0.22;
  static constexpr int ZEM_CHECK_EVERY = 1000;

  // the reference bond from a point at x0i to one at x0j: x0j - x0i imaged
  // in the reference box (the box the families were built in, followed
  // through flips), the same vector as the pair styles' x0s difference (to
  // rounding) whatever the box has become since; antisymmetric bit for bit,
  // so both ends of a bond (on any rank) see exact negatives.  Every
  // consumer of a reference bond outside the pair's passes takes it here.
  void reference_bond(const double *x0i, const double *x0j, double *xi) const;

  // ---- state read by pair styles, computes and the damage fix ----
  // the bond lists (nospd_family_store.h), owned here, under the names
  // their readers use
  NOSPD::FamilyStore fam;
  int &nbond_atoms = fam.natoms;    // owned atoms covered by the lists (-1:
                                    // atoms moved, added or deleted since)
  bool bond_arrays_current() const;
  int &bond_version = fam.version;    // changes whenever the lists change
  int *&bond_first = fam.first;       // [nlocal+1] offsets into bond_j/bond_w
  int *&bond_j = fam.j;               // local index of the partner (closest image)
  int *&bond_slot = fam.slot;         // partner slot in FixPeriNeigh::partner[i]
  double *&bond_w = fam.w;            // omega(|xi|) * V_j
  // in pair order, point i's bonds are [bond_first[i], bond_pair[i]) to
  // owned points j < i, [bond_pair[i], bond_ghost[i]) to owned points j > i,
  // then [bond_ghost[i], bond_first[i+1]) to ghosts
  int *&bond_pair = fam.pair;    // [nlocal], only in pair order
  int *&bond_ghost = fam.ghost;
  // the reference bond of point i's bond b (reference_bond of the two x0):
  // the bond geometry of every reader outside the force passes, which
  // take the same vector from x0s (to rounding)
  void bond_vector(int i, int b, double *xi) const;
  double **x0s;           // x0 in the periodic image of x, owned + ghost
  double **kinv;          // K^-1, 9 per atom, row-major; zero if singular
  double **kinv2;         // the quadratic fit's K2^-1 and its flag, or a damaged family's
                          // carried record, then G (model.quadratic only:
                          // nospd_quadratic_carry.h, CarriedQuadratic::ATOM_RECORD per atom)
  double **xi_moment;     // sum_j w xi (reference; zero inside a regular grid)
  double **u_moment;      // sum_j w U, filled by pass 1
  int *family_size;       // bonds at the first build, broken ones included
  int *singular;          // 1 if K is singular: no correspondence force;
                          // 2 if the atom's type is not the style's (pair hybrid)
  double **defgrad;       // F, 9 per atom
  double **pk1;           // first Piola-Kirchhoff stress P, 9 per atom
  double **fcarry;        // F_c, 9 per atom: the law sees F F_c (nospd_carry.h)
  double *energy_density; // stored-energy density W(F) (plus stabilization)
  bigint nsingular;       // global count of singular families
  bigint nbonds_total, nbonds_broken;
  bigint nbonds_vanished;    // broken because the partner atom no longer exists

  // the conditioning atom i's family must keep to be regular: the damaged
  // tolerance once it has lost bonds (fewer intact than at its first build;
  // bond arrays current), and none once it was found singular after that:
  // damage is irreversible (see update_shape_tensors)
  double conditioning_tolerance(int i) const
  {
    if (!lost_bonds(i)) return model.singular_tol;
    return singular[i] == 1 ? std::numeric_limits<double>::infinity() : model.damaged_tol;
  }
  bool lost_bonds(int i) const { return bond_first[i + 1] - bond_first[i] < family_size[i]; }
  double max_bond_leverage(int i, const NOSPD::Mat3 &Kinv) const;

  using FixPeriNeigh::npartner;
  using FixPeriNeigh::partner;
  using FixPeriNeigh::vinter;
  using FixPeriNeigh::maxpartner;

 protected:
  NospdBondModel model;
  int nmax_x0s;
  int *stale;               // [nmax] K^-1 to recompute
  bool all_stale;
  void layout_history(int n_atom, int n_bond);
  int pack_history(int i, double *buf) const;
  int unpack_history(int i, const double *buf, int n_atom, int n_bond);
  double **x0s_store;    // x0s when the box is periodic (else x0s = atom->x0)
  std::vector<double> x_padded, x0_padded;    // padded_positions()' copies, when needed
  // the reference box (lengths and tilts as domain->h) in the basis of the
  // current box, followed through flips; the reference bonds' geometry
  NOSPD::ReferenceBox ref_box;
  void follow_box();
  int built_periodic = -1;    // periodic dimensions (bits x y z) at the first build
  double created_h[6];        // the box when the fix was made (first pair_coeff)
  void adopt_box_of_creation();
  double x0_print[7];          // bounds and sum of the x0: which reference body
  bool x0_print_set = false;
  void print_x0(double *print) const;
  void choose_reference_box(bool had_reference_box);
  bool take_replaced_box();
  void check_periodicity(bool built_now);
  int style_kind = 0;      // the owning pair style's family_kind()
  int restart_kind = 0;    // that of the restart file's writer (0: none)
  void start_over();

  void build_families();
  void warn_unbonded_reference_pairs();
  void clear_atom(int i);
  void check_coincident(int i, int j, double r) const;
  void update_x0s();
  void mean_displacement(double *um) const;
  void build_bond_arrays();
  struct MissingPartner {
    int i, slot;
    tagint tag;
  };
  struct FarBond {
    int i, slot;
    tagint tag;
    double length;    // current
  };
  void resolve_missing(const std::vector<MissingPartner> &missing, std::vector<FarBond> &far);
  void settle_far_bonds(const std::vector<FarBond> &far);
  bool far_warned = false;
  bigint far_broken = 0;
  int partner_index(tagint t) const;
  void follow_renumbered_tags();
  void warn_vanished(bigint nbroken);
  std::vector<double> family_horizon;    // [(ntypes+1)^2] horizons the families were built with
  void check_horizons();
  void report_stable_timestep();
  void bound_stable_timesteps(std::vector<double> &dtmin);
  // forward communication: FixPeriNeigh's (0) or the operator bound's (1)
  int comm_mode = 0;
  std::vector<double> op_point;    // per owned + ghost atom: D_i, |K_i^-1|
  void check_volumes();
  void check_solid_volumes();
  bool volumes_warned = false;    // 2D thickness or 3D volumes: warned once
  void check_min_dmax();
  void check_zero_energy_modes();
  template <class Sum> void add_bond_motion(int i, Sum &sum) const;
  bool zem_warned = false;    // the zero-energy-mode warning, once per fix
  double dmax_warned = -1.0;          // the min_modify dmax last warned about
  NOSPD::StableStep dt_est;    // the estimate of the last setup (nospd_stable_step.h)
  tagint *own_tag;    // the atom's ID when its partners' IDs were last written
  int *family_type;   // the atom's type at the last setup (0: no family)
  void check_family_types();
  bool count_bonds_pending = false;
  int pair_votes[2] = {0, 0};    // against, for, since the last setup
  bool &pair_order = fam.pair_order;    // bond lists in pair order
  void update_shape_tensors(bool count = true);
  void count_singular();
  // the refits of the families that lose bonds (nospd_carry.h): their F
  // before, at the current positions; after, F_c or singular
  // (and, with the quadratic fit, the F F_c and the fit's curvature Q_s before)
  struct Before {
    NOSPD::Mat3 F, FFc;
    NOSPD::Mat36 Qs;
    bool curved;    // Q_s from an intact family's quadratic fit: G starts from it
  };
  void fits_before_change(std::vector<int> &changed, std::vector<Before> &before);
  void carry_refits(const std::vector<int> &changed, const std::vector<Before> &before);
  void quadratic_fit_of(int i);
  void count_bonds();
  void report_families();
  double weight(double r, double delta) const;
};

}    // namespace LAMMPS_NS

#endif
#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(nospd/damage,FixNospdDamage);
// clang-format on
#else

#ifndef LMP_FIX_NOSPD_DAMAGE_H
#define LMP_FIX_NOSPD_DAMAGE_H

#include "fix.h"

#include "nospd_constitutive.h"
#include "nospd_energy_audit.h"

#include <array>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixNospdBonds;
class PairPeriNospdBase;

/* Bond breaking for the correspondence styles.  After each force
   computation (post_force) the fix stores the atoms' state the criteria
   need (A = P K^-1, stress or strain); at the start of the next force
   computation (pre_force) it evaluates every bond from the current
   positions and that state, breaks bonds on both ends, and lets the bonds
   fix rebuild K^-1, so that the forces of every step belong to the bond
   state a restart file written after it holds.  Pre-cracks are cut before
   the first force evaluation; an optional short-range contact force acts
   between points that share no intact bond. */
class FixNospdDamage : public Fix {
 public:
  FixNospdDamage(class LAMMPS *, int, char **);
  ~FixNospdDamage() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup_pre_force(int) override;
  void setup(int) override;
  void pre_force(int) override;
  void post_force(int) override;
  void setup_pre_reverse(int, int) override;
  void pre_reverse(int, int) override;
  void post_integrate() override;
  double compute_scalar() override;
  double compute_vector(int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;

  enum Criterion {
    NONE = -1, STRETCH, ENERGY, STRESS_PRINCIPAL, STRAIN_PRINCIPAL, STRESS_VONMISES, EQPS, JC_DAMAGE
  };

 protected:
  // threads of the per-atom loops: 1 here, comm->nthreads in the /omp
  // variant (fix nospd/damage/omp, what `-sf omp` picks)
  int nthreads;
  int criterion;
  bool from_g0;             // critical value from the fracture energy
  double value;             // critical value (or G0 when from_g0 and given)
  bool g0_given;
  double scatter_width;
  double alpha;             // stretch: s_c - alpha s_min (Silling & Askari 2005)
  int scatter_seed;
  int nevery;
  int nofail_groupbit;
  char *nofail_region_id;
  class Region *nofail_region;
  bool detach_singular;
  std::vector<std::array<double, 9>> precracks;    // 2D: 4 used; 3D: 9

  bool contact;
  double contact_scale;     // stiffness factor on the micromodulus
  double contact_radius;    // 0: from the point spacing
  double contact_rc;        // radius in use
  class NeighList *list;

  PairPeriNospdBase *pair;
  FixNospdBonds *bonds;
  double **crit;            // [ntypes+1][ntypes+1] critical value per type pair
  double **kcontact;        // contact stiffness per type pair
  double **delta;           // horizon per type pair (from the pair style)

  // per-atom state of the last force computation (migrates with atoms)
  int nstate;
  double **state;
  // state column of the point's thermal strain alpha (T - T_ref) (-1: the
  // criterion needs none); communicated only where a type has one (thermal)
  int ecol = -1;
  bool thermal = false;
  bool small_law = true;    // the thermal strain adds (small) or multiplies
  // per-atom data forward-communicated before the bond loop
  int ncomm, nmax_comm;
  double **cdata;
  bool precracks_done;

  // counts
  bigint nbroken_total;     // bonds (pairs) broken by this fix, restart-persistent
  bigint families_seen = 0;    // the bonds fix's families_serial at the last setup
  bigint nbroken_step;      // bonds broken at the last evaluation
  bigint ncontact;          // pairs in contact at the last force evaluation
  double econtact;          // contact energy of the owned atoms, last evaluation
  double econtact_volume = 0.0;    // the same, sum V_i e_i (the energy audit's)

  // the energy audit (nospd_energy_audit.h, fix_nospd_damage_audit.cpp):
  // per owned atom the material's force of the last evaluation (the pair
  // style's, then the contact's), the work it did on this rank since the
  // run started, and a warning once if the material creates energy
  bool audit_wanted = true;    // keyword audit
  bool auditing = false;       // this run
  bool audit_warned = false;
  std::vector<double> fmat;
  double work_local = 0.0;
  NOSPD::EnergyAudit audit;
  void audit_init();
  void audit_forces();
  void audit_half_step();
  void audit_observe();
  double far2 = 0.0;        // the ghost cutoff squared, at the last evaluation
  bool rerun_warned = false;    // rerun's warning given
  bool settings_warned = false;    // warn_settings() done
  // contact: per atom, the rest distances of pairs whose bond broke while
  // they were closer than the nominal one (NOSPD::ContactMemory records)
  double **cmem = nullptr;
  bigint cmem_full = 0;            // breaks not remembered (record full), this rank
  bool cmem_warned = false;

  // the fix's arguments and the keyword a number belongs to, for its error
  struct Args {
    class Error *error;
    std::string cmd;
    int narg;
    char **arg;
    std::string key;
    double number(int i) const;
    void need(int iarg, int n, const std::string &what) const;
  };
  int parse_criterion(Args &);
  int parse_keyword(Args &, int iarg, const char *&contact_keyword_given);
  int add_precrack(Args &, int iarg);
  void setup_tables();
  void warn_settings(const std::string &cmd);
  void store_state();
  void store_state_range(NOSPD::Law law, int from, int to);
  void fill_comm_data();
  void evaluate_and_break(bool apply = true);
  void init_thermal();
  template <bool THERMAL> void stretch_cuts(std::vector<std::pair<int, int>> &cut);
  template <class Crit>
  std::vector<std::pair<int, int>> scan_bonds(const Crit &, bool apply);
  void bond_geometry(const double *x0a, const double *x0c, const double *ua, const double *uc,
                     bool periodic, double *xi, double *U, double *Y) const;
  void apply_precracks();
  int break_list(std::vector<std::pair<int, int>> &);
  void remember_contacts(const std::vector<std::pair<int, int>> &);
  void contact_forces();
  bool bonded(int i, tagint tj) const;
  void contact_virial(int i, double fpair, double dx, double dy, double dz, double *vsum);
  bool peratom() const { return nstate > 0 || contact; }
};

}    // namespace LAMMPS_NS

#endif
#endif

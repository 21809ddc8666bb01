/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_PERI_NOSPD_BASE_H
#define LMP_PAIR_PERI_NOSPD_BASE_H

#include "atom.h"
#include "pair.h"

#include "nospd_bond_sums.h"
#include "nospd_material.h"
#include "nospd_plasticity.h"
#include "nospd_stabilization.h"
#include "nospd_user_material.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixNospdBonds;
class FixNospdHeat;
struct NospdBondModel;

/* What the two correspondence styles share (siblings: PairPeriNospd, the
   classical one, and PairPeriNospdHS, the bond-associated one): settings,
   pair_coeff and the material table (materials: one law per type behind
   NOSPD::Material), init and the bonds fix, temperature, restart, and the
   stabilization's force pass over the bonds (nospd_bond_sums.h), which the
   classical style runs as its pass 2 and the bond-associated one on top of
   its own forces.  Each style's compute() is its own. */
class PairPeriNospdBase : public Pair {
 public:
  PairPeriNospdBase(class LAMMPS *);
  ~PairPeriNospdBase() override;

  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  double memory_usage() override;
  void *extract(const char *, int &) override;

  static PairPeriNospdBase *find(class Force *);

  // read by computes and the damage fix
  NOSPD::Law law() const { return strain_law; }
  NOSPD::Plane plane() const { return plane_mode; }
  FixNospdBonds *bonds() const { return fix_bonds; }
  const NOSPD::Lame &material(int itype) const { return lame[itype]; }
  double fracture_energy(int itype) const { return g0[itype]; }
  double youngs_modulus(int itype) const { return youngs[itype]; }
  double poisson_ratio(int itype) const { return poisson[itype]; }
  double plate_thickness() const { return thickness; }
  double horizon(int itype, int jtype) const { return cut[itype][jtype]; }
  // a type this style owns (under pair hybrid others may belong to other styles)
  bool owns_type(int itype) const { return active[itype] != 0; }
  int stabilization_kind() const { return static_cast<int>(stab); }
  double stabilization_parameter() const { return stab_param; }    // Silling G or hourglass C
  // Silling's springs on the quadratic fit (stabilization/fit quadratic)
  bool quadratic_active() const { return fit_quadratic && stab == NOSPD::Stab::SILLING; }
  bool bond_associated() const { return family_kind() == 2; }
  // the classical law sees F F_c of a family that lost bonds (nospd_carry.h)
  bool carries_deformation() const { return !bond_associated() && !damaged_refit; }
  // built-in inelastic materials (history kept by the bonds fix)
  bool has_history(int itype) const { return inelastic[itype] == POINT_PLASTIC; }
  // a type with history that the bond-associated style runs per bond through
  // the material interface alone (NOSPD::FamilyMaterial): every law but
  // J2/Johnson-Cook, whose compact per-bond state (NOSPD::FamilyPlasticity,
  // the same law: doc pair_peri_nospd_hs) keeps 7 values per bond instead
  // of the point's 39
  bool bond_material(int itype) const
  {
    const NOSPD::Material *m = itype < (int) materials.size() ? materials[itype].get() : nullptr;
    return m && m->history_size() > 0 && !dynamic_cast<const NOSPD::J2Material *>(m);
  }
  const NOSPD::Material &material_law(int itype) const { return *materials[itype]; }
  // a type whose stress comes from a UMAT (history in UmatHist's layout)
  bool is_umat(int itype) const { return inelastic[itype] == POINT_UMAT; }
  const NOSPD::FlowLaw &flow_law(int itype) const { return flow[itype]; }
  const NOSPD::ThermalLaw &thermal_law(int itype) const { return thermal[itype]; }
  // temperature of owned atom i at the last force evaluation: the user's
  // (temperature keyword, fix nospd/heat's field, else the type's
  // reference) plus adiabatic heating not yet moved into the field
  double temperature(int i) const;
  // the thermal strain alpha (T - T_ref) the built-in laws remove from owned
  // atom i's deformation (0 for a type without; small strain subtracts it,
  // Hencky divides by the stretch 1 + it)
  bool has_thermal_strain(int itype) const
  {
    return has_history(itype) && thermal[itype].alpha != 0.0;
  }
  double thermal_strain(int i) const;
  // the adiabatic heating of owned atom i's accepted state (0 for laws
  // without); newest: the trial state's where a force evaluation made one
  // that the step has not yet accepted
  double adiabatic_heat(int i, bool newest = false) const;
  // fix nospd/heat owns the temperature (its init attaches, its destructor
  // detaches; the temperature keyword must then be none)
  void attach_heat(FixNospdHeat *f) { heat_field = f; }
  FixNospdHeat *attached_heat() const { return heat_field; }
  bool temperature_given() const { return temperature_kind != TEMP_NONE; }
  // why the forces are no energy's gradient ("" if they are one): the
  // Newton minimizer picks its Krylov solver by it
  std::string potential_cause() const { return not_a_potential(); }
  // the Newton minimizer's probes: until end_linearization, every owned
  // point whose law offers a consistent tangent (nospd_material.h) takes
  // P0 + D : (F - F0) about the last force evaluation instead of its law,
  // so that a directional difference sees that tangent exactly (no return
  // mapping switching across the yield surface within a probe).  Returns
  // the number of such points on this rank (0: the style has none)
  virtual int begin_linearization() { return 0; }
  virtual void end_linearization() {}

 protected:
  FixNospdBonds *fix_bonds;
  NOSPD::Law strain_law;
  NOSPD::Plane plane_mode;
  NOSPD::Stab stab;
  double stab_param;     // Silling G or hourglass C
  bool fit_quadratic;    // Silling's springs on the residual of a quadratic fit
  int influence;         // NospdBondModel::Influence
  double thickness;      // 2D: thickness carried by the volumes
  std::vector<double> wave_c;    // per type: micromodulus for the time step estimate
  std::vector<double> stress_norm;    // per type: |C|, for the bound on the stiffness
  double singular_tol;    // conditioning below which a family's K is singular
  double damaged_tol;     // the same for a family that lost bonds
  double damaged_leverage;    // largest bond leverage a family that lost bonds may keep
  bool damaged_refit = false;    // damaged_state refit: no carried F_c (nospd_carry.h)

  // per type
  double *youngs, *poisson, *g0;
  std::vector<NOSPD::Lame> lame;
  std::vector<std::string> material_name;
  std::vector<int> active;    // types this style owns (pair hybrid may give others away)
  std::vector<NOSPD::FlowLaw> flow;          // J2 flow law (flow[i].active: plastic)
  std::vector<NOSPD::ThermalLaw> thermal;    // expansion, heating, JC failure
  std::vector<NOSPD::DruckerPrager> drucker_prager;    // pressure-dependent flow (.active)
  // each active type's law behind the material-point interface, built at init
  std::vector<std::unique_ptr<NOSPD::Material>> materials;
  void build_materials();
  void material_failure(int i, NOSPD::PointStatus st, const NOSPD::Mat3 &F) const;
  int restart_layout = 0;    // the layout of the restart file read (0: none)
  // how a type's stress is found: its law alone, the built-in inelastic
  // point (nospd_plasticity.h) or a UMAT; the last two keep history
  enum { POINT_ELASTIC = 0, POINT_PLASTIC = 1, POINT_UMAT = 2 };
  std::vector<int> inelastic;
  std::unique_ptr<NospdUserMaterials> user_materials;    // formulas and UMATs
  // user temperature: none (the type's reference), a per-atom property
  // d_name (fix property/atom) or an atom-style variable v_name
  enum { TEMP_NONE, TEMP_PROPERTY, TEMP_VARIABLE } temperature_kind;
  std::string temperature_name;
  int temperature_index;
  double *temperature_base;    // per owned atom, filled by the constitutive pass
  FixNospdHeat *heat_field = nullptr;    // the temperature's owner, if any
  double *stab_scalar;    // Silling alpha or hourglass c_hg, per type
  double **cut;

  // per atom (owned + ghost), forward-communicated: B = P K^-1 - S H,
  // and S (Wan) or H (hourglass) where the stabilization needs a tensor
  int nmax_work;
  // per atom, as the bond sums load them (nospd_bond_sums.h): bmat holds
  // B = P K^-1 - S H transposed (column by column) and the stabilization
  // scalar (0 where K is singular); tmat the stabilization's tensor (Wan's
  // S or the hourglass H) transposed, with a spare row
  double **bmat, **tmat, **moments;
  // the quadratic fit (stabilization/fit quadratic): per atom alpha Q (the
  // fit's quadratic part, 6 columns of 3, forward-communicated, with a
  // spare row) and per owned atom its sums (nospd_bond_sums.h, QSUMS)
  double **qmat, **qsums;
  std::string zem_control() const;
  void warn_plastic_flow(const std::string &cmd);
  bool plastic_flow_warned = false;
  static constexpr int STAB_SCALAR = 9;    // its place in bmat
  NOSPD::Positions positions{};    // this step's padded positions (pass 1 and 2)
  static void store_transposed(const NOSPD::Mat3 &M, double *to)
  {
    NOSPD::store(NOSPD::Mat3(M.transpose()), to);
  }
  int comm_tensors;    // 1 or 2 tensors of 9 in the forward comm

  // The energy and virial sums of a pass over a range of owned atoms: one
  // per thread in the /omp style, added to eng_vdwl and virial after it.
  struct Tally {
    double eng = 0.0;
    double virial[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  };
  // fn(from, to, tid, tally): a pass over the atoms [from, to) by thread tid
  using RangeFn = std::function<void(int from, int to, int tid, Tally &)>;
  // Run fn over the atoms [0, n): here in one range; the /omp styles split
  // it over their threads where the work is thread_safe.  The classical
  // passes write only their own atoms' rows (gathers over the bonds), so
  // the ranges are independent.  LAMMPS errors raised inside reach the
  // caller.
  virtual void for_ranges(int n, bool thread_safe, const RangeFn &fn)
  {
    threaded_ranges(1, n, fn);
  }
  // the same over up to nthreads threads (NOSPD::run_ranges), the tallies
  // added in thread order
  void threaded_ranges(int nthreads, int n, const RangeFn &fn);
  void add_tally(const Tally &t);

  void allocate();
  void ensure_bonds_fix();
  void grow_work();
  NOSPD::Mat3 nonaffine_moment(int i, const NOSPD::Mat3 &H, const NOSPD::Mat3 &Ki) const;
  template <NOSPD::StabPass STAB, int VIRIAL> void force_pass(int eflag);
  // the hourglass pass over pairs of owned points, in the bonds fix's pair
  // order, which this style asks for where it can use it: the hourglass on
  // one thread (the /omp styles split the passes by atoms; the
  // bond-associated style's patterns follow the partner order)
  // which families and state the bonds fix holds: 1 classical, 2 bond-associated
  virtual int family_kind() const = 0;
  virtual bool pair_order_usable() const { return stab == NOSPD::Stab::HOURGLASS; }
  template <int VIRIAL> void hourglass_pair_pass();
  std::vector<double> inv_volume;    // 1 / V of owned atoms, for the pairs pass
  template <NOSPD::StabPass STAB, int VIRIAL> void force_range(int from, int to, Tally &t);
  void tally_energy(int i, double e);
  void tally_energy(int i, double e, Tally &t)
  {
    if (eflag_global) t.eng += e;
    if (eflag_atom) eatom[i] += e;
  }
  // the last step of a force pass for owned atom i: its force and the
  // virial of its bonds (v = xx yy zz xy xz yz)
  void add_force_virial(int i, double fx, double fy, double fz, const double *v, bool virial,
                        Tally &t)
  {
    double **f = atom->f;
    f[i][0] += fx;
    f[i][1] += fy;
    f[i][2] += fz;
    if (!virial) return;
    if (vflag_global)
      for (int k = 0; k < 6; k++) t.virial[k] += v[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom[i][k] += v[k];
  }
  void add_force_virial(int i, double fx, double fy, double fz, const double *v, bool virial)
  {
    Tally t;
    add_force_virial(i, fx, fy, fz, v, virial, t);
    add_tally(t);
  }
  double stabilization_energy(int i) const;
  // one entry of a material file (name E nu density G0 [keywords])
  struct FileMaterial {
    double E = 0.0, nu = 0.0, density = 0.0, G0 = 0.0;
    int line = 0;                      // where the entry starts in the file
    std::vector<std::string> extra;    // the inelastic keywords after the numbers
  };
  FileMaterial read_material_file(const std::string &file, const std::string &name);
  void check_file_material(const std::string &where, const FileMaterial &m) const;
  void check_modulus(const std::string &where, double E) const;
  double inline_number(const std::string &cmd, const char *what, const char *arg) const;
  void check_poisson(const std::string &where, double nu) const;
  void parse_inelastic(const std::vector<std::string> &words, NOSPD::FlowLaw &fl,
                       NOSPD::ThermalLaw &th, NOSPD::DruckerPrager &dp,
                       NospdUserMaterials::Spec &us,
                       bool &thermal_ref_given, const std::string &where) const;
  NOSPD::FlowLaw johnson_cook_of(const std::vector<double> &v, double Hkin,
                                 const std::string &where) const;
  void check_jc_failure(const std::vector<double> &v, const std::string &where) const;
  NOSPD::DruckerPrager drucker_prager_of(const std::vector<double> &v,
                                         const std::string &where) const;
  NOSPD::UmatPoint umat_env(int i) const;
  void umat_failure(int i, NOSPD::UmatStatus st, const NOSPD::Mat3 &F) const;
  void check_inelastic(int itype) const;
  void check_history_law();
  void warn_barostats(const std::string &cmd);
  void raise_hybrid_comm_forward();
  void set_stiffness_bound(NospdBondModel &m);
  // the steps of parse_inelastic (pair_peri_nospd_input.cpp)
  std::vector<double> keyword_values(const std::vector<std::string> &words, size_t &k, size_t n,
                                     const std::string &key, const std::string &where) const;
  void flow_law_exclusions(const std::vector<std::string> &words, NOSPD::FlowLaw &fl,
                           NOSPD::DruckerPrager &dp, const std::string &where) const;
  size_t hardening_of(const std::vector<std::string> &words, size_t k, NOSPD::FlowLaw &fl,
                      const std::string &where) const;
  void check_flow_law(const NOSPD::FlowLaw &fl, const NOSPD::ThermalLaw &th,
                      const NOSPD::DruckerPrager &dp, const std::string &where) const;
  // the steps of settings: which keywords were given, the keywords, the checks
  struct SettingsGiven {
    bool plane = false, thickness = false, singular = false, damaged = false, state = false;
  };
  int model_keyword(const std::string &cmd, int narg, char **arg, int iarg);
  int geometry_keyword(const std::string &cmd, int narg, char **arg, int iarg,
                       SettingsGiven &given);
  void check_settings(const std::string &cmd, const SettingsGiven &given);
  // the steps of init_style (pair_peri_nospd_init.cpp)
  void check_run_environment(const std::string &cmd);
  void check_points(const std::string &cmd);
  void setup_type_constants();
  int setup_laws(const std::string &cmd);
  void configure_bonds_fix(int history_size);
  // the bond-associated style bounds its own force for the stable time step
  // (NospdBondModel::family_rows); none here: the bonds fix bounds pass 2's
  virtual std::function<void(std::vector<double> &)> family_row_bound() { return {}; }
  // the multiple of that bound the estimate takes (its measured slack)
  virtual double bound_margin() const { return 2.0; }
  // what makes the forces of this setting no gradient of an energy ("" if
  // they are one), for the warning at the setup of minimize
  virtual std::string not_a_potential() const;
  bool minimize_warned = false;
  void check_one_plane(double spacing);
  void fill_base_temperature();
  void inelastic_failure(int i, NOSPD::ReturnStatus st, const NOSPD::Mat3 &F) const;
  void law_failure(int i, const NOSPD::Mat3 &F) const;
  void check_material(int itype) const;
  void check_hybrid_names();
  bool user_law() const
  {
    return strain_law == NOSPD::Law::USER || strain_law == NOSPD::Law::UMAT_SMALL ||
        strain_law == NOSPD::Law::UMAT_FINITE;
  }
};

}    // namespace LAMMPS_NS

#endif

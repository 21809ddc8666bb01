/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(nospd/heat,FixNospdHeat);
// clang-format on
#else

#ifndef LMP_FIX_NOSPD_HEAT_H
#define LMP_FIX_NOSPD_HEAT_H

#include "fix.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixNospdBonds;
class PairPeriNospdBase;

/* fix nospd/heat: bond-based peridynamic heat conduction on the points of
   a correspondence body (nospd_heat.h), advanced explicitly once per MD
   step before the forces (subcycled below the stable thermal step), so
   that a step's forces and the temperature written at its end agree (a
   restart's setup forces are the run's), in the reference frame or the
   current one (frame current: bonds, volumes and faces as deformed), with fixed
   temperatures, convection, surface flux and a volumetric source.  Owner
   of the temperature field: the pair style's laws, compute nospd/atom and
   dumps (f_ID) read it here.  Plastic heating (pair_coeff heat cp chi)
   stays in the law's history until the end of its step, then moves into
   the field, so a law always sees field + heating not yet moved. */
class FixNospdHeat : public Fix {
 public:
  FixNospdHeat(class LAMMPS *, int, char **);
  ~FixNospdHeat() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void pre_force(int) override;
  void pre_force_respa(int, int, int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
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
  double memory_usage() override;

  // the temperature the pair's laws add their un-moved heating to
  double base_temperature(int i, int itype) const;
  // -k grad T of owned atom i (grad T = K^-1 sum_j w (T_j - T_i) xi);
  // call prepare_flux() on all ranks first (ghost temperatures)
  void prepare_flux();
  void heat_flux(int i, double *q) const;

 private:
  double *tfield;    // per atom (owned and ghost): the temperature (vector_atom)
  // per atom: the law's heating moved into tfield so far, the micro-
  // conductivity (-1: not calibrated), the reference area of one face, the
  // exposed faces (bits, nospd_heat.h); frame current: kappa of the current
  // family and the moment it was taken from (taken again when the moment
  // moves by more than MOMENT_TOLERANCE)
  enum { SEEN, KAPPA, AREA0, FACES, KCUR, MCAL, NAUX = MCAL + 6 };
  double **aux;
  // frame current: per atom (owned and ghost) this step's kappa and J, and
  // per owned atom the exposed area
  bool current_frame = false;
  std::vector<double> kcur, jcur, area_now;
  std::vector<double> blen;    // per bond: this step's current length
  bool warned_frame = false;
  // boundary conditions and sources, in input order
  struct Value {
    double number = 0.0;
    std::string var;    // v_name: equal- or atom-style variable
    int index = -1;
    int style = 0;      // 1 equal, 2 atom
  };
  struct Condition {
    enum Kind { FIXED, CONVECTION, FLUX } kind;
    std::string group;        // or the region's ID where region is set
    int groupbit = 0;
    bool by_region = false;
    class Region *region = nullptr;
    Value value;         // T, h or q
    double T_inf = 0.0;  // convection
  };
  std::vector<Condition> conditions;
  Value source, initial;
  bool have_source = false, have_initial = false;
  int substeps_user = 0;    // 0: auto

  PairPeriNospdBase *pair = nullptr;
  FixNospdBonds *bonds = nullptr;
  std::vector<double> k_type, c_type;    // per type
  std::vector<double> coef;              // per bond of the bonds fix's lists
  std::vector<double> rowsum;            // per owned atom: sum of its coef
  std::vector<double> rate, extra;       // per atom: dE, this step's sources
  std::vector<std::vector<double>> values;    // per condition, this step's value per atom
  int coef_version = -1, coef_atoms = -1;
  double dt_stable = 0.0;
  int nsub = 1;
  bool warned_step = false;
  double inflow = 0.0, plastic_in = 0.0;    // cumulative, this rank
  int comm_mode = 0;                        // 0: T and kappa, 1: J
  int nlevels_respa = 0;                    // run_style respa: its levels

  void parse(int narg, char **arg);
  Value value_of(const char *word, const char *what, bool allow_var);
  void resolve(Value &v, const char *what);
  void evaluate(const Value &v, std::vector<double> &out);
  void initialize_new_points();
  void calibrate();
  void build_coefficients();
  void move_plastic_heat();
  void substep(double dt);
  void step_geometry(bool retake);
  void check_frame();
  double kappa_of(int i) const { return current_frame ? kcur[i] : aux[i][KAPPA]; }
  void step_sources();
  void apply_fixed();
  double capacity(int i) const;
  // owned atom i is in the fix group and under condition c (its group, or
  // its region now)
  bool under(const Condition &c, int i) const;
  double area(int i) const;
  double pending(int i) const;
  double stable_step() const;
  void check_types_and_groups();
};

}    // namespace LAMMPS_NS

#endif
#endif

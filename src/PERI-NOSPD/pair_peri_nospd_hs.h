/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(peri/nospd/hs,PairPeriNospdHS);
// clang-format on
#else

#ifndef LMP_PAIR_PERI_NOSPD_HS_H
#define LMP_PAIR_PERI_NOSPD_HS_H

#include "pair_peri_nospd_base.h"

#include "nospd_bond_associated.h"
#include "nospd_bond_history.h"
#include "nospd_stencil.h"

#include <array>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <vector>

namespace LAMMPS_NS {

/* Horizon-stabilized (bond-associated) correspondence peridynamics (Chen
   2018; Chen and Spencer 2019): every bond gets the deformation gradient
   of the part of the family within ratio*delta of its far end.  Forms I
   and II, see nospd_bond_associated.h.  A sibling of the classical style:
   settings, materials, the bonds fix and the stabilization's force pass
   come from their common base (PairPeriNospdBase); the force pass is its own.

   Each owned atom evaluates its own family and scatters the forces onto
   its partners, ghosts included; a reverse communication brings those
   home.  That needs ghosts only within delta, as the classical style does,
   and no per-bond data in flight. */
class PairPeriNospdHS : public PairPeriNospdBase {
 public:
  PairPeriNospdHS(class LAMMPS *);
  ~PairPeriNospdHS() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void init_style() override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;

  // Bond-associated deformation gradient of the bond at position b of the
  // bonds fix's arrays (owned atom i).  Returns 1 if the bond has its own
  // F, 0 if it falls back to the family's F (singular K_ij), -1 if the
  // state is unavailable.  For output (a local compute) and tests.
  virtual int bond_defgrad(int i, int b, double *F);

  NOSPD::HSForm form() const { return hs_form; }
  std::string not_a_potential() const override;
  double ratio() const { return hs_ratio; }
  bigint singular_bond_families() const { return nsingular_bonds; }
  int pattern_count() const { return (int) patterns.size(); }
  bigint stencil_points() const { return nstencil_all; }
  bool stencil_enabled() const { return stencil_on; }
  // stencils built since the style was created (they are kept between runs
  // while the law they were built for stays; for tests)
  bigint stencils_built() const { return nstencils_built; }
  // the Newton minimizer's probes: each bond of an inelastic family whose
  // law offers a consistent tangent answers P0 + D:(F - F0) about the
  // bond's F at the positions of begin_linearization (recorded by one
  // force pass there; pair_peri_nospd_hs_history.cpp)
  int begin_linearization() override;
  void end_linearization() override;

 protected:
  // the patterns and stencils follow each family's partner order
  bool pair_order_usable() const override { return false; }
  int family_kind() const override { return 2; }
  std::function<void(std::vector<double> &)> family_row_bound() override
  {
    return [this](std::vector<double> &rows) { bound_family_rows(rows); };
  }
  void bound_family_rows(std::vector<double> &rows);
  // the runs measured stayed stable to 1.5-3.2 times this style's bound (the
  // classical style's to 2.4-4 times its own): the estimate takes 1.25 times it
  double bound_margin() const override { return 1.25; }
  NOSPD::HSForm hs_form;
  double hs_ratio;

  // reference patterns shared by families of the same shape
  std::vector<NOSPD::BondPattern> patterns;
  std::unordered_multimap<uint64_t, int> pattern_lookup;

  // per owned atom, valid until the bonds fix rebuilds its arrays:
  // pattern, and for each pattern slot the bond's offset in the fix's
  // arrays (slot order -> bond_first[i] + perm)
  int mapped_version;
  std::vector<int> state_pattern, state_first, state_count;
  std::vector<tagint> state_tag;
  std::vector<uint16_t> state_perm;
  bigint nsingular_bonds, nfallback_states;
  bool reported;

  // forces and per-atom virial landing on ghosts, sent home afterwards
  int nmax_ghost;
  double **fghost, **vghost;
  int reverse_virial;

  // per type: the law's linear form, where it has one (small strain)
  std::vector<NOSPD::LinearLaw> linear_law;

  // what one thread needs to evaluate families: scratch, lanes and, for
  // the threads after the first, the forces (and per-atom virial) it
  // scatters to partners, added to fghost (vghost) in thread order after
  // the pass.  work[0] scatters into fghost itself.
  struct FamilyWork {
    NOSPD::StateScratch scratch;
    std::vector<double> ubuf[2], tbuf[2];    // per lane: U and t of a family
    std::vector<int> jbuf[2];                // per lane: partners' local indices
    std::vector<int> sbuf[2];                // per lane: partner slots (bond history)
    std::vector<double> fg, vg;              // threads > 0: scattered forces, virial
    bool used = false;
  };
  std::vector<FamilyWork> work;
  int nbig;                                // the largest family
  void prepare_work(int nthreads, int nall);
  void grow_ghost_buffers();
  std::vector<int> state_order;            // owned atoms grouped by pattern
  std::vector<double> inv_vfrac;           // 1/V, owned and ghost atoms

  void map_families();
  // the steps of map_families
  void match_families(std::vector<int> &npat, std::vector<int> &nfirst, std::vector<int> &ncount,
                      std::vector<tagint> &ntag, std::vector<uint16_t> &nperm);
  void drop_unused_patterns(std::vector<int> &npat, std::vector<int> &users,
                            std::vector<int> &renum);
  void count_fallbacks();
  int match_pattern(int i, std::vector<uint16_t> &perm);
  void report_patterns();
  template <int DIM, int VIRIAL> void force_pass(int eflag, bool stencil_step);
  template <int DIM, int VIRIAL, bool MASKED>
  void force_range(const int *order, int from, int to, int tid, int eflag, Tally &t);
  template <int VIRIAL, bool MASKED>
  void apply_family(int i, const NOSPD::BondPattern &p, FamilyWork &w, int lane, double *fg,
                    double *vg, const NOSPD::StateOutput &out, int eflag, Tally &t);
  void gather_family(int i, const NOSPD::BondPattern &p, const uint16_t *perm, FamilyWork &w,
                     int lane);
  // inelastic families: their law with history per bond-associated family
  // (J2/Johnson-Cook's compact per-bond state, or any other law of the
  // material interface, UMATs included); `active` is the one in use, if any
  struct LaneLaws {
    NOSPD::FamilyPlasticity plastic;
    NOSPD::FamilyMaterial material;
    NOSPD::UmatPoint point_data;    // a UMAT's (Material::wants_point_data)
    NOSPD::BondLaw *active = nullptr;
  };
  void begin_history(int i, const NOSPD::BondPattern &p, FamilyWork &w, int lane,
                     LaneLaws &laws);
  // the linearization's F rows (FamilyRows::record, about): per owned atom
  // from lin_first[i] to lin_first[i + 1], empty for families without a law
  enum class LinMode { OFF, RECORD, PROBE } lin_mode = LinMode::OFF;
  std::vector<double> lin_F;
  std::vector<size_t> lin_first;
  void finish_history(int i, LaneLaws &laws, int eflag, bool minimizing, Tally &t);
  void family_failure(int i, const LaneLaws &laws, const NOSPD::Mat3 &F) const;
  void bond_failure(int i, const NOSPD::StateOutput &out, tagint partner) const;

  // The linear law's stencil (nospd_stencil.h): points whose whole
  // horizon is one grid pattern take their force from it on steps that
  // need no energy and no virial, and points near surfaces from a
  // one-sided stencil that many of them share; the families whose every
  // target is such a point are not evaluated then, the others scatter
  // only onto the rest.
  bool stencil_on;                                     // keyword stencil yes|no
  std::vector<std::map<int, NOSPD::Stencil>> pattern_stencils;    // [pattern][type]
  struct StencilRun {
    const NOSPD::Stencil *st;
    std::vector<int> pair_lin, slot_lin;    // offsets in the cell grid
    std::vector<int> atoms, cells;          // its owned atoms and their cells
  };
  std::vector<StencilRun> stencil_runs;
  std::vector<std::array<int, 3>> stencil_blocks;    // run, first and last + 1 point
  std::vector<int> cell_grid;               // lattice cell -> owned or ghost atom
  std::vector<int> cell_of;                 // owned or ghost atom -> cell (-1 none)
  std::vector<char> on_stencil;             // owned and ghost atoms
  std::vector<double> stencil_key;          // owned and ghost: pattern and material
  std::vector<int> family_order;            // state_order less the families not needed
  std::vector<double> ustencil;             // displacements, 4 per cell
  bigint nstencil_all;
  bigint nstencils_built = 0;
  std::vector<double> stencil_law;          // what the kept stencils were built for
  std::vector<double> stencil_law_signature() const;
  int comm_mode;                            // forward comm: 0 classical B, 1 key, 2 flag
  bool stencils_stale;                      // the families were remapped since
  void map_stencils();
  // the steps of map_stencils
  void family_keys(const std::vector<int> &users, std::vector<const NOSPD::Stencil *> &st_of,
                   std::map<double, std::pair<int, int>> &family_of);
  bool stencil_grid(const std::vector<int> &users,
                    const std::vector<const NOSPD::Stencil *> &st_of, double *h,
                    std::vector<std::array<int, 3>> &coords, long *stride);
  bigint map_grid_points(const std::vector<const NOSPD::Stencil *> &st_of,
                         const std::vector<std::array<int, 3>> &coords, const long *stride,
                         const double *h, std::map<const NOSPD::Stencil *, int> &run_of);
  void order_stencil_runs();
  void families_off_stencil();
  const NOSPD::Stencil *stencil_for(int pattern, int type);
  bool build_cell_grid(const double *h, std::vector<std::array<int, 3>> &coords,
                       long stride[3]);
  bool stencil_cells_present(const NOSPD::Stencil &st, const std::array<int, 3> &at,
                             const long *stride) const;
  void join_stencil_run(int i, const NOSPD::Stencil *st, const long *stride,
                        std::map<const NOSPD::Stencil *, int> &run_of);
  // one-sided stencils, by neighbourhood (neighbourhood_key)
  std::map<std::vector<int64_t>, NOSPD::Stencil> point_stencils;
  bool first_point_mapping;    // the run's first: every shared neighbourhood built
  void neighbourhood_key(int i, std::vector<int64_t> &key) const;
  int map_point_stencils(const std::vector<std::array<int, 3>> &coords, const long *stride,
                         const double *h, const std::map<double, std::pair<int, int>> &family_of,
                         std::map<const NOSPD::Stencil *, int> &run_of);
  void build_point_stencils(const std::vector<std::pair<const std::vector<int64_t> *, int>> &needs,
                            const double *h,
                            const std::map<double, std::pair<int, int>> &family_of);
  struct PointPlan;
  void plan_point_stencils(const std::vector<std::pair<const std::vector<int64_t> *, int>> &needs,
                           const double *h, const std::map<double, std::pair<int, int>> &family_of,
                           PointPlan &P);
  void assemble_point_stencils(
      const std::vector<std::pair<const std::vector<int64_t> *, int>> &needs, const double *h,
      PointPlan &P);
  void ghosts_for_stencil();
  void restore_ghost_cutoff();
  // the user's comm cutoff this style replaced, and the value it set (-1: none)
  double cutghost_replaced = -1.0, cutghost_raised = -1.0;
  void stencil_pass();
  void store_stencil_state(int i, const NOSPD::Stencil &st, const double *H, const double *Hbar);

  // optional stabilization (silling, hourglass) on top of the
  // bond-associated forces
  bool stab_on;
  std::vector<double> stab_energy;    // Silling energy density per owned atom
  void stabilization_pass(int eflag);
};

// tuning of pattern sharing and the stencil accelerator (pair_peri_nospd_hs_*.cpp)
namespace HSTuning {
// offsets are matched to patterns after rounding to this fraction of the
// horizon: far below any spacing, far above the round-off of x0 differences
constexpr double KEY_QUANTUM = 1.0e-10;
// weights of two families of one pattern agree to this relative tolerance
constexpr double WEIGHT_TOL = 1.0e-12;
// patterns shared by at least this many families get a sum program (its
// construction costs about as much as evaluating a few hundred families)
constexpr int PROGRAM_USERS = 64;
// a neighbourhood shared by at least this many points gets a one-sided
// stencil (its assembly costs about as much as evaluating a hundred
// families, besides the operators of the families it reads)
constexpr int POINT_STENCIL_USERS = 4;
// the one-sided stencils' assembly holds a dense cube of blocks per
// neighbourhood: at most this many bytes of them at once
constexpr double POINT_STENCIL_BATCH_BYTES = 256.0e6;
// the stencil pass takes points in blocks of this many (its kernel's loop
// over them is its own)
constexpr int STENCIL_BLOCK = 64;


// FNV-1a over a pattern's quantized offsets
inline uint64_t key_hash(const std::vector<int64_t> &key)
{
  uint64_t h = 1469598103934665603ULL;
  for (int64_t v : key) h = (h ^ (uint64_t) v) * 1099511628211ULL;
  return h;
}

}    // namespace HSTuning

}    // namespace LAMMPS_NS

#endif
#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Inelastic history per bond-associated family (horizon-stabilized style).
   Knows nothing of LAMMPS.

   In the bond-associated model every bond j of a family has its own
   deformation gradient F_j, so an inelastic material has a plastic state
   per bond: the return mapping of nospd_plasticity.h runs on each F_j
   from that bond's history.  Per bond only what the return cannot rebuild
   is kept (BondHist: the plastic strain and the equivalent plastic strain,
   7 values; the Prager back stress is (2/3) H_kin eps_p and is rebuilt).
   The family keeps a point history in the classical layout (Hist) whose
   entries are the beta-weighted sums over its bonds, the beta_j of the
   energy E = sum_i V_i sum_j beta_j W(F_j):
     - WORK, HEAT, DAMAGE accumulate beta_j times each bond's increment:
       the family's plastic work, adiabatic temperature rise and
       Johnson-Cook damage;
     - EQPS, PLASTIC, BACK and YIELDING are the means of the bonds' states
       (output and the damage criteria);
     - the equivalent strain rate, the accepted F (FPREV) and the
       temperature of the accepted step come from the whole family's F.
   All bonds of a family share its temperature and strain rate, as they
   share its material point.

   The flow stress of a step uses the rate and temperature of the step
   before (as in the classical style).  RATE_USED and HEAT_USED keep the
   values the accepted step itself used: when a force evaluation finds the
   family at its accepted configuration (the setup of a run that follows
   another, or a restart) it returns the accepted stresses by evaluating
   the bonds with them and leaves the history as it was.  Unlike the
   classical style, the energy that a Johnson-Cook surface moving between
   steps releases is not added to the plastic work (it would need each
   bond's accepted F): with rate and thermal softening the energy balance
   holds to the order of that change.
------------------------------------------------------------------------- */

#ifndef NOSPD_BOND_HISTORY_H
#define NOSPD_BOND_HISTORY_H

#include "nospd_bond_associated.h"
#include "nospd_material.h"
#include "nospd_plastic_tangent.h"
#include "nospd_plasticity.h"
#include "nospd_umat.h"

namespace NOSPD {

// one bond's history
namespace BondHist {
  constexpr int PLASTIC = 0;    // 6: as Hist::PLASTIC
  constexpr int EQPS = 6;       // equivalent plastic strain
  constexpr int SIZE = 7;
}    // namespace BondHist

// the family's own history: Hist, then these
namespace FamilyHist {
  constexpr int RATE_USED = Hist::SIZE;        // the rate the accepted step used
  constexpr int HEAT_USED = Hist::SIZE + 1;    // the heating the accepted step started from
  constexpr int FALLBACK = Hist::SIZE + 2;     // BondHist of the whole family's F
  constexpr int SIZE = FALLBACK + BondHist::SIZE;
}    // namespace FamilyHist

namespace detail {
  // the point history (Hist) a bond entry stands for: its plastic state,
  // Prager's back stress rebuilt from it; rate and heat are the caller's
  inline void bond_point_history(const double *bond, double Hkin, double *pn)
  {
    for (int k = 0; k < Hist::SIZE; ++k) pn[k] = 0.0;
    for (int k = 0; k < 6; ++k) pn[Hist::PLASTIC + k] = bond[BondHist::PLASTIC + k];
    pn[Hist::EQPS] = bond[BondHist::EQPS];
    if (Hkin > 0.0)
      for (int k = 0; k < 6; ++k) pn[Hist::BACK + k] = (2.0 / 3.0) * Hkin * pn[Hist::PLASTIC + k];
  }

  // the return of one bond at F under the plane assumption (plane stress
  // solves F33 for P33 = 0, as the classical point does)
  inline ReturnStatus bond_return(Law law, Plane plane, const Lame &m, const FlowLaw &fl,
                                  const ThermalLaw &th, const PointEnv &env, Mat3 &F,
                                  const double *pn, double *p1, Mat3 &P, double &W)
  {
    double Wt;
    if (plane != Plane::STRESS) return point_core(law, m, fl, th, env, F, pn, p1, P, W, Wt);
    ReturnStatus st = ReturnStatus::OK;
    auto eval = [&](const Mat3 &Ft, Mat3 &Pt, double &Wtt) {
      st = point_core(law, m, fl, th, env, Ft, pn, p1, Pt, Wtt, Wt);
      return st == ReturnStatus::OK;
    };
    if (!solve_plane_stress(m, F, P, W, eval) && st == ReturnStatus::OK)
      st = ReturnStatus::NO_CONVERGENCE;
    return st;
  }
}    // namespace detail

using BondReturn = ReturnStatus (*)(Law, Plane, const Lame &, const FlowLaw &, const ThermalLaw &,
                                    const PointEnv &, Mat3 &, const double *, double *, Mat3 &,
                                    double &);

/* Where a family's law finds its rows: the accepted row hn and trial row
   h1 of the family (its own values, then an entry of bond_stride values
   per partner slot from bond_offset on), the pattern (for beta) and the
   partner slot of each pattern slot. */
struct FamilyRows {
  const BondPattern *pattern = nullptr;
  const double *hn = nullptr;      // accepted row
  double *h1 = nullptr;            // trial row (a copy of hn when the family starts)
  const int *slot_of = nullptr;    // pattern slot -> partner slot
  int bond_offset = 0, bond_stride = 0;
  // the Newton minimizer's probes (PairPeriNospdHS::begin_linearization):
  // 9 values per F, the family's first, then the fallback's, then a bond's
  // per pattern slot.  `record` receives the F the laws see; with `about`
  // (those of the point linearized about) a bond whose law has a
  // consistent tangent answers P0 + dP/dF:(F - F0) instead of its law
  double *record = nullptr;
  const double *about = nullptr;

  // offset of a pattern slot's entry in a row
  int entry(int slot) const { return bond_offset + bond_stride * slot_of[slot]; }
  // offset of a slot's F (slot -1: the fallback) in record and about
  static int lin_entry(int slot) { return 9 * (slot + 2); }
  // the weight of the whole family's state: that of the singular bonds
  double fallback_beta() const
  {
    double b = 0.0;
    for (int j = 0; j < pattern->n; ++j)
      if (pattern->singular[j]) b += pattern->beta[j];
    return b;
  }
};

/* The built-in J2/Johnson-Cook/thermal material on one bond-associated
   family.  Set up per family: the material and the rows (FamilyHist,
   then a BondHist entry per partner slot).  evaluate_families() then calls
   begin() and stress(); finish() completes the family's trial row. */
class FamilyPlasticity : public BondLaw, public FamilyRows {
 public:
  Law law = Law::SMALL;    // SMALL or HENCKY
  Plane plane = Plane::NONE;
  const Lame *m = nullptr;
  const FlowLaw *fl = nullptr;
  const ThermalLaw *th = nullptr;
  PointEnv env;
  ReturnStatus status = ReturnStatus::OK;
  // the return of one bond: detail::bond_return, or a copy of it that the
  // caller built for its CPU (a virtual stress() cannot be multiversioned)
  BondReturn bond_return = detail::bond_return;

  void begin(const Mat3 &F_family) override
  {
    status = ReturnStatus::OK;
    Ffam = F_family;
    replay = false;
    if (record) store(F_family, record);
    if (hn[Hist::VALID] > 0.0 && hn[Hist::TACC] == env.T_base) {
      // a probe replays where the point it linearizes about did
      Mat3 d = (about ? load(about) : F_family) - Mat3::Identity() - load(hn + Hist::FPREV);
      if (plane != Plane::NONE) d(2, 2) = 0.0;
      replay = d.cwiseAbs().maxCoeff() <= 1.0e-12;
    }
    for (double &v : sum) v = 0.0;
    for (double &v : plastic) v = 0.0;
    // the bonds share the family's rate and temperature: the flow stress's
    // factor of the two once for all of them
    env.has_factor = fl->active;
    if (fl->active)
      env.factor = fl->factor(replay ? hn[FamilyHist::RATE_USED]
                                     : (env.dt > 0.0 ? hn[Hist::RATE] : 0.0),
                              env.T_base + (replay ? hn[FamilyHist::HEAT_USED] : hn[Hist::HEAT]));
  }

  bool stress(int slot, Mat3 &F, Mat3 &P, double &W) override
  {
    const int off = slot < 0 ? FamilyHist::FALLBACK : entry(slot);
    const double *bn = hn + off;
    double *b1 = h1 + off;
    double pn[Hist::SIZE], p1[Hist::SIZE];
    detail::bond_point_history(bn, fl->Hkin, pn);
    pn[Hist::RATE] = replay ? hn[FamilyHist::RATE_USED] : hn[Hist::RATE];
    pn[Hist::HEAT] = replay ? hn[FamilyHist::HEAT_USED] : hn[Hist::HEAT];
    if (record) store(F, record + lin_entry(slot));
    if (about && linearized(slot, pn, F, P, W)) return true;    // a probe: no history
    const ReturnStatus st = bond_return(law, plane, *m, *fl, *th, env, F, pn, p1, P, W);
    if (st != ReturnStatus::OK) {
      status = st;
      return false;
    }
    if (replay) return true;    // the accepted state: history unchanged

    for (int k = 0; k < 6; ++k) b1[BondHist::PLASTIC + k] = p1[Hist::PLASTIC + k];
    b1[BondHist::EQPS] = p1[Hist::EQPS];
    const double beta = slot < 0 ? fallback_beta() : pattern->beta[slot];
    sum[S_WORK] += beta * p1[Hist::WORK];    // pn[WORK] = 0: the bond's increment
    sum[S_HEAT] += beta * (p1[Hist::HEAT] - pn[Hist::HEAT]);
    sum[S_DAMAGE] += beta * p1[Hist::DAMAGE];
    sum[S_YIELD] += beta * p1[Hist::YIELDING];
    sum[S_EQPS] += beta * p1[Hist::EQPS];
    for (int k = 0; k < 6; ++k) plastic[k] += beta * p1[Hist::PLASTIC + k];
    return true;
  }

  // the family's trial row after its bonds (not called for a family
  // without a regular shape tensor: its row stays the accepted one)
  void finish()
  {
    if (replay) return;
    h1[FamilyHist::RATE_USED] = env.dt > 0.0 ? hn[Hist::RATE] : 0.0;
    h1[FamilyHist::HEAT_USED] = hn[Hist::HEAT];
    h1[Hist::WORK] = hn[Hist::WORK] + sum[S_WORK];
    h1[Hist::HEAT] = hn[Hist::HEAT] + sum[S_HEAT];
    h1[Hist::DAMAGE] = hn[Hist::DAMAGE] + sum[S_DAMAGE];
    h1[Hist::YIELDING] = sum[S_YIELD];
    h1[Hist::EQPS] = sum[S_EQPS];
    for (int k = 0; k < 6; ++k) {
      h1[Hist::PLASTIC + k] = plastic[k];
      h1[Hist::BACK + k] = (2.0 / 3.0) * fl->Hkin * plastic[k];
    }
    // the family's strain rate over the step, as the classical point's
    h1[Hist::RATE] = strain_rate(law, Ffam, hn, env.dt);
    store(Ffam - Mat3::Identity(), h1 + Hist::FPREV);
    h1[Hist::TACC] = env.T_base;
    h1[Hist::VALID] = 1.0;
  }

  bool replaying() const { return replay; }

 private:
  // P0 + D:(F - F0) of the bond's return at its F0 from pn (none in plane
  // stress, whose F33 comes from a secant solve)
  bool linearized(int slot, const double *pn, const Mat3 &F, Mat3 &P, double &W)
  {
    if (plane == Plane::STRESS) return false;
    Mat3 F0 = load(about + lin_entry(slot));
    Tangent9 D;
    if (!core_tangent(law, *m, *fl, *th, env, F0, pn, D)) return false;
    double p1[Hist::SIZE];
    Mat3 P0;
    if (bond_return(law, plane, *m, *fl, *th, env, F0, pn, p1, P0, W) != ReturnStatus::OK)
      return false;
    P = P0 + linear_step(D, F - F0);
    return true;
  }

  enum { S_WORK, S_HEAT, S_DAMAGE, S_YIELD, S_EQPS, S_N };
  double sum[S_N] = {};
  double plastic[6] = {};
  Mat3 Ffam = Mat3::Identity();
  bool replay = false;
};

/* Any law of the material-point interface (nospd_material.h) on one
   bond-associated family: every bond is a material point of its own with
   an entry of the law's history per partner slot; the family's row holds
   an entry of beta-weighted means (the output, in the law's layout: Hist's
   columns for a plasticity law, UmatHist's for a UMAT), in the columns
   that accumulate (Material::accumulates: the dissipation, a UMAT's
   energies) the sum of the bonds' increments, and from `fallback` on the
   entry of the whole family's F.  A UMAT sees each bond as an integration
   point of its own (NPT 2 + its slot in the pattern, 1 for the whole
   family's F).  A new law needs nothing here. */
class FamilyMaterial : public BondLaw, public FamilyRows {
 public:
  const Material *mat = nullptr;
  MaterialEnv env;
  PointStatus status;

  // the family row's entries: the means, then the whole family's
  static int family_size(const Material &m) { return 2 * m.history_size(); }
  int fallback() const { return mat->history_size(); }

  void begin(const Mat3 &) override
  {
    status = PointStatus();
    const int n = mat->history_size();
    acc.assign(n, 0.0);
    if ((int) accum.size() != n || accum_of != mat) {
      accum.resize(n);
      for (int k = 0; k < n; ++k) accum[k] = mat->accumulates(k);
      accum_of = mat;
    }
  }

  bool stress(int slot, Mat3 &F, Mat3 &P, double &W) override
  {
    const int off = slot < 0 ? fallback() : entry(slot);
    MaterialEnv e = env;
    e.point = slot < 0 ? 0 : slot + 1;
    if (record) store(F, record + lin_entry(slot));
    if (about && linearized(slot, off, e, F, P, W)) return true;    // a probe: no history
    status = mat->stress(F, hn + off, h1 + off, e, P, W);
    if (!status.ok()) return false;
    const double beta = slot < 0 ? fallback_beta() : pattern->beta[slot];
    const int n = mat->history_size();
    for (int k = 0; k < n; ++k)
      acc[k] += beta * (accum[k] ? h1[off + k] - hn[off + k] : h1[off + k]);
    return true;
  }

  // the family's row after its bonds
  void finish()
  {
    const int n = mat->history_size();
    for (int k = 0; k < n; ++k) h1[k] = (accum[k] ? hn[k] : 0.0) + acc[k];
  }

 private:
  // P0 + D:(F - F0) of the law at the bond's F0, where it offers D
  bool linearized(int slot, int off, const MaterialEnv &e, const Mat3 &F, Mat3 &P, double &W)
  {
    Mat3 F0 = load(about + lin_entry(slot));
    Tangent9 D;
    if (!mat->tangent(F0, hn + off, e, D)) return false;
    Mat3 P0;
    if (!mat->stress(F0, hn + off, h1 + off, e, P0, W).ok()) return false;
    P = P0 + linear_step(D, F - F0);
    return true;
  }

  std::vector<double> acc;
  std::vector<char> accum;    // accumulates(k) of mat, once per law
  const Material *accum_of = nullptr;
};

/* The stress of one bond (or of the whole family's F, for the fallback
   entry) at F from its accepted state, elastic from that state (no
   return): at the accepted configuration this is the accepted stress.
   T is the point's temperature.  For output. */
inline bool accepted_bond_stress(Law law, Plane plane, const Lame &m, const FlowLaw &fl,
                                 const ThermalLaw &th, double T, const double *bond, Mat3 &F,
                                 Mat3 &P)
{
  FlowLaw elastic = fl;
  elastic.active = false;
  PointEnv env;
  env.T_base = T;
  double pn[Hist::SIZE], p1[Hist::SIZE], W;
  detail::bond_point_history(bond, 0.0, pn);
  return detail::bond_return(law, plane, m, elastic, th, env, F, pn, p1, P, W) == ReturnStatus::OK;
}

}    // namespace NOSPD

#endif

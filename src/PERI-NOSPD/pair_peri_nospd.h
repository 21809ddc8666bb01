/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(peri/nospd,PairPeriNospd);
// clang-format on
#else

#ifndef LMP_PAIR_PERI_NOSPD_H
#define LMP_PAIR_PERI_NOSPD_H

#include "pair_peri_nospd_base.h"

#include <vector>

namespace LAMMPS_NS {

/* Classical correspondence peridynamics (Silling et al. 2007):
     T_i<xi> = omega P_i K_i^-1 xi  (+ zero-energy-mode control)
   One step: F of every family (pass 1, the bonds fix), P through the
   material table (the constitutive pass, with Silling's springs on the
   quadratic fit where asked), the bond forces with the stabilization
   (pass 2, PairPeriNospdBase's force pass). */
class PairPeriNospd : public PairPeriNospdBase {
 public:
  PairPeriNospd(class LAMMPS *);
  void compute(int, int) override;
  int begin_linearization() override;
  void end_linearization() override
  {
    linearized = false;
    std::vector<double>().swap(lin);
    std::vector<int>().swap(lin_row);
  }

 protected:
  int family_kind() const override { return 1; }
  void constitutive_pass(int eflag);
  void constitutive_range(int from, int to, int eflag, Tally &t);
  void point_stress(int i, NOSPD::Mat3 &F, NOSPD::Mat3 &P, double &W, const NOSPD::PointEnv &env);
  NOSPD::MaterialEnv law_env(int i, double dt, NOSPD::UmatPoint &pt);
  void carried_stress(int i, NOSPD::Mat3 &F, NOSPD::Mat3 &P, double &W, const NOSPD::PointEnv &env);
  void quadratic_pass();
  // the linearized laws (begin_linearization): per owned atom its row in
  // lin (-1: the law itself), each row F0 (9), P0 (9), D (81)
  bool linearized = false;
  std::vector<int> lin_row;
  std::vector<double> lin;
  static constexpr int LIN_RECORD = 99;
  void quadratic_spring(int i, const NOSPD::Mat3 &H, NOSPD::Mat3 &H2, double &e2, bool energy);
};

}    // namespace LAMMPS_NS

#endif
#endif

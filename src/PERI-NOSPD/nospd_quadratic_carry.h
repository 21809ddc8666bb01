/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Silling's springs on the quadratic fit for a family that lost bonds:
   the fit's curvature carried.  Knows nothing of LAMMPS.

   Intact, the springs resist z2 = U - A phi(xi), the residual of the
   family's quadratic fit (nospd_stabilization.h).  Refitting a quadratic
   on the ragged family a crack leaves is ill-posed, and dropping to the
   linear fit's residual z = U - H xi, which holds the curvature as well,
   loads the springs at the break (energy from nothing).  Instead the
   family keeps the curvature it had: with psi(xi) = phi_q(xi) - M K^-1 xi,
   M = sum w phi_q xi^T (the quadratic basis made w-orthogonal to the
   linear one over the current family),
       z = (U - H xi) - Q psi(xi),   Q = F G',   E = 1/2 alpha sum w |z|^2,
   G' = F_c G constant (F_c of nospd_carry.h, G set when the family first
   loses bonds so that Q equals its last fit's quadratic part Q_s).  Q
   turns with F, so a curved fragment turning rigidly keeps its energy.
   At a break z = P(U - Q phi_q) over the bonds left (P: the residual of
   the linear fit), the least squares over fewer bonds: E cannot rise.

   E is quadratic in U (F = I + H, H = N K^-1 linear in U), and, as
   sum w z xi^T = 0, its force state is
       T<xi> = omega alpha (U - H2 xi - Q phi_q(xi)),
       H2 = H - Q M K^-1 + Z K^-1,  Z = (N_psi - Q K_psipsi) G'^T,
   N_psi = sum w U psi^T = N_q - H M^T, K_psipsi = sum w psi psi^T
   = K_qq - M K^-1 M^T: the form of the intact quadratic spring, so pass
   2 is unchanged.  And sum w |z|^2 = sum w |U - H xi|^2 - 2 N_psi : Q
   + Q K_psipsi : Q.
------------------------------------------------------------------------- */

#ifndef NOSPD_QUADRATIC_CARRY_H
#define NOSPD_QUADRATIC_CARRY_H

#include "nospd_stabilization.h"

namespace NOSPD {

namespace CarriedQuadratic {
  constexpr double FLAG = 2.0;    // rec[QuadraticFit::PACKED]: a damaged family's record
  constexpr int M_AT = 0;         // M, 6 x 3 row by row
  constexpr int KPP_AT = 18;      // K_psipsi, upper triangle of 6 x 6 row by row (21)
  constexpr int G_SIZE = 18;      // G per atom, 3 x 6 column by column
  // the bonds fix's kinv2 row per atom: the fit record, then G
  constexpr int G_AT = QuadraticFit::RECORD;
  constexpr int ATOM_RECORD = QuadraticFit::RECORD + G_SIZE;
}    // namespace CarriedQuadratic

using Mat36 = Eigen::Matrix<double, 3, 6>;

inline int packed6(int r, int c)
{
  if (r > c) std::swap(r, c);
  return r * 6 - r * (r - 1) / 2 + (c - r);
}

/* the record of a family that lost bonds, from its K2 (9 x 9, symmetric,
   over the bonds left) and K^-1 */
inline void carried_quadratic_record(const Eigen::Matrix<double, 9, 9> &K2, const Mat3 &Kinv,
                                     double *rec)
{
  using namespace CarriedQuadratic;
  for (int k = 0; k < QuadraticFit::RECORD; k++) rec[k] = 0.0;
  const Eigen::Matrix<double, 6, 3> M = K2.block<6, 3>(3, 0);
  const Eigen::Matrix<double, 6, 6> Kpp = K2.block<6, 6>(3, 3) - M * Kinv * M.transpose();
  for (int r = 0; r < 6; r++)
    for (int c = 0; c < 3; c++) rec[M_AT + 3 * r + c] = M(r, c);
  for (int r = 0; r < 6; r++)
    for (int c = r; c < 6; c++) rec[KPP_AT + packed6(r, c)] = Kpp(r, c);
  rec[QuadraticFit::PACKED] = FLAG;
}

/* the spring of a family with a carried record: H (live linear fit F - I),
   FcG = F_c G, N2 = sum w U phi^T (3 x 9), elin = sum w |U - H xi|^2 (only
   read with `energy`).  Out: H2 and Q for pass 2, e2 = sum w |z|^2. */
inline void carried_quadratic_spring(const Mat3 &H, const Mat36 &FcG,
                                     const Eigen::Matrix<double, 3, 9> &N2, const double *rec,
                                     const Mat3 &Kinv, double elin, bool energy, Mat3 &H2,
                                     Mat36 &Q, double &e2)
{
  using namespace CarriedQuadratic;
  Eigen::Matrix<double, 6, 3> M;
  Eigen::Matrix<double, 6, 6> Kpp;
  for (int r = 0; r < 6; r++)
    for (int c = 0; c < 3; c++) M(r, c) = rec[M_AT + 3 * r + c];
  for (int r = 0; r < 6; r++)
    for (int c = 0; c < 6; c++) Kpp(r, c) = rec[KPP_AT + packed6(r, c)];
  Q = (Mat3::Identity() + H) * FcG;
  const Mat36 Npsi = N2.rightCols<6>() - H * M.transpose();
  const Mat36 R = Npsi - Q * Kpp;
  const Mat3 Z = R * FcG.transpose();
  H2 = H - Q * (M * Kinv) + Z * Kinv;
  e2 = energy ? elin - 2.0 * Npsi.cwiseProduct(Q).sum() + (Q * Kpp).cwiseProduct(Q).sum() : 0.0;
}

/* G from the last intact fit's quadratic part Q_s and the family's F F_c
   before the change (F F_c is continuous across the refit) */
inline Mat36 carried_quadratic_start(const Mat36 &Qs, const Mat3 &FFc_before)
{
  return FFc_before.inverse() * Qs;
}

}    // namespace NOSPD

#endif

/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The deformation a point carries across a change of its family.  Knows
   nothing of LAMMPS.

   F is the least-squares fit of a point's bonds, F = sum w Y (x) xi K^-1.
   When bonds break, the fit of the bonds left, at the same positions,
   differs from the old one by the non-affine part of the lost bonds'
   motion: no deformation of the material, yet W(F) would jump, up as often
   as down, and a plastic law would flow to follow the jump.  The point
   carries the difference instead,
       F_c <- F_new^-1 F_old F_c,
   and the law sees F F_c, the same just before and just after the change:
   a break creates no energy and no plastic work.  F_c acts from the right
   (the reference side), so W(Q F F_c) = W(F F_c): a fragment that rotates
   stays unstressed.  The forces are the gradient of V W(F F_c), that is
   the force state with P F_c^T in place of P.

   A refit that inverts the family (det F_new <= 0), or that takes F_c
   farther than CARRY_LIMIT from I (Frobenius norm), says that the bonds
   left no longer describe the point: it is then singular (false).
------------------------------------------------------------------------- */

#ifndef NOSPD_CARRY_H
#define NOSPD_CARRY_H

#include "nospd_tensor.h"

namespace NOSPD {

constexpr double CARRY_LIMIT = 0.5;

// F_c updated for a refit from Fold to Fnew at the same positions; false
// (F_c unchanged) when the point must become singular instead
inline bool carry_deformation(const Mat3 &Fold, const Mat3 &Fnew, Mat3 &Fc,
                              double limit = CARRY_LIMIT)
{
  if (!(Fnew.determinant() > 0.0)) return false;
  const Mat3 next = Fnew.inverse() * Fold * Fc;
  if (!((next - Mat3::Identity()).norm() <= limit)) return false;
  Fc = next;
  return true;
}

// what a carried deformation can be (a restart file's, checked): finite,
// within the limit, orientation kept
inline bool carried_deformation_valid(const Mat3 &Fc, double limit = CARRY_LIMIT)
{
  return (Fc - Mat3::Identity()).norm() <= limit && Fc.determinant() > 0.0;
}

}    // namespace NOSPD

#endif

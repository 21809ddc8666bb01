/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The reference box of a periodic body: the box its families were built
   in, followed through the flips of a triclinic box, and the one reference
   bond geometry every consumer takes (the minimum image in that box).
   Knows nothing of LAMMPS: boxes are given as LAMMPS's h (xx yy zz yz xz
   xy), the upper triangular matrix of the box vectors a, b, c.
------------------------------------------------------------------------- */

#ifndef NOSPD_REFERENCE_BOX_H
#define NOSPD_REFERENCE_BOX_H

#include "nospd_tensor.h"

#include <cmath>

namespace NOSPD {

struct ReferenceBox {
  double ref[6] = {0, 0, 0, 0, 0, 0};     // the reference box
  double last[6] = {0, 0, 0, 0, 0, 0};    // the current box at the last follow()
  bool set = false;                       // ref holds the box of the first build

  static Mat3 matrix(const double *v)
  {
    Mat3 m;
    m << v[0], v[5], v[4], 0.0, v[1], v[3], 0.0, 0.0, v[2];
    return m;
  }

  /* The reference box follows the basis of the current one h: a triclinic
     box that fix deform or change_box flips (xy -> xy - lx, ...) expresses
     the same periodic lattice with new vectors h' = h M, M an integer
     matrix; applied to the reference box, the same M keeps every image's
     reference offset.  Called often enough that between two calls the box
     deforms by far less than half a period, so M is last^-1 h rounded.
     The first call takes h as the reference. */
  void follow(const double *h)
  {
    if (!set) {
      for (int k = 0; k < 6; k++) ref[k] = last[k] = h[k];
      set = true;
      return;
    }
    const Mat3 A = matrix(last).inverse() * matrix(h);
    const Mat3 M = A.array().round().matrix();
    // a flip changes the basis by whole box vectors and leaves every tilt
    // within half a box length; a large one-shot change (change_box xy
    // final 0.6*lx remap) is a deformation, whatever M rounds to
    const bool flipped = !M.isIdentity(0.0) && (A - M).cwiseAbs().maxCoeff() < 0.1 &&
        std::abs(h[5]) <= 0.500001 * h[0] && std::abs(h[4]) <= 0.500001 * h[0] &&
        std::abs(h[3]) <= 0.500001 * h[1];
    if (flipped) {
      const Mat3 R = matrix(ref) * M;
      const double r[6] = {R(0, 0), R(1, 1), R(2, 2), R(1, 2), R(0, 2), R(0, 1)};
      for (int k = 0; k < 6; k++) ref[k] = r[k];
    }
    for (int k = 0; k < 6; k++) last[k] = h[k];
  }

  /* The reference bond xi from x0i to x0j: the minimum image of x0j - x0i
     in the reference box (in h_now, the current box, before the first
     follow()), as LAMMPS's Domain::minimum_image; each branch adds the
     negative of what the mirrored branch adds, so xi(j, i) = -xi(i, j) bit
     for bit. */
  void bond(const double *x0i, const double *x0j, const int *periodic, const double *h_now,
            double *xi) const
  {
    for (int k = 0; k < 3; k++) xi[k] = x0j[k] - x0i[k];
    const double *r = set ? ref : h_now;
    if (periodic[2])
      while (std::abs(xi[2]) > 0.5 * r[2]) {
        const double s = xi[2] < 0.0 ? 1.0 : -1.0;
        xi[2] += s * r[2];
        xi[1] += s * r[3];
        xi[0] += s * r[4];
      }
    if (periodic[1])
      while (std::abs(xi[1]) > 0.5 * r[1]) {
        const double s = xi[1] < 0.0 ? 1.0 : -1.0;
        xi[1] += s * r[1];
        xi[0] += s * r[5];
      }
    if (periodic[0])
      while (std::abs(xi[0]) > 0.5 * r[0]) xi[0] += (xi[0] < 0.0 ? 1.0 : -1.0) * r[0];
  }

  /* The reference image of a point shifted by n0 a + n1 b + n2 c in the
     current box: the same whole vectors of the reference box. */
  void image(double n0, double n1, double n2, double *shift) const
  {
    shift[0] = n0 * ref[0] + n1 * ref[5] + n2 * ref[4];
    shift[1] = n1 * ref[1] + n2 * ref[3];
    shift[2] = n2 * ref[2];
  }
};

}    // namespace NOSPD

#endif

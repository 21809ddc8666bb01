/* ----------------------------------------------------------------------
   PERI-NOSPD: bond-based peridynamic heat conduction (no LAMMPS headers).

   rho c dT_i/dt = sum_j kappa_ij (T_j - T_i) / |xi_ij| V_j + s_i
   (Bobaru and Duangpanya, Int. J. Heat Mass Transfer 53 (2010) 4047-4059;
   Oterkus, Madenci and Agwai, J. Comput. Phys. 265 (2014) 71-96).

   The micro-conductivity is calibrated point by point from the point's own
   family: a quadratic field T = x.H.x/2 gives (kappa/2) M : H with the
   moment M = sum_j |xi| xi^ xi^ V_j, so the point conducts with the tensor
   k_i = kappa M / 2.  kappa_i = 2 k / lambda_max(M) makes it exact along
   M's widest direction: in a full family (M isotropic on a lattice with
   cubic symmetry, M = sum_j |xi| V_j / d) that is k in every direction and
   in a full 3D ball the published 6 k / (pi delta^4); at a free surface it
   is k along the surface and less across it, where an insulated surface
   carries nothing anyway (a scalar from tr M instead over-conducts along
   the surface by the in-plane layer's share).  Two points conduct
   through the harmonic mean of their kappas (conductances in series), so a
   bond's coefficient c_ij = kappa_ij V_i V_j / |xi| is the same number on
   both ends, bit for bit, and the exchange conserves energy to rounding.
------------------------------------------------------------------------- */
#ifndef NOSPD_HEAT_H
#define NOSPD_HEAT_H

#include "nospd_tensor.h"

#include <cmath>
#include <initializer_list>

namespace NOSPD {
namespace Heat {

// the moment M += |xi| xi^ xi^ V of one bond
inline void add_moment(Mat3 &M, const double *xi, double V)
{
  const double len = std::sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
  if (!(len > 0.0)) return;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) M(a, b) += xi[a] * xi[b] / len * V;
}

// kappa_i = 2 k / lambda_max(M) (0 for a point with no bonds)
inline double micro_conductivity(double k, const Mat3 &M)
{
  // the iterative solver: the closed form (computeDirect) loses half the
  // digits where eigenvalues coincide, as they do inside a body
  const double top = Eigen::SelfAdjointEigenSolver<Mat3>(M, Eigen::EigenvaluesOnly).eigenvalues()(2);
  return top > 0.0 ? 2.0 * k / top : 0.0;
}

// c_ij = kappa_ij V_i V_j / |xi|, kappa_ij the harmonic mean; symmetric in
// (i, j) bit for bit (products and sums commute in IEEE arithmetic)
inline double bond_coefficient(double kappa_i, double kappa_j, double len, double vi, double vj)
{
  const double s = kappa_i + kappa_j;
  if (!(s > 0.0) || !(len > 0.0)) return 0.0;
  return (2.0 * kappa_i * kappa_j / s) * (vi * vj) / len;
}

/* Faces a point exposes, for convection and surface flux: the sides +-a
   of each axis a with no partner in the cone of 45 degrees about that
   direction within 1.5 spacings h (the lattice neighbour that would cover
   the face).  A face point of a box-aligned body exposes 1, an edge 2, a
   corner 3, so an n^3 cube's faces add up to its surface 6 n^2; the layer
   below exposes none.  On an inclined or curved surface the count is the
   lattice's staircase.  xi: n bond vectors (x, y, z).  The faces as bits:
   2a for +a, 2a + 1 for -a. */
inline int exposed_faces(const double (*xi)[3], int n, double h, int dim)
{
  int faces = 0;
  for (int a = 0; a < dim; a++)
    for (int side = 0; side < 2; side++) {
      const double s = side ? -1.0 : 1.0;
      bool covered = false;
      for (int b = 0; b < n && !covered; b++) {
        const double along = s * xi[b][a];
        double perp2 = 0.0, len2 = 0.0;
        for (int c = 0; c < 3; c++) {
          len2 += xi[b][c] * xi[b][c];
          if (c != a) perp2 += xi[b][c] * xi[b][c];
        }
        covered = along > 0.0 && along * along >= perp2 && len2 < 2.25 * h * h;
      }
      if (!covered) faces |= 1 << (2 * a + side);
    }
  return faces;
}

inline int face_count(int faces)
{
  int n = 0;
  for (int f = faces; f; f >>= 1) n += f & 1;
  return n;
}

// the current area of the faces of a point deformed by F, each of reference
// area A0 (Nanson: J |F^-T N| A0 per face)
inline double deformed_area(int faces, double A0, const Mat3 &F)
{
  const double J = F.determinant();
  if (!(J > 0.0)) return 0.0;
  const Mat3 FinvT = F.inverse().transpose();
  double A = 0.0;
  for (int a = 0; a < 3; a++)
    if (faces & (3 << (2 * a))) A += face_count(faces & (3 << (2 * a))) * J * FinvT.col(a).norm() * A0;
  return A;
}

// the area of one face of a point of volume V: V^(2/3) in 3D; in 2D
// (volumes area x thickness t) the edge dx = sqrt(V/t) times t
inline double face_area(double V, int dim, double thickness)
{
  if (!(V > 0.0)) return 0.0;
  return dim == 3 ? std::cbrt(V * V) : std::sqrt(V * thickness);
}

/* The forward Euler step's bound for point i: heat capacity m_i = rho c V
   over its conductances sum_j c_ij (+ h A_i with convection).  Below it the
   new temperature is a convex combination of the old ones (no new extremes);
   Gershgorin's theorem puts every eigenvalue of the operator within 2 sum_j
   c_ij / m_i, so the bound is also the stability limit's lower bound. */
inline double step_bound(double capacity, double conductance)
{
  return conductance > 0.0 ? capacity / conductance : HUGE_VAL;
}

// energy rates of points [from, to) of a CSR list: dE_i = sum_b c_b (T_j - T_i)
inline void exchange(const int *first, const int *j, const double *c, const double *T, int from,
                     int to, double *dE)
{
  for (int i = from; i < to; i++) {
    const double Ti = T[i];
    double s = 0.0;
    for (int b = first[i]; b < first[i + 1]; b++) s += c[b] * (T[j[b]] - Ti);
    dE[i] = s;
  }
}

}    // namespace Heat
}    // namespace NOSPD

#endif

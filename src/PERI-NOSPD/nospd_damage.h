/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Bond-breaking criteria, their calibration from the fracture energy, the
   random scatter of critical values, and the geometry of pre-cracks.
   Knows nothing of LAMMPS.

   Every function here is written so that the two owners of a bond, which
   evaluate it on different MPI ranks, get bit-for-bit the same answer when
   they pass the bond's data in the same (atom-ID-sorted) order.
------------------------------------------------------------------------- */

#ifndef NOSPD_DAMAGE_H
#define NOSPD_DAMAGE_H

#include "nospd_stabilization.h"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace NOSPD {

/* ---------------------------------------------------------------------
   Critical stretch from the fracture energy G0.

   A bond-based (PMB) material with micromodulus c and critical stretch
   s0 releases, per unit area of a new crack surface, the energy of every
   bond that crosses it, w = c s0^2 |xi| / 2 per pair of unit volumes:

     3D:  G0 = pi c s0^2 delta^5 / 10         (Silling & Askari 2005)
     2D:  G0 = c s0^2 t delta^4 / 4            (thickness t)

   (the bonds crossing a unit area number pi delta^4/4 in 3D and, per unit
   length, 2 delta^3/3 in 2D, when integrated over their length as below).
   With the micromoduli of nospd_stabilization.h this gives

     3D:                s0 = sqrt( 5 G0 / (9 K delta) ),  K = E/(3(1-2 nu))
                        (Silling & Askari, Comput. Struct. 83 (2005) 1526)
     2D plane stress:   s0 = sqrt( 4 pi G0 / (9 E delta) )
                        (Ha & Bobaru, Int. J. Fract. 162 (2010) 229)
     2D plane strain:   s0 = sqrt( 5 pi G0 / (12 E delta) )
                        (same derivation with c = 48 E/(5 pi t delta^3))
   --------------------------------------------------------------------- */
inline double critical_stretch_from_g0(int dim, Plane plane, double E, double nu, double delta,
                                       double G0)
{
  if (dim == 3) {
    const double K = E / (3.0 * (1.0 - 2.0 * nu));
    return std::sqrt(5.0 * G0 / (9.0 * K * delta));
  }
  if (plane == Plane::STRESS) return std::sqrt(4.0 * PI * G0 / (9.0 * E * delta));
  return std::sqrt(5.0 * PI * G0 / (12.0 * E * delta));
}

/* ---------------------------------------------------------------------
   Critical bond energy from G0 (constant critical energy per bond, the
   calibration of Foster, Silling & Chen, "An energy based failure
   criterion for use with peridynamic states", Int. J. Multiscale Comput.
   Eng. 9 (2011) 675): every bond crossing the crack surface holds w_c,

     3D:  G0 = w_c * pi delta^4 / 4       ->  w_c = 4 G0 / (pi delta^4)
     2D:  G0 t = w_c t^2 * 2 delta^3 / 3   ->  w_c = 3 G0 / (2 t delta^3)

   w_c is an energy per pair of unit volumes (J/m^6), the unit of the bond
   energy w_ij below.
   --------------------------------------------------------------------- */
inline double critical_energy_from_g0(int dim, double delta, double thickness, double G0)
{
  if (dim == 3) return 4.0 * G0 / (PI * delta * delta * delta * delta);
  return 3.0 * G0 / (2.0 * thickness * delta * delta * delta);
}

/* ---------------------------------------------------------------------
   A bond's mechanical part: its thermal strain e (the mean of its ends')
   removed as the laws remove it, small strain additively (s - e, and
   U - e xi), finite strain through the thermal stretch 1 + e
   ((1 + s)/(1 + e) - 1, and Y/(1 + e) - xi).  A body expanding freely has
   no mechanical stretch.
   --------------------------------------------------------------------- */
inline double mechanical_stretch(bool small, double e, double s)
{
  return small ? s - e : (1.0 + s) / (1.0 + e) - 1.0;
}

inline void mechanical_displacement(bool small, double e, const double *xi, const double *Y,
                                    double *U)
{
  for (int k = 0; k < 3; k++) U[k] = small ? (Y[k] - xi[k]) - e * xi[k] : Y[k] / (1.0 + e) - xi[k];
}

/* ---------------------------------------------------------------------
   Bond energy of the correspondence model:
       w_ij = 1/2 omega_ij ((A_i + A_j) xi) . U,   A = P K^-1,  U = Y - xi.
   omega (A_i + A_j) xi is the pair force density of bond ij (its
   correspondence part, stabilization left out), so w_ij is the elastic
   energy held by the bond: in a homogeneous deformation
   sum_j w_ij V_j = 2 W(F) and the body's energy is 1/2 sum_i sum_j
   w_ij V_i V_j.  Asum holds A_i + A_j (row-major).
   --------------------------------------------------------------------- */
inline double bond_energy(double omega, const double *Asum, const double *xi, const double *U)
{
  const double tx = Asum[0] * xi[0] + Asum[1] * xi[1] + Asum[2] * xi[2];
  const double ty = Asum[3] * xi[0] + Asum[4] * xi[1] + Asum[5] * xi[2];
  const double tz = Asum[6] * xi[0] + Asum[7] * xi[1] + Asum[8] * xi[2];
  return 0.5 * omega * (tx * U[0] + ty * U[1] + tz * U[2]);
}

// n . S n for a symmetric tensor stored as xx yy zz xy xz yz
inline double normal_component(const double *S, const double *n)
{
  return S[0] * n[0] * n[0] + S[1] * n[1] * n[1] + S[2] * n[2] * n[2] +
      2.0 * (S[3] * n[0] * n[1] + S[4] * n[0] * n[2] + S[5] * n[1] * n[2]);
}

// von Mises equivalent of a symmetric tensor stored as xx yy zz xy xz yz
inline double von_mises6(const double *S)
{
  const double a = S[0] - S[1], b = S[1] - S[2], c = S[2] - S[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3.0 * (S[3] * S[3] + S[4] * S[4] + S[5] * S[5]));
}

/* ---------------------------------------------------------------------
   Scatter of critical values: a factor 1 + width (2 h - 1), h uniform in
   [0, 1), drawn from a hash of the seed and of the two end points' keys,
   taken in increasing order.  The keys hash the bits of the reference
   positions x0 (position_key), which do not depend on how atom IDs were
   assigned: the factor is the same on every rank, for every decomposition
   (create_atoms numbers atoms per rank) and after a restart.  (splitmix64
   finalizer, Steele, Lea & Flood, OOPSLA 2014.)
   --------------------------------------------------------------------- */
inline uint64_t splitmix64(uint64_t z)
{
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

inline uint64_t position_key(const double *x0)
{
  uint64_t h = 0x2545F4914F6CDD1DULL;
  for (int k = 0; k < 3; k++) {
    uint64_t b;
    std::memcpy(&b, x0 + k, sizeof(b));
    h = splitmix64(h ^ b);
  }
  return h;
}

inline double scatter_factor(uint64_t seed, uint64_t key_a, uint64_t key_b, double width)
{
  const uint64_t lo = key_a < key_b ? key_a : key_b, hi = key_a < key_b ? key_b : key_a;
  const uint64_t h = splitmix64(splitmix64(splitmix64(seed) ^ lo) ^ hi);
  const double u = (double) (h >> 11) * (1.0 / 9007199254740992.0);    // [0, 1)
  return 1.0 + width * (2.0 * u - 1.0);
}

/* ---------------------------------------------------------------------
   Pre-crack geometry.  A bond is the reference segment A-B.

   2D: the crack is the segment C1-C2 (z ignored).  The bond is cut when A
   and B lie on different sides of the crack's line and C1 and C2 do not
   lie strictly on the same side of the bond's line.  A point exactly on
   the crack line counts as lying on its left (orient >= 0) side, so an
   atom on the line keeps its bonds to that side and loses those to the
   other; better, place cracks between rows of points.

   3D: the crack is the parallelogram with corners P1, P2, P3 and
   P2 + P3 - P1.  The bond is cut when A and B lie on different sides of
   its plane (a point on the plane counts as the side the normal
   (P2-P1)x(P3-P1) points to) and the bond meets the plane inside the
   parallelogram (edges included).
   --------------------------------------------------------------------- */
inline double orient2d(const double *p, const double *q, const double *r)
{
  return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
}

inline bool crosses_segment_2d(const double *A, const double *B, const double *C1,
                               const double *C2)
{
  const bool sa = orient2d(C1, C2, A) >= 0.0;
  const bool sb = orient2d(C1, C2, B) >= 0.0;
  if (sa == sb) return false;
  const double o1 = orient2d(A, B, C1);
  const double o2 = orient2d(A, B, C2);
  return !((o1 > 0.0 && o2 > 0.0) || (o1 < 0.0 && o2 < 0.0));
}

inline bool crosses_parallelogram_3d(const double *A, const double *B, const double *P1,
                                     const double *P2, const double *P3)
{
  const Vec3 a(A[0], A[1], A[2]), b(B[0], B[1], B[2]);
  const Vec3 p1(P1[0], P1[1], P1[2]);
  const Vec3 e1 = Vec3(P2[0], P2[1], P2[2]) - p1;
  const Vec3 e2 = Vec3(P3[0], P3[1], P3[2]) - p1;
  const Vec3 n = e1.cross(e2);
  const double da = n.dot(a - p1), db = n.dot(b - p1);
  if ((da >= 0.0) == (db >= 0.0)) return false;
  const double t = da / (da - db);
  const Vec3 q = a + t * (b - a) - p1;
  // q = alpha e1 + beta e2 (least squares in the plane)
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const double r1 = q.dot(e1), r2 = q.dot(e2);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 0.0)) return false;
  const double alpha = (r1 * g22 - r2 * g12) / det;
  const double beta = (r2 * g11 - r1 * g12) / det;
  const double eps = 1e-12;
  return alpha >= -eps && alpha <= 1.0 + eps && beta >= -eps && beta <= 1.0 + eps;
}

}    // namespace NOSPD

#endif

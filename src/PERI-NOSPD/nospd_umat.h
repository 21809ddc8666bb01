/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The bridge to a user's Abaqus UMAT: one material point's increment from
   the accepted state (history hn) to the current F, with the stress the
   UMAT returns converted to the first Piola-Kirchhoff stress.  Knows
   nothing of LAMMPS; the library is opened by the caller (dlopen).

   Kinematics (what the UMAT is given):
     small:  STRAN = eps_n, DSTRAN = eps_{n+1} - eps_n, eps = sym(F) - I,
             DROT = I; P = sigma.
     finite: F = R U, V = R U R^T; with the increment's rotation
             DROT = R_{n+1} R_n^T, STRESS in = DROT sigma_n DROT^T,
             STRAN = DROT ln V_n DROT^T, DSTRAN = ln V_{n+1} - STRAN
             (logarithmic strain, as Abaqus with NLGEOM);
             P = J sigma F^-T.
   Voigt order as Abaqus: 11 22 33 12 13 23 (NTENS = 6, 3D) or 11 22 33 12
   (NTENS = 4, plane strain); shear strains are engineering (2 eps_ij).
------------------------------------------------------------------------- */

#ifndef NOSPD_UMAT_H
#define NOSPD_UMAT_H

#include "nospd_tensor.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace NOSPD {

// Per-point history of a UMAT material; all zero is the virgin state.
// WORK and HEAT sit where the built-in plasticity keeps them
// (nospd_plasticity.h, Hist), so the dissipation sum reads both alike.
namespace UmatHist {
  constexpr int FPREV = 0;      // 9: F - I of the accepted step (row-major)
  constexpr int SSE = 9;        // elastic strain energy per unit volume
  constexpr int SPD = 10;       // plastic dissipation per unit volume
  constexpr int SCD = 11;       // creep dissipation per unit volume
  constexpr int WORK = 13;      // SPD + SCD: the dissipation summed by the bonds fix
  constexpr int HEAT = 14;      // always 0 (a UMAT's RPL is not used)
  constexpr int STRESS = 15;    // 6: Cauchy stress, Abaqus order 11 22 33 12 13 23
  constexpr int STATEV = 21;    // NSTATV solution-dependent variables
  inline int size(int nstatev) { return STATEV + nstatev; }
}    // namespace UmatHist

// The Abaqus/Standard UMAT interface as compiled by gfortran (every
// argument by reference, CMNAME's length appended as a hidden size_t).
using UmatFunction = void (*)(double *stress, double *statev, double *ddsdde, double *sse,
                              double *spd, double *scd, double *rpl, double *ddsddt,
                              double *drplde, double *drpldt, double *stran, double *dstran,
                              double *time, double *dtime, double *temp, double *dtemp,
                              double *predef, double *dpred, char *cmname, int *ndi, int *nshr,
                              int *ntens, int *nstatv, double *props, int *nprops,
                              double *coords, double *drot, double *pnewdt, double *celent,
                              double *dfgrd0, double *dfgrd1, int *noel, int *npt, int *layer,
                              int *kspt, int *kstep, int *kinc, std::size_t cmname_len);

// What a UMAT asked for through Abaqus's error utilities (STDB_ABQERR with
// LOP = -3, XIT): the caller checks it after every call and stops.
struct UmatReport {
  bool abort = false;
  std::string message;
};
inline UmatReport &umat_report()
{
  static UmatReport r;
  return r;
}

struct UmatMaterial {
  UmatFunction fn = nullptr;
  std::vector<double> props;
  int nstatev = 0;
  int ntens = 6;         // 6 (3D) or 4 (plane strain)
  bool finite = false;
  char cmname[80];       // blank-padded material name
  void set_name(const std::string &name)
  {
    std::memset(cmname, ' ', sizeof(cmname));
    std::memcpy(cmname, name.data(), std::min(name.size(), sizeof(cmname)));
  }
};

struct UmatPoint {
  double time = 0.0, dt = 0.0, temperature = 0.0;
  double coords[3] = {0.0, 0.0, 0.0};
  double celent = 0.0;
  int noel = 0, kinc = 0;
  int npt = 1;    // integration point: 1, or 2 + the bond's slot (bond-associated families)
};

enum class UmatStatus { OK, UNDEFINED, NONFINITE, ABORT, STATEV_OVERFLOW };

/* A UMAT that writes more STATEV than NSTATV would overwrite the heap
   past its buffer.  The buffer carries a guard zone of one finite value
   (about 1.24, all 52 mantissa bits set in an odd pattern) compared bit for
   bit after each call: an assignment past NSTATV changes it, and so does
   arithmetic that accumulates into it (a NaN would stay the same NaN under
   addition and hide STATEV(I) = STATEV(I) + X).  The zone absorbs the
   overflow of a UMAT that writes up to STATEV_GUARD values too many. */
constexpr int STATEV_GUARD = 64;
constexpr std::uint64_t STATEV_SENTINEL = 0x3ff3dead5eed1e55ULL;

inline void fill_guard(double *g)
{
  for (int k = 0; k < STATEV_GUARD; k++) std::memcpy(g + k, &STATEV_SENTINEL, sizeof(double));
}

inline bool guard_intact(const double *g)
{
  std::uint64_t diff = 0;
  for (int k = 0; k < STATEV_GUARD; k++) {
    std::uint64_t bits;
    std::memcpy(&bits, g + k, sizeof(bits));
    diff |= bits ^ STATEV_SENTINEL;
  }
  return diff == 0;
}

// symmetric tensor <-> Abaqus Voigt vector of length ntens; shear x2 for strains
inline void to_voigt(const Mat3 &a, int ntens, double shear, double *v)
{
  v[0] = a(0, 0);
  v[1] = a(1, 1);
  v[2] = a(2, 2);
  v[3] = shear * a(0, 1);
  if (ntens == 6) {
    v[4] = shear * a(0, 2);
    v[5] = shear * a(1, 2);
  }
}

inline Mat3 from_voigt(const double *v, int ntens)
{
  Mat3 a = Mat3::Zero();
  a(0, 0) = v[0];
  a(1, 1) = v[1];
  a(2, 2) = v[2];
  a(0, 1) = a(1, 0) = v[3];
  if (ntens == 6) {
    a(0, 2) = a(2, 0) = v[4];
    a(1, 2) = a(2, 1) = v[5];
  }
  return a;
}

// ln V and R of F = R U = V R; false if F is not invertible with det > 0
inline bool log_stretch(const Mat3 &F, Mat3 &lnV, Mat3 &R)
{
  if (!(F.determinant() > 0.0)) return false;
  const Mat3 b = F * F.transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (b + b.transpose()));
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 0.0)) return false;
  Vec3 l, invl;
  for (int a = 0; a < 3; a++) {
    l(a) = 0.5 * std::log(eig.eigenvalues()(a));
    invl(a) = 1.0 / std::sqrt(eig.eigenvalues()(a));
  }
  const Mat3 &N = eig.eigenvectors();
  lnV = N * l.asDiagonal() * N.transpose();
  R = N * invl.asDiagonal() * N.transpose() * F;    // V^-1 F
  return true;
}

/* One UMAT increment: from the accepted history hn (with F_n inside) to F.
   Writes the new history h1, P and W (= SSE, energy per unit volume), and
   the UMAT's DDSDDE (ntens x ntens, column-major) where asked. */
inline UmatStatus umat_point(const UmatMaterial &m, const UmatPoint &pt, const Mat3 &F,
                             const double *hn, double *h1, Mat3 &P, double &W,
                             double *ddsdde_out = nullptr)
{
  using namespace UmatHist;
  const Mat3 I = Mat3::Identity();
  const Mat3 F0 = I + load(hn + FPREV);
  const int nt = m.ntens;
  double stress[6], stran[6], dstran[6];
  Mat3 drot = I;
  if (!m.finite) {
    const Mat3 e0 = 0.5 * (F0 + F0.transpose()) - I;
    const Mat3 e1 = 0.5 * (F + F.transpose()) - I;
    to_voigt(e0, nt, 2.0, stran);
    to_voigt(e1 - e0, nt, 2.0, dstran);
    for (int k = 0; k < nt; k++) stress[k] = hn[STRESS + k];
  } else {
    Mat3 lnV0, lnV1, R0, R1;
    if (!log_stretch(F0, lnV0, R0) || !log_stretch(F, lnV1, R1)) return UmatStatus::UNDEFINED;
    drot = R1 * R0.transpose();
    const Mat3 s0 = drot * from_voigt(hn + STRESS, nt) * drot.transpose();
    const Mat3 e0 = drot * lnV0 * drot.transpose();
    to_voigt(s0, nt, 1.0, stress);
    to_voigt(e0, nt, 2.0, stran);
    to_voigt(lnV1 - e0, nt, 2.0, dstran);
  }

  // the UMAT may write into both: per-call copies, in buffers kept per
  // thread so that a step allocates nothing; STATEV ends in a guard zone
  thread_local std::vector<double> statev, props;
  statev.resize(m.nstatev + STATEV_GUARD);
  for (int k = 0; k < m.nstatev; k++) statev[k] = hn[STATEV + k];
  fill_guard(statev.data() + m.nstatev);
  props.assign(m.props.begin(), m.props.end());
  if (props.empty()) props.push_back(0.0);
  double ddsdde[36] = {}, ddsddt[6] = {}, drplde[6] = {};
  double sse = hn[SSE], spd = hn[SPD], scd = hn[SCD];
  double rpl = 0.0, drpldt = 0.0, dtemp = 0.0, predef = 0.0, dpred = 0.0;
  double time[2] = {pt.time, pt.time}, dtime = pt.dt, temp = pt.temperature;
  double coords[3] = {pt.coords[0], pt.coords[1], pt.coords[2]};
  double pnewdt = 1.0, celent = pt.celent;
  // Fortran arrays are column-major, as Eigen's default
  Mat3 rot = drot, dfgrd0 = F0, dfgrd1 = F;
  char cmname[80];
  std::memcpy(cmname, m.cmname, sizeof(cmname));
  int ndi = 3, nshr = nt - 3, ntens = nt, nstatv = m.nstatev;
  int nprops = static_cast<int>(m.props.size());
  int noel = pt.noel, npt = pt.npt, layer = 1, kspt = 1, kstep = 1, kinc = pt.kinc;

  umat_report().abort = false;
  m.fn(stress, statev.data(), ddsdde, &sse, &spd, &scd, &rpl, ddsddt, drplde, &drpldt, stran,
       dstran, time, &dtime, &temp, &dtemp, &predef, &dpred, cmname, &ndi, &nshr, &ntens,
       &nstatv, props.data(), &nprops, coords, rot.data(), &pnewdt, &celent, dfgrd0.data(),
       dfgrd1.data(), &noel, &npt, &layer, &kspt, &kstep, &kinc, sizeof(cmname));
  if (!guard_intact(statev.data() + m.nstatev)) return UmatStatus::STATEV_OVERFLOW;
  if (umat_report().abort) return UmatStatus::ABORT;

  bool finite_out = std::isfinite(sse) && std::isfinite(spd) && std::isfinite(scd);
  for (int k = 0; k < nt; k++) finite_out = finite_out && std::isfinite(stress[k]);
  for (int k = 0; k < m.nstatev; k++) finite_out = finite_out && std::isfinite(statev[k]);
  if (!finite_out) return UmatStatus::NONFINITE;
  if (ddsdde_out)
    for (int k = 0; k < 36; k++) ddsdde_out[k] = ddsdde[k];

  const Mat3 sigma = from_voigt(stress, nt);
  P = m.finite ? Mat3(F.determinant() * sigma * F.inverse().transpose()) : sigma;
  W = sse;
  store(F - I, h1 + FPREV);
  h1[SSE] = sse;
  h1[SPD] = spd;
  h1[SCD] = scd;
  h1[12] = 0.0;
  h1[WORK] = spd + scd;
  h1[HEAT] = 0.0;
  for (int k = 0; k < 6; k++) h1[STRESS + k] = (k < nt) ? stress[k] : 0.0;
  for (int k = 0; k < m.nstatev; k++) h1[STATEV + k] = statev[k];
  return UmatStatus::OK;
}

}    // namespace NOSPD

#endif

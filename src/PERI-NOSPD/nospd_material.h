/* ----------------------------------------------------------------------
   PERI-NOSPD: the material-point interface (no LAMMPS headers).

   One law of one atom type: its history size, then
       (F, history h_n, environment) -> (P, history h_n+1, stored energy W)
   with the step's dissipation h_n+1[WORK] - h_n[WORK] (Hist::WORK and
   UmatHist::WORK are the same column), and the tangent dP/dF where the law
   has one.  F may come back changed: plane stress solves its F33.  The
   classical style calls every type's law through this interface; a new
   law is a class here (or in its own header) and one line in
   PairPeriNospdBase::build_materials.
------------------------------------------------------------------------- */

#ifndef NOSPD_MATERIAL_H
#define NOSPD_MATERIAL_H

#include "nospd_constitutive.h"
#include "nospd_drucker_prager.h"
#include "nospd_plastic_tangent.h"
#include "nospd_plasticity.h"
#include "nospd_umat.h"

#include <vector>

namespace NOSPD {

// what a point needs from its surroundings besides F
struct MaterialEnv {
  double dt = 0.0;                      // time step (0: quasi-static, a minimize step)
  double T = 0.0;                       // the user's temperature
  double rho = 0.0;                     // mass density
  const UmatPoint *umat = nullptr;      // a UMAT's point data (wants_point_data)
  int point = 0;    // integration point within the point: 0 itself (or a bond-
                    // associated family's whole F), 1 + slot a bond of its family
};

// what went wrong, for the caller's message: the law's family and its code
struct PointStatus {
  enum Family { OK, ELASTIC, RETURN, UMAT } family = OK;
  int code = 0;    // ReturnStatus or UmatStatus
  bool ok() const { return family == OK; }
};

class Material {
 public:
  virtual ~Material() = default;
  virtual int history_size() const { return 0; }
  virtual bool wants_point_data() const { return false; }
  // a history column that accumulates increments (a bond-associated family
  // sums its bonds' increments there, and averages every other column)
  virtual bool accumulates(int column) const { return column == Hist::WORK; }
  virtual PointStatus stress(Mat3 &F, const double *hn, double *h1, const MaterialEnv &env,
                             Mat3 &P, double &W) const = 0;
  // dP/dF at F from hn (false where the law offers none)
  virtual bool tangent(const Mat3 & /*F*/, const double * /*hn*/, const MaterialEnv & /*env*/,
                       Tangent9 & /*D*/) const
  {
    return false;
  }
};

// the hyperelastic laws of nospd_constitutive.h (formula laws through lame.user)
class ElasticMaterial : public Material {
 public:
  ElasticMaterial(Law law, Plane plane, const Lame &m) : law(law), plane(plane), m(m) {}
  PointStatus stress(Mat3 &F, const double *, double *, const MaterialEnv &, Mat3 &P,
                     double &W) const override
  {
    if (first_piola(law, plane, m, F, P, W)) return {};
    return {PointStatus::ELASTIC, 0};
  }

 private:
  Law law;
  Plane plane;
  Lame m;
};

// J2 and Johnson-Cook plasticity with thermal strain (nospd_plasticity.h)
class J2Material : public Material {
 public:
  J2Material(Law law, Plane plane, const Lame &m, const FlowLaw &fl, const ThermalLaw &th) :
      law(law), plane(plane), m(m), fl(fl), th(th)
  {
  }
  int history_size() const override { return Hist::SIZE; }
  PointStatus stress(Mat3 &F, const double *hn, double *h1, const MaterialEnv &env, Mat3 &P,
                     double &W) const override
  {
    PointEnv pe;
    pe.dt = env.dt;
    pe.T_base = env.T;
    pe.rho = env.rho;
    const ReturnStatus st = inelastic_point(law, plane, m, fl, th, pe, F, hn, h1, P, W);
    if (st == ReturnStatus::OK) return {};
    return {PointStatus::RETURN, static_cast<int>(st)};
  }
  // small strain and hencky, every hardening, 3D or plane strain (the 3D
  // point); plane stress has none (nospd_plastic_tangent.h says why)
  bool tangent(const Mat3 &F, const double *hn, const MaterialEnv &env, Tangent9 &D) const override
  {
    if (plane == Plane::STRESS) return false;
    PointEnv pe;
    pe.dt = env.dt;
    pe.T_base = env.T;
    pe.rho = env.rho;
    return j2_tangent(law, m, fl, th, pe, F, hn, D);
  }

 private:
  Law law;
  Plane plane;
  Lame m;
  FlowLaw fl;
  ThermalLaw th;
};

// Drucker-Prager plasticity (nospd_drucker_prager.h); plane stress solves
// F33 for P33 = 0 with the history of the step start, as the other laws
class DruckerPragerMaterial : public Material {
 public:
  DruckerPragerMaterial(Law law, Plane plane, const Lame &m, const DruckerPrager &dp) :
      law(law), plane(plane), m(m), dp(dp)
  {
  }
  int history_size() const override { return Hist::SIZE; }
  PointStatus stress(Mat3 &F, const double *hn, double *h1, const MaterialEnv &, Mat3 &P,
                     double &W) const override
  {
    ReturnStatus st = ReturnStatus::OK;
    auto eval = [&](const Mat3 &Ft, Mat3 &Pt, double &Wt) {
      st = law == Law::SMALL ? drucker_prager_small(m, dp, Ft, hn, h1, Pt, Wt)
                             : drucker_prager_hencky(m, dp, Ft, hn, h1, Pt, Wt);
      return st == ReturnStatus::OK;
    };
    if (plane != Plane::STRESS) eval(F, P, W);
    else if (!solve_plane_stress(m, F, P, W, eval) && st == ReturnStatus::OK)
      st = ReturnStatus::NO_CONVERGENCE;
    if (st == ReturnStatus::OK) return {};
    return {PointStatus::RETURN, static_cast<int>(st)};
  }
  bool tangent(const Mat3 &F, const double *hn, const MaterialEnv &, Tangent9 &D) const override
  {
    if (law != Law::SMALL || plane == Plane::STRESS) return false;
    double h1[Hist::SIZE], W;
    Mat3 P;
    return drucker_prager_small(m, dp, F, hn, h1, P, W, &D) == ReturnStatus::OK;
  }

 private:
  Law law;
  Plane plane;
  Lame m;
  DruckerPrager dp;
};

// an Abaqus UMAT (nospd_umat.h); its point data (time, coordinates, ids) from env
class UmatPointMaterial : public Material {
 public:
  explicit UmatPointMaterial(const UmatMaterial &u) : u(u) {}
  int history_size() const override { return UmatHist::size(u.nstatev); }
  bool wants_point_data() const override { return true; }
  bool accumulates(int column) const override
  {
    return column == UmatHist::SSE || column == UmatHist::SPD || column == UmatHist::SCD ||
        column == UmatHist::WORK;
  }
  PointStatus stress(Mat3 &F, const double *hn, double *h1, const MaterialEnv &env, Mat3 &P,
                     double &W) const override
  {
    UmatPoint pt = *env.umat;
    pt.npt += env.point;    // NPT 1 the point, 2 + slot a bond of its family
    const UmatStatus st = umat_point(u, pt, F, hn, h1, P, W);
    if (st == UmatStatus::OK) return {};
    return {PointStatus::UMAT, static_cast<int>(st)};
  }
  // small strain: P = sigma(eps), eps = sym(F) - I, so dP/dF is DDSDDE on
  // the Voigt pairs (its engineering shear strains count each of e_kl and
  // e_lk once); none where the UMAT leaves DDSDDE's diagonal zero (it wrote
  // none) or for umat/finite
  bool tangent(const Mat3 &F, const double *hn, const MaterialEnv &env, Tangent9 &D) const override
  {
    if (u.finite || !env.umat) return false;
    UmatPoint pt = *env.umat;
    pt.npt += env.point;
    std::vector<double> h1(history_size());
    double dd[36] = {}, W = 0.0;
    Mat3 P;
    if (umat_point(u, pt, F, hn, h1.data(), P, W, dd) != UmatStatus::OK) return false;
    const int nt = u.ntens;
    static const int voigt[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    for (int k = 0; k < 3; k++)
      if (!(dd[k + k * nt] != 0.0)) return false;
    D.setZero();
    for (int a = 0; a < 9; a++)
      for (int c = 0; c < 9; c++) {
        const int I = voigt[a / 3][a % 3], J = voigt[c / 3][c % 3];
        if (I < nt && J < nt) D(a, c) = dd[I + J * nt];
      }
    return true;
  }

 private:
  const UmatMaterial &u;
};

}    // namespace NOSPD

#endif

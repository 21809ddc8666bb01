/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   An isotropic hyperelastic law typed as a formula: W is a Lepton
   expression of the invariants of C = F^T F or of the principal stretches,
   and P = dW/dF is assembled from Lepton's symbolic partial derivatives
   (no finite differences).  Knows nothing of LAMMPS; needs the Lepton
   library (LAMMPS's lib/lepton).

   Variables of W:
     I1, I2     invariants of C: tr C, ((tr C)^2 - tr C^2)/2
     J          det F
     I1b, I2b   isochoric invariants J^-2/3 I1, J^-4/3 I2
     l1, l2, l3 principal stretches (W must be symmetric in them)
   and named constants: "expr; name=value; ..." in the Lepton manner, or
   given separately (params), which replace the formula's definition of
   their name or are appended the same way.  A constant defined twice or
   named like a variable is an error.

   P from the invariants (closed form):
     dI1/dF = 2F,  dI2/dF = 2(I1 F - F C),  dJ/dF = J F^-T,
     dI1b/dF = J^-2/3 (2F - 2/3 I1 F^-T),
     dI2b/dF = J^-4/3 (2(I1 F - F C) - 4/3 I2 F^-T).
   With any stretch in W the spectral form is used instead: with
   b = F F^T = sum_a l_a^2 n_a n_a, the Kirchhoff stress is
   tau = sum_a l_a dW/dl_a n_a n_a and P = tau F^-T, where dW/dl_a also
   collects the invariants' terms by the chain rule.  For a symmetric W the
   result does not depend on the eigenvectors chosen for equal stretches.
------------------------------------------------------------------------- */

#ifndef NOSPD_FORMULA_H
#define NOSPD_FORMULA_H

#include "nospd_constitutive.h"

#include "Lepton.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace NOSPD {

class FormulaLaw : public PointLaw {
 public:
  enum Var { I1, I2, J, I1B, I2B, L1, L2, L3, NVAR };
  static const char *var_name(int v)
  {
    static const char *names[NVAR] = {"I1", "I2", "J", "I1b", "I2b", "l1", "l2", "l3"};
    return names[v];
  }

  /* Parse W and differentiate it.  Throws std::invalid_argument with a
     message that names what is wrong (syntax, unknown variable, a W that
     is not symmetric in the stretches). */
  FormulaLaw(const std::string &expression,
             const std::vector<std::pair<std::string, double>> &params = {}) :
      text(expression)
  {
    const std::string full = with_constants(expression, params);
    Lepton::ParsedExpression parsed;
    try {
      parsed = Lepton::Parser::parse(full).optimize();
    } catch (std::exception &e) {
      throw std::invalid_argument(std::string("cannot parse W = '") + expression + "': " + e.what());
    }
    std::set<std::string> names;
    try {
      names = parsed.createCompiledExpression().getVariables();
    } catch (std::exception &e) {
      throw std::invalid_argument(std::string("cannot compile W = '") + expression + "': " + e.what());
    }
    for (const auto &n : names) {
      int v = lookup(n);
      if (v < 0)
        throw std::invalid_argument("W = '" + expression + "' uses unknown variable '" + n +
                                    "' (variables: I1 I2 J I1b I2b l1 l2 l3; constants as "
                                    "'; name=value' or param name value)");
      used[v] = true;
    }
    spectral = used[L1] || used[L2] || used[L3];
    try {
      energy = parsed.createCompiledExpression();
      for (int v = 0; v < NVAR; v++)
        if (used[v]) {
          partial_var.push_back(v);
          partials.push_back(parsed.differentiate(var_name(v)).optimize().createCompiledExpression());
        }
    } catch (std::exception &e) {
      throw std::invalid_argument(std::string("cannot differentiate W = '") + expression + "': " + e.what());
    }
    bind();
    if (spectral) check_symmetric();
  }
  FormulaLaw(const FormulaLaw &) = delete;
  FormulaLaw &operator=(const FormulaLaw &) = delete;

  // the names W's variables take, which no constant may take
  static bool is_variable(const std::string &n) { return lookup(n) >= 0; }
  static std::string variable_list()
  {
    std::string list = var_name(0);
    for (int v = 1; v < NVAR; v++) list += std::string(" ") + var_name(v);
    return list;
  }

  const std::string &expression() const { return text; }
  bool uses(Var v) const { return used[v]; }
  bool uses_stretches() const { return spectral; }

  bool first_piola(const Mat3 &F, Mat3 &P, double &W) const override
  {
    const double Jv = F.determinant();
    if (!(Jv > 0.0)) return false;
    const Mat3 Finv_t = F.inverse().transpose();
    const Mat3 C = F.transpose() * F;
    const double i1 = C.trace();
    const double i2 = 0.5 * (i1 * i1 - C.squaredNorm());
    const double j23 = std::pow(Jv, -2.0 / 3.0);
    vars[I1] = i1;
    vars[I2] = i2;
    vars[J] = Jv;
    vars[I1B] = j23 * i1;
    vars[I2B] = j23 * j23 * i2;
    Mat3 N;
    Vec3 lam(1.0, 1.0, 1.0);
    if (spectral) {
      const Mat3 b = F * F.transpose();
      Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (b + b.transpose()));
      if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 0.0)) return false;
      for (int a = 0; a < 3; a++) lam(a) = std::sqrt(eig.eigenvalues()(a));
      N = eig.eigenvectors();
      vars[L1] = lam(0);
      vars[L2] = lam(1);
      vars[L3] = lam(2);
    }
    W = energy.evaluate();
    double d[NVAR] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (size_t k = 0; k < partials.size(); k++) d[partial_var[k]] = partials[k].evaluate();

    if (!spectral) {
      const Mat3 dI2 = 2.0 * (i1 * F - F * C);
      P = (2.0 * d[I1]) * F + d[I2] * dI2 + (d[J] * Jv) * Finv_t;
      if (used[I1B]) P += (d[I1B] * j23) * (2.0 * F - (2.0 / 3.0) * i1 * Finv_t);
      if (used[I2B]) P += (d[I2B] * j23 * j23) * (dI2 - (4.0 / 3.0) * i2 * Finv_t);
    } else {
      Vec3 tau;
      for (int a = 0; a < 3; a++) {
        const double l = lam(a), l2 = l * l;
        double dw = d[L1 + a] + d[I1] * 2.0 * l + d[I2] * 2.0 * l * (i1 - l2) + d[J] * Jv / l;
        dw += d[I1B] * (j23 * 2.0 * l - (2.0 / 3.0) * vars[I1B] / l);
        dw += d[I2B] * (j23 * j23 * 2.0 * l * (i1 - l2) - (4.0 / 3.0) * vars[I2B] / l);
        tau(a) = l * dw;
      }
      P = N * tau.asDiagonal() * N.transpose() * Finv_t;
    }
    return std::isfinite(W) && P.allFinite();
  }

 private:
  std::string text;
  bool used[NVAR] = {false, false, false, false, false, false, false, false};
  bool spectral = false;
  // the variables' values, shared by W and its partials (bound by address)
  mutable double vars[NVAR] = {3.0, 3.0, 1.0, 3.0, 3.0, 1.0, 1.0, 1.0};
  mutable Lepton::CompiledExpression energy;
  std::vector<int> partial_var;
  mutable std::vector<Lepton::CompiledExpression> partials;

  static int lookup(const std::string &n)
  {
    for (int v = 0; v < NVAR; v++)
      if (n == var_name(v)) return v;
    return -1;
  }

  /* The text Lepton parses: W and its definitions "; name=value", in which
     a param takes the place of the formula's own definition of its name
     and the other params follow the formula's.  Lepton reads definitions
     from the last one back, each seeing those after it, and a name defined
     again silently keeps its first definition; a constant named like a
     variable would silently replace the variable.  Both are errors here. */
  static std::string with_constants(const std::string &expression,
                                    const std::vector<std::pair<std::string, double>> &params)
  {
    auto fail = [&](const std::string &why) {
      throw std::invalid_argument("W = '" + expression + "': " + why);
    };
    auto check_name = [&](const std::string &n, const std::string &how) {
      if (is_variable(n))
        fail(how + " '" + n + "' is a variable of W (" + variable_list() + "), not a constant");
    };
    std::map<std::string, std::string> given;    // param name -> value text
    for (const auto &p : params) {
      check_name(p.first, "param");
      char buf[64];
      std::snprintf(buf, sizeof(buf), "%.17g", p.second);
      if (!given.emplace(p.first, buf).second) fail("param '" + p.first + "' given twice");
    }
    std::set<std::string> defined;
    size_t cut = expression.find(';');
    std::string full = expression.substr(0, cut);
    while (cut != std::string::npos) {
      const size_t next = expression.find(';', cut + 1);
      const size_t len = (next == std::string::npos) ? next : next - cut - 1;
      const std::string def = expression.substr(cut + 1, len);
      cut = next;
      const size_t eq = def.find('=');
      const std::string name = trim(def.substr(0, eq));
      if (eq == std::string::npos || name.empty()) {
        full += ";" + def;    // Lepton names what is wrong with it
        continue;
      }
      check_name(name, "the constant");
      if (!defined.insert(name).second) fail("the constant '" + name + "' is defined twice");
      const auto p = given.find(name);
      full += (p == given.end()) ? ";" + def : "; " + name + "=" + p->second;
    }
    for (const auto &p : params)
      if (!defined.count(p.first)) full += "; " + p.first + "=" + given[p.first];
    return full;
  }

  static std::string trim(const std::string &t)
  {
    const size_t a = t.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return "";
    return t.substr(a, t.find_last_not_of(" \t\r\n") - a + 1);
  }

  void bind()
  {
    std::map<std::string, double *> loc;
    for (int v = 0; v < NVAR; v++) loc[var_name(v)] = &vars[v];
    energy.setVariableLocations(loc);
    for (auto &p : partials) p.setVariableLocations(loc);
  }

  // an isotropic W is symmetric in the stretches; the spectral P needs it
  void check_symmetric() const
  {
    const double l[3] = {1.13, 0.91, 1.04};
    const int perm[5][3] = {{1, 0, 2}, {0, 2, 1}, {2, 1, 0}, {1, 2, 0}, {2, 0, 1}};
    auto w_at = [&](const double *s) {
      const double jv = s[0] * s[1] * s[2], i1 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
      const double i2 = s[0] * s[0] * s[1] * s[1] + s[1] * s[1] * s[2] * s[2] + s[0] * s[0] * s[2] * s[2];
      vars[I1] = i1;
      vars[I2] = i2;
      vars[J] = jv;
      vars[I1B] = std::pow(jv, -2.0 / 3.0) * i1;
      vars[I2B] = std::pow(jv, -4.0 / 3.0) * i2;
      vars[L1] = s[0];
      vars[L2] = s[1];
      vars[L3] = s[2];
      return energy.evaluate();
    };
    const double w0 = w_at(l);
    for (const auto &p : perm) {
      const double s[3] = {l[p[0]], l[p[1]], l[p[2]]};
      const double w = w_at(s);
      if (!(std::abs(w - w0) <= 1e-12 * (std::abs(w0) + 1e-300) || (w == w0)))
        throw std::invalid_argument("W = '" + text + "' is not symmetric in l1, l2, l3: an "
                                    "isotropic energy must not depend on their order");
    }
  }
};

}    // namespace NOSPD

#endif

/* PERI-NOSPD kernel tests: the root of a function piecewise linear in x
   (a lateral stress against a lateral strain), by the secant method from
   x0 and x1, to |g| <= tol; a few steps are exact once both points lie on
   the same linear piece. */
#ifndef NOSPD_TEST_SECANT_H
#define NOSPD_TEST_SECANT_H

#include <cmath>

template <class G> double secant_root(G g, double x0, double x1, double tol, int maxit = 100)
{
  double g0 = g(x0), g1 = g(x1);
  for (int it = 0; it < maxit && std::abs(g1) > tol && g1 != g0; ++it) {
    const double x2 = x1 - g1 * (x1 - x0) / (g1 - g0);
    x0 = x1;
    g0 = g1;
    x1 = x2;
    g1 = g(x1);
  }
  return x1;
}

#endif

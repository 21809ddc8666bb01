/* ----------------------------------------------------------------------
   PERI-NOSPD: Krylov solvers for A x = b with a preconditioner, on
   distributed vectors: each rank holds n entries and `dot` returns the
   global inner product (the caller's MPI reduction).  Used by min_style
   nospd/newton; nothing here knows LAMMPS.

   gmres: restarted GMRES(m), right-preconditioned (A M^-1 y = b, x = M^-1 y)
   so that the norm it minimizes and stops on is the true residual's;
   Givens rotations on the Hessenberg matrix (Saad and Schultz 1986).
   cg: preconditioned conjugate gradients for symmetric positive definite A
   and M; a direction of non-positive curvature stops it (flagged).
   Both start from x = 0, the Newton correction's natural first guess.
------------------------------------------------------------------------- */

#ifndef NOSPD_KRYLOV_H
#define NOSPD_KRYLOV_H

#include <cmath>
#include <vector>

namespace NOSPD {

struct KrylovResult {
  int iterations = 0;      // operator applications
  double residual = 0.0;   // ||b - A x|| at the end (GMRES: from the recurrence)
  double initial = 0.0;    // ||b||
  bool converged = false;
  bool indefinite = false; // cg met p^T A p <= 0
};

// x = 0, |b|; true when b = 0 (solved)
template <class Dot> bool start(int n, const double *b, double *x, Dot &&dot, KrylovResult &res)
{
  for (int i = 0; i < n; i++) x[i] = 0.0;
  res.initial = std::sqrt(dot(b, b));
  res.residual = res.initial;
  res.converged = res.initial == 0.0;
  return res.converged;
}

// A(v, Av), M(r, z) (z = M^-1 r), dot(u, v): callables over n local entries
template <class Op, class Prec, class Dot>
KrylovResult gmres(int n, const double *b, double *x, Op &&A, Prec &&M, Dot &&dot, double rtol,
                   int restart, int maxit)
{
  KrylovResult res;
  const int m = restart < 1 ? 1 : restart;
  std::vector<double> V(static_cast<size_t>(m + 1) * n), Z(static_cast<size_t>(m) * n);
  std::vector<double> H(static_cast<size_t>(m + 1) * m), cs(m), sn(m), g(m + 1), w(n), y(m);
  if (start(n, b, x, dot, res)) return res;
  const double target = rtol * res.initial;
  bool first = true;
  while (res.iterations < maxit) {
    // r = b - A x (x = 0 on the first cycle: no application needed)
    double *v0 = V.data();
    if (first) {
      for (int i = 0; i < n; i++) v0[i] = b[i];
    } else {
      A(x, w.data());
      res.iterations++;
      for (int i = 0; i < n; i++) v0[i] = b[i] - w[i];
    }
    first = false;
    const double beta = std::sqrt(dot(v0, v0));
    res.residual = beta;
    if (beta <= target) break;
    for (int i = 0; i < n; i++) v0[i] /= beta;
    for (int k = 0; k <= m; k++) g[k] = 0.0;
    g[0] = beta;
    int k = 0;
    for (; k < m && res.iterations < maxit; k++) {
      double *vk = V.data() + static_cast<size_t>(k) * n, *zk = Z.data() + static_cast<size_t>(k) * n;
      double *vn = V.data() + static_cast<size_t>(k + 1) * n;
      M(vk, zk);
      A(zk, vn);
      res.iterations++;
      // modified Gram-Schmidt
      for (int j = 0; j <= k; j++) {
        const double *vj = V.data() + static_cast<size_t>(j) * n;
        const double h = dot(vn, vj);
        H[j * m + k] = h;
        for (int i = 0; i < n; i++) vn[i] -= h * vj[i];
      }
      const double hn = std::sqrt(dot(vn, vn));
      H[(k + 1) * m + k] = hn;
      if (hn > 0.0)
        for (int i = 0; i < n; i++) vn[i] /= hn;
      for (int j = 0; j < k; j++) {
        const double a = H[j * m + k], c = H[(j + 1) * m + k];
        H[j * m + k] = cs[j] * a + sn[j] * c;
        H[(j + 1) * m + k] = -sn[j] * a + cs[j] * c;
      }
      const double a = H[k * m + k], c = H[(k + 1) * m + k];
      const double r = std::hypot(a, c);
      cs[k] = r > 0.0 ? a / r : 1.0;
      sn[k] = r > 0.0 ? c / r : 0.0;
      H[k * m + k] = r;
      H[(k + 1) * m + k] = 0.0;
      g[k + 1] = -sn[k] * g[k];
      g[k] = cs[k] * g[k];
      res.residual = std::fabs(g[k + 1]);
      if (!std::isfinite(hn) || !std::isfinite(r)) {    // a non-finite operator: give up now
        res.residual = std::nan("");
        res.iterations = maxit;
        break;
      }
      if (res.residual <= target || hn == 0.0) {
        k++;
        break;
      }
    }
    // y = H^-1 g (upper triangular k x k), x += Z y
    for (int i = k - 1; i >= 0; i--) {
      double s = g[i];
      for (int j = i + 1; j < k; j++) s -= H[i * m + j] * y[j];
      y[i] = H[i * m + i] != 0.0 ? s / H[i * m + i] : 0.0;
    }
    for (int j = 0; j < k; j++) {
      const double *zj = Z.data() + static_cast<size_t>(j) * n;
      for (int i = 0; i < n; i++) x[i] += y[j] * zj[i];
    }
    if (res.residual <= target || !std::isfinite(res.residual)) break;
  }
  res.converged = res.residual <= target;
  return res;
}

template <class Op, class Prec, class Dot>
KrylovResult cg(int n, const double *b, double *x, Op &&A, Prec &&M, Dot &&dot, double rtol, int maxit)
{
  KrylovResult res;
  std::vector<double> r(b, b + n), z(n), p(n), q(n);
  if (start(n, b, x, dot, res)) return res;
  const double target = rtol * res.initial;
  M(r.data(), z.data());
  p = z;
  double rz = dot(r.data(), z.data());
  while (res.iterations < maxit) {
    A(p.data(), q.data());
    res.iterations++;
    const double pq = dot(p.data(), q.data());
    if (!(pq > 0.0)) {
      res.indefinite = true;
      break;
    }
    const double alpha = rz / pq;
    for (int i = 0; i < n; i++) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
    }
    res.residual = std::sqrt(dot(r.data(), r.data()));
    if (res.residual <= target) break;
    M(r.data(), z.data());
    const double rz_new = dot(r.data(), z.data());
    const double beta = rz_new / rz;
    rz = rz_new;
    for (int i = 0; i < n; i++) p[i] = z[i] + beta * p[i];
  }
  res.converged = res.residual <= target;
  return res;
}

}    // namespace NOSPD

#endif

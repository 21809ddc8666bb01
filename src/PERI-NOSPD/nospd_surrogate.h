/* ----------------------------------------------------------------------
   PERI-NOSPD: the Newton minimizer's preconditioner, a bond-based
   surrogate of the tangent (no LAMMPS headers).

   Per bond i-j with reference vector xi and weight w (omega V_j), the
   bond-based (PMB) body of micromodulus c has the stiffness block
       k_ij = c_ij V_i w_ij xi (x) xi / |xi|^3,
   on the (i,i) and (j,j) diagonal and, negated, off it.  It is spectrally
   close to the correspondence tangent (both discretize the Navier
   operator), so Krylov iterations preconditioned by its inverse hardly
   grow with the resolution, unlike Jacobi's.  The matrix is assembled per
   rank over its owned points (bonds to ghosts on the diagonal only: an
   additive Schwarz block without overlap), held components get identity
   rows, and it is factored once: sparse Cholesky (exact inverse) while the
   factor stays small, incomplete Cholesky with a diagonal shift beyond.
------------------------------------------------------------------------- */

#ifndef NOSPD_SURROGATE_H
#define NOSPD_SURROGATE_H

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <cmath>
#include <memory>
#include <vector>

namespace NOSPD {

class SurrogatePreconditioner {
 public:
  enum class Kind { DIRECT, INCOMPLETE };
  struct Bond {
    int i, j;          // owned point i; j owned (j < n) or not (j >= n)
    double xi[3];      // reference bond vector
    double c;          // c_ij V_i w_ij: symmetric in i, j
  };

  // n points, their bonds (each owned pair from both ends or one: the
  // blocks are summed per listed end), mask[3n] (1 free, 0 held).
  // Returns false when the factorization fails.
  bool build(int n, const std::vector<Bond> &bonds, const double *mask, Kind kind)
  {
    n_ = n;
    kind_ = kind;
    const int N = 3 * n;
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(bonds.size() * 18 + N);
    std::vector<double> diag(9 * static_cast<size_t>(n), 0.0);
    for (const Bond &b : bonds) {
      const double l2 = b.xi[0] * b.xi[0] + b.xi[1] * b.xi[1] + b.xi[2] * b.xi[2];
      if (!(l2 > 0.0) || !(b.c > 0.0)) continue;
      const double s = b.c / (l2 * std::sqrt(l2));
      for (int a = 0; a < 3; a++)
        for (int e = 0; e < 3; e++) {
          const double k = s * b.xi[a] * b.xi[e];
          diag[9 * static_cast<size_t>(b.i) + 3 * a + e] += k;
          if (b.j < n && mask[3 * b.i + a] != 0.0 && mask[3 * b.j + e] != 0.0)
            t.emplace_back(3 * b.i + a, 3 * b.j + e, -k);
        }
    }
    // the diagonal blocks; a held component is decoupled (identity row)
    double mean = 0.0;
    for (int i = 0; i < n; i++) mean += diag[9 * i] + diag[9 * i + 4] + diag[9 * i + 8];
    mean = n > 0 && mean > 0.0 ? mean / (3.0 * n) : 1.0;
    for (int i = 0; i < n; i++)
      for (int a = 0; a < 3; a++)
        for (int e = 0; e < 3; e++) {
          const bool fa = mask[3 * i + a] != 0.0, fe = mask[3 * i + e] != 0.0;
          double k = diag[9 * static_cast<size_t>(i) + 3 * a + e];
          if (a == e && (!fa || !(k > 0.0))) k = mean;    // held, or no bond along it
          else if (!fa || !fe) k = 0.0;
          if (k != 0.0) t.emplace_back(3 * i + a, 3 * i + e, k);
        }
    A_.resize(N, N);
    A_.setFromTriplets(t.begin(), t.end());
    A_.makeCompressed();
    if (kind == Kind::DIRECT) {
      direct_ = std::make_unique<Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>>();
      direct_->compute(A_);
      if (direct_->info() == Eigen::Success) return true;
      kind_ = Kind::INCOMPLETE;    // not positive definite (a free piece): shifted IC
    }
    incomplete_ = std::make_unique<Eigen::IncompleteCholesky<double>>();
    incomplete_->compute(A_);
    return incomplete_->info() == Eigen::Success;
  }

  // z = P^-1 r over 3n entries
  void apply(const double *r, double *z) const
  {
    const int N = 3 * n_;
    Eigen::Map<const Eigen::VectorXd> rv(r, N);
    Eigen::Map<Eigen::VectorXd> zv(z, N);
    if (kind_ == Kind::DIRECT) zv = direct_->solve(rv);
    else zv = incomplete_->solve(rv);
  }

  // y = P x (the assembled surrogate itself, for tests)
  void multiply(const double *x, double *y) const
  {
    const int N = 3 * n_;
    Eigen::Map<Eigen::VectorXd>(y, N) = A_ * Eigen::Map<const Eigen::VectorXd>(x, N);
  }
  Kind kind() const { return kind_; }
  long nonzeros() const { return A_.nonZeros(); }

 private:
  int n_ = 0;
  Kind kind_ = Kind::DIRECT;
  Eigen::SparseMatrix<double> A_;
  std::unique_ptr<Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>> direct_;
  std::unique_ptr<Eigen::IncompleteCholesky<double>> incomplete_;
};

}    // namespace NOSPD

#endif

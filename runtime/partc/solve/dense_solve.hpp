// partc/solve/dense_solve.hpp: solve_dense(A, b), a dense linear solve with a
// condition estimate, for the systems of `solve w` whose sum has no cutoff
// (RBF interpolation: sum_j phi(|x_i - x_j|) w_j = f_i; Kansa collocation).
//
//   Eigen::MatrixXd A(n, n);  // A(i, j) = phi(|x_i - x_j|), or a boundary row
//   Eigen::VectorXd f(n);
//   const partc::SolveResult r = partc::solve_dense(A, f, {"w"});
//   std::cout << r.summary() << "\n";  // see solve_result.hpp
//   if (!r.warning.empty()) std::cerr << "warning: " << r.warning << "\n";
//
// Method: LU with partial pivoting (Eigen::PartialPivLU, 2/3 n^3 flops) and
// its reciprocal condition estimate rcond (1-norm, O(n^2) more). When rcond is
// below options.rcond_threshold, LU's x is discarded and the system is solved
// again by a complete orthogonal decomposition (column-pivoting Householder QR
// with a rank decision, then an RQ of the leading rows; 7 times LU's time at
// n = 1600, since Eigen does not block its column pivoting): x is then the
// least-norm least-squares solution of A with its numerically null directions
// dropped, the numerical rank is reported and warning says why.
//
// The threshold's default, machine epsilon (2.2e-16), is LAPACK's criterion
// for "singular to working precision" (xGESVX, INFO = N+1), the one MATLAB
// warns at too. Above it LU is backward stable and its x is as good as the data
// allow (relative error about eps / rcond < 1); below it a change of A the size
// of its own rounding can make A singular, and LU's x can be noise of any size
// along the near-null directions. A higher threshold (1e-12, say) would send
// merely ill-conditioned systems, such as multiquadric RBF matrices with a small
// shape parameter, whose LU solution still has a residual near eps, to a method
// many times the cost that drops part of their data. They keep LU's answer
// with a warning instead, from a condition estimate of 1e12 on
// (options.warn_condition): the digits it costs are said, not hidden.
//
// Surprises:
// - The fallback's rank decision is Eigen's default: a pivot |R_kk| counts when
//   above n eps |R_00|. R's diagonal only approximates the singular values, so
//   where they fall near that line the rank can differ from the SVD's count
//   (for the Hilbert matrix of size 12, both say 11).
// - With OpenMP (partc_runtime builds with it), Eigen runs LU's block updates
//   on OMP_NUM_THREADS threads. They split the rows and columns of an update;
//   the sums inside keep their order while the update's depth (LU's panel, at
//   most 256 columns) fits Eigen's cache blocking, as it does for common L1
//   sizes: x was the same bit for bit for 1 to 8 threads, and test_solve checks
//   1 against 2.
// - A and b are checked for NaN and Inf first (solve_result.hpp); an exactly
//   singular A is no error: its LU has rcond 0 and takes the fallback (Eigen's
//   NaN for an exact zero pivot is reported as 0).
#pragma once

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "partc/solve/solve_result.hpp"

namespace partc {

struct DenseSolveOptions {
  std::string name = "x";  // the unknown, for messages
  // LU's answer is kept when its rcond is at least this (see the header).
  double rcond_threshold = std::numeric_limits<double>::epsilon();
  // Above this condition estimate LU's answer is kept with a warning.
  double warn_condition = 1e12;
};

namespace detail {

// The first non-finite entry row by row, as a model's equations are numbered.
inline void check_finite_dense(const Eigen::MatrixXd& A, const std::string& name) {
  if (A.allFinite()) return;  // vectorised; the search below runs only for the error
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      if (!std::isfinite(A(i, j))) throw non_finite_entry(name, i, j, A(i, j));
}

}  // namespace detail

[[nodiscard]] inline SolveResult solve_dense(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                             const DenseSolveOptions& options = {}) {
  const auto start = std::chrono::steady_clock::now();
  detail::check_system_shape(A.rows(), A.cols(), b.size(), options.name);
  detail::check_finite_dense(A, options.name);
  detail::check_finite_vector(b, options.name);

  SolveResult result;
  result.name = options.name;
  result.n = A.rows();
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
  // An exact zero pivot (two equal rows, say) makes Eigen's estimate NaN; the
  // reciprocal condition number of a singular matrix is 0, and so we report it.
  const double estimate = lu.rcond();
  const double rcond = std::isnan(estimate) ? 0.0 : estimate;
  result.rcond = rcond;
  if (rcond >= options.rcond_threshold) {  // false for NaN too
    result.method = "dense LU";
    result.x = lu.solve(b);
    if (rcond * options.warn_condition < 1)
      result.warning = "solve " + options.name + ": ill-conditioned: condition estimate " +
                       detail::scientific(1 / rcond) + " > " +
                       detail::scientific(options.warn_condition) + ", so about " +
                       std::to_string(static_cast<int>(std::floor(-std::log10(rcond)))) +
                       " of 16 digits of " + options.name +
                       " may be rounding noise, however small the residual; fewer or "
                       "farther-apart nodes, or a less flat basis, lower it";
  } else {
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
    result.method = "dense least-norm (complete orthogonal decomposition)";
    result.x = cod.solve(b);
    result.rank = cod.rank();
    result.warning =
        "solve " + options.name + ": the matrix is singular to working precision (LU's rcond " +
        detail::scientific(rcond) + " < " + detail::scientific(options.rcond_threshold) +
        "); solved by a complete orthogonal decomposition instead, numerical rank " +
        std::to_string(cod.rank()) + " of " + std::to_string(result.n) + ", least-norm solution";
  }
  result.residual = detail::relative_residual(A, result.x, b);
  result.seconds = detail::seconds_since(start);
  return result;
}

}  // namespace partc

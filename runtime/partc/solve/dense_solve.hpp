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
// - Compiled once, in the runtime library (dense_solve.cpp): a model
//   including this header parses Eigen's core, not its decompositions.
#pragma once

#include <Eigen/Core>
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

// Compiled once, in the runtime library (dense_solve.cpp).
[[nodiscard]] SolveResult solve_dense(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                      const DenseSolveOptions& options = {});

}  // namespace partc

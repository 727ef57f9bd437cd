// partc/solve/dense_solve.cpp: solve_dense (dense_solve.hpp says how it chooses).
#include "partc/solve/dense_solve.hpp"

#include <Eigen/Dense>
#include <chrono>
#include <cmath>

namespace partc {

namespace detail {

namespace {

// The first non-finite entry row by row, as a model's equations are numbered.
void check_finite_dense(const Eigen::MatrixXd& A, const std::string& name) {
  if (A.allFinite()) return;  // vectorised; the search below runs only for the error
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      if (!std::isfinite(A(i, j))) throw non_finite_entry(name, i, j, A(i, j));
}

}  // namespace

}  // namespace detail

SolveResult solve_dense(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                        const DenseSolveOptions& options) {
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

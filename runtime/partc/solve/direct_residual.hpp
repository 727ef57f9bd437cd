// partc/solve/direct_residual.hpp: the accuracy contract of a matrix-free
// solve (matrix_free_solve.hpp), checked against the direct sums.
//
//   Eigen::VectorXd fast_ax(n);
//   apply(r.x, fast_ax);  // the fast products on the answer
//   partc::check_direct_residual(r, entry, fast_ax, b, tolerance, order);
//   // r.product_error: ||(A_fast x - A x)_S|| / ||b_S|| over sampled rows S
//
// What a user asks of a solve is its residual against the exact operator,
// ||A x - b|| / ||b|| <= tol. GMRES meets tol against the fast operator; the
// two residuals differ by at most the fast products' error on the answer,
// ||(A_fast - A) x|| / ||b||. That error is measured here on a sample of
// rows, each summed directly from single entries A(i, j), and the contract
// is residual + product error <= tol. It is the error relative to ||b||
// that matters, not the fast sum's own relative error: RBF weights cancel,
// so the product's error relative to its sum of |terms| can be several
// times the fast sum's tolerance while still a small share of tol
// (solve_matrix_free keeps a tenth of tol for it).
//
// Surprises:
// - The sample is every (n / samples)-th row, deterministic, as the fast
//   sums' own check samples targets (fast_sum/accuracy.hpp); each row costs
//   n entries, so the check costs about samples / n of a dense product.
// - A miss throws NumericalError naming the solve, what was asked, the two
//   parts measured and a fixed order that makes the products tighter.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "partc/errors.hpp"
#include "partc/fast_sum/accuracy.hpp"
#include "partc/parallel.hpp"
#include "partc/solve/solve_result.hpp"

namespace partc {

// ||(fast_ax - A x)_S|| / ||b_S|| over sampled rows S, A from its entries.
template <class Entry>
double sampled_product_error(Entry entry, const Eigen::VectorXd& x, const Eigen::VectorXd& fast_ax,
                             const Eigen::VectorXd& b, std::size_t samples = 500) {
  const auto n = static_cast<std::size_t>(x.size());
  const std::vector<std::size_t> rows = fast_sum::detail::sample_targets(n, samples);
  std::vector<double> difference(rows.size());
  parallel_for(rows.size(), LoopWork::blocks, [&](std::size_t s) {
    const std::size_t i = rows[s];
    double direct = 0;
    for (std::size_t j = 0; j < n; ++j) direct += entry(i, j) * x[static_cast<Eigen::Index>(j)];
    difference[s] = fast_ax[static_cast<Eigen::Index>(i)] - direct;
  });
  double error2 = 0, b2 = 0;
  for (std::size_t s = 0; s < rows.size(); ++s) {
    error2 += difference[s] * difference[s];
    const double bi = b[static_cast<Eigen::Index>(rows[s])];
    b2 += bi * bi;
  }
  return b2 > 0 ? std::sqrt(error2 / b2) : std::sqrt(error2);
}

// Sets result.product_error; throws when residual + product error > tol.
// `order` is the highest expansion order the products ran at.
template <class Entry>
void check_direct_residual(SolveResult& result, Entry entry, const Eigen::VectorXd& fast_ax,
                           const Eigen::VectorXd& b, double tolerance, int order) {
  result.product_error = sampled_product_error(entry, result.x, fast_ax, b);
  const double bound = result.residual + *result.product_error;
  if (bound <= tolerance) return;
  throw NumericalError("solve " + result.name + ": asked tol " + detail::scientific(tolerance) +
                       " (relative residual against the direct sums), measured up to " +
                       detail::scientific(bound) + ": residual " +
                       detail::scientific(result.residual) +
                       " against the fast products, whose error on the answer is " +
                       detail::scientific(*result.product_error) +
                       " of ||b|| (sampled rows); a fixed order makes them tighter (schedule: "
                       "order = " +
                       std::to_string(order + 2) + ")");
}

}  // namespace partc

// partc/solve/solve_result.hpp: what a linear solve A x = b reports
// (dense_solve.hpp, sparse_solve.hpp), and the input checks both make.
//
//   const partc::SolveResult r = partc::solve_dense(A, f, {"w"});
//   if (!r.converged) throw partc::NumericalError(r.warning);  // the caller decides
//   if (!r.warning.empty()) std::cerr << "warning: " << r.warning << "\n";
//   std::cout << r.summary() << "\n";
//   // solve w: dense LU, n = 1600, rcond 8.2e-09, residual 4.1e-15, 0.26 s
//
// Surprises:
// - residual is recomputed from x as ||A x - b|| / ||b|| (2-norms), never an
//   iterative method's own figure, which may be preconditioned or drift from
//   the truth. With b = 0 it is ||A x||, absolute (0 for the exact x = 0).
//   Matrix-free, A is the fast products' operator; with the accuracy check,
//   product_error bounds how far that is from the direct sums'
//   (direct_residual.hpp).
// - What does not apply to a method is an empty std::optional: rcond (dense),
//   rank (dense fallback), nonzeros and iterations (sparse).
// - converged is false only for an iterative method that missed its tolerance
//   (or whose preconditioner could not be built); x is then its last iterate.
//   A dense solve always converges, but may warn (a near-singular matrix).
// - Errors: a NaN or Inf in A or b is a NumericalError naming the first one,
//   row by row, with 0-based row and column (the i and j of the model's sum);
//   a non-square A or a b of the wrong size is std::invalid_argument, a bug of
//   the caller rather than of the data.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include "partc/errors.hpp"

namespace partc {

namespace detail {

// "8.2e-09": two significant digits, as much as a condition estimate means.
inline std::string scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", value);
  return text;
}

// "0.26 s", "0.0013 s": two significant digits are all a timing can promise.
inline std::string format_seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, s >= 0.1 ? "%.2f s" : "%.2g s", s);
  return text;
}

}  // namespace detail

struct SolveResult {
  Eigen::VectorXd x;
  std::string name;    // the unknown, as in "solve w"
  std::string method;  // "dense LU", "CG + diagonal", ...
  Eigen::Index n = 0;  // unknowns (and equations)
  std::optional<Eigen::Index> nonzeros;
  std::optional<double> rcond;       // LU's estimate of 1 / (1-norm condition number)
  std::optional<Eigen::Index> rank;  // numerical rank
  std::optional<Eigen::Index> iterations;
  double residual = 0.0;
  std::optional<double> product_error;  // matrix-free, checked: fast products' error on x, of ||b||
  double seconds = 0.0;                 // wall time of the whole solve, checks included
  bool converged = true;
  std::string warning;  // for the user, starting "solve <name>: "; empty when all went well

  // One line for the driver's log, e.g.
  // "solve w: dense LU, n = 1600, rcond 8.2e-09, residual 4.1e-15, 0.26 s".
  std::string summary() const {
    std::string line = "solve " + name + ": " + method + ", n = " + std::to_string(n);
    if (nonzeros) line += ", " + std::to_string(*nonzeros) + " nonzeros";
    if (rank) line += ", rank " + std::to_string(*rank);
    if (rcond) line += ", rcond " + detail::scientific(*rcond);
    if (iterations)
      line += (converged ? ", " : ", NOT CONVERGED after ") + std::to_string(*iterations) +
              " iterations";
    else if (!converged)
      line += ", NOT CONVERGED";
    line += ", residual " + detail::scientific(residual);
    if (product_error)
      line += " (+ " + detail::scientific(*product_error) + " fast products' error, sampled)";
    line += ", " + detail::format_seconds(seconds);
    return line;
  }
};

namespace detail {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline void check_system_shape(Eigen::Index rows, Eigen::Index cols, Eigen::Index b_size,
                               const std::string& name) {
  if (rows != cols || b_size != rows)
    throw std::invalid_argument("solve " + name + ": the matrix is " + std::to_string(rows) +
                                " x " + std::to_string(cols) + " and the right-hand side has " +
                                std::to_string(b_size) + " entries; a solve needs n x n and n");
}

// The error for A(row, column) = value, or for b(row) = value when column < 0.
inline NumericalError non_finite_entry(const std::string& name, Eigen::Index row,
                                       Eigen::Index column, double value) {
  // A NaN's sign bit is meaningless; libstdc++ would print "-nan".
  const std::string text = std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf";
  if (column < 0)
    return NumericalError("solve " + name + ": the right-hand side is " + text + " at row " +
                          std::to_string(row) + " (0-based)");
  return NumericalError("solve " + name + ": the matrix entry at row " + std::to_string(row) +
                        ", column " + std::to_string(column) + " (0-based) is " + text);
}

inline void check_finite_vector(const Eigen::VectorXd& b, const std::string& name) {
  if (b.allFinite()) return;  // vectorised; the search below runs only for the error
  for (Eigen::Index i = 0; i < b.size(); ++i)
    if (!std::isfinite(b[i])) throw non_finite_entry(name, i, -1, b[i]);
}

// ||A x - b|| / ||b||, or ||A x|| for b = 0; A dense or sparse.
template <class Matrix>
double relative_residual(const Matrix& A, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  const double b_norm = b.norm();
  const double r_norm = (A * x - b).norm();
  return b_norm > 0 ? r_norm / b_norm : r_norm;
}

}  // namespace detail

}  // namespace partc

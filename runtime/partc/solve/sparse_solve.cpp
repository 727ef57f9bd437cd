// partc/solve/sparse_solve.cpp: solve_sparse (sparse_solve.hpp says what it does).
#include "partc/solve/sparse_solve.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <unsupported/Eigen/IterativeSolvers>

#include "partc/solve/krylov_restarts.hpp"

namespace partc {

namespace detail {

namespace {

void check_finite_sparse(const SparseMatrixCRS& A, const std::string& name) {
  for (Eigen::Index i = 0; i < A.outerSize(); ++i)
    for (SparseMatrixCRS::InnerIterator entry(A, i); entry; ++entry)
      if (!std::isfinite(entry.value()))
        throw non_finite_entry(name, entry.row(), entry.col(), entry.value());
}

std::string preconditioner_name(Preconditioner preconditioner) {
  switch (preconditioner) {
    case Preconditioner::diagonal: return "diagonal";
    case Preconditioner::incomplete_lut: return "ILUT";
    case Preconditioner::incomplete_cholesky: return "IC";
  }
  return "";
}

std::string method_name(const SparseSolveOptions& options) {
  std::string krylov;
  switch (options.method) {
    case KrylovMethod::cg: krylov = "CG"; break;
    case KrylovMethod::bicgstab: krylov = "BiCGSTAB"; break;
    case KrylovMethod::gmres:
      krylov = "GMRES(" + std::to_string(options.gmres_restart) + ")";
      break;
  }
  return krylov + " + " + preconditioner_name(options.preconditioner);
}

using IncompleteLUT = Eigen::IncompleteLUT<double, SparseMatrixCRS::StorageIndex>;
using IncompleteCholesky =
    Eigen::IncompleteCholesky<double, Eigen::Lower,
                              Eigen::AMDOrdering<SparseMatrixCRS::StorageIndex>>;

template <class Solver>
void configure_preconditioner(Solver& solver, const SparseSolveOptions& options) {
  if constexpr (std::is_same_v<typename Solver::Preconditioner, IncompleteLUT>) {
    solver.preconditioner().setDroptol(options.ilut_drop_tolerance);
    solver.preconditioner().setFillfactor(options.ilut_fill_factor);
  }
}

// Builds the preconditioner, then runs `solver` to the tolerance (krylov_restarts.hpp).
template <class Solver>
void run_krylov(Solver& solver, const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                const SparseSolveOptions& options, SolveResult& result) {
  configure_preconditioner(solver, options);
  solver.compute(A);
  if (solver.info() != Eigen::Success) {
    result.residual = relative_residual(A, result.x, b);
    result.converged = false;
    result.iterations = 0;
    // Eigen's ILUT fails only on a zero row; its IC after shifting the
    // diagonal ten times, for an A far from positive definite.
    result.warning =
        "solve " + options.name + ": the " + preconditioner_name(options.preconditioner) +
        " preconditioner could not be built from the matrix (" +
        (options.preconditioner == Preconditioner::incomplete_lut ? "a row is zero"
                                                                  : "not positive definite") +
        ")";
    return;
  }
  const Eigen::Index limit = options.max_iterations > 0 ? options.max_iterations : 2 * A.cols();
  iterate_to_tolerance(solver, A, b, options.tolerance, limit,
                       options.method == KrylovMethod::gmres, method_name(options), result);
}

template <class Preconditioner>
void run_method(const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                const SparseSolveOptions& options, SolveResult& result) {
  switch (options.method) {
    case KrylovMethod::cg: {
      Eigen::ConjugateGradient<SparseMatrixCRS, Eigen::Lower | Eigen::Upper, Preconditioner> cg;
      run_krylov(cg, A, b, options, result);
      return;
    }
    case KrylovMethod::bicgstab: {
      Eigen::BiCGSTAB<SparseMatrixCRS, Preconditioner> bicgstab;
      run_krylov(bicgstab, A, b, options, result);
      return;
    }
    case KrylovMethod::gmres: {
      Eigen::GMRES<SparseMatrixCRS, Preconditioner> gmres;
      gmres.set_restart(options.gmres_restart);
      run_krylov(gmres, A, b, options, result);
      return;
    }
  }
}

}  // namespace

}  // namespace detail

SolveResult solve_sparse(const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                         const SparseSolveOptions& options, const Eigen::VectorXd& guess) {
  const auto start = std::chrono::steady_clock::now();
  detail::check_system_shape(A.rows(), A.cols(), b.size(), options.name);
  detail::check_system_shape(A.rows(), A.cols(), guess.size(), options.name + " (its guess)");
  if (options.method == KrylovMethod::cg &&
      options.preconditioner == Preconditioner::incomplete_lut)
    throw std::invalid_argument("solve " + options.name +
                                ": CG needs a symmetric preconditioner (diagonal or "
                                "incomplete_cholesky), not incomplete_lut");
  detail::check_finite_sparse(A, options.name);
  detail::check_finite_vector(b, options.name);
  detail::check_finite_vector(guess, options.name + " (its guess)");

  SolveResult result;
  result.name = options.name;
  result.method = detail::method_name(options);
  result.n = A.rows();
  result.nonzeros = A.nonZeros();
  result.x = guess;
  switch (options.preconditioner) {
    case Preconditioner::diagonal:
      detail::run_method<Eigen::DiagonalPreconditioner<double>>(A, b, options, result);
      break;
    case Preconditioner::incomplete_lut:
      detail::run_method<detail::IncompleteLUT>(A, b, options, result);
      break;
    case Preconditioner::incomplete_cholesky:
      detail::run_method<detail::IncompleteCholesky>(A, b, options, result);
      break;
  }
  result.seconds = detail::seconds_since(start);
  return result;
}

SolveResult solve_sparse(const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                         const SparseSolveOptions& options) {
  return solve_sparse(A, b, options, Eigen::VectorXd::Zero(b.size()));
}

}  // namespace partc

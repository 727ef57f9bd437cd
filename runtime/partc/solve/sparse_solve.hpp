// partc/solve/sparse_solve.hpp: solve_sparse(A, b), a Krylov solve of a sparse
// system in compressed row storage, for the systems of `solve w` whose sum has
// a cutoff (compact-support kernels: a few dozen nonzeros per row).
//
//   std::vector<Eigen::Triplet<double>> entries;  // (i, j, value), any order,
//   entries.emplace_back(i, j, phi(r));            // duplicates summed
//   partc::SparseMatrixCRS A(n, n);
//   A.setFromTriplets(entries.begin(), entries.end());
//   partc::SparseSolveOptions options;
//   options.name = "w";
//   options.method = partc::KrylovMethod::cg;  // A symmetric positive definite
//   const partc::SolveResult r = partc::solve_sparse(A, f, options);
//   if (!r.converged) throw partc::NumericalError(r.warning);  // or go on, warned
//   std::cout << r.summary() << "\n";
//   // solve w: CG + diagonal, n = 1000, 2998 nonzeros, 1000 iterations, residual 8.1e-11, 0.0049 s
//
// (Row by row works too: A.reserve(nonzeros per row), then A.insert(i, j) = v.)
//
// Methods (Eigen's): cg, conjugate gradients, for symmetric positive definite A
// only, reading both triangles (Lower|Upper), so A is stored whole and the
// product runs on OpenMP threads; bicgstab, the default, for any nonsingular
// A; gmres (restarted, unsupported/Eigen/IterativeSolvers), slower per
// iteration but smoother and more robust where BiCGSTAB stagnates or breaks
// down. Preconditioners: diagonal (Jacobi, the default; cheap, and enough
// when the diagonal dominates, as for an RBF matrix with a narrow support);
// incomplete_lut (dual-threshold incomplete LU, for nonsymmetric A);
// incomplete_cholesky (for SPD A, with CG).
//
// Convergence means the recomputed ||A x - b|| / ||b|| is at most tolerance,
// not the method's own figure (krylov_restarts.hpp).
//
// Surprises:
// - max_iterations 0 means 2 n, Eigen's default (CG needs at most n in exact
//   arithmetic); iterations in the result count every restart's.
// - Non-convergence is no exception: converged is false, x is the last
//   iterate, warning says how far it got; the caller decides (solve_result.hpp).
// - cg with incomplete_lut is refused (std::invalid_argument): CG needs a
//   symmetric preconditioner, and an ILUT of a symmetric A is not.
// - A NaN or Inf entry in A or b is a NumericalError naming the first one,
//   row by row (solve_result.hpp); stored zeros count as nonzeros.
#pragma once

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unsupported/Eigen/IterativeSolvers>

#include "partc/solve/krylov_restarts.hpp"
#include "partc/solve/solve_result.hpp"

namespace partc {

using SparseMatrixCRS = Eigen::SparseMatrix<double, Eigen::RowMajor>;

enum class KrylovMethod { cg, bicgstab, gmres };
enum class Preconditioner { diagonal, incomplete_lut, incomplete_cholesky };

struct SparseSolveOptions {
  std::string name = "x";  // the unknown, for messages
  KrylovMethod method = KrylovMethod::bicgstab;
  Preconditioner preconditioner = Preconditioner::diagonal;
  double tolerance = 1e-10;            // on the recomputed ||A x - b|| / ||b||
  Eigen::Index max_iterations = 0;     // 0: 2 n
  Eigen::Index gmres_restart = 30;     // Krylov vectors kept between GMRES restarts
  double ilut_drop_tolerance = 1e-12;  // ILUT drops entries below this times their row's norm
  int ilut_fill_factor = 10;           // ILUT keeps up to this times A's nonzeros per row
};

namespace detail {

inline void check_finite_sparse(const SparseMatrixCRS& A, const std::string& name) {
  for (Eigen::Index i = 0; i < A.outerSize(); ++i)
    for (SparseMatrixCRS::InnerIterator entry(A, i); entry; ++entry)
      if (!std::isfinite(entry.value()))
        throw non_finite_entry(name, entry.row(), entry.col(), entry.value());
}

inline std::string preconditioner_name(Preconditioner preconditioner) {
  switch (preconditioner) {
    case Preconditioner::diagonal: return "diagonal";
    case Preconditioner::incomplete_lut: return "ILUT";
    case Preconditioner::incomplete_cholesky: return "IC";
  }
  return "";
}

inline std::string method_name(const SparseSolveOptions& options) {
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

}  // namespace detail

// As solve_sparse(A, b, options), starting from `guess` (the previous step's
// solution, say) instead of 0.
[[nodiscard]] inline SolveResult solve_sparse(const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                                              const SparseSolveOptions& options,
                                              const Eigen::VectorXd& guess) {
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

[[nodiscard]] inline SolveResult solve_sparse(const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                                              const SparseSolveOptions& options = {}) {
  return solve_sparse(A, b, options, Eigen::VectorXd::Zero(b.size()));
}

}  // namespace partc

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
// - Compiled once, in the runtime library (sparse_solve.cpp): a model
//   including this header parses Eigen's sparse core, not its Krylov solvers.
#pragma once

#include <Eigen/SparseCore>
#include <string>

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

// Compiled once, in the runtime library (sparse_solve.cpp).
[[nodiscard]] SolveResult solve_sparse(const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                                       const SparseSolveOptions& options = {});

// As solve_sparse(A, b, options), starting from `guess` (the previous step's
// solution, say) instead of 0.
[[nodiscard]] SolveResult solve_sparse(const SparseMatrixCRS& A, const Eigen::VectorXd& b,
                                       const SparseSolveOptions& options,
                                       const Eigen::VectorXd& guess);

}  // namespace partc

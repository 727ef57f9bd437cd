// partc/solve/krylov_restarts.hpp: runs one of Eigen's Krylov solvers until
// the true relative residual ||A x - b|| / ||b|| meets the tolerance, for
// sparse_solve.hpp and matrix_free_solve.hpp.
//
// Eigen's methods stop on their own figure: CG's and BiCGSTAB's is updated
// recursively and can drift below the true residual; GMRES's is the
// left-preconditioned residual relative to the one it starts from. So when a
// method stops content but the true residual is still too large, it is
// restarted from its x (where its residual is exact again) for the
// iterations left, with GMRES asked for the reduction still missing.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <string>

#include "partc/solve/solve_result.hpp"

namespace partc::detail {

// `solver` has been computed on A; result.x holds the start and gets the
// answer, result.residual, iterations and converged are set, and warning
// (naming `method`) when the limit is reached first.
template <class Solver, class Operator>
void iterate_to_tolerance(Solver& solver, const Operator& A, const Eigen::VectorXd& b,
                          double tolerance, Eigen::Index limit, bool gmres,
                          const std::string& method, SolveResult& result) {
  Eigen::Index used = 0;
  result.residual = relative_residual(A, result.x, b);
  while (result.residual > tolerance && used < limit) {
    solver.setTolerance(gmres ? std::min(1.0, tolerance / result.residual) : tolerance);
    solver.setMaxIterations(limit - used);
    result.x = solver.solveWithGuess(b, result.x);
    used += solver.iterations();
    result.residual = relative_residual(A, result.x, b);
    if (solver.info() != Eigen::Success || solver.iterations() == 0) break;
  }
  result.iterations = used;
  result.converged = result.residual <= tolerance;
  if (!result.converged)
    result.warning = "solve " + result.name + ": " + method +
                     " did not converge: relative residual " + scientific(result.residual) +
                     " after " + std::to_string(used) + " iterations (limit " +
                     std::to_string(limit) + "), tolerance " + scientific(tolerance);
}

}  // namespace partc::detail

// partc/solve/matrix_free_solve.hpp: solve_matrix_free(points, apply, entry,
// b), a dense system A x = b over points solved without storing A: GMRES
// whose products A x are a function (a fast sum, fast_sum/fmm.hpp),
// preconditioned by two-level restricted Schwarz on blocks of A built from
// single entries (schwarz_preconditioner.hpp). For RBF interpolation and
// Kansa collocation at sizes where a dense LU's n^3 is too slow.
//
//   const auto apply = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
//     fmm.potential(x.data(), y.data());  // y = A x, to the fast sum's tol
//   };
//   const auto entry = [&](std::size_t i, std::size_t j) {
//     return phi(partc::norm(points[j] - points[i]));
//   };
//   partc::MatrixFreeSolveOptions options;
//   options.name = "w";
//   options.tolerance = 1e-8;
//   const partc::SolveResult r = partc::solve_matrix_free(points, apply, entry, f, options);
//   // solve w: GMRES(100) + restricted Schwarz (16 blocks of up to 171, 0 in
//   //   double, 57 coarse points), matrix-free, n = 900, 18 iterations,
//   //   residual 3.0e-12, 0.49 s
//
// The residual is the true ||A x - b|| / ||b|| with A as apply() computes
// it (krylov_restarts.hpp): with a fast sum, A is the fast sum's, whose
// relative error is its tolerance. A residual well below that error means
// nothing more about the exact A, so the fast sum's tolerance should be a
// hundredth of the solver's (what partc's code generator asks); a looser one
// stalls GMRES or makes its answer the solution of another system. GMRES
// stops at nine tenths of the tolerance: the last tenth is the products'
// error on the answer, so that the residual against the exact A meets the
// tolerance (checked by direct_residual.hpp) even when the weights cancel
// and that error is several times the fast sum's.
//
// Surprises:
// - Eigen's GMRES is left-preconditioned: its own stopping figure is the
//   preconditioned residual, and the loop restarts it until the true one
//   meets tolerance.
// - The preconditioner (schwarz_preconditioner.hpp) applies A once more for
//   its coarse level: an iteration costs two products.
// - The preconditioner's blocks are LU-factored in float, except those too
//   ill-conditioned for it ("k in double" in the summary).
// - Flat kernels (multiquadrics or Gaussians whose shape parameter times the
//   node spacing is well below 0.3; condition numbers above about 1e10) may
//   not converge at all; a dense LU (solve_dense) still answers those, at n^3.
// - With a fast product, the product's error is relative to the sum of
//   |terms|, not to the result: weights that cancel (as RBF weights do) make
//   it larger against ||b||, and the residual stalls there.
// - Non-convergence is no exception: converged is false, warning says how far
//   it got, x is the last iterate (solve_result.hpp).
// - b is checked for NaN and Inf; A's entries are never all seen, so a NaN in
//   A shows as a NaN residual, reported as not converged.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <chrono>
#include <functional>
#include <string>
#include <unsupported/Eigen/IterativeSolvers>
#include <vector>

#include "partc/solve/krylov_restarts.hpp"
#include "partc/solve/schwarz_preconditioner.hpp"
#include "partc/solve/solve_result.hpp"
#include "partc/vec.hpp"

namespace partc {
class LinearOperator;
}

// Eigen learns an operator's shape from its traits before the class is complete.
template <>
struct Eigen::internal::traits<partc::LinearOperator>
    : public Eigen::internal::traits<Eigen::SparseMatrix<double>> {};

namespace partc {

// A x as a function, for Eigen's iterative solvers (Eigen's "matrix-free
// solvers" pattern: an EigenBase whose products call the function).
class LinearOperator : public Eigen::EigenBase<LinearOperator> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = false };

  LinearOperator(Eigen::Index n, std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)> apply)
      : n_(n), apply_(std::move(apply)) {}
  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return n_; }
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const { apply_(x, y); }

  template <class Rhs>
  Eigen::Product<LinearOperator, Rhs, Eigen::AliasFreeProduct> operator*(
      const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<LinearOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

 private:
  Eigen::Index n_;
  std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)> apply_;
};

}  // namespace partc

namespace Eigen::internal {

// A x for the solvers: the operator's function, into a plain vector.
template <class Rhs>
struct generic_product_impl<partc::LinearOperator, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<partc::LinearOperator, Rhs,
                                generic_product_impl<partc::LinearOperator, Rhs>> {
  template <class Dest>
  static void scaleAndAddTo(Dest& dst, const partc::LinearOperator& A, const Rhs& rhs,
                            const double& alpha) {
    const Eigen::VectorXd x = rhs;
    Eigen::VectorXd y(A.rows());
    A.apply(x, y);
    dst.noalias() += alpha * y;
  }
};

}  // namespace Eigen::internal

namespace partc {

// RestrictedSchwarz in the shape Eigen's solvers call a preconditioner.
template <int D>
class SchwarzPreconditioner {
 public:
  void use(const RestrictedSchwarz<D>& schwarz, const LinearOperator& A) {
    schwarz_ = &schwarz;
    A_ = &A;
  }
  template <class Matrix>
  SchwarzPreconditioner& analyzePattern(const Matrix&) { return *this; }
  template <class Matrix>
  SchwarzPreconditioner& factorize(const Matrix&) { return *this; }
  template <class Matrix>
  SchwarzPreconditioner& compute(const Matrix&) { return *this; }
  template <class Rhs>
  Eigen::VectorXd solve(const Rhs& r) const {
    return schwarz_->apply(r, [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { A_->apply(x, y); });
  }
  Eigen::ComputationInfo info() const { return Eigen::Success; }

 private:
  const RestrictedSchwarz<D>* schwarz_ = nullptr;
  const LinearOperator* A_ = nullptr;
};

struct MatrixFreeSolveOptions {
  std::string name = "x";            // the unknown, for messages
  double tolerance = 1e-8;           // on ||A x - b|| / ||b||, A the exact operator
  Eigen::Index max_iterations = 0;   // 0: 1000
  Eigen::Index gmres_restart = 100;  // Krylov vectors kept (n of them in memory)
  SchwarzOptions schwarz;
};

template <int D, class T, class Apply, class Entry>
[[nodiscard]] SolveResult solve_matrix_free(const std::vector<Vec<D, T>>& points, Apply apply,
                                            Entry entry, const Eigen::VectorXd& b,
                                            const MatrixFreeSolveOptions& options = {}) {
  const auto start = std::chrono::steady_clock::now();
  const auto n = static_cast<Eigen::Index>(points.size());
  detail::check_system_shape(n, n, b.size(), options.name);
  detail::check_finite_vector(b, options.name);

  const RestrictedSchwarz<D> schwarz(points, entry, options.schwarz);
  const LinearOperator A(n, apply);
  Eigen::GMRES<LinearOperator, SchwarzPreconditioner<D>> gmres;
  gmres.set_restart(options.gmres_restart);
  gmres.compute(A);
  gmres.preconditioner().use(schwarz, A);

  SolveResult result;
  result.name = options.name;
  result.method = "GMRES(" + std::to_string(options.gmres_restart) + ") + restricted Schwarz (" +
                  std::to_string(schwarz.clusters()) + " blocks of up to " +
                  std::to_string(schwarz.largest_block()) + ", " +
                  std::to_string(schwarz.double_blocks()) + " in double, " +
                  std::to_string(schwarz.coarse_points()) + " coarse points), matrix-free";
  result.n = n;
  result.x = Eigen::VectorXd::Zero(n);
  const Eigen::Index limit = options.max_iterations > 0 ? options.max_iterations : 1000;
  const double products_share = 0.1;  // of the tolerance, for the fast products' error
  detail::iterate_to_tolerance(gmres, A, b, (1 - products_share) * options.tolerance, limit,
                               true, "GMRES + restricted Schwarz", result);
  result.seconds = detail::seconds_since(start);
  return result;
}

}  // namespace partc

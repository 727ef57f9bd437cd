// solve/dense_solve.hpp, sparse_solve.hpp and matrix_market.hpp, each against
// a reference that does not go through them: systems built as b = A x_true,
// least-norm solutions from the factors a singular matrix was made of,
// difference equations whose exact discrete solution is known (a quadratic,
// which central differences differentiate exactly), condition numbers from an
// explicit inverse, and Matrix Market files parsed by a reader written here.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unsupported/Eigen/IterativeSolvers>
#include <vector>

#include "partc/errors.hpp"
#include "partc/solve/dense_solve.hpp"
#include "partc/solve/matrix_market.hpp"
#include "partc/solve/sparse_solve.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using Catch::Matchers::Matches;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

VectorXd random_vector(Index n, unsigned seed) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  VectorXd v(n);
  for (Index i = 0; i < n; ++i) v[i] = uniform(engine);
  return v;
}

MatrixXd random_matrix(Index rows, Index cols, unsigned seed) {
  const VectorXd entries = random_vector(rows * cols, seed);
  return Eigen::Map<const MatrixXd>(entries.data(), rows, cols);
}

// Entries uniform in (-1, 1) put the eigenvalues in a disc of radius
// sqrt(n / 3) about 0 (the circular law); shifted by 2 sqrt(n), they keep
// well away from 0: a condition number of a few.
MatrixXd well_conditioned(Index n, unsigned seed) {
  MatrixXd A = random_matrix(n, n, seed);
  A.diagonal().array() += 2 * std::sqrt(static_cast<double>(n));
  return A;
}

// Q with orthonormal columns, from the Householder QR of a random matrix.
MatrixXd random_orthogonal(Index n, unsigned seed) {
  return Eigen::HouseholderQR<MatrixXd>(random_matrix(n, n, seed)).householderQ();
}

double relative_error(const VectorXd& x, const VectorXd& reference) {
  return (x - reference).norm() / reference.norm();
}

// 1 / (||A||_1 ||A^-1||_1), with the inverse formed explicitly.
double exact_rcond_1(const MatrixXd& A) {
  const MatrixXd inverse = Eigen::FullPivLU<MatrixXd>(A).inverse();
  return 1.0 /
         (A.cwiseAbs().colwise().sum().maxCoeff() * inverse.cwiseAbs().colwise().sum().maxCoeff());
}

MatrixXd hilbert(Index n) {
  MatrixXd H(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) H(i, j) = 1.0 / static_cast<double>(i + j + 1);
  return H;
}

// Points of the interior of (0, 1) on a grid of spacing 1 / (n + 1), and the
// difference operator -u'' + c u' with central differences and u(0) = u(1) = 0:
// tridiagonal, symmetric positive definite for c = 0. Central differences are
// exact for quadratics, so u = x (1 - x) solves the discrete problem with
// f = -u'' + c u' = 2 + c (1 - 2 x), to rounding.
struct DifferenceProblem {
  partc::SparseMatrixCRS A;
  VectorXd f, u;
};

DifferenceProblem convection_diffusion(Index n, double c) {
  const double h = 1.0 / static_cast<double>(n + 1);
  std::vector<Eigen::Triplet<double>> entries;
  DifferenceProblem p;
  p.f.resize(n);
  p.u.resize(n);
  for (Index i = 0; i < n; ++i) {
    const double x = static_cast<double>(i + 1) * h;
    entries.emplace_back(i, i, 2.0 / (h * h));
    if (i > 0) entries.emplace_back(i, i - 1, -1.0 / (h * h) - c / (2 * h));
    if (i + 1 < n) entries.emplace_back(i, i + 1, -1.0 / (h * h) + c / (2 * h));
    p.f[i] = 2.0 + c * (1.0 - 2.0 * x);
    p.u[i] = x * (1.0 - x);
  }
  p.A.resize(n, n);
  p.A.setFromTriplets(entries.begin(), entries.end());
  return p;
}

}  // namespace

// ---------------------------------------------------------------- dense

TEST_CASE("solve_dense: LU recovers a known solution, with a sound rcond", "[solve][dense]") {
  const Index n = 60;
  const MatrixXd A = well_conditioned(n, 1);
  const VectorXd x_true = random_vector(n, 2);
  const VectorXd b = A * x_true;

  const partc::SolveResult r = partc::solve_dense(A, b, {"w"});
  CHECK(r.method == "dense LU");
  CHECK(r.warning.empty());
  CHECK(r.converged);
  CHECK(r.n == n);
  CHECK_FALSE(r.rank);
  CHECK_FALSE(r.iterations);
  CHECK(relative_error(r.x, x_true) < 100 * eps);
  CHECK(r.residual == (A * r.x - b).norm() / b.norm());
  CHECK(r.residual < 10 * eps);
  // Hager-Higham underestimates ||A^-1||_1, so the estimate is an upper bound
  // of the true rcond; usually within a factor 3 of it, as here.
  const double exact = exact_rcond_1(A);
  REQUIRE(r.rcond);
  CHECK(*r.rcond >= exact * (1 - 1e-12));
  CHECK(*r.rcond <= 3 * exact);
  CHECK(r.seconds >= 0);
  CHECK_THAT(r.summary(), Matches("solve w: dense LU, n = 60, rcond \\d\\.\\de-0\\d, "
                                  "residual \\d\\.\\de-1\\d, [0-9.e-]+ s"));
}

TEST_CASE("solve_dense: an ill-conditioned matrix keeps LU's answer and says what it costs",
          "[solve][dense]") {
  // Hilbert's matrix of size 8: condition 3.4e10 (1-norm), below the warning;
  // size 10: 3.5e13, above it and still far from singular to working precision.
  for (const Index n : {8, 10}) {
    const MatrixXd H = hilbert(n);
    const VectorXd b = H * VectorXd::Ones(n);
    const partc::SolveResult r = partc::solve_dense(H, b, {"w"});
    INFO("n = " << n << ", exact condition " << 1 / exact_rcond_1(H));
    CHECK(r.method == "dense LU");
    REQUIRE(r.rcond);
    if (n == 8) {
      CHECK(r.warning.empty());
      continue;
    }
    CHECK(1 / *r.rcond > 1e12);
    CHECK_THAT(r.warning, Matches("solve w: ill-conditioned: condition estimate \\d\\.\\de\\+13 > "
                                  "1\\.0e\\+12, so about 13 of 16 digits of w may be rounding "
                                  "noise, however small the residual; .*"));
    // The digits said are lost: x = 1 comes back with an error near eps / rcond.
    CHECK(relative_error(r.x, VectorXd::Ones(n)) > 1e-6);
    CHECK(r.residual < 100 * eps);
  }
}

TEST_CASE("solve_dense: a Hilbert matrix of size 12 takes the fallback and warns",
          "[solve][dense]") {
  const Index n = 12;
  const MatrixXd H = hilbert(n);
  const VectorXd x_true = VectorXd::Ones(n);
  const VectorXd b = H * x_true;

  const partc::SolveResult r = partc::solve_dense(H, b, {"w"});
  REQUIRE(r.rcond);
  CHECK(*r.rcond < eps);  // about 1e-17: singular to working precision
  CHECK(r.method == "dense least-norm (complete orthogonal decomposition)");
  CHECK_THAT(r.warning, Matches("solve w: the matrix is singular to working precision "
                                "\\(LU's rcond \\d\\.\\de-1\\d < 2\\.2e-16\\); solved by a "
                                "complete orthogonal decomposition instead, numerical rank "
                                "\\d+ of 12, least-norm solution"));
  CHECK(r.converged);
  // The rank against the SVD's count of singular values above n eps sigma_max,
  // the same threshold: H's smallest is 1e-16, its next 1e-14, well apart.
  const VectorXd sigma = Eigen::JacobiSVD<MatrixXd>(H).singularValues();
  Index svd_rank = 0;
  for (Index k = 0; k < n; ++k) svd_rank += sigma[k] > n * eps * sigma[0];
  REQUIRE(r.rank);
  CHECK(*r.rank == svd_rank);
  CHECK(svd_rank == 11);
  CHECK_THAT(r.summary(), Contains(", rank 11, rcond "));
  // b is consistent, so dropping a direction along which H is 1e-16 costs
  // a residual near eps. The direction dropped is near the SVD's smallest
  // singular vector, not the same: x is the truncated SVD's solution to 1%.
  CHECK(r.residual == (H * r.x - b).norm() / b.norm());
  CHECK(r.residual < 100 * eps);
  Eigen::JacobiSVD<MatrixXd> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  VectorXd x_svd = VectorXd::Zero(n);
  for (Index k = 0; k < svd_rank; ++k)
    x_svd += svd.matrixV().col(k) * (svd.matrixU().col(k).dot(b) / sigma[k]);
  CHECK(relative_error(r.x, x_svd) < 1e-2);
}

TEST_CASE("solve_dense: a singular matrix gives its rank and the least-norm solution",
          "[solve][dense]") {
  SECTION("3 x 3: x1 + x2 = 2 twice and 2 x3 = 4, least norm at x1 = x2") {
    MatrixXd A(3, 3);
    A << 1, 1, 0, 1, 1, 0, 0, 0, 2;
    const VectorXd b = (VectorXd(3) << 2, 2, 4).finished();
    const partc::SolveResult r = partc::solve_dense(A, b, {"w"});
    REQUIRE(r.rcond);
    CHECK(!(*r.rcond >= eps));  // 0 or NaN: LU met a zero pivot
    REQUIRE(r.rank);
    CHECK(*r.rank == 2);
    CHECK(relative_error(r.x, (VectorXd(3) << 1, 1, 2).finished()) < 10 * eps);
    CHECK_THAT(r.warning, Contains("numerical rank 2 of 3"));
  }
  SECTION("40 x 40 of rank 25, made as U S V^T") {
    const Index n = 40, rank = 25;
    const MatrixXd U = random_orthogonal(n, 3), V = random_orthogonal(n, 4);
    VectorXd s = VectorXd::Zero(n);
    for (Index k = 0; k < rank; ++k) s[k] = 1.0 + static_cast<double>(k);
    const MatrixXd A = U * s.asDiagonal() * V.transpose();
    const VectorXd b = A * random_vector(n, 5);  // in the range of A
    // The least-norm solution: V S^+ U^T b.
    VectorXd s_plus = VectorXd::Zero(n);
    s_plus.head(rank) = s.head(rank).cwiseInverse();
    const VectorXd x_least_norm = V * s_plus.asDiagonal() * U.transpose() * b;

    const partc::SolveResult r = partc::solve_dense(A, b, {"w"});
    REQUIRE(r.rank);
    CHECK(*r.rank == rank);
    CHECK(relative_error(r.x, x_least_norm) < 1e-12);
    CHECK(r.residual < 1e-13);
    CHECK_THAT(r.warning, Contains("numerical rank 25 of 40, least-norm solution"));
  }
}

TEST_CASE("solve_dense: rcond_threshold decides between LU and the fallback", "[solve][dense]") {
  const MatrixXd A = well_conditioned(20, 6);
  const VectorXd x_true = random_vector(20, 7);
  partc::DenseSolveOptions options;
  options.rcond_threshold = 1.0;  // no matrix but the identity passes
  const partc::SolveResult r = partc::solve_dense(A, A * x_true, options);
  CHECK(r.method == "dense least-norm (complete orthogonal decomposition)");
  CHECK(*r.rank == 20);
  CHECK(relative_error(r.x, x_true) < 100 * eps);
  CHECK_THAT(r.warning, Contains("solve x: "));  // the default name
}

TEST_CASE("solve_dense: the answer does not depend on the thread count", "[solve][dense]") {
  // n = 400: LU's updates are large enough for Eigen to run them on threads.
  const MatrixXd A = well_conditioned(400, 8);
  const VectorXd b = random_vector(400, 9);
  const int threads = Eigen::nbThreads();
  Eigen::setNbThreads(1);
  const VectorXd x1 = partc::solve_dense(A, b).x;
  Eigen::setNbThreads(2);
  const VectorXd x2 = partc::solve_dense(A, b).x;
  Eigen::setNbThreads(threads);
  CHECK(std::memcmp(x1.data(), x2.data(), sizeof(double) * 400) == 0);
}

TEST_CASE("solve_dense refuses NaN and Inf, naming the first entry row by row", "[solve][dense]") {
  MatrixXd A = MatrixXd::Identity(8, 8);
  VectorXd b = VectorXd::Ones(8);
  A(5, 1) = std::numeric_limits<double>::infinity();
  A(3, 7) = std::nan("");  // row 3 comes first, though column 7 is stored later
  const auto message = [&] {
    try {
      (void)partc::solve_dense(A, b, {"w"});
    } catch (const partc::NumericalError& e) {
      return std::string(e.what());
    }
    return std::string("no NumericalError");
  };
  CHECK(message() == "solve w: the matrix entry at row 3, column 7 (0-based) is nan");
  A(3, 7) = 0;
  A(5, 1) = -std::numeric_limits<double>::infinity();
  CHECK(message() == "solve w: the matrix entry at row 5, column 1 (0-based) is -inf");
  A(5, 1) = 0;
  b[4] = std::numeric_limits<double>::infinity();
  CHECK(message() == "solve w: the right-hand side is inf at row 4 (0-based)");
}

TEST_CASE("solve_dense refuses a system of the wrong shape", "[solve][dense]") {
  CHECK_THROWS_WITH(partc::solve_dense(MatrixXd::Identity(3, 3), VectorXd::Ones(4), {"w"}),
                    "solve w: the matrix is 3 x 3 and the right-hand side has 4 entries; a "
                    "solve needs n x n and n");
  CHECK_THROWS_AS(partc::solve_dense(MatrixXd::Ones(3, 2), VectorXd::Ones(3)),
                  std::invalid_argument);
}

// ---------------------------------------------------------------- sparse

TEST_CASE("solve_sparse: CG solves the 1D Laplacian -u'' = 2 exactly", "[solve][sparse]") {
  const DifferenceProblem p = convection_diffusion(200, 0.0);
  partc::SparseSolveOptions options;
  options.name = "u";
  options.method = partc::KrylovMethod::cg;
  // Above the residual double precision can promise, eps cond(A) = 3.5e-12:
  // 1e-12 was met on SSE2 and missed by 10% with AVX-512's sums.
  options.tolerance = 1e-11;

  SECTION("diagonal preconditioner") {
    const partc::SolveResult r = partc::solve_sparse(p.A, p.f, options);
    CHECK(r.method == "CG + diagonal");
    CHECK(r.converged);
    CHECK(r.warning.empty());
    CHECK(r.residual <= 1e-11);
    CHECK(r.residual == (p.A * r.x - p.f).norm() / p.f.norm());
    // Condition number 4 (n + 1)^2 / pi^2 = 1.6e4 turns 1e-11 into 2e-7 at most.
    CHECK((r.x - p.u).lpNorm<Eigen::Infinity>() < 2e-7 * p.u.lpNorm<Eigen::Infinity>());
    REQUIRE(r.iterations);
    // In exact arithmetic CG ends after as many iterations as f has
    // eigencomponents: f is symmetric about the middle, so n / 2 = 100
    // (rounding may add a few).
    INFO(r.summary());
    CHECK(*r.iterations <= 110);
    CHECK(r.nonzeros == 598);
    CHECK_FALSE(r.rcond);
    CHECK_THAT(r.summary(),
               Matches("solve u: CG \\+ diagonal, n = 200, 598 nonzeros, \\d+ iterations, "
                       "residual \\d\\.\\de-1\\d, [0-9.e-]+ s"));
  }
  SECTION("incomplete Cholesky, which is exact for a tridiagonal matrix") {
    options.preconditioner = partc::Preconditioner::incomplete_cholesky;
    const partc::SolveResult r = partc::solve_sparse(p.A, p.f, options);
    CHECK(r.method == "CG + IC");
    CHECK(r.converged);
    CHECK(*r.iterations <= 2);
    CHECK((r.x - p.u).lpNorm<Eigen::Infinity>() < 2e-8 * p.u.lpNorm<Eigen::Infinity>());
  }
}

TEST_CASE("solve_sparse: a nonsymmetric convection-diffusion matrix by BiCGSTAB and GMRES",
          "[solve][sparse]") {
  // c h / 2 = 0.05: central differences stay monotone; A is far from symmetric.
  const DifferenceProblem p = convection_diffusion(199, 20.0);
  partc::SparseSolveOptions options;
  options.tolerance = 1e-11;
  const auto check = [&](const partc::SolveResult& r, const std::string& method) {
    INFO(r.summary());
    CHECK(r.method == method);
    CHECK(r.converged);
    CHECK(r.residual <= 1e-11);
    CHECK(r.residual == (p.A * r.x - p.f).norm() / p.f.norm());
    CHECK((r.x - p.u).lpNorm<Eigen::Infinity>() < 1e-7 * p.u.lpNorm<Eigen::Infinity>());
  };
  SECTION("BiCGSTAB, the default") {
    check(partc::solve_sparse(p.A, p.f, options), "BiCGSTAB + diagonal");
  }
  SECTION("GMRES") {
    options.method = partc::KrylovMethod::gmres;
    options.gmres_restart = 50;
    options.max_iterations = 5000;
    check(partc::solve_sparse(p.A, p.f, options), "GMRES(50) + diagonal");
  }
  SECTION("BiCGSTAB with ILUT, which is exact for a tridiagonal matrix") {
    options.preconditioner = partc::Preconditioner::incomplete_lut;
    const partc::SolveResult r = partc::solve_sparse(p.A, p.f, options);
    check(r, "BiCGSTAB + ILUT");
    CHECK(*r.iterations <= 2);
  }
}

TEST_CASE("solve_sparse: GMRES is held to the true residual, not its preconditioned one",
          "[solve][sparse]") {
  // The second half of the rows scaled by 100, and b zero there: the diagonal
  // preconditioner undoes the scaling, so GMRES's own (left-preconditioned)
  // residual weighs all rows alike, while ||A x - b|| / ||b|| weighs the
  // heavy rows 100 times against a b that lives in the light ones.
  DifferenceProblem p = convection_diffusion(49, 20.0);
  VectorXd scale(49);
  for (Index i = 0; i < 49; ++i) {
    scale[i] = i < 24 ? 1.0 : 100.0;
    p.f[i] = i < 24 ? 1.0 : 0.0;
  }
  p.A = scale.asDiagonal() * p.A;
  p.f = scale.asDiagonal() * p.f;
  const double tolerance = 1e-10;

  // The case matters: Eigen's GMRES alone, content, stops well above the tolerance.
  Eigen::GMRES<partc::SparseMatrixCRS, Eigen::DiagonalPreconditioner<double>> eigen_gmres(p.A);
  eigen_gmres.setTolerance(tolerance);
  eigen_gmres.setMaxIterations(1000);
  const VectorXd x_eigen = eigen_gmres.solve(p.f);
  REQUIRE(eigen_gmres.info() == Eigen::Success);
  REQUIRE((p.A * x_eigen - p.f).norm() / p.f.norm() > 10 * tolerance);

  partc::SparseSolveOptions options;
  options.method = partc::KrylovMethod::gmres;
  options.tolerance = tolerance;
  options.max_iterations = 1000;
  const partc::SolveResult r = partc::solve_sparse(p.A, p.f, options);
  INFO(r.summary());
  CHECK(r.converged);
  CHECK((p.A * r.x - p.f).norm() / p.f.norm() <= tolerance);
  CHECK(*r.iterations > eigen_gmres.iterations());  // restarted, and counted
}

TEST_CASE("solve_sparse reports non-convergence instead of returning quietly", "[solve][sparse]") {
  const DifferenceProblem p = convection_diffusion(200, 0.0);
  partc::SparseSolveOptions options;
  options.name = "u";
  options.method = partc::KrylovMethod::cg;
  options.max_iterations = 3;
  const partc::SolveResult r = partc::solve_sparse(p.A, p.f, options);
  CHECK_FALSE(r.converged);
  CHECK(r.iterations == 3);
  CHECK(r.residual == (p.A * r.x - p.f).norm() / p.f.norm());
  CHECK(r.residual > 1e-3);
  CHECK_THAT(r.warning, Matches("solve u: CG \\+ diagonal did not converge: relative residual "
                                "\\d\\.\\de[-+]\\d\\d after 3 iterations \\(limit 3\\), tolerance "
                                "1\\.0e-10"));
  CHECK_THAT(r.summary(), Contains(", NOT CONVERGED after 3 iterations, residual "));
  // What a caller that finds it fatal does: the driver maps it to exit code 3.
  CHECK_THROWS_AS(throw partc::NumericalError(r.warning), partc::NumericalError);
}

TEST_CASE("solve_sparse starts from a guess", "[solve][sparse]") {
  const DifferenceProblem p = convection_diffusion(50, 0.0);
  partc::SparseSolveOptions options;
  options.method = partc::KrylovMethod::cg;
  const partc::SolveResult cold = partc::solve_sparse(p.A, p.f, options);
  const partc::SolveResult warm = partc::solve_sparse(p.A, p.f, options, p.u);
  CHECK(*cold.iterations > 0);
  CHECK(warm.converged);
  CHECK(*warm.iterations == 0);  // the exact discrete solution already meets the tolerance
  CHECK(warm.x == p.u);
}

TEST_CASE("solve_sparse: a preconditioner that cannot be built is reported", "[solve][sparse]") {
  DifferenceProblem p = convection_diffusion(20, 0.0);
  for (partc::SparseMatrixCRS::InnerIterator entry(p.A, 7); entry; ++entry)
    entry.valueRef() = 0.0;  // a zero row, of stored zeros
  partc::SparseSolveOptions options;
  options.name = "u";
  options.preconditioner = partc::Preconditioner::incomplete_lut;
  const partc::SolveResult r = partc::solve_sparse(p.A, p.f, options);
  CHECK_FALSE(r.converged);
  CHECK(r.warning ==
        "solve u: the ILUT preconditioner could not be built from the matrix (a row is zero)");
  CHECK(r.x == VectorXd::Zero(20));
  CHECK(r.residual == 1.0);
}

TEST_CASE("solve_sparse refuses bad input", "[solve][sparse]") {
  DifferenceProblem p = convection_diffusion(10, 0.0);
  partc::SparseSolveOptions options;
  options.name = "u";
  SECTION("CG with ILUT") {
    options.method = partc::KrylovMethod::cg;
    options.preconditioner = partc::Preconditioner::incomplete_lut;
    CHECK_THROWS_WITH(partc::solve_sparse(p.A, p.f, options),
                      "solve u: CG needs a symmetric preconditioner (diagonal or "
                      "incomplete_cholesky), not incomplete_lut");
  }
  SECTION("NaN and Inf, the first row by row") {
    p.A.coeffRef(6, 5) = std::nan("");
    p.A.coeffRef(4, 5) = std::numeric_limits<double>::infinity();
    try {
      (void)partc::solve_sparse(p.A, p.f, options);
      FAIL("no NumericalError");
    } catch (const partc::NumericalError& e) {
      CHECK(std::string(e.what()) ==
            "solve u: the matrix entry at row 4, column 5 (0-based) is inf");
    }
    p.A.coeffRef(4, 5) = 0;
    p.A.coeffRef(6, 5) = 0;
    p.f[9] = std::nan("");
    CHECK_THROWS_WITH(partc::solve_sparse(p.A, p.f, options),
                      "solve u: the right-hand side is nan at row 9 (0-based)");
  }
  SECTION("wrong sizes") {
    CHECK_THROWS_AS(partc::solve_sparse(p.A, VectorXd::Ones(9), options), std::invalid_argument);
    CHECK_THROWS_WITH(partc::solve_sparse(p.A, p.f, options, VectorXd::Zero(3)),
                      "solve u (its guess): the matrix is 10 x 10 and the right-hand side has "
                      "3 entries; a solve needs n x n and n");
  }
}

// ---------------------------------------------------------------- Matrix Market

namespace {

fs::path scratch_directory() {
  struct Directory {
    fs::path path;
    Directory() {
      std::string pattern = (fs::temp_directory_path() / "partc-runtime-solve-XXXXXX").string();
      if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
      path = pattern;
    }
    ~Directory() { fs::remove_all(path); }
  };
  static const Directory directory;
  return directory.path;
}

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The reader: a Matrix Market file as a dense matrix, from its own lines.
struct MatrixMarketFile {
  std::string header;
  std::vector<std::string> comments;
  MatrixXd matrix;
  Index entries = 0;  // coordinate files: the count the size line gives
};

MatrixMarketFile read_matrix_market(const std::string& path) {
  const std::vector<std::string> lines = lines_of(path);
  MatrixMarketFile file;
  REQUIRE(!lines.empty());
  file.header = lines[0];
  std::size_t k = 1;
  while (k < lines.size() && lines[k].rfind('%', 0) == 0) file.comments.push_back(lines[k++]);
  REQUIRE(k < lines.size());
  std::istringstream size_line(lines[k++]);
  Index rows = 0, cols = 0;
  size_line >> rows >> cols;
  const bool coordinate = file.header.find(" coordinate ") != std::string::npos;
  if (coordinate) size_line >> file.entries;
  file.matrix = MatrixXd::Zero(rows, cols);
  const std::regex value("-?\\d\\.\\d{16}e[-+]\\d{2,3}");  // 17 significant digits
  const std::regex entry("(\\d+) (\\d+) (.*)");
  std::vector<double> values;
  for (; k < lines.size(); ++k) {
    INFO("line " << k + 1 << ": " << lines[k]);
    std::smatch match;
    if (coordinate) {
      REQUIRE(std::regex_match(lines[k], match, entry));
      const std::string text = match[3];
      REQUIRE(std::regex_match(text, value));
      const Index i = std::stol(match[1]) - 1, j = std::stol(match[2]) - 1;
      REQUIRE((0 <= i && i < rows && 0 <= j && j < cols));
      file.matrix(i, j) += std::strtod(text.c_str(), nullptr);
      values.push_back(0);
    } else {
      REQUIRE(std::regex_match(lines[k], value));
      values.push_back(std::strtod(lines[k].c_str(), nullptr));
    }
  }
  if (coordinate) {
    CHECK(static_cast<Index>(values.size()) == file.entries);
  } else {
    REQUIRE(static_cast<Index>(values.size()) == rows * cols);
    file.matrix = Eigen::Map<const MatrixXd>(values.data(), rows, cols);  // column by column
  }
  return file;
}

}  // namespace

TEST_CASE("write_matrix_market: a dense matrix as an array, read back exactly",
          "[solve][matrix_market]") {
  MatrixXd A(2, 3);
  A << 0.1, -1.0 / 3, 1e300, -0.0, 4.9e-324, 123456789.125;
  const std::string path = (scratch_directory() / "A.mtx").string();
  partc::write_matrix_market(path, A, "RBF matrix of solve w\nmodel demo");
  const std::vector<std::string> lines = lines_of(path);
  REQUIRE(lines.size() == 10);
  CHECK(lines[0] == "%%MatrixMarket matrix array real general");
  CHECK(lines[1] == "% RBF matrix of solve w");
  CHECK(lines[2] == "% model demo");
  CHECK(lines[3] == "2 3");
  CHECK(lines[4] == "1.0000000000000001e-01");  // column by column
  CHECK(lines[5] == "-0.0000000000000000e+00");
  CHECK(lines[6] == "-3.3333333333333331e-01");
  const MatrixMarketFile file = read_matrix_market(path);
  CHECK(file.matrix == A);
  CHECK_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("write_matrix_market: a vector is one column", "[solve][matrix_market]") {
  const VectorXd f = random_vector(5, 10);
  const std::string path = (scratch_directory() / "f.mtx").string();
  partc::write_matrix_market(path, f);
  const std::vector<std::string> lines = lines_of(path);
  REQUIRE(lines.size() == 7);
  CHECK(lines[0] == "%%MatrixMarket matrix array real general");
  CHECK(lines[1] == "5 1");  // no comment lines without a comment
  CHECK(read_matrix_market(path).matrix == MatrixXd(f));
}

TEST_CASE("write_matrix_market: a sparse matrix as coordinates, read back exactly",
          "[solve][matrix_market]") {
  const DifferenceProblem p = convection_diffusion(6, 3.0);
  partc::SparseMatrixCRS A = p.A;
  A.coeffRef(0, 5) = 1.0 / 7;
  A.coeffRef(5, 0) = 0.0;  // a stored zero is an entry too
  A.makeCompressed();
  const std::string path = (scratch_directory() / "A_sparse.mtx").string();
  partc::write_matrix_market(path, A, "solve u");
  const std::vector<std::string> lines = lines_of(path);
  REQUIRE(lines.size() == 3 + 18);
  CHECK(lines[0] == "%%MatrixMarket matrix coordinate real general");
  CHECK(lines[1] == "% solve u");
  CHECK(lines[2] == "6 6 18");
  CHECK(lines[3].rfind("1 1 ", 0) == 0);  // row by row, 1-based
  CHECK(lines[5] == "1 6 1.4285714285714285e-01");
  CHECK(lines[6].rfind("2 1 ", 0) == 0);
  const MatrixMarketFile file = read_matrix_market(path);
  CHECK(file.entries == 18);
  CHECK(file.matrix == MatrixXd(A));

  // Column-major storage: the same entries, column by column.
  const Eigen::SparseMatrix<double> by_columns = A;
  partc::write_matrix_market(path, by_columns);
  CHECK(read_matrix_market(path).matrix == MatrixXd(A));
  const std::vector<std::string> column_lines = lines_of(path);
  CHECK(column_lines[1] == "6 6 18");  // no comment this time
  CHECK(column_lines[2].rfind("1 1 ", 0) == 0);
  CHECK(column_lines[3].rfind("2 1 ", 0) == 0);
}

TEST_CASE("write_matrix_market leaves nothing behind when it cannot write",
          "[solve][matrix_market]") {
  const std::string path = (scratch_directory() / "no-such-directory" / "A.mtx").string();
  CHECK_THROWS_WITH(partc::write_matrix_market(path, MatrixXd::Identity(2, 2)),
                    "cannot create '" + path + ".tmp': No such file or directory");
  CHECK_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("write_matrix_market writes into a named pipe, not over it", "[solve][matrix_market]") {
  const std::string path = (scratch_directory() / "pipe.mtx").string();
  REQUIRE(mkfifo(path.c_str(), 0600) == 0);
  // A reader that does not block: the writer's open then finds it, and the
  // few bytes fit in the pipe's buffer, so one thread does both ends.
  const int reader = open(path.c_str(), O_RDONLY | O_NONBLOCK);
  REQUIRE(reader >= 0);
  partc::write_matrix_market(path, VectorXd::Ones(2));
  char buffer[256];
  const ssize_t size = read(reader, buffer, sizeof buffer);
  close(reader);
  CHECK(std::string(buffer, size > 0 ? static_cast<std::size_t>(size) : 0) ==
        "%%MatrixMarket matrix array real general\n2 1\n"
        "1.0000000000000000e+00\n1.0000000000000000e+00\n");
  CHECK(fs::is_fifo(path));
  CHECK_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("write_matrix_market writes through a symbolic link, keeping it",
          "[solve][matrix_market]") {
  // As /dev/stdout, a link to /proc/self/fd/1, when the output goes to a file.
  const fs::path target = scratch_directory() / "target.mtx";
  const fs::path link = scratch_directory() / "link.mtx";
  std::ofstream(target) << "old\n";
  fs::create_symlink(target.filename(), link);
  partc::write_matrix_market(link.string(), VectorXd::Ones(1));
  CHECK(fs::is_symlink(link));
  CHECK(lines_of(target.string()) ==
        std::vector<std::string>{"%%MatrixMarket matrix array real general", "1 1",
                                 "1.0000000000000000e+00"});
  CHECK_FALSE(fs::exists(link.string() + ".tmp"));
}

// Dense solves near and past singularity (tests/stability/collocation.part):
// RBF interpolation of exp(x) sin(3x) with multiquadrics and Kansa collocation
// of -u'' = pi^2 sin(pi x) with Gaussians, on the line [0, 1]. References,
// from mpmath at 60 digits (the exact solve of the same systems, written out
// below): the 1-norm condition numbers, and the largest error of the exact
// interpolants against the analytic functions on the evaluation points.
// - cond 2.8e6 (RBF, n = 12, eps = 3) and 3.1e8 (Kansa, n = 16, eps = 4):
//   above the threshold, so dense LU, no warning, the condition estimate
//   reported within a factor 3 of the true one (Higham's estimator is a lower
//   bound on cond, usually within that), and the largest error equal to the
//   exact interpolant's within LU's forward error bound, 10 eps cond max|f|
//   (backward stable LU: relative error <= c eps cond).
// - cond 4.7e22 (RBF, n = 20, eps = 1) and 7.7e42 (Kansa, n = 30, eps = 2):
//   singular to working precision, so the rank-revealing fallback with its
//   warning and numerical rank. No forward bound exists there (eps cond >> 1);
//   what must hold is that the fallback degrades gracefully: residual small
//   and the error against the analytic function within 10x of what was
//   measured (7.5e-7, 1.3e-9), the order of NumPy's LU on the same matrices
//   (2.2e-7, 1.2e-8), where the exact interpolants reach 2.1e-8 and 6e-17.
// - A node given twice (set D, multiquadrics with eps = 3 at 8 distinct nodes):
//   two equal rows and columns, exactly singular, so the fallback with rank 8
//   of 9; the least-norm solution of equal columns splits their weight evenly,
//   and the weights must equal those of the 8 distinct nodes (solved here in
//   long double) within 10 eps cond_1 max|w| of that distinct system.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "collocation.hpp"

namespace {

struct Errors {
  double rbf = 0, kansa = 0, max_f = 0;
};

Errors errors(const Collocation& model) {
  Errors e;
  const auto& G = model.G();
  REQUIRE(G.size() == 101);
  for (std::size_t i = 0; i < G.size(); ++i) {
    const double x = G.positions()[i][0];
    const double f = std::exp(x) * std::sin(3 * x);
    e.max_f = std::max(e.max_f, std::abs(f));
    e.rbf = std::max(e.rbf, std::abs(G.get<Collocation::G_s>()[i] - f));
    e.kansa = std::max(e.kansa, std::abs(G.get<Collocation::G_u>()[i] - std::sin(M_PI * x)));
  }
  return e;
}

// The report line of one solve ("solve w: ...") and its numbers.
struct Line {
  std::string text;
  double rcond = -1, residual = -1;
  long rank = -1;
};

Line line_of(const std::vector<std::string>& report, const std::string& start) {
  Line line;
  for (const std::string& l : report)
    if (l.rfind(start, 0) == 0) line.text = l;
  REQUIRE(!line.text.empty());
  const auto number_after = [&](const std::string& key) {
    const std::size_t at = line.text.find(key);
    return at == std::string::npos ? -1.0 : std::atof(line.text.c_str() + at + key.size());
  };
  line.rcond = number_after(", rcond ");
  line.residual = number_after(", residual ");
  line.rank = static_cast<long>(number_after(", rank "));
  return line;
}

Collocation run(std::int64_t n_r, double eps_r, std::int64_t n_k, double eps_k) {
  Collocation model;
  model.params().n_r = n_r;
  model.params().eps_r = eps_r;
  model.params().n_k = n_k;
  model.params().eps_k = eps_k;
  model.init();
  model.check_finite();
  return model;
}

}  // namespace

TEST_CASE("RBF and Kansa systems with condition 2.8e6 and 3.1e8 are solved by LU, report "
          "their condition, and match the exact interpolants' errors",
          "[stability][solve]") {
  const Collocation model = run(12, 3, 16, 4);
  const auto report = model.solve_report();
  for (const auto& l : report) INFO(l);
  int warnings = 0;  // set D's solve warns; these two must not
  for (const auto& l : report)
    warnings += l.rfind("warning: solve w:", 0) == 0 || l.rfind("warning: solve lambda:", 0) == 0;
  CHECK(warnings == 0);
  const Line w = line_of(report, "solve w: "), lambda = line_of(report, "solve lambda: ");
  CHECK_THAT(w.text, Catch::StartsWith("solve w: dense LU, n = 12, rcond "));
  CHECK_THAT(lambda.text, Catch::StartsWith("solve lambda: dense LU, n = 16, rcond "));
  const double cond_w = 2.7995e6, cond_lambda = 3.0792e8;  // mpmath
  CHECK(w.rcond * cond_w >= 0.9);  // an estimate of 1 / cond from below: rcond >= 1 / cond,
  CHECK(w.rcond * cond_w <= 3);    // printed to 2 digits
  CHECK(lambda.rcond * cond_lambda >= 0.9);
  CHECK(lambda.rcond * cond_lambda <= 3);
  CHECK(w.residual <= 1e-13);
  CHECK(lambda.residual <= 1e-11);
  const Errors e = errors(model);
  const double eps = std::numeric_limits<double>::epsilon();
  INFO("errors: RBF " << e.rbf << ", Kansa " << e.kansa);
  CHECK(std::abs(e.rbf - 3.344028e-3) <= 10 * eps * cond_w * e.max_f + 1e-9);  // + the constant's digits
  CHECK(std::abs(e.kansa - 4.213981e-4) <= 10 * eps * cond_lambda * 1.0 + 1e-10);
}

TEST_CASE("RBF and Kansa systems singular to working precision (cond 4.7e22, 7.7e42) fall "
          "back to the least-norm solve with a warning, and stay accurate",
          "[stability][solve]") {
  const Collocation model = run(20, 1, 30, 2);
  const auto report = model.solve_report();
  for (const auto& l : report) INFO(l);
  const Line w = line_of(report, "solve w: "), lambda = line_of(report, "solve lambda: ");
  for (const Line* l : {&w, &lambda}) {
    INFO(l->text);
    CHECK_THAT(l->text, Catch::Contains("dense least-norm (complete orthogonal decomposition)"));
    CHECK(l->rcond >= 0);
    CHECK(l->rcond < std::numeric_limits<double>::epsilon());
    CHECK(l->rank > 4);  // the flat limit keeps a few directions...
  }
  CHECK(w.rank < 20);  // ... and drops the rest
  CHECK(lambda.rank < 30);
  CHECK(w.residual <= 1e-6);
  CHECK(lambda.residual <= 1e-7);
  const std::string rank_w = "numerical rank " + std::to_string(w.rank) + " of 20, least-norm solution";
  const std::string rank_lambda =
      "numerical rank " + std::to_string(lambda.rank) + " of 30, least-norm solution";
  int warned = 0;
  for (const auto& l : report) {
    if (l.rfind("warning: solve w: the matrix is singular to working precision", 0) == 0) {
      CHECK_THAT(l, Catch::EndsWith(rank_w));
      ++warned;
    }
    if (l.rfind("warning: solve lambda: the matrix is singular to working precision", 0) == 0) {
      CHECK_THAT(l, Catch::EndsWith(rank_lambda));
      ++warned;
    }
  }
  CHECK(warned == 2);
  const Errors e = errors(model);
  INFO("errors: RBF " << e.rbf << ", Kansa " << e.kansa);
  CHECK(e.rbf <= 1e-5);
  CHECK(e.kansa <= 1e-7);
}

namespace {

// Gaussian elimination with partial pivoting in long double: A x = b, and
// the 1-norm condition number from the inverse (columns of A^-1 solved for).
std::vector<long double> solve_long_double(std::vector<std::vector<long double>> A,
                                           std::vector<long double> b) {
  const std::size_t n = b.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(A[r][c]) > std::abs(A[pivot][c])) pivot = r;
    std::swap(A[c], A[pivot]);
    std::swap(b[c], b[pivot]);
    for (std::size_t r = c + 1; r < n; ++r) {
      const long double m = A[r][c] / A[c][c];
      for (std::size_t k = c; k < n; ++k) A[r][k] -= m * A[c][k];
      b[r] -= m * b[c];
    }
  }
  std::vector<long double> x(n);
  for (std::size_t r = n; r-- > 0;) {
    long double s = b[r];
    for (std::size_t k = r + 1; k < n; ++k) s -= A[r][k] * x[k];
    x[r] = s / A[r][r];
  }
  return x;
}

}  // namespace

TEST_CASE("RBF interpolation with a node given twice: the exactly singular system falls back "
          "to the least-norm solve, which splits the node's weight evenly",
          "[stability][solve]") {
  const Collocation model = run(12, 3, 16, 4);  // set D: n_d = 8 nodes, node 3 twice
  const auto report = model.solve_report();
  for (const auto& l : report) INFO(l);
  const Line v = line_of(report, "solve v: ");
  CHECK_THAT(v.text, Catch::Contains("dense least-norm (complete orthogonal decomposition), n = 9"));
  CHECK(v.rank == 8);
  CHECK(v.rcond == 0);  // exactly singular: LU meets an exact zero pivot (the equal rows stay equal)
  bool warned = false;
  for (const auto& l : report)
    warned = warned || (l.rfind("warning: solve v: the matrix is singular to working precision", 0) == 0 &&
                        l.find("(LU's rcond 0.0e+00 < 2.2e-16)") != std::string::npos &&
                        l.find("numerical rank 8 of 9, least-norm solution") != std::string::npos);
  CHECK(warned);
  // Reference: the 8 distinct nodes, solved in long double; cond_1 from its inverse.
  const std::size_t n = 8;
  const long double eps_d = model.params().eps_d;
  std::vector<std::vector<long double>> A(n, std::vector<long double>(n));
  std::vector<long double> f(n);
  for (std::size_t a = 0; a < n; ++a) {
    const long double xa = static_cast<long double>(a) / (n - 1);
    f[a] = std::exp(xa) * std::sin(3 * xa);
    for (std::size_t b = 0; b < n; ++b) {
      const long double r = std::abs(xa - static_cast<long double>(b) / (n - 1));
      A[a][b] = std::sqrt(1 + eps_d * eps_d * r * r);
    }
  }
  const std::vector<long double> want = solve_long_double(A, f);
  long double norm_a = 0, norm_inverse = 0, largest = 0;
  for (std::size_t c = 0; c < n; ++c) {
    std::vector<long double> e(n, 0);
    e[c] = 1;
    const auto column = solve_long_double(A, e);
    long double sa = 0, si = 0;
    for (std::size_t r = 0; r < n; ++r) {
      sa += std::abs(A[r][c]);
      si += std::abs(column[r]);
    }
    norm_a = std::max(norm_a, sa);
    norm_inverse = std::max(norm_inverse, si);
    largest = std::max(largest, std::abs(want[c]));
  }
  const double cond = static_cast<double>(norm_a * norm_inverse);
  const double tolerance = 10 * std::numeric_limits<double>::epsilon() * cond * static_cast<double>(largest);
  const auto got = model.D().get<Collocation::D_v>();
  std::vector<double> by_id(n + 1);
  for (std::size_t i = 0; i < n + 1; ++i) by_id[model.D().ids()[i]] = got[i];
  INFO("cond_1 of the distinct system " << cond << ", tolerance " << tolerance);
  CHECK(cond > 10);
  CHECK(std::abs(by_id[3] - by_id[8]) <= tolerance);  // split evenly
  CHECK(std::abs(by_id[3] + by_id[8] - static_cast<double>(want[3])) <= tolerance);
  for (std::size_t k = 0; k < n; ++k)
    if (k != 3) CHECK(std::abs(by_id[k] - static_cast<double>(want[k])) <= tolerance);
}

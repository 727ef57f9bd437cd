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
  CHECK(report.size() == 2);  // no warnings
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
  REQUIRE(report.size() == 4);  // two summaries, two warnings
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

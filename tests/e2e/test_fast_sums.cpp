// Dense sums partc runs by the fast multipole method (tests/e2e/fast_sums.part),
// against brute-force sums written here: every pair, in long double. The
// measured relative L2 error must be within the schedule's tolerance, and
// not zero to rounding (a direct sum passing itself off as a fast one would
// be); results are bitwise the same for one and two threads; the run's
// accuracy check (--check-accuracy) agrees and reports each sum.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "fast_sums.hpp"
#include "partc/parallel.hpp"

namespace {

using Vec3 = partc::Vec<3>;

// sqrt(sum |got - want|^2 / sum |want|^2) over every target.
template <class Got, class Want>
double relative_l2(const std::vector<Got>& got, const std::vector<Want>& want) {
  long double error = 0, norm = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    if constexpr (std::is_same_v<Got, double>) {
      error += (got[i] - want[i]) * (got[i] - want[i]);
      norm += want[i] * want[i];
    } else {
      for (int d = 0; d < 3; ++d) {
        error += (got[i][d] - want[i][d]) * (got[i][d] - want[i][d]);
        norm += want[i][d] * want[i][d];
      }
    }
  }
  return static_cast<double>(std::sqrt(error / norm));
}

FastSums run(int threads, bool check_accuracy = false) {
  return partc::with_threads(threads, [&] {
    FastSums model;
    model.set_seed(5);
    model.set_check_accuracy(check_accuracy);
    model.init();
    model.step();
    return model;
  });
}

}  // namespace

TEST_CASE("fast sums meet their tolerance against brute force", "[e2e][fast_sum]") {
  const FastSums model = run(2);
  const auto& sources = model.S().positions();
  const auto& targets = model.T().positions();
  const auto& q = model.S().get<FastSums::S_q>();
  const double eps = model.params().eps;
  const std::size_t n = sources.size(), m = targets.size();
  REQUIRE(n == 3000);
  REQUIRE(m == 2000);

  std::vector<long double> phi(n, 0), multiquadric(m, 0), gaussian(m, 0);
  std::vector<std::array<long double, 3>> e(n, {0, 0, 0});
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      long double dx[3], r2 = 0;
      for (int d = 0; d < 3; ++d) {
        dx[d] = static_cast<long double>(sources[j][d]) - sources[i][d];
        r2 += dx[d] * dx[d];
      }
      if (r2 == 0) continue;
      const long double r = std::sqrt(r2);
      phi[i] += q[j] / r;
      for (int d = 0; d < 3; ++d) e[i][d] -= q[j] * dx[d] / (r2 * r);
    }
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      long double r2 = 0;
      for (int d = 0; d < 3; ++d) {
        const long double dx = static_cast<long double>(sources[j][d]) - targets[i][d];
        r2 += dx * dx;
      }
      multiquadric[i] += std::sqrt(1 + eps * eps * r2) * q[j];
      gaussian[i] -= std::exp(-eps * eps * r2) * q[j];
    }

  const double tol_coulomb = model.params().tol_coulomb;
  const double coulomb = relative_l2(model.S().get<FastSums::S_phi>(), phi);
  const double field = relative_l2(model.S().get<FastSums::S_e>(), e);
  const double mq = relative_l2(model.T().get<FastSums::T_multiquadric>(), multiquadric);
  const double gauss = relative_l2(model.T().get<FastSums::T_gaussian>(), gaussian);
  INFO("relative L2: coulomb " << coulomb << ", field " << field << ", multiquadric " << mq
                               << ", gaussian (order 6) " << gauss);
  CHECK(coulomb <= tol_coulomb);
  CHECK(coulomb > tol_coulomb / 1000);
  CHECK(field <= tol_coulomb);
  CHECK(field > tol_coulomb / 1000);
  CHECK(mq <= model.params().tol_multiquadric);
  CHECK(gauss < 1e-4);
  CHECK(gauss > 1e-12);
}

TEST_CASE("fast sums are bitwise the same for one and two threads", "[e2e][fast_sum]") {
  const FastSums one = run(1), two = run(2);
  CHECK(one.S().get<FastSums::S_phi>() == two.S().get<FastSums::S_phi>());
  CHECK(one.S().get<FastSums::S_e>() == two.S().get<FastSums::S_e>());
  CHECK(one.T().get<FastSums::T_multiquadric>() == two.T().get<FastSums::T_multiquadric>());
  CHECK(one.T().get<FastSums::T_gaussian>() == two.T().get<FastSums::T_gaussian>());
}

TEST_CASE("the accuracy check measures every fast sum and reports it", "[e2e][fast_sum]") {
  const FastSums checked = run(2, true);
  const std::vector<std::string> report = checked.fast_sum_report();
  REQUIRE(report.size() == 4);
  for (const std::string& line : report) {
    INFO(line);
    CHECK(line.find("order") != std::string::npos);
    CHECK(line.find("measured") != std::string::npos);
  }
  CHECK(report[0].find("fast_sums.part:39") != std::string::npos);
  CHECK(report[3].find("order 6") != std::string::npos);
  // Checking reads the results only: they are the unchecked run's, bit for bit.
  const FastSums unchecked = run(2);
  CHECK(checked.S().get<FastSums::S_phi>() == unchecked.S().get<FastSums::S_phi>());
  CHECK(unchecked.fast_sum_report()[0].find("measured") == std::string::npos);
}

// A spring beyond its stability limit (tests/stability/spring_limit.part),
// run through the driver as a user runs it. At dt = 1.5 (the limit is
// sqrt(2) = 1.414) the step's amplification matrix has eigenvalues -2 and
// -1/2, so the stretch doubles in size every step and overflows after about
// 1020 steps: the run must stop with exit 3, name the variable, the particle
// and the step, and write the state of the step before, which must match
// the exact recurrence (in long double). At dt = 1.4, just inside the limit,
// the same recurrence stays within its analytic bound for 20000 steps and
// the model follows it.
#include <catch2/catch.hpp>

#include <array>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "partc/driver.hpp"
#include "spring_limit.hpp"

namespace {

// Symplectic Euler for the two particles, as the model writes it, in long
// double: v_i += dt/m * k (x_j - x_i), then x_i += dt v_i.
struct Pair {
  std::array<long double, 2> x{-0.05L, 0.05L}, v{0, 0};
  void step(long double dt) {
    const long double dx0 = x[1] - x[0];
    v[0] += dt * dx0;
    v[1] += dt * -dx0;
    x[0] += dt * v[0];
    x[1] += dt * v[1];
  }
  bool beyond_double() const {
    for (int q = 0; q < 2; ++q)
      if (std::fabs(x[q]) > DBL_MAX || std::fabs(v[q]) > DBL_MAX) return true;
    return false;
  }
};

int run(const std::vector<std::string>& args, std::string& err) {
  std::vector<std::string> words{"spring_limit"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  std::ostringstream out, error;
  const int status = partc::run_driver<SpringLimit>(static_cast<int>(argv.size()), argv.data(),
                                                    out, error);
  err = error.str();
  return status;
}

}  // namespace

TEST_CASE("a spring at 1.06x its stable time step blows up: the driver names variable, "
          "particle and step, and writes the last finite state, which matches the exact "
          "recurrence",
          "[stability][integrator]") {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("partc_spring_limit_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string kept = (dir / "kept.csv").string();
  std::string err;
  REQUIRE(run({"--steps", "5000", "--quiet", "--output", (dir / "final.csv").string(),
               "--last-finite", kept},
              err) == 3);
  INFO(err);
  std::smatch found;
  REQUIRE(std::regex_search(err, found,
                            std::regex("numerical blow-up: variable '(p|v)' of particle id ([01]) "
                                       "is (-?inf|nan) at step ([0-9]+) \\(set P\\)")));
  const long step = std::stol(found[4]);
  CHECK(std::regex_search(err, std::regex("note: the last state found finite, at step " +
                                          std::to_string(step - 1) + ", is in .*kept.csv")));
  CHECK_FALSE(std::filesystem::exists(dir / "final.csv"));

  // The exact recurrence leaves double's range at step n; the model's
  // displacement x_j - x_i (twice |x|) may overflow one step earlier.
  Pair exact;
  long n = 0;
  std::vector<Pair> history{exact};
  while (!exact.beyond_double()) {
    exact.step(1.5L);
    history.push_back(exact);
    ++n;
  }
  CHECK(step >= n - 1);
  CHECK(step <= n);
  CHECK(n > 1000);  // 0.1 * 2^n reaches DBL_MAX

  const partc::CsvTable table = partc::read_csv(kept);
  REQUIRE(table.rows.size() == 2);
  const int id = table.column("id"), p = table.column("p_0"), v = table.column("v_0");
  const Pair& before = history.at(static_cast<std::size_t>(step - 1));
  for (const auto& row : table.rows) {
    const auto q = static_cast<std::size_t>(row[id]);
    CHECK(std::fabs(row[p] - before.x[q]) <= 1e-12L * std::fabs(before.x[q]));
    CHECK(std::fabs(row[v] - before.v[q]) <= 1e-12L * std::fabs(before.v[q]));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("the same spring just inside its limit (dt = 1.4) stays bounded for 20000 steps "
          "and follows the exact recurrence",
          "[stability][integrator]") {
  SpringLimit model;
  model.params().dt = 1.4;
  model.init();
  Pair exact;
  long double largest = 0;
  for (int n = 0; n < 20000; ++n) {
    model.step();
    exact.step(1.4L);
    largest = std::max(largest, std::fabs(exact.x[1] - exact.x[0]));
  }
  CHECK_NOTHROW(model.check_finite());
  // The scheme keeps a quadratic form of (stretch, relative velocity): from
  // rest at stretch r0 the stretch stays within r0 / sqrt(1 - h^2 / 4), with
  // h = dt sqrt(2 k / m) (7.07 r0 here), and comes close to it.
  const long double h2 = 1.4L * 1.4L * 2, bound = 0.1L / std::sqrt(1 - h2 / 4);
  CHECK(largest <= bound * (1 + 1e-12L));
  CHECK(largest >= 0.99L * bound);
  const auto& ids = model.P().ids();
  for (std::size_t i = 0; i < 2; ++i) {
    const auto q = static_cast<std::size_t>(ids[i]);
    const long double got = model.P().positions()[i][0];
    CHECK(std::fabs(got - exact.x[q]) <= 1e-9L * bound);
  }
}

// summation = compensated (tests/e2e/compensated_sum.part): against exact
// integer sums of the same terms. Plain summation in order loses every 1
// against 1e16, and the test shows it does.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include "compensated_sum.hpp"

TEST_CASE("compensated summation keeps the small terms that plain summation loses",
          "[e2e][summation]") {
  CompensatedSum model;
  model.set_seed(5);
  model.init();
  model.step();
  const auto& P = model.P();
  const auto& w = P.get<CompensatedSum::P_w>();
  // Exact sums: every term is an integer of at most 1e16, well inside int64.
  std::int64_t total = 0;
  for (double x : w) total += static_cast<std::int64_t>(x);
  REQUIRE(total == 1000);
  int checked_near = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    CHECK(P.get<CompensatedSum::P_kept>()[i] == 1000.0);
    CHECK(P.get<CompensatedSum::P_plain>()[i] != 1000.0);  // what compensation fixes
    std::int64_t near = 0;
    for (std::size_t j = 0; j < P.size(); ++j)
      if (std::abs(P.positions()[j][0] - P.positions()[i][0]) < 0.3)
        near += static_cast<std::int64_t>(w[j]);
    CHECK(P.get<CompensatedSum::P_near>()[i] == static_cast<double>(near));
    checked_near += std::abs(static_cast<double>(near)) > 1e15;  // 1e16 among the neighbours
  }
  CHECK(checked_near > 100);
}

// Observables (tests/e2e/thermostat.part) against the same reductions
// written out here over the particles' final state, the thermostat's
// promise (the kinetic energy after each step is E), and t = step * dt.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "thermostat.hpp"
#include "reference.hpp"

TEST_CASE("observables: reductions over a set, read by later statements", "[e2e][observables]") {
  Thermostat model;
  model.set_seed(3);
  model.init();
  const auto m = reference::values_by_id<Thermostat::P_m>(model.P());
  const auto v0 = reference::values_by_id<Thermostat::P_v>(model.P());
  double e0 = 0;
  for (std::size_t k = 0; k < m.size(); ++k)
    e0 += 0.5 * m[k] * (v0[k][0] * v0[k][0] + v0[k][1] * v0[k][1]);
  CHECK(model.observables().e_kin == Approx(e0).epsilon(1e-12));
  CHECK(model.observables().e_before == -1);  // its initial value until a step assigns it
  CHECK(model.time() == 0);
  CHECK_FALSE(model.observables().moved);

  const double E = model.params().E;
  for (int k = 0; k < 25; ++k) {
    model.step();
    // The thermostat read e_before, computed by the statement before it.
    CHECK(model.observables().e_kin == Approx(E).epsilon(1e-12));
    CHECK(model.observables().e_before != Approx(E).epsilon(1e-9));
  }
  CHECK(model.step_count() == 25);
  CHECK(model.time() == Approx(25 * model.params().dt).epsilon(1e-14));
  CHECK(model.observables().moved);  // t > 0 during step 25

  const auto v = reference::values_by_id<Thermostat::P_v>(model.P());
  double p[2] = {0, 0}, fastest = 0;
  std::int64_t fast = 0;
  for (std::size_t k = 0; k < m.size(); ++k) {
    p[0] += m[k] * v[k][0];
    p[1] += m[k] * v[k][1];
    const double speed = std::sqrt(v[k][0] * v[k][0] + v[k][1] * v[k][1]);
    fastest = std::max(fastest, speed);
    fast += speed > 1;
  }
  CHECK(model.observables().p_tot[0] == Approx(p[0]).margin(1e-12));
  CHECK(model.observables().p_tot[1] == Approx(p[1]).margin(1e-12));
  CHECK(model.observables().v_max == fastest);
  CHECK(model.observables().n_fast == fast);
  REQUIRE(fast > 0);
  REQUIRE(fast < static_cast<std::int64_t>(m.size()));

  const std::vector<std::string> columns = {"step",    "t",       "e_kin", "p_tot_0",
                                            "p_tot_1", "v_max", "n_fast"};
  CHECK(Thermostat::log_columns() == columns);
  CHECK(model.log_every() == 10);
  const std::vector<double> row = model.log_row();
  REQUIRE(row.size() == columns.size());
  CHECK(row[0] == 25);
  CHECK(row[2] == model.observables().e_kin);
  CHECK(row[6] == static_cast<double>(fast));
}

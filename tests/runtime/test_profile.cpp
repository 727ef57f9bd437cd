#include <catch2/catch.hpp>

#include <chrono>
#include <sstream>
#include <thread>

#include "partc/profile.hpp"

namespace {

partc::Profile lj_coulomb() {
  return partc::Profile({{"step_f", {"lj", "coulomb"}, "", {{0}, {1}}},
                         {"step_v", {"verlet"}, "", {}},
                         {"step_e_kin", {}, "line 30", {}}},
                        {{"sums over A", {"lj", "coulomb"}}, {"sums over B", {"lj"}}});
}

const partc::EffectTime& row(const std::vector<partc::EffectTime>& rows, const std::string& name) {
  for (const partc::EffectTime& r : rows)
    if (r.name == name) return r;
  FAIL("no row " << name);
  return rows.front();
}

}  // namespace

TEST_CASE("profile: a merged kernel is split by the calibration's marginal costs") {
  partc::Profile p = lj_coulomb();
  p.add(p.step_slot(), 0.1);
  p.add(p.kernel_slot(0), 2.0);
  p.add(p.kernel_slot(1), 0.5);
  p.add(p.kernel_slot(2), 0.2);
  p.add(p.search_slot(0), 0.4);
  p.add(p.search_slot(1), 0.3);
  // Whole 1.0; without lj 0.7, without coulomb 0.9: marginals 0.3 and 0.1.
  p.set_calibration(0, {1.0, 0.7, 0.9});
  const std::vector<partc::EffectTime> rows = p.attribute();
  CHECK(row(rows, "lj").seconds == Approx(2.0 * 0.75 + 0.3));
  CHECK(row(rows, "lj").saving == Approx(2.0 * 0.3 + 0.3));  // its own search too
  CHECK(row(rows, "coulomb").seconds == Approx(2.0 * 0.25));
  CHECK(row(rows, "coulomb").saving == Approx(2.0 * 0.1));
  CHECK(row(rows, "verlet").saving == Approx(0.5));
  CHECK(row(rows, "scene, line 30").seconds == Approx(0.2));
  CHECK(row(rows, "search: sums over A").seconds == Approx(0.4));
  CHECK(row(rows, "search: sums over A").saving == 0);
  CHECK(row(rows, "step() outside kernels").seconds == Approx(0.1));
  double sum = 0;
  for (const partc::EffectTime& r : rows) sum += r.seconds;
  CHECK(sum == Approx(p.step_seconds()));
  CHECK(p.step_seconds() == Approx(3.5));
}

TEST_CASE("profile: a fused kernel's reader gets the rest, with no saving claimed") {
  // gravity's and pressure's merged acceleration, computed where verlet's kick reads it.
  partc::Profile p({{"step_v", {"gravity", "pressure", "verlet"}, "", {{0}, {1}}}}, {});
  p.add(p.kernel_slot(0), 2.0);
  // Whole 1.0; without gravity 0.9, without pressure 0.6: the kick is the rest, 0.5.
  p.set_calibration(0, {1.0, 0.9, 0.6});
  const std::vector<partc::EffectTime> rows = p.attribute();
  CHECK(row(rows, "gravity").seconds == Approx(0.2));
  CHECK(row(rows, "gravity").saving == Approx(0.2));
  CHECK(row(rows, "pressure").seconds == Approx(0.8));
  CHECK(row(rows, "pressure").saving == Approx(0.8));
  CHECK(row(rows, "verlet").seconds == Approx(1.0));
  CHECK(row(rows, "verlet").unpredicted == "rest of a fused pass");
  CHECK(row(rows, "gravity").unpredicted.empty());
  // Variants that cost more than the whole (noise) leave no rest: the parts share t.
  p.set_calibration(0, {1.0, 0.4, 0.2});
  const std::vector<partc::EffectTime> noisy = p.attribute();
  CHECK(row(noisy, "verlet").seconds == Approx(0.0));
  CHECK(row(noisy, "gravity").seconds + row(noisy, "pressure").seconds == Approx(2.0));
}

TEST_CASE("profile: a part of several effects left out at once is their joint row") {
  partc::Profile p({{"step_p", {"xsph", "drag", "euler"}, "", {{0, 1}}}}, {});
  p.add(p.kernel_slot(0), 1.0);
  p.set_calibration(0, {1.0, 0.25});
  const std::vector<partc::EffectTime> rows = p.attribute();
  CHECK(row(rows, "xsph+drag").seconds == Approx(0.75));
  CHECK(row(rows, "xsph+drag").unpredicted == "joint: not split");
  CHECK(row(rows, "euler").seconds == Approx(0.25));
}

TEST_CASE("profile: an uncalibrated kernel of several effects is one joint row") {
  partc::Profile p = lj_coulomb();
  p.add(p.kernel_slot(0), 2.0);
  const std::vector<partc::EffectTime> rows = p.attribute();
  CHECK(row(rows, "lj+coulomb").seconds == Approx(2.0));
  CHECK(row(rows, "lj+coulomb").unpredicted == "joint: not split");
  std::ostringstream out;
  p.report(out, 10);
  CHECK_THAT(out.str(), Catch::Contains("joint: not split"));
}

TEST_CASE("profile: a calibration needs the whole and one variant per part left out") {
  partc::Profile p = lj_coulomb();
  int calls = 0;
  auto variant = [&] { ++calls; };
  CHECK_THROWS_AS(p.calibrate(0, 3, {variant, variant}), std::invalid_argument);
  // No minimum time: one call to size the rounds, then each variant once a round.
  p.calibrate(0, 3, {variant, variant, variant}, 0.0);
  CHECK(calls == 1 + 3 * 3);
  p.add(p.kernel_slot(0), 1.0);
  const double before = p.step_seconds();
  p.calibrate(0, 3, {variant, variant, variant}, 0.0);
  CHECK(p.step_seconds() == before);  // calibrating is not stepping
}

TEST_CASE("profile: timers are exclusive, and together they are the step") {
  partc::Profile p = lj_coulomb();
  const auto start = std::chrono::steady_clock::now();
  {
    const partc::ProfileTimer step(p, p.step_slot());
    {
      const partc::ProfileTimer kernel(p, p.kernel_slot(1));
      const partc::ProfileTimer search(p, p.search_slot(0));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  const double outside =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(p.seconds(p.search_slot(0)) >= 0.02);
  CHECK(p.seconds(p.kernel_slot(1)) >= 0);
  CHECK(p.step_seconds() <= outside);
  CHECK(p.step_seconds() >= p.seconds(p.search_slot(0)));
}

TEST_CASE("profile: a part whose search builds at a smaller radius saves the builds' difference") {
  partc::Profile p = lj_coulomb();
  p.add(p.kernel_slot(0), 2.0);
  // Without coulomb the walk is nearer (0.2 of the whole) and each of the
  // run's builds too: 0.05 s over the run; without lj, one more (-0.01).
  p.set_calibration(0, {1.0, 0.7, 0.2});
  p.set_build_saving(0, 1, 0.05);
  p.set_build_saving(0, 0, -0.01);
  const std::vector<partc::EffectTime> rows = p.attribute();
  CHECK(row(rows, "coulomb").saving == Approx(2.0 * 0.8 + 0.05));
  CHECK(row(rows, "lj").saving == Approx(2.0 * 0.3 - 0.01));
  CHECK(row(rows, "coulomb").seconds + row(rows, "lj").seconds == Approx(2.0));  // times unchanged
}

TEST_CASE("profile: calibrate_build counts the run's builds of the search, timed in step()") {
  partc::Profile p = lj_coulomb();
  {
    const partc::ProfileTimer outside_step(p, p.search_slot(0));  // init's build: not counted
  }
  for (int step = 0; step < 3; ++step) {
    const partc::ProfileTimer timer(p, p.step_slot());
    const partc::ProfileTimer build(p, p.search_slot(0));
  }
  CHECK(p.calls(p.search_slot(0)) == 3);
  // A build at the whole radius 2 ms dearer than at the variant's: 3 builds, ~6 ms.
  p.add(p.kernel_slot(0), 1.0);
  p.set_calibration(0, {1.0, 1.0, 1.0});
  p.calibrate_build(0, 1, 0, 3, [] { std::this_thread::sleep_for(std::chrono::milliseconds(2)); },
                    [] {}, 0.0);
  const double saving = row(p.attribute(), "coulomb").saving;
  CHECK(saving >= 3 * 0.002);
  CHECK(saving < 3 * 0.02);  // a loaded machine's sleep overshoots, not tenfold
}

// Float against double storage on the seed model (issue 9): examples/md.part
// compiled twice, with `schedule { precision = double }` (md_double.part) and
// `precision = float` (md_float.part), run from the same initial state (N =
// 1000 points that are floats, v = 0) beside a reference written here, in
// long double, brute force over all pairs. The errors against the reference
// are printed (ctest -V -R stability_precision) and bounded by this model:
//
// - After step 1 each run's error is one rounding of each stored position
//   component (the velocity's is 1e-5 of it): uniform in +-ulp/2, so its RMS
//   is sqrt(sum of ulp^2 / 12) over the components, at the storage's ulp:
//   1.8e-8 for float, 2^-29 of that, 3.4e-17, for double. Checked to 10%.
// - Later steps add one such rounding each, and the dynamics amplify what is
//   there: the seed model at N = 1000 is chaotic, errors grow by e^0.42 a
//   step (8x every 5 steps, in both runs alike). As long as the errors are
//   small the growth is linear in them, so float's error stays 2^29 times
//   double's (the ratio of their ulps, 2^-24 / 2^-53) at every step: checked
//   within a factor 2 up to step 10, where double's is 1e-15 and float's 6e-7.
// - Beyond that float's errors reach the cutoff: the force -exp(-|dx|) jumps
//   to 0 at rc, so a pair within the position error of rc is counted by one
//   run and not by the other, and both particles' velocities then differ by
//   c exp(-rc) ~ 1e-3 (a "cutoff flip"; counted as a velocity error > 1e-4).
//   The table goes on to step 20 to show where that begins (step 15 here).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "md_double.hpp"
#include "md_float.hpp"

namespace {

constexpr int N = 1000;
constexpr int K = 20;       // steps: bounded up to 10, figures beyond
constexpr double c = 1e-3;  // the model's default force strength
using Real = long double;

struct State {
  std::vector<std::array<Real, 2>> p, v;  // by id
};

// The seed model's step, all pairs, in long double.
void reference_step(State& s, Real rc) {
  std::vector<std::array<Real, 2>> force(N, {0, 0});
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      std::array<Real, 2> d{};
      for (int k = 0; k < 2; ++k) {
        d[k] = s.p[j][k] - s.p[i][k];  // both in [0, 1): one shift at most
        if (d[k] > 0.5L) d[k] -= 1;
        if (d[k] < -0.5L) d[k] += 1;
      }
      const Real r = std::sqrt(d[0] * d[0] + d[1] * d[1]);
      if (r < rc && r > 0)
        for (int k = 0; k < 2; ++k) force[i][k] += -std::exp(-r) * d[k] / r;
    }
  for (int i = 0; i < N; ++i)
    for (int k = 0; k < 2; ++k) {
      s.v[i][k] += static_cast<Real>(c) * force[i][k];
      s.p[i][k] += s.v[i][k];
      s.p[i][k] -= std::floor(s.p[i][k]);
    }
}

struct Errors {
  double rms_p = 0, max_p = 0, rms_v = 0, max_v = 0;
  int flipped = 0;  // particles with a velocity error of a cutoff flip's size
};

// Errors of a model's set against the reference, by id; positions by minimum image.
template <class Set, class Velocities>
Errors errors_of(const Set& set, const Velocities& velocities, const State& ref) {
  Errors e;
  double sum_p = 0, sum_v = 0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    const auto id = static_cast<std::size_t>(set.ids()[i]);
    const auto p = partc::widen(set.positions()[i]);
    const auto v = partc::widen(velocities[i]);
    double dp2 = 0, dv2 = 0;
    for (int k = 0; k < 2; ++k) {
      Real d = static_cast<Real>(p[k]) - ref.p[id][k];
      d -= std::round(d);
      dp2 += static_cast<double>(d * d);
      const Real dv = static_cast<Real>(v[k]) - ref.v[id][k];
      dv2 += static_cast<double>(dv * dv);
    }
    sum_p += dp2;
    sum_v += dv2;
    e.max_p = std::max(e.max_p, std::sqrt(dp2));
    e.max_v = std::max(e.max_v, std::sqrt(dv2));
    if (std::sqrt(dv2) > 1e-4) ++e.flipped;
  }
  e.rms_p = std::sqrt(sum_p / N);
  e.rms_v = std::sqrt(sum_v / N);
  return e;
}

}  // namespace

// RMS of one rounding of every position component to T: ulp / sqrt(12) each.
template <class T>
double rounding_rms(const State& s) {
  double sum = 0;
  for (const auto& p : s.p)
    for (const Real x : p) {
      const T t = static_cast<T>(x);
      const double ulp = static_cast<double>(std::nextafter(t, T(2)) - t);
      sum += ulp * ulp / 12;
    }
  return std::sqrt(sum / N);
}

TEST_CASE("float storage of the seed model: error against long double, beside double's",
          "[stability][precision]") {
  // The initial state: floats, so both storages hold it exactly.
  partc::CsvTable table;
  table.path = "(initial state)";
  table.header = {"id", "p_0", "p_1"};
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  State ref;
  for (int i = 0; i < N; ++i) {
    const double x = partc::round_inside<float>(u(rng), 0, 1);
    const double y = partc::round_inside<float>(u(rng), 0, 1);
    table.rows.push_back({static_cast<double>(i), x, y});
    table.lines.push_back(static_cast<std::size_t>(i) + 2);
    ref.p.push_back({x, y});
    ref.v.push_back({0, 0});
  }
  MdDouble wide;
  MdFloat single;
  wide.set_param("N", std::to_string(N));
  single.set_param("N", std::to_string(N));
  wide.load({{"P", table}});
  single.load({{"P", table}});
  const Real rc = std::sqrt(3.0 / N);  // as the models compute it

  std::printf(
      "md, N = %d, c = %g, from the same float state: error against long double\n"
      "(p in box lengths; float/double: the ratio of their rms p errors, 2^29 = %.3g)\n",
      N, c, 0x1p29);
  std::printf("%4s | %9s %9s %9s %9s | %9s %9s %9s %9s %7s | %12s\n", "step", "double", "", "", "",
              "float", "", "", "", "", "float/double");
  std::printf("%4s | %9s %9s %9s %9s | %9s %9s %9s %9s %7s |\n", "", "rms p", "max p", "rms v",
              "max v", "rms p", "max p", "rms v", "max v", "flipped");
  for (int step = 1; step <= K; ++step) {
    wide.step();
    single.step();
    reference_step(ref, rc);
    const Errors d = errors_of(wide.P(), wide.P().get<MdDouble::P_v>(), ref);
    const Errors f = errors_of(single.P(), single.P().get<MdFloat::P_v>(), ref);
    const double ratio = f.rms_p / d.rms_p;
    if (step <= 2 || step % 5 == 0)
      std::printf("%4d | %9.2e %9.2e %9.2e %9.2e | %9.2e %9.2e %9.2e %9.2e %7d | %12.3g\n", step,
                  d.rms_p, d.max_p, d.rms_v, d.max_v, f.rms_p, f.max_p, f.rms_v, f.max_v, f.flipped,
                  ratio);
    INFO("step " << step << ": double rms p " << d.rms_p << ", float rms p " << f.rms_p);
    if (step == 1) {
      const double float_rounding = rounding_rms<float>(ref),
                   double_rounding = rounding_rms<double>(ref);
      std::printf("     | one rounding %9.2e %29s one rounding %9.2e\n", double_rounding, "",
                  float_rounding);
      CHECK(d.rms_p == Approx(double_rounding).epsilon(0.1));
      CHECK(f.rms_p == Approx(float_rounding).epsilon(0.1));
    }
    if (step > 10) continue;  // past the linear regime: figures only
    CHECK(ratio > 0x1p28);
    CHECK(ratio < 0x1p30);
    CHECK(f.flipped == 0);
    CHECK(d.rms_p < 1e-14);
    CHECK(d.max_p < 1e-13);
    CHECK(f.rms_p < 1e-5);
  }
}

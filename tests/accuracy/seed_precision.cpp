// seed_precision: Figure 7's seed half (examples/accuracy/precision.py, bash
// .ci/figures precision): what each precision choice of the schedule costs
// and buys on the seed velocity update
//
//   v[i] += c * sum(j, |dx| < rc and |dx| > 0, -exp(-|dx|) * dx / |dx|),  rc = sqrt(3 / N)
//
// as partc emits it (tests/bench/md_velocity.part.in) four times: double;
// `precision = float` (positions and v stored as float, computed in double);
// `arithmetic = float` (the pair terms on float lanes, added into double
// sums); and both. On the same uniform points of the periodic unit square
// (doubles), one thread, positions fixed. Per N and choice:
//   update_s      the time of one update: median of --repeats timings of
//                 floor(3e6 / N) + 1 updates, the choices interleaved;
//   rms_error     v's increment after one update from v = 0 against the long
//                 double reference on the points as given (seed_reference.hpp),
//                 relative L2; max_error: the largest point's error relative
//                 to the largest increment. Float storage rounds the points
//                 to floats when they are loaded, so its error holds what that
//                 rounding moves the force, as it would in a run;
//   rms_stored    the same against the reference on the points as the build
//                 stores them: the update's own error, without the positions'
//                 rounding (equal to rms_error for double storage);
//   cutoff_flips  the points whose increment is off the given points'
//                 reference by more than half a term at the cutoff, c exp(-rc)
//                 / 2: a pair the rounded positions moved across rc, counted
//                 by one and not the other (every other error is 1e-5 of it).
//
// Usage: seed_precision [--n 10000,100000,1000000] [--repeats 5] [--csv FILE]
// prints a table; --csv writes its rows (n, schedule, rms_error, max_error,
// rms_stored, cutoff_flips, update_s) for precision.py, which adds the threads and commit.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "partc/parallel.hpp"
#include "partc/vec.hpp"
#include "seed_model.hpp"
#include "seed_points.hpp"
#include "seed_precision_double.hpp"
#include "seed_precision_float_arithmetic.hpp"
#include "seed_precision_float_both.hpp"
#include "seed_precision_float_storage.hpp"
#include "seed_reference.hpp"
#include "size_list.hpp"
#include "timing.hpp"

namespace {

using Vec2 = partc::Vec<2>;
constexpr double force_strength = 1e-3;  // c

// One build under measurement: its schedule as the figure names it, and what
// it measured.
struct Choice {
  const char* schedule = "";
  std::function<void()> step;
  std::vector<Vec2> increment, stored_points;
  bench::SeedErrors given, stored;
  std::size_t cutoff_flips = 0;
  std::vector<double> seconds;
};

// Positions by id, widened to double whatever their storage.
template <class Model>
std::vector<Vec2> stored_points(const Model& model) {
  const auto& set = model.P();
  std::vector<Vec2> by_id(set.size());
  for (std::size_t k = 0; k < set.size(); ++k)
    by_id[static_cast<std::size_t>(set.ids()[k])] = partc::widen(set.positions()[k]);
  return by_id;
}

// The points whose increment is off the reference by more than half a term.
std::size_t count_flips(const std::vector<Vec2>& increment,
                        const std::vector<std::array<long double, 2>>& reference, double term) {
  std::size_t flips = 0;
  for (std::size_t i = 0; i < increment.size(); ++i) {
    const long double e0 = increment[i][0] - reference[i][0],
                      e1 = increment[i][1] - reference[i][1];
    if (std::sqrt(e0 * e0 + e1 * e1) > term / 2) ++flips;
  }
  return flips;
}

template <class Model>
Choice measured(const char* schedule, Model& model, const std::vector<Vec2>& points, double rc) {
  bench::load_seed_points(model, points, rc, force_strength);
  // One update from v = 0 (v then holds the increment), before any timing;
  // it builds the model's search too.
  model.step();
  Choice choice;
  choice.schedule = schedule;
  choice.step = [&model] { model.step(); };
  choice.increment = bench::seed_velocities(model);
  choice.stored_points = stored_points(model);
  return choice;
}

int run(const std::vector<std::size_t>& sizes, int repeats, const std::string& csv_path) {
  std::FILE* csv = nullptr;
  if (!csv_path.empty()) {
    csv = std::fopen(csv_path.c_str(), "w");
    if (!csv) {
      std::fprintf(stderr, "seed_precision: cannot write %s\n", csv_path.c_str());
      return 3;
    }
    std::fprintf(csv, "n,schedule,rms_error,max_error,rms_stored,cutoff_flips,update_s\n");
  }
  std::printf(
      "seed velocity update as partc emits it, one thread; times in s per update (medians of "
      "%d);\nerrors of v's increment against long double, on the points as given (rms, max) "
      "and as stored\n",
      repeats);
  std::printf("%9s  %-38s %10s %10s %10s %6s %10s\n", "N", "schedule", "rms", "max", "rms stored",
              "flips", "update_s");
  for (const std::size_t n : sizes) {
    const double rc = std::sqrt(3.0 / static_cast<double>(n));
    const std::vector<Vec2> points = bench::uniform_points(n);
    std::tuple<SeedPrecisionDouble, SeedPrecisionFloatStorage, SeedPrecisionFloatArithmetic,
               SeedPrecisionFloatBoth>
        models;
    std::vector<Choice> choices;
    choices.push_back(measured("double", std::get<0>(models), points, rc));
    choices.push_back(measured("precision = float", std::get<1>(models), points, rc));
    choices.push_back(measured("arithmetic = float", std::get<2>(models), points, rc));
    choices.push_back(
        measured("precision = float, arithmetic = float", std::get<3>(models), points, rc));

    const auto given = bench::seed_reference(points, rc, force_strength);
    // Float storage holds other points than those given; both its builds the same ones.
    std::vector<Vec2> rounded;
    std::vector<std::array<long double, 2>> on_rounded;
    for (Choice& choice : choices) {
      choice.given = bench::seed_errors(choice.increment, given);
      choice.cutoff_flips = count_flips(choice.increment, given, force_strength * std::exp(-rc));
      if (choice.stored_points == points) {
        choice.stored = choice.given;
        continue;
      }
      if (choice.stored_points != rounded) {
        rounded = choice.stored_points;
        on_rounded = bench::seed_reference(rounded, rc, force_strength);
      }
      choice.stored = bench::seed_errors(choice.increment, on_rounded);
    }

    // About 3e6 point updates a timing (0.1 to 0.2 s here): long enough to
    // average over the scheduler's slices when other jobs share the cores.
    const int per_timing = static_cast<int>(3000000 / n) + 1;
    for (int r = 0; r < repeats; ++r)
      for (Choice& choice : choices)
        choice.seconds.push_back(bench::seconds(choice.step, per_timing) / per_timing);
    for (const Choice& choice : choices) {
      const double t = bench::median(choice.seconds);
      std::printf("%9zu  %-38s %10.3e %10.3e %10.3e %6zu %10.3e\n", n, choice.schedule,
                  choice.given.relative_l2, choice.given.relative_max, choice.stored.relative_l2,
                  choice.cutoff_flips, t);
      if (csv)
        std::fprintf(csv, "%zu,\"%s\",%.6e,%.6e,%.6e,%zu,%.6e\n", n, choice.schedule,
                     choice.given.relative_l2, choice.given.relative_max, choice.stored.relative_l2,
                     choice.cutoff_flips, t);
    }
  }
  if (csv) std::fclose(csv);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes = {10000, 100000, 1000000};
  int repeats = 5;
  std::string csv;
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string flag = argv[a];
    if (flag == "--n") {
      sizes = bench::parse_sizes(argv[a + 1]);
    } else if (flag == "--repeats") {
      repeats = std::atoi(argv[a + 1]);
    } else if (flag == "--csv") {
      csv = argv[a + 1];
    } else {
      std::fprintf(stderr,
                   "usage: seed_precision [--n 10000,100000,1000000] [--repeats 5] [--csv FILE]\n");
      return 2;
    }
  }
  if (argc % 2 == 0) {
    std::fprintf(stderr, "seed_precision: %s needs a value\n", argv[argc - 1]);
    return 2;
  }
  if (repeats < 1) repeats = 1;
  return partc::with_threads(1, [&] { return run(sizes, repeats, csv); });
}

// bench_two_cutoffs: two neighbour sums over one set at cutoffs rc and k rc
// (two_cutoffs.part.in), a density at rc and a force at k rc, with one search
// shared at k rc (sharing = shared), with a search apart for each radius
// (sharing = separate), and as the compiler's cost model chooses (auto);
// k = 1, 1.25, 1.5, 2, 3, in 2D and 3D, N = 1e4 and 1e5 uniform points in the
// periodic unit box, rc giving `target_neighbours` neighbours within rc.
//
// Each evaluation moves the set (p[i] = p[i]), so it builds its searches
// anew, as a step does: times include builds. A time is the median of
// `repetitions` batches, each after an untimed one, the three variants taking
// turns. Columns: the times, auto's choice (shared when its set has one
// search), auto over the faster forced variant, and the builds per evaluation
// of the shared search (one per position change).
//
// Usage: bench_two_cutoffs [--quick] (--quick: N = 1e4 only; see .ci/bench).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "timing.hpp"
#include "two_cutoffs_2d_k1.hpp"
#include "two_cutoffs_2d_k1_25.hpp"
#include "two_cutoffs_2d_k1_5.hpp"
#include "two_cutoffs_2d_k2.hpp"
#include "two_cutoffs_2d_k3.hpp"
#include "two_cutoffs_3d_k1.hpp"
#include "two_cutoffs_3d_k1_25.hpp"
#include "two_cutoffs_3d_k1_5.hpp"
#include "two_cutoffs_3d_k2.hpp"
#include "two_cutoffs_3d_k3.hpp"

namespace {

constexpr double target_neighbours = 30.0;
constexpr int repetitions = 5;
constexpr double min_batch_seconds = 0.1;

// Calls of f that last at least min_batch_seconds.
template <class F>
int calls_per_batch(F&& f) {
  int calls = 1;
  while (bench::seconds(f, calls) < min_batch_seconds) calls *= 2;
  return calls;
}

template <class Model>
std::size_t searches_of(const Model& model, const std::string& set) {
  std::size_t n = 0;
  for (const auto& s : model.search_report()) n += s.serves.rfind("sums over " + set, 0) == 0;
  return n;
}

template <class Model>
void row(int dim, double k, std::int64_t n) {
  Model model;
  model.params().N = n;
  // N times the volume of a ball of radius rc = target_neighbours.
  const double ball = dim == 2 ? M_PI : 4.0 / 3.0 * M_PI;
  model.params().rc = std::pow(target_neighbours / (ball * static_cast<double>(n)), 1.0 / dim);
  model.set_seed(1);
  model.init();
  std::size_t shared_calls = 0;
  const std::function<void()> variants[] = {[&] { model.shared_sums(), ++shared_calls; },
                                            [&] { model.separate_sums(); },
                                            [&] { model.auto_sums(); }};
  const int calls = calls_per_batch(variants[0]);
  std::vector<double> times[3];
  for (int r = 0; r < repetitions; ++r)
    for (int v = 0; v < 3; ++v) {
      variants[v]();  // untimed
      times[v].push_back(bench::seconds(variants[v], calls) / calls);
    }
  std::size_t builds = 0;
  for (const auto& s : model.search_report())
    if (s.serves.rfind("sums over S", 0) == 0) builds += s.builds;
  const double shared = bench::median(times[0]), separate = bench::median(times[1]),
               automatic = bench::median(times[2]);
  std::printf("%3d %7lld %5.2f %11.3f %11.3f %11.3f %9s %8.3f %8.2f\n", dim,
              static_cast<long long>(n), k, 1e3 * shared, 1e3 * separate, 1e3 * automatic,
              searches_of(model, "U") == 1 ? "shared" : "separate",
              automatic / std::min(shared, separate),
              static_cast<double>(builds) / static_cast<double>(shared_calls));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  if (argc > 1 && !quick) {
    std::fprintf(stderr, "usage: bench_two_cutoffs [--quick]\n");
    return 2;
  }
  std::printf(
      "two sums over one set at rc and k rc (%g neighbours within rc), ms per evaluation "
      "with its builds; median of %d batches\n",
      target_neighbours, repetitions);
  std::printf(
      "dim       N     k      shared    separate        auto    auto's  auto/best  "
      "builds/eval (shared)\n");
  for (const std::int64_t n :
       quick ? std::vector<std::int64_t>{10000} : std::vector<std::int64_t>{10000, 100000}) {
    row<TwoCutoffs2dK1>(2, 1, n);
    row<TwoCutoffs2dK125>(2, 1.25, n);
    row<TwoCutoffs2dK15>(2, 1.5, n);
    row<TwoCutoffs2dK2>(2, 2, n);
    row<TwoCutoffs2dK3>(2, 3, n);
    row<TwoCutoffs3dK1>(3, 1, n);
    row<TwoCutoffs3dK125>(3, 1.25, n);
    row<TwoCutoffs3dK15>(3, 1.5, n);
    row<TwoCutoffs3dK2>(3, 2, n);
    row<TwoCutoffs3dK3>(3, 3, n);
  }
}

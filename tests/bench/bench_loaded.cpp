// bench_loaded: partc's threads on an idle machine and on a loaded one. Each
// workload runs with 1 and 2 threads (partc::with_threads) while 0, 1 or 2
// busy loops run beside it: child processes that this benchmark starts,
// that spin on nothing, and that it always stops (they also stop themselves
// after `busy_loop_seconds`, and die with the benchmark). On a 2-core machine
// one busy loop is "another job keeps the other core busy", the case that
// made OpenMP's spinning barrier collapse (a DEM model: 71 s on 2 threads, 0.48 s
// on one); two busy loops leave no core free at all.
//
// - md (examples/md.part, the whole step: the cell list rebuilt, the force
//   pair walk in two phases of slabs, the particle loops) at N = 500 and
//   2000, where a step is tens to hundreds of microseconds: the parallel
//   loops are short and frequent, and what they cost around the work shows.
// - DEM grains (dem_grains.part: two pair walks a step) at N = 3000.
// - Fork-join alone: a parallel loop over 2048 iterations of a few
//   nanoseconds' arithmetic, through partc::parallel_for and through the
//   plain OpenMP parallel for that parallel_for was before; per loop.
// Times are per step (per loop), medians of `repetitions` runs that take
// turns (every condition once, then again), from the same start. The final
// state of every run is compared with the first 1-thread idle run's, bit for
// bit, and the answer printed.
//
// Usage: bench_loaded (no arguments; see .ci/bench). Needs OpenMP and 2 cores.
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

// Generated headers have no include guard: each is included exactly once.
#include "dem_grains.hpp"
#include "md.hpp"
#include "partc/parallel.hpp"
#include "timing.hpp"

namespace {

constexpr int repetitions = 5;
constexpr int thread_counts[] = {1, 2};
constexpr int busy_counts[] = {0, 1, 2};
constexpr unsigned busy_loop_seconds = 60;  // a busy loop's own bound (alarm)

// `count` processes that spin until the object goes away.
class BusyLoops {
 public:
  explicit BusyLoops(int count) {
    for (int k = 0; k < count; ++k) {
      const pid_t pid = fork();
      if (pid == 0) {  // the child: async-signal-safe calls only, then spin
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        alarm(busy_loop_seconds);
        volatile unsigned long spins = 0;
        for (;;) spins = spins + 1;
      }
      if (pid > 0) pids_.push_back(pid);
    }
    // Let them get going (and the scheduler spread them) before timing starts.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ~BusyLoops() {
    for (const pid_t pid : pids_) kill(pid, SIGKILL);
    for (const pid_t pid : pids_) waitpid(pid, nullptr, 0);
  }
  BusyLoops(const BusyLoops&) = delete;
  BusyLoops& operator=(const BusyLoops&) = delete;

 private:
  std::vector<pid_t> pids_;
};

// The bits of a set's positions and variables, in id order.
template <class Set>
std::vector<unsigned char> state_bits(const Set& set) {
  std::vector<std::size_t> order(set.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  const auto& id = set.ids();
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
  std::vector<unsigned char> bits;
  const auto append = [&](const auto& values) {
    for (const std::size_t k : order) {
      const auto* first = reinterpret_cast<const unsigned char*>(&values[k]);
      bits.insert(bits.end(), first, first + sizeof values[k]);
    }
  };
  append(set.positions());
  set.for_each_variable([&](const char*, const auto& values) { append(values); });
  return bits;
}

struct Figures {
  std::vector<double> seconds[std::size(busy_counts)][std::size(thread_counts)];
  bool identical = true;
};

// Every condition `repetitions` times, taking turns; run(threads) returns the
// time per unit of work and leaves the final state in `bits` (empty: none).
template <class Run>
Figures measure(Run&& run) {
  Figures figures;
  std::vector<unsigned char> first, bits;
  for (int r = 0; r < repetitions; ++r)
    for (std::size_t b = 0; b < std::size(busy_counts); ++b) {
      const BusyLoops busy(busy_counts[b]);
      for (std::size_t t = 0; t < std::size(thread_counts); ++t) {
        figures.seconds[b][t].push_back(
            partc::with_threads(thread_counts[t], [&] { return run(bits); }));
        if (first.empty()) first = bits;
        figures.identical = figures.identical && bits == first;
      }
    }
  return figures;
}

void print_header() {
  std::printf("%-34s %6s", "per step (loop) / us", "N");
  for (const int busy : busy_counts)
    std::printf(" | %d busy: %8s %8s %6s", busy, "1 thr", "2 thr", "1/2");
  std::printf("\n");
}

void print_row(const std::string& label, std::size_t n, const Figures& figures, bool compared) {
  std::printf("%-34s %6zu", label.c_str(), n);
  for (std::size_t b = 0; b < std::size(busy_counts); ++b) {
    const double one = bench::median(figures.seconds[b][0]);
    const double two = bench::median(figures.seconds[b][1]);
    std::printf(" | %6s  %8.1f %8.1f %6.2f", "", one * 1e6, two * 1e6, one / two);
  }
  std::printf("%s\n", compared ? (figures.identical ? "  bitwise same" : "  DIFFERENT") : "");
}

// A generated model: `steps` steps after one to build its searches.
template <class Model, class GetSet>
void model_row(const char* label, std::size_t n, int steps, GetSet&& get_set) {
  const Figures figures = measure([&](std::vector<unsigned char>& bits) {
    Model model;
    model.params().N = static_cast<std::int64_t>(n);
    model.set_seed(3);
    model.init();
    model.step();
    const double t = bench::seconds([&] { model.step(); }, steps) / steps;
    bits = state_bits(get_set(model));
    return t;
  });
  print_row(label, n, figures, true);
}

// Fork-join alone: `loops` loops over n iterations of a little arithmetic.
constexpr std::size_t fork_join_n = 2048;
double work_of(std::size_t i) { return std::sqrt(static_cast<double>(i) + 0.5); }

void fork_join_rows() {
  std::vector<double> out(fork_join_n);
  const int loops = 2000;
  const Figures partc_loop = measure([&](std::vector<unsigned char>& bits) {
    bits.clear();
    return bench::seconds(
               [&] {
                 partc::parallel_for(fork_join_n, partc::LoopWork::heavy,
                                     [&](std::size_t i) { out[i] += work_of(i); });
               },
               loops) /
           loops;
  });
  print_row("fork-join: partc::parallel_for", fork_join_n, partc_loop, false);
#if defined(_OPENMP)
  // Fewer loops, and no more than a second of them: on a loaded machine
  // each can take milliseconds.
  const int omp_loops = 200;
  const auto count = static_cast<long long>(fork_join_n);
  const Figures omp_loop = measure([&](std::vector<unsigned char>& bits) {
    bits.clear();
    const auto start = std::chrono::steady_clock::now();
    int done = 0;
    std::chrono::duration<double> elapsed{};
    while (done < omp_loops && elapsed.count() < 1.0) {
#pragma omp parallel for schedule(static)
      for (long long i = 0; i < count; ++i)
        out[static_cast<std::size_t>(i)] += work_of(static_cast<std::size_t>(i));
      ++done;
      elapsed = std::chrono::steady_clock::now() - start;
    }
    return elapsed.count() / done;
  });
  print_row("fork-join: omp parallel for", fork_join_n, omp_loop, false);
#endif
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

}  // namespace

int main() {
#if defined(_OPENMP)
  std::printf("1 vs 2 threads beside 0, 1 and 2 busy loops (%d processors). Compiler: %s\n",
              omp_get_num_procs(), __VERSION__);
#else
  std::printf("Built without OpenMP: both thread columns are one thread. Compiler: %s\n",
              __VERSION__);
#endif
  std::printf("Load average before (1, 5, 15 min): %s\n\n", load_average().c_str());
  print_header();
  model_row<Md>(
      "md (examples/md.part)", 500, 2000, [](const Md& m) -> const auto& { return m.P(); });
  model_row<Md>(
      "md (examples/md.part)", 2000, 500, [](const Md& m) -> const auto& { return m.P(); });
  model_row<DemGrains>(
      "DEM grains (dem_grains.part)", 3000, 300,
      [](const DemGrains& m) -> const auto& { return m.G(); });
  fork_join_rows();
  std::printf("\nLoad average after: %s\n", load_average().c_str());
}

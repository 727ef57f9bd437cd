// partc::parallel_for on partc's own threads (thread_pool.hpp): every
// iteration exactly once, for any thread count and loop kind; loops inside
// loops, loops from several threads at once, exceptions, and a forked child
// (whose copy of the parent's pool has no threads) all still run every
// iteration. No timings here: see tests/bench/bench_loaded for those.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "partc/parallel.hpp"

namespace {

using partc::LoopWork;

// How often parallel_for(n, work) ran each index, with `threads` threads.
std::vector<int> visits(std::size_t n, LoopWork work, int threads) {
  std::vector<std::atomic<int>> count(n);
  partc::with_threads(threads, [&] {
    partc::parallel_for(n, work, [&](std::size_t i) { count[i].fetch_add(1); });
    return 0;
  });
  std::vector<int> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = count[i].load();
  return out;
}

bool each_once(const std::vector<int>& v) {
  for (const int c : v)
    if (c != 1) return false;
  return true;
}

}  // namespace

TEST_CASE("parallel_for runs every iteration once", "[runtime][threads]") {
  for (const LoopWork work : {LoopWork::light, LoopWork::heavy, LoopWork::blocks})
    for (const int threads : {1, 2, 3, 5})
      for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{255},
                                  std::size_t{256}, std::size_t{257}, std::size_t{1000},
                                  std::size_t{8191}, std::size_t{8192}, std::size_t{100003}}) {
        INFO("work " << static_cast<int>(work) << ", " << threads << " threads, n = " << n);
        CHECK(each_once(visits(n, work, threads)));
      }
}

TEST_CASE("chunk counts: one per block task, a few per thread otherwise", "[runtime][threads]") {
  using partc::detail::chunk_count;
  CHECK(chunk_count(7, LoopWork::blocks, 2) == 7);
  CHECK(chunk_count(1, LoopWork::heavy, 2) == 1);
  CHECK(chunk_count(256, LoopWork::heavy, 2) == 256 / partc::detail::min_chunk(LoopWork::heavy));
  CHECK(chunk_count(1000000, LoopWork::light, 2) == 2 * partc::detail::chunks_per_thread);
  CHECK(chunk_count(8192, LoopWork::light, 4) == 8192 / partc::detail::min_chunk(LoopWork::light));
}

#if defined(_OPENMP)
TEST_CASE("parallel_for uses at most the threads asked for", "[runtime][threads]") {
  for (const int threads : {1, 2, 3}) {
    std::mutex mutex;
    std::set<std::thread::id> seen;
    partc::with_threads(threads, [&] {
      // Enough work a chunk that a worker has time to join.
      partc::parallel_for(4096, LoopWork::heavy, [&](std::size_t) {
        std::lock_guard<std::mutex> lock(mutex);
        seen.insert(std::this_thread::get_id());
      });
      return 0;
    });
    CHECK(seen.size() >= 1);
    CHECK(seen.size() <= static_cast<std::size_t>(threads));
    if (threads == 1) CHECK(seen.count(std::this_thread::get_id()) == 1);
  }
}

TEST_CASE("a loop in a loop runs, serially", "[runtime][threads]") {
  std::vector<std::atomic<int>> count(64 * 512);
  partc::with_threads(2, [&] {
    partc::parallel_for(64, LoopWork::blocks, [&](std::size_t a) {
      partc::parallel_for(512, LoopWork::heavy,
                          [&](std::size_t b) { count[a * 512 + b].fetch_add(1); });
    });
    return 0;
  });
  for (const auto& c : count) REQUIRE(c.load() == 1);
}

TEST_CASE("loops from two threads at once both run every iteration", "[runtime][threads]") {
  const std::size_t n = 20000;
  std::vector<std::vector<int>> results(2);
  std::vector<std::thread> callers;
  for (int t = 0; t < 2; ++t)
    callers.emplace_back([&, t] {
      for (int round = 0; round < 20; ++round) {
        const std::vector<int> v = visits(n, round % 2 ? LoopWork::light : LoopWork::heavy, 2);
        if (!each_once(v)) results[t] = v;
      }
    });
  for (auto& c : callers) c.join();
  CHECK(results[0].empty());
  CHECK(results[1].empty());
}

TEST_CASE("an exception in the body reaches the caller; the pool goes on", "[runtime][threads]") {
  partc::with_threads(2, [&] {
    CHECK_THROWS_AS(partc::parallel_for(100000, LoopWork::light,
                                        [&](std::size_t i) {
                                          if (i == 77777) throw std::runtime_error("body");
                                        }),
                    std::runtime_error);
    return 0;
  });
  CHECK(each_once(visits(100000, LoopWork::light, 2)));
}

TEST_CASE("a forked child runs every iteration, with a pool of its own", "[runtime][threads]") {
  CHECK(each_once(visits(50000, LoopWork::heavy, 2)));  // the parent has started its workers
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) _exit(each_once(visits(50000, LoopWork::heavy, 2)) ? 0 : 1);
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
}
#endif

// partc/parallel.hpp: the parallel loop generated kernels use over particles.
//
//   partc::parallel_for(n, partc::LoopWork::heavy, [&](std::size_t i) { ... });
//
// Built with OpenMP (-fopenmp), large loops are split into chunks of
// consecutive iterations that partc's own threads (thread_pool.hpp) and the
// calling thread claim one by one; without OpenMP, or for small loops, the
// loop is plain and serial. The thread count is OpenMP's: OMP_NUM_THREADS, or
// with_threads below, else one per processor. Generated kernels use it only
// where every iteration writes its own particle's values and reads nothing
// another iteration writes (the compiler's aliasing analysis decides this),
// and each particle accumulates its neighbours in a fixed order, so results
// are bitwise identical for any number of threads and any assignment of
// chunks to threads.
//
// Surprises:
// - OpenMP is used for its thread count only, not its parallel regions: on a
//   machine where another program keeps a core busy, libgomp's spinning
//   barrier made a DEM model 10-150x slower on 2 threads than on one, and its
//   wait policy cannot be changed from inside the program (thread_pool.hpp).
// - Small loops never reach the threads: handing out a job and waiting for
//   it costs microseconds, more than a cheap pass over a few thousand
//   particles; so below min_parallel(work) the body runs in an ordinary loop.
// - A loop inside a parallel loop's body, or one started while another
//   thread's parallel loop runs, is serial.
// - An exception thrown by the body reaches the caller (after the chunks that
//   had started have ended); the rest of the loop is skipped.
#pragma once

#include <algorithm>
#include <cstddef>

#if defined(_OPENMP)
#include <omp.h>

#include "partc/thread_pool.hpp"
#endif

namespace partc {

// light: per-particle arithmetic; heavy: loops over neighbours; blocks: a few
// large tasks of unequal size (each a block of particles), handed out one by one.
enum class LoopWork { light, heavy, blocks };

constexpr std::size_t min_parallel(LoopWork work) {
  return work == LoopWork::blocks ? 2 : work == LoopWork::heavy ? 256 : 8192;
}

namespace detail {

// How many chunks a loop of n iterations is cut into for `threads` threads:
// a blocks loop one per task; the others up to chunks_per_thread per thread
// (so that a thread that runs late or slowly leaves its share to the others),
// but no chunk shorter than min_chunk(work) iterations.
constexpr std::size_t chunks_per_thread = 8;
constexpr std::size_t min_chunk(LoopWork work) {
  return work == LoopWork::blocks ? 1 : work == LoopWork::heavy ? 32 : 1024;
}
constexpr std::size_t chunk_count(std::size_t n, LoopWork work, unsigned threads) {
  if (work == LoopWork::blocks) return n;
  return std::max<std::size_t>(1, std::min(n / min_chunk(work), chunks_per_thread * threads));
}

}  // namespace detail

// How many threads partc's loops may use (1 without OpenMP): for sizing the
// blocks of a loop whose result does not depend on how it is cut.
inline int max_threads() {
#if defined(_OPENMP)
  return omp_get_max_threads();
#else
  return 1;
#endif
}

template <class Body>
void parallel_for(std::size_t n, LoopWork work, Body&& body) {
#if defined(_OPENMP)
  const int threads = n >= min_parallel(work) ? max_threads() : 1;
  if (threads > 1) {
    const std::size_t chunks =
        std::min(detail::chunk_count(n, work, static_cast<unsigned>(threads)),
                 detail::ThreadPool::max_chunks);
    const std::size_t size = n / chunks, longer = n % chunks;  // the first `longer` get size + 1
    auto chunk = [&](std::size_t c) {
      const std::size_t first = c * size + std::min(c, longer);
      const std::size_t stop = first + size + (c < longer ? 1 : 0);
      for (std::size_t i = first; i < stop; ++i) body(i);
    };
    if (detail::ThreadPool::instance().run(static_cast<unsigned>(threads), chunks, chunk)) return;
  }
#else
  (void)work;
#endif
  for (std::size_t i = 0; i < n; ++i) body(i);
}

// f() with at most `threads` threads in partc's loops (and OpenMP's), then the
// previous limit again: for tests and benchmarks that compare thread counts.
// Without OpenMP, just f().
template <class F>
auto with_threads(int threads, F&& f) {
#if defined(_OPENMP)
  struct Restore {
    int previous = omp_get_max_threads();
    ~Restore() { omp_set_num_threads(previous); }
  } restore;
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  return f();
}

}  // namespace partc

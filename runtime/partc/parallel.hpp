// partc/parallel.hpp: the parallel loop generated kernels use over particles.
//
//   partc::parallel_for(n, partc::LoopWork::heavy, [&](std::size_t i) { ... });
//
// With OpenMP (-fopenmp) large loops are split statically across threads;
// without it, or for small loops, the loop is plain and serial. Generated
// kernels use it only where every iteration writes its own particle's values
// and reads nothing another iteration writes (the compiler's aliasing
// analysis decides this), and each particle accumulates its neighbours in a
// fixed order, so results are bitwise identical for any number of threads.
//
// Surprise: small loops never enter OpenMP at all. Starting a team of threads
// costs microseconds, more than a cheap pass over a few thousand particles,
// and even an `if (false)` parallel region costs a call; so below
// min_parallel(work) the body runs in an ordinary loop.
#pragma once

#include <cstddef>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace partc {

// light: per-particle arithmetic; heavy: loops over neighbours; blocks: a few
// large tasks of unequal size (each a block of particles), handed out one by one.
enum class LoopWork { light, heavy, blocks };

constexpr std::size_t min_parallel(LoopWork work) {
  return work == LoopWork::blocks ? 2 : work == LoopWork::heavy ? 256 : 8192;
}

template <class Body>
void parallel_for(std::size_t n, LoopWork work, Body&& body) {
#if defined(_OPENMP)
  if (n >= min_parallel(work)) {
    const auto count = static_cast<long long>(n);  // OpenMP 4.5 wants a signed index
    if (work == LoopWork::blocks) {
#pragma omp parallel for schedule(dynamic, 1)
      for (long long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
      return;
    }
#pragma omp parallel for schedule(static)
    for (long long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
    return;
  }
#else
  (void)work;
#endif
  for (std::size_t i = 0; i < n; ++i) body(i);
}

// f() with at most `threads` OpenMP threads, then the previous limit again: for
// tests and benchmarks that compare thread counts. Without OpenMP, just f().
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

// partc/parallel.hpp: the parallel loop generated kernels use over particles.
//
//   PARTC_PARALLEL_FOR(n, work) for (std::size_t i = 0; i < n; ++i) { ... }
//
// With OpenMP (-fopenmp) the loop is split statically across threads;
// without it the macro is empty and the loop is serial. Generated kernels use
// it only where every iteration writes its own particle's values and reads
// nothing another iteration writes (the compiler's aliasing analysis decides
// this), and each particle accumulates its neighbours in a fixed order, so
// results are bitwise identical for any number of threads.
//
// Surprise: small loops stay serial. Starting a team of threads costs a few
// microseconds, more than a cheap pass over a few thousand particles, so the
// loop runs in parallel only from n >= min_parallel(work): work is `light`
// for per-particle arithmetic and `heavy` for loops over neighbours.
#pragma once

#include <cstddef>

namespace partc {

enum class LoopWork { light, heavy };

constexpr std::size_t min_parallel(LoopWork work) {
  return work == LoopWork::heavy ? 256 : 8192;
}

}  // namespace partc

#if defined(_OPENMP)
#define PARTC_PRAGMA(text) _Pragma(#text)
#define PARTC_PARALLEL_FOR(n, work) \
  PARTC_PRAGMA(omp parallel for schedule(static) if ((n) >= partc::min_parallel(work)))
#else
#define PARTC_PARALLEL_FOR(n, work)
#endif

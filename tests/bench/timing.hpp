// Timing helpers shared by the benchmarks.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace bench {

// Wall time of `times` calls of f, in seconds (steady clock).
template <class F>
double seconds(F&& f, int times = 1) {
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < times; ++k) f();
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  return elapsed.count();
}

// The median (upper median for an even count): unlike the mean, it ignores
// the odd interruption by the operating system.
inline double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace bench

// partc/math.hpp: scalar helpers for generated code.
//
// - ipow<N>(x) is x to a small integer power by repeated squaring (x^-7 is
//   1 / (x^4 * x^2 * x)), which is what hand-written MD kernels do instead of
//   calling pow: several times faster.
// - floor_div(a, b) and mod(a, b) are floored, as Python's // and %: the
//   remainder has the divisor's sign, so mod(-1, 3) is 2 (C++'s % gives -1),
//   which is what periodic indexing wants.
// - sign(x) is -1, 0 or 1 in x's type; clamp<T>(x, lo, hi) is min(max(x, lo), hi).
// - neumaier_add(sum, error, x) adds x to sum and keeps what rounding lost in
//   error (Neumaier's improvement of Kahan's summation): sum + error at the
//   end is the sum as if in twice the precision, whatever the order of sizes
//   (schedule: summation = compensated). Not with -ffast-math, which would
//   simplify the error away.
//
// Surprises:
// - ipow may differ from std::pow in the last bits (a few roundings instead of one).
// - Integer floor_div and mod by zero give 0 (as Halide defines them), so no
//   input makes a kernel trap; partc rejects a divisor that is 0 at compile
//   time. A real mod by zero is NaN, which the finite check reports.
// - clamp with lo > hi gives hi (std::clamp would be undefined).
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "partc/vec.hpp"

namespace partc {

template <int N>
constexpr double ipow(double x) {
  if constexpr (N < 0) {
    return 1.0 / ipow<-N>(x);
  } else if constexpr (N == 0) {
    return 1.0;
  } else if constexpr (N == 1) {
    return x;
  } else {
    const double half = ipow<N / 2>(x);
    return N % 2 == 0 ? half * half : half * half * x;
  }
}

// Ints (of any width the generated code mixes: literals are int, variables
// std::int64_t) or reals, floored.
template <class A, class B>
constexpr auto mod(A a, B b) {
  if constexpr (std::is_integral_v<A> && std::is_integral_v<B>) {
    const std::int64_t x = a, y = b;
    if (y == 0) return std::int64_t{0};
    const std::int64_t r = x % y;
    return r != 0 && (r < 0) != (y < 0) ? r + y : r;
  } else {
    const double x = a, y = b;
    return x - y * std::floor(x / y);
  }
}

template <class A, class B>
constexpr std::int64_t floor_div(A a, B b) {
  static_assert(std::is_integral_v<A> && std::is_integral_v<B>, "// divides ints");
  const std::int64_t x = a, y = b;
  if (y == 0) return 0;
  const std::int64_t q = x / y;
  return (x % y != 0) && ((x < 0) != (y < 0)) ? q - 1 : q;
}

template <class T>
constexpr T sign(T x) {
  return static_cast<T>((x > T(0)) - (x < T(0)));
}

template <class T>
constexpr T clamp(T x, T lo, T hi) {
  return x < lo ? lo : x > hi ? hi : x;
}

inline void neumaier_add(double& sum, double& error, double x) {
  const double t = sum + x;
  error += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
  sum = t;
}

template <int D>
void neumaier_add(Vec<D>& sum, Vec<D>& error, const Vec<D>& x) {
  for (int k = 0; k < D; ++k) neumaier_add(sum[k], error[k], x[k]);
}

}  // namespace partc

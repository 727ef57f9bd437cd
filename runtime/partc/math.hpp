// partc/math.hpp: scalar helpers for generated code.
//
// ipow<N>(x) is x to a small integer power by repeated squaring (x^-7 is
// 1 / (x^4 * x^2 * x)), which is what hand-written MD kernels do instead of
// calling pow: several times faster. Surprise: the result may differ from
// std::pow in the last bits (a few roundings instead of one).
#pragma once

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

}  // namespace partc

// partc/rng.hpp: counter-based random numbers, reproducible whatever the thread
// count or particle order.
//
// A draw is a pure function of (seed, id, step, stream, k): no state advances,
// so particles can be visited in any order, on any thread, and still get the
// same numbers. The generator is Philox4x32-10 (Salmon, Moraes, Dror, Shaw,
// "Parallel random numbers: as easy as 1, 2, 3", SC 2011), the one in Random123.
//
// Counter layout (128 bits), chosen so that distinct tuples never collide:
//   counter[0] = id bits 0..31
//   counter[1] = id bits 32..47     | stream << 16
//   counter[2] = step bits 0..31
//   counter[3] = step bits 32..47   | k << 16
//   key        = seed (low 32 bits, high 32 bits)
// Surprises:
// - id and step must be below 2^48 and stream and k below 2^16; anything
//   larger throws std::out_of_range rather than silently reusing numbers.
// - uniform() and normal() with the same (id, step, stream, k) read the same
//   Philox block, so they are not independent: give each call site its own stream.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace partc {

using PhiloxCounter = std::array<std::uint32_t, 4>;
using PhiloxKey = std::array<std::uint32_t, 2>;

// The raw bijection, exposed for the known-answer tests.
inline PhiloxCounter philox4x32_10(PhiloxCounter counter, PhiloxKey key) {
  constexpr std::uint32_t multiplier0 = 0xD2511F53, multiplier1 = 0xCD9E8D57;
  constexpr std::uint32_t weyl0 = 0x9E3779B9, weyl1 = 0xBB67AE85;  // key schedule increments
  for (int round = 0; round < 10; ++round) {
    const std::uint64_t product0 = std::uint64_t{multiplier0} * counter[0];
    const std::uint64_t product1 = std::uint64_t{multiplier1} * counter[2];
    counter = {std::uint32_t(product1 >> 32) ^ counter[1] ^ key[0], std::uint32_t(product1),
               std::uint32_t(product0 >> 32) ^ counter[3] ^ key[1], std::uint32_t(product0)};
    key[0] += weyl0;
    key[1] += weyl1;
  }
  return counter;
}

class CounterRng {
 public:
  explicit CounterRng(std::uint64_t seed = 0) : seed_(seed) {}

  std::uint64_t seed() const { return seed_; }

  // The generator of one effect instance: Philox under another key, so its
  // draws are independent of every other key's (partc passes the hash of
  // the instance's name).
  CounterRng keyed(std::uint64_t key) const { return CounterRng(seed_ ^ key); }

  // The top 53 bits of the block's first 64 bits: every double in [0, 1) that
  // is a multiple of 2^-53, equally likely.
  double uniform(std::uint64_t id, std::uint64_t step, std::uint32_t stream,
                 std::uint32_t k = 0) const {
    const PhiloxCounter bits = block(id, step, stream, k);
    return unit_interval(bits[0], bits[1]);
  }

  // Box-Muller on the block's two 64-bit halves; the sine partner is dropped
  // so that a draw stays a function of one tuple.
  double normal(std::uint64_t id, std::uint64_t step, std::uint32_t stream,
                std::uint32_t k = 0) const {
    const PhiloxCounter bits = block(id, step, stream, k);
    const double radius_draw = 1.0 - unit_interval(bits[0], bits[1]);  // (0, 1]: log is finite
    const double angle_draw = unit_interval(bits[2], bits[3]);
    constexpr double two_pi = 6.283185307179586476925286766559;
    return std::sqrt(-2.0 * std::log(radius_draw)) * std::cos(two_pi * angle_draw);
  }

 private:
  PhiloxCounter block(std::uint64_t id, std::uint64_t step, std::uint32_t stream,
                      std::uint32_t k) const {
    if ((id >> 48) != 0 || (step >> 48) != 0 || (stream >> 16) != 0 || (k >> 16) != 0)
      throw std::out_of_range("CounterRng: (id " + std::to_string(id) + ", step " +
                              std::to_string(step) + ", stream " + std::to_string(stream) + ", k " +
                              std::to_string(k) +
                              ") is outside the collision-free range: id and step < 2^48, "
                              "stream and k < 2^16");
    const PhiloxCounter counter = {std::uint32_t(id), std::uint32_t(id >> 32) | (stream << 16),
                                   std::uint32_t(step), std::uint32_t(step >> 32) | (k << 16)};
    return philox4x32_10(counter, {std::uint32_t(seed_), std::uint32_t(seed_ >> 32)});
  }

  static double unit_interval(std::uint32_t low, std::uint32_t high) {
    const std::uint64_t bits = (std::uint64_t{high} << 32) | low;
    return double(bits >> 11) * 0x1.0p-53;
  }

  std::uint64_t seed_;
};

}  // namespace partc

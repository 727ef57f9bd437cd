// Int arithmetic in generated code is 64-bit (tests/e2e/int_arithmetic.part):
// each value against the one written out here. With ints as C++ `int`,
// 100000 * 100000 stored 1410065408 and 65536 * 65536 + 0.5 stored 0.5.
#include <catch2/catch.hpp>

#include <cstdint>
#include <limits>

#include "int_arithmetic.hpp"

TEST_CASE("int literals and their arithmetic are exact in 64 bits", "[e2e][ints]") {
  IntArithmetic model;
  model.init();
  model.step();
  const auto& P = model.P();
  REQUIRE(P.size() == 2);
  for (std::size_t i = 0; i < P.size(); ++i) {
    CHECK(P.get<IntArithmetic::P_product>()[i] == 10000000000LL);
    CHECK(P.get<IntArithmetic::P_mixed>()[i] == 4294967296.5);
    CHECK(P.get<IntArithmetic::P_chosen>()[i] ==
          (P.ids()[i] == 0 ? 10000000000LL : 300000LL) + 4294967296LL);
    CHECK(P.get<IntArithmetic::P_highest>()[i] == std::numeric_limits<std::int64_t>::max());
    CHECK(P.get<IntArithmetic::P_low>()[i] == std::numeric_limits<std::int64_t>::min());
    CHECK(P.get<IntArithmetic::P_floor_quotient>()[i] == -2333333333334LL);  // floored
  }
}

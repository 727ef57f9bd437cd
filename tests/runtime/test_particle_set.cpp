// ParticleSet: ids, stable erase, consistent permutation of every array,
// variable visiting order, and the uint8 storage of bool.
#include <catch2/catch.hpp>

#include "sample_set.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "partc/particle_set.hpp"

using partc::Vec;

namespace {

using namespace sample;  // P_v, P_e, P_hits, P_moving, Set

// Every array of particle i holds values derived from its id, so any
// inconsistency between arrays after erase/permute shows up.
void fill_from_ids(Set& set) {
  for (std::size_t i = 0; i < set.size(); ++i) {
    const auto id = static_cast<double>(set.ids()[i]);
    set.positions()[i] = Vec<2>{{id, -id}};
    set.get<P_v>()[i] = Vec<2>{{10 * id, 0.5}};
    set.get<P_e>()[i] = 100 * id;
    set.get<P_hits>()[i] = 1000 * set.ids()[i];
    set.get<P_moving>()[i] = static_cast<std::uint8_t>(set.ids()[i] % 2);
  }
}

void check_consistent(const Set& set) {
  const std::size_t n = set.size();
  REQUIRE(set.positions().size() == n);
  REQUIRE(set.ids().size() == n);
  REQUIRE(set.alive().size() == n);
  REQUIRE(set.get<P_v>().size() == n);
  REQUIRE(set.get<P_e>().size() == n);
  REQUIRE(set.get<P_hits>().size() == n);
  REQUIRE(set.get<P_moving>().size() == n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t id = set.ids()[i];
    const auto x = static_cast<double>(id);
    INFO("index " << i << ", id " << id);
    CHECK(set.positions()[i] == Vec<2>{{x, -x}});
    CHECK(set.get<P_v>()[i] == Vec<2>{{10 * x, 0.5}});
    CHECK(set.get<P_e>()[i] == 100 * x);
    CHECK(set.get<P_hits>()[i] == 1000 * id);
    CHECK(set.get<P_moving>()[i] == id % 2);
  }
}

Set make_set(std::size_t n) {
  Set set;
  for (std::size_t i = 0; i < n; ++i) set.push_back(Vec<2>{});
  fill_from_ids(set);
  return set;
}

}  // namespace

TEST_CASE("bool variables are stored as uint8", "[particle_set]") {
  static_assert(std::is_same_v<partc::storage_t<bool>, std::uint8_t>);
  static_assert(std::is_same_v<partc::storage_t<double>, double>);
  static_assert(std::is_same_v<partc::storage_t<Vec<3>>, Vec<3>>);
  static_assert(std::is_same_v<decltype(std::declval<Set&>().get<P_moving>()),
                               std::vector<std::uint8_t>&>);
  static_assert(std::is_same_v<decltype(std::declval<const Set&>().get<P_hits>()),
                               const std::vector<std::int64_t>&>);
  static_assert(Set::dim == 2);
  Set set;
  set.push_back(Vec<2>{});
  set.get<P_moving>()[0] = 1;
  const std::uint8_t* data = set.get<P_moving>().data();  // contiguous storage
  CHECK(data[0] == 1);
}

TEST_CASE("push_back assigns increasing ids and zero variables", "[particle_set]") {
  Set set;
  CHECK(set.empty());
  CHECK(set.next_id() == 0);
  set.reserve(10);
  CHECK(set.size() == 0);
  for (std::size_t i = 0; i < 5; ++i) {
    const Vec<2> p{{0.5 * static_cast<double>(i), 1.0}};
    CHECK(set.push_back(p) == i);
    CHECK(set.positions()[i] == p);
  }
  CHECK(set.size() == 5);
  CHECK_FALSE(set.empty());
  CHECK(set.ids() == std::vector<std::int64_t>{0, 1, 2, 3, 4});
  CHECK(set.alive() == std::vector<std::uint8_t>(5, 1));
  CHECK(set.get<P_v>() == std::vector<Vec<2>>(5, Vec<2>{{0.0, 0.0}}));
  CHECK(set.get<P_e>() == std::vector<double>(5, 0.0));
  CHECK(set.get<P_hits>() == std::vector<std::int64_t>(5, 0));
  CHECK(set.get<P_moving>() == std::vector<std::uint8_t>(5, 0));
  CHECK(set.next_id() == 5);
}

TEST_CASE("ids are never reused", "[particle_set]") {
  Set set = make_set(3);
  set.alive()[2] = 0;
  set.erase_dead();
  CHECK(set.push_back(Vec<2>{}) == 2);
  CHECK(set.ids().back() == 3);
  set.clear();
  CHECK(set.empty());
  CHECK(set.get<P_e>().empty());
  CHECK(set.next_id() == 4);
  set.push_back(Vec<2>{});
  CHECK(set.ids() == std::vector<std::int64_t>{4});
}

TEST_CASE("push_back_with_id and set_next_id", "[particle_set]") {
  Set set;
  set.push_back_with_id(Vec<2>{{1.0, 2.0}}, 10);
  CHECK(set.next_id() == 11);
  set.push_back_with_id(Vec<2>{{3.0, 4.0}}, 3);  // lower id: next id unchanged
  CHECK(set.next_id() == 11);
  CHECK(set.ids() == std::vector<std::int64_t>{10, 3});
  CHECK(set.alive() == std::vector<std::uint8_t>{1, 1});
  CHECK(set.get<P_e>() == std::vector<double>{0.0, 0.0});
  set.push_back(Vec<2>{});
  CHECK(set.ids().back() == 11);
  set.set_next_id(100);
  set.push_back(Vec<2>{});
  CHECK(set.ids().back() == 100);
  CHECK(set.next_id() == 101);
}

TEST_CASE("erase_dead keeps the survivors' order and ids", "[particle_set]") {
  const std::size_t n = 50;
  for (const auto pattern : {"none", "all", "first", "last", "random"}) {
    INFO("pattern " << pattern);
    Set set = make_set(n);
    std::vector<std::int64_t> expected_ids;
    std::mt19937 rng(3);
    for (std::size_t i = 0; i < n; ++i) {
      const std::string p = pattern;
      const bool dead = p == "all" || (p == "first" && i == 0) || (p == "last" && i == n - 1) ||
                        (p == "random" && rng() % 3 == 0);
      set.alive()[i] = dead ? 0 : 1;
      if (!dead) expected_ids.push_back(set.ids()[i]);
    }
    set.erase_dead();
    CHECK(set.ids() == expected_ids);
    CHECK(set.alive() == std::vector<std::uint8_t>(expected_ids.size(), 1));
    check_consistent(set);
    CHECK(set.next_id() == static_cast<std::int64_t>(n));
  }
}

TEST_CASE("permute moves every array consistently", "[particle_set]") {
  const std::size_t n = 40;
  Set set = make_set(n);
  for (std::size_t i = 0; i < n; i += 3) set.alive()[i] = 0;  // alive moves too
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(11));
  const std::vector<std::int64_t> old_ids = set.ids();
  const std::vector<std::uint8_t> old_alive = set.alive();
  set.permute(order);
  for (std::size_t k = 0; k < n; ++k) {
    CHECK(set.ids()[k] == old_ids[order[k]]);  // new[k] = old[order[k]]
    CHECK(set.alive()[k] == old_alive[order[k]]);
  }
  check_consistent(set);
  CHECK_THROWS_AS(set.permute(std::vector<std::size_t>(n - 1)), std::invalid_argument);
  Set empty;
  CHECK_NOTHROW(empty.permute({}));
}

TEST_CASE("for_each_variable visits p, then the variables in declaration order", "[particle_set]") {
  Set set = make_set(3);
  std::vector<std::string> names;
  std::vector<std::size_t> sizes;
  const Set& const_set = set;
  const_set.for_each_variable([&](const char* name, const auto& values) {
    static_assert(std::is_const_v<std::remove_reference_t<decltype(values)>>);
    names.emplace_back(name);
    sizes.push_back(values.size());
  });
  CHECK(names == std::vector<std::string>{"p", "v", "e", "hits", "moving"});
  CHECK(sizes == std::vector<std::size_t>(5, 3));

  names.clear();
  set.for_each_variable([&](const char* name, auto& values) {
    names.emplace_back(name);
    using Value = typename std::remove_reference_t<decltype(values)>::value_type;
    if constexpr (std::is_same_v<Value, double>) values[0] = -1.0;
    if constexpr (std::is_same_v<Value, std::uint8_t>) values[1] = 7;
  });
  CHECK(names == std::vector<std::string>{"p", "v", "e", "hits", "moving"});
  CHECK(set.get<P_e>()[0] == -1.0);
  CHECK(set.get<P_moving>()[1] == 7);
}

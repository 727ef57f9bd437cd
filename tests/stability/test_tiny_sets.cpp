// N = 0 and N = 1 (tests/stability/tiny_sets.part), set before init: init and
// step run; a sum over no neighbours is 0, a count 0, the observables'
// reductions over an empty set 0 (and the count of a singleton 1).
#include <catch2/catch.hpp>

#include "tiny_sets.hpp"

TEST_CASE("an empty set: init and steps run, sums and counts over it are 0",
          "[stability][tiny]") {
  TinySets model;
  model.params().N = 0;
  model.init();
  for (int k = 0; k < 3; ++k) model.step();
  CHECK_NOTHROW(model.check_finite());
  CHECK(model.P().size() == 0);
  CHECK(model.step_count() == 3);
  CHECK(model.observables().total == 0.0);
  CHECK(model.observables().alive_count == 0);
  CHECK(model.observables().pairs == 0);
}

TEST_CASE("a single particle: no neighbour, so its sums are 0 and its count 0",
          "[stability][tiny]") {
  TinySets model;
  model.params().N = 1;
  model.init();
  for (int k = 0; k < 3; ++k) model.step();
  CHECK_NOTHROW(model.check_finite());
  REQUIRE(model.P().size() == 1);
  CHECK(model.P().get<TinySets::P_s>()[0] == 0.0);
  CHECK(model.P().get<TinySets::P_n>()[0] == 0);
  CHECK(model.P().get<TinySets::P_f>()[0][0] == 0.0);
  CHECK(model.P().get<TinySets::P_f>()[0][1] == 0.0);
  CHECK(model.observables().total == 0.0);
  CHECK(model.observables().alive_count == 1);
  CHECK(model.observables().pairs == 0);
}

// ir/terms.hpp's origins_of_sum: which effects' terms hold a sum of a
// statement several effects were merged or fused into, against statements
// built by hand whose answer is known term by term.
#include <catch2/catch.hpp>

#include <memory>

#include "ir/terms.hpp"

namespace {

using namespace partc::ir;

Expr sum(int id) {
  return std::make_shared<Accumulate>(Type::Real, Reduction::Sum, 1, nullptr,
                                      std::make_shared<Literal>(Type::Real, 1.0, partc::Location{}),
                                      id, partc::Location{});
}

Expr literal(double v) { return std::make_shared<Literal>(Type::Real, v, partc::Location{}); }

Expr plus(Expr a, Expr b) {
  return std::make_shared<Binary>(Type::Real, BinaryOp::Add, std::move(a), std::move(b),
                                  partc::Location{});
}

Statement merged(std::vector<std::string> effects, Expr value) {
  Statement st;
  for (std::string& e : effects) st.origins.push_back({std::move(e), {}});
  st.terms_by_origin = st.origins.size() > 1;
  st.value = std::move(value);
  return st;
}

using Origins = std::vector<std::size_t>;

}  // namespace

TEST_CASE("terms: a merged statement's sum is the effect's whose term holds it") {
  // f = lj's sum 0 + (coulomb's sums 1 and 2) + drag's 0.5 (no sum)
  const Statement st = merged({"lj", "coulomb", "drag"},
                              plus(plus(sum(0), plus(sum(1), sum(2))), literal(0.5)));
  CHECK(origins_of_sum(st, 0) == Origins{0});
  CHECK(origins_of_sum(st, 1) == Origins{1});
  CHECK(origins_of_sum(st, 2) == Origins{1});
}

TEST_CASE("terms: a statement of one effect, or of unsplit terms, holds its sums for all") {
  CHECK(origins_of_sum(merged({"lj"}, sum(0)), 0) == Origins{0});
  Statement unsplit = merged({"lj", "coulomb"}, plus(sum(0), sum(1)));
  unsplit.terms_by_origin = false;  // fusion inlined a writer: terms no longer by origin
  CHECK(origins_of_sum(unsplit, 1) == (Origins{0, 1}));
  CHECK(origins_of_sum(merged({}, sum(0)), 0).empty());  // the scene's own statement
}

TEST_CASE("terms: in a fused statement, sums no part leaves out are the reader's") {
  // v += dt * (gravity's sum 0 + pressure's sum 1), verlet's kick reading them:
  // fusion records the value without gravity and without pressure.
  Statement st = merged({"gravity", "pressure", "verlet"}, plus(sum(0), plus(sum(1), sum(2))));
  st.terms_by_origin = false;
  st.without = {{{0}, plus(sum(1), sum(2))}, {{1}, plus(sum(0), sum(2))}};
  CHECK(origins_of_sum(st, 0) == Origins{0});
  CHECK(origins_of_sum(st, 1) == Origins{1});
  CHECK(origins_of_sum(st, 2) == Origins{2});  // in every part: verlet's, the rest
}

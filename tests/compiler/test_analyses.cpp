// The analyses' facts for small models: which accumulations are
// neighbourhood sums and with what radius, and which statements are
// buffered.
#include <catch2/catch.hpp>

#include "driver/pipeline.hpp"
#include "ir/printer.hpp"

namespace {

partc::Compilation compile(const std::string& step_body) {
  const std::string text =
      "model m\ndim 3\ndomain lo=(0, 0, 0) hi=(1, 1, 1)\n"
      "param r: real = 0.1\nconst r2 = r * r\n"
      "particles P(10) {\n  u: real = 0\n  w: real = 1\n}\n"
      "step {\n" + step_body + "\n}\n";
  static std::vector<std::unique_ptr<partc::SourceFile>> keep;  // facts point into the text
  keep.push_back(std::make_unique<partc::SourceFile>("t.part", text));
  return partc::analyse(*keep.back());
}

// "dense", or the radius expression of the first accumulation.
std::string search_of(const std::string& step_body) {
  const partc::Compilation c = compile(step_body);
  const partc::SearchFact& fact = c.facts.neighbourhoods.at(0);
  if (fact.kind == partc::SearchFact::Kind::Dense) return "dense";
  return partc::ir::to_string(fact.radius, c.model, c.model.stages[0].statements[0].labels);
}

bool buffered(const std::string& step_body) {
  return compile(step_body).facts.aliasing.at(0).at(0).buffered;
}

}  // namespace

TEST_CASE("neighbourhood: upper bounds on |dx| become search radii", "[analysis]") {
  CHECK(search_of("u[i] = sum(j, |dx| < r, w[j])") == "r");
  CHECK(search_of("u[i] = sum(j, norm(dx) <= 2 * r, w[j])") == "(2 * r)");
  CHECK(search_of("u[i] = sum(j, r > |dx|, w[j])") == "r");
  CHECK(search_of("u[i] = sum(j, w[j] > 0 and |dx| < r and |dx| > 0, w[j])") == "r");
  CHECK(search_of("u[i] = sum(j, dot(dx, dx) < r2, w[j])") == "sqrt(r2)");
  CHECK(search_of("u[i] = sum(j, |dx| < r and |dx| < 0.05, w[j])") == "min(r, 0.05)");
}

TEST_CASE("neighbourhood: per-particle bounds are sized by their largest terms", "[analysis]") {
  const partc::Compilation c =
      compile("u[i] = sum(j, |dx| < w[i] + w[j] + r and |dx| > 0, w[j])");
  const partc::SearchFact& fact = c.facts.neighbourhoods.at(0);
  REQUIRE(fact.kind == partc::SearchFact::Kind::Neighbours);
  std::vector<std::string> terms;
  for (const auto& t : fact.radius_terms)
    terms.push_back(partc::ir::to_string(t, c.model, c.model.stages[0].statements[0].labels));
  CHECK(terms == std::vector<std::string>{"w[i]", "w[j]", "r"});
  // A uniform bound beside a per-particle one: the uniform one sizes the search.
  CHECK(search_of("u[i] = sum(j, |dx| < w[i] + w[j] and |dx| < r, w[j])") == "r");
}

TEST_CASE("neighbourhood: anything else is dense", "[analysis]") {
  CHECK(search_of("u[i] = sum(j, w[j])") == "dense");
  CHECK(search_of("u[i] = sum(j, |dx| > r, w[j])") == "dense");              // a lower bound
  CHECK(search_of("u[i] = sum(j, |dx| < r or w[j] > 0, w[j])") == "dense");  // under `or`
  CHECK(search_of("u[i] = sum(j, |dx| < w[i] * w[j], w[j])") == "dense");  // no per-particle split
}

TEST_CASE("aliasing: reading another particle's copy of the target buffers", "[analysis]") {
  CHECK(buffered("u[i] = sum(j, |dx| < r, u[j])"));
  CHECK(buffered("p[i] += sum(j, |dx| < r, dx)"));  // dx reads p[j]
  CHECK_FALSE(buffered("u[i] = 2 * u[i] + sum(j, |dx| < r, w[j])"));
  CHECK_FALSE(buffered("w[i] = sum(j, |dx| < r, u[j])"));
  CHECK_FALSE(buffered("p[i] += vec(u[i], 0, 0)"));
}

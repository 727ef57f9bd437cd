// The analyses' facts for small models: which accumulations are
// neighbourhood sums and with what radius, which statements are buffered,
// which sums may take each pair once, and which are the same for every i.
#include <catch2/catch.hpp>

#include "driver/pipeline.hpp"
#include "ir/printer.hpp"

namespace {

partc::Compilation compile_text(const std::string& text) {
  static std::vector<std::unique_ptr<partc::SourceFile>> keep;  // facts point into the text
  keep.push_back(std::make_unique<partc::SourceFile>("t.part", text));
  return partc::analyse(*keep.back());
}

partc::Compilation compile(const std::string& step_body) {
  return compile_text(
      "model m\ndim 3\ndomain lo=(0, 0, 0) hi=(1, 1, 1)\n"
      "param r: real = 0.1\nconst r2 = r * r\n"
      "particles P(10) {\n  u: real = 0\n  w: real = 1\n}\n"
      "step {\n" +
      step_body + "\n}\n");
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

// The pair-symmetry fact of the first accumulation of a statement of set P,
// in a 2-d model with the variables and functions the cases need.
partc::PairSymmetryFact symmetry_of(const std::string& statement) {
  const partc::Compilation c = compile_text(
      "model m\ndim 2\ndomain lo=(0, 0) hi=(1, 1)\n"
      "param rc: real = 0.1\n"
      "fn lj_force(s: real) = 24 * pow(s, 4) * (2 * pow(s, 3) - 1)\n"
      "fn W(q: real) = exp(-q * q)\n"
      "fn amix(x: real, y: real) = sqrt(x * y)\n"
      "fn smix(x: real, y: real) = (x + y) / 2\n"
      "fn lj(e: real, s: real, r: real) = 4 * e * (pow(s / r, 12) - pow(s / r, 6))\n"
      "fn ratio(x: real, y: real) = x / y\n"
      "fn gap(x: real, y: real) = x - y\n"
      "fn twice(x: real) = amix(x, x) + amix(x, x)\n"
      "particles P(10) {\n  v: vec = 0\n  r: real = 0.01\n  m: real = 1\n  h: real = 0.1\n"
      "  u: real = 0\n  n: int = 0\n  f: vec = 0\n}\n"
      "particles Q(5) {\n  m: real = 1\n}\n"
      "step P {\n" +
      statement + "\n}\n");
  return c.facts.symmetry.at(0);
}

// +1 or -1: the sign j's share takes; 0: each pair is evaluated both ways.
int newton_sign(const std::string& statement) {
  const partc::PairSymmetryFact fact = symmetry_of(statement);
  return fact.newton ? fact.sign : 0;
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
  const partc::Compilation c = compile("u[i] = sum(j, |dx| < w[i] + w[j] + r and |dx| > 0, w[j])");
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
  // A sum computed once before the loop sees only old values.
  CHECK_FALSE(buffered("u[i] -= sum(j, true, u[j]) / 10"));
  CHECK(buffered("u[i] -= sum(j, true, u[j]) / 10 + sum(k, u[k] > u[i], 1.0)"));
}

TEST_CASE("symmetry: odd terms under an even condition take each pair once", "[analysis]") {
  // The md force and the Lennard-Jones force (through a user function).
  CHECK(newton_sign("f[i] = sum(j, |dx| < rc and |dx| > 0, -exp(-|dx|) * dx / |dx|)") == -1);
  CHECK(newton_sign("f[i] = sum(j, dot(dx, dx) < rc * rc and dot(dx, dx) > 0, "
                    "-lj_force(1 / dot(dx, dx)) * dx)") == -1);
  // DEM contacts: the bound and the overlap are symmetric in r[i] + r[j].
  CHECK(newton_sign("f[i] = sum(j, |dx| < r[i] + r[j] and |dx| > 0, "
                    "-(r[i] + r[j] - |dx|) * dx / |dx|)") == -1);
  // A difference of twins changes sign: v[i] - v[j].
  CHECK(newton_sign("f[i] = sum(j, |dx| < rc, v[j] - v[i])") == -1);
  CHECK(newton_sign("f[i] = sum(j, |dx| < rc, vec(dx.y, -dx.x) * W(|dx|))") == -1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, sin(dx.x))") == -1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, tanh(dx.y) * sign(dx.x) * atan(dx.x))") == -1);
  CHECK(newton_sign("f[i] = sum(j, |dx| < rc, if(|dx| < rc / 2, dx, -2 * dx))") == -1);
}

TEST_CASE("symmetry: even terms under an even condition take each pair once", "[analysis]") {
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, exp(-|dx|))") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, m[i] * m[j] * exp(-|dx|))") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < max(h[i], h[j]), W(|dx| / min(h[i], h[j])))") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc and id[i] != id[j], dot(dx, dx) + abs(dx.x))") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc and dx.x == dx.y, cos(dx.y))") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, 1)") == 1);
  CHECK(newton_sign("u[i] = sum(j, m[i] + m[j])") == 1);  // no condition: every pair
  CHECK(newton_sign("n[i] = count(j, |dx| < r[i] + r[j])") == 1);
  CHECK(newton_sign("n[i] = count(j, |dx| < rc and id[j] != id[i])") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, cross(dx, v[i] - v[j]))") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, if(m[i] + m[j] > 1, exp(-|dx|), 0))") == 1);
  // Mixing rules in user functions: judged by their bodies.
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, amix(m[i], m[j]) * W(|dx|))") == 1);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc and |dx| > 0, "
                    "lj(amix(m[i], m[j]), smix(h[i], h[j]), |dx|))") == 1);
  CHECK(newton_sign("f[i] = sum(j, |dx| < smix(r[i], r[j]), amix(m[i], m[j]) * dx)") == -1);
  CHECK(newton_sign("f[i] = sum(j, |dx| < rc, gap(h[j], h[i]) * dx)") == 1);  // odd * odd
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, twice(m[i] * m[j]))") == 1);    // calls in calls
  // Twins across a product's grouping: (-k * q[i]) * q[j] / r^3 * dx, Coulomb's force.
  CHECK(newton_sign(
            "f[i] = sum(j, |dx| < rc and |dx| > 0, -2 * m[i] * m[j] / pow(|dx|, 3) * dx)") == -1);
  CHECK(newton_sign(
            "u[i] = sum(j, |dx| < rc, m[i] * h[i] * W(|dx|) * h[j] / (r[j] * r[i]) * m[j])") == 1);
}

TEST_CASE("symmetry: anything else is evaluated both ways", "[analysis]") {
  // One particle's variable without its twin.
  CHECK(newton_sign("u[i] = sum(j, |dx| < h[i], m[j] * W(|dx|))") == 0);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, m[j] * W(|dx|))") == 0);
  CHECK(newton_sign("n[i] = count(j, |dx| < r[i])") == 0);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, m[i] / m[j])") == 0);  // T gives m[j] / m[i]
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, 2 * m[i] / (h[i] * m[j]) * h[j])") == 0);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, m[i] * m[i] * m[j])") == 0);  // one twin short
  // Mixed parity, in the term or the condition.
  CHECK(newton_sign("f[i] = sum(j, |dx| < rc, dx + vec(1, 0))") == 0);
  CHECK(newton_sign("u[i] = sum(j, dx.x > 0 and |dx| < 1, 1.0)") == 0);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc and dx.x == 0.5, 1.0)") == 0);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, lj_force(dx.x))") == 0);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, if(dx.x > 0, 1, -1))") == 0);       // condition odd
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, if(|dx| < 0.05, dx.x, 1))") == 0);  // odd, even
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, mod(dx.x, 0.1))") == 0);
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, ratio(m[i], m[j]))") == 0);  // m[i] / m[j]
  CHECK(newton_sign("u[i] = sum(j, |dx| < rc, amix(m[i], h[j]))") == 0);   // no twins
  // Not a sum, or not over i's own set.
  CHECK(newton_sign("u[i] = min(j, |dx| < rc, |dx|)") == 0);
  CHECK(newton_sign("u[i] = max(j, |dx| < rc, m[i] * m[j])") == 0);
  CHECK(newton_sign("u[i] = sum(j in Q, |dx| < rc, exp(-|dx|))") == 0);
  CHECK(newton_sign("u[i] = sum(j in Q, |dx| < rc, m[i] * m[j])") == 0);
}

TEST_CASE("symmetry: the reasons say what was found, in the model's terms", "[analysis]") {
  CHECK(symmetry_of("f[i] = sum(j, |dx| < rc, -dx)").reason ==
        "the term is antisymmetric and the condition symmetric under i <-> j, dx -> -dx: j takes "
        "-term");
  CHECK(symmetry_of("u[i] = sum(j, |dx| < rc, m[j] * W(|dx|))").reason ==
        "the term reads m[j] alone, not paired symmetrically with m[i]");
  CHECK(symmetry_of("u[i] = sum(k, dx.x > 0 and |dx| < 1, 1.0)").reason ==
        "the condition is not symmetric under i <-> k, dx -> -dx");
  CHECK(symmetry_of("u[i] = min(j, |dx| < rc, |dx|)").reason ==
        "min is not a sum: only sums and counts add a pair's term to both particles");
  CHECK(symmetry_of("u[i] = sum(j in Q, |dx| < rc, m[j])").reason ==
        "j ranges over Q, not P: only i takes the term");
}

// Whether each accumulation of one statement of the 3-d model is computed once.
std::vector<bool> once(const std::string& step_body) {
  const partc::Compilation c = compile(step_body);
  std::vector<bool> out;
  for (const auto& [id, fact] : c.facts.uniform_sums) out.push_back(fact.once);
  return out;
}

TEST_CASE("uniform sums: a sum reading nothing of i is computed once", "[analysis]") {
  CHECK(once("u[i] -= sum(j, true, w[j]) / 10") == std::vector<bool>{true});
  CHECK(once("u[i] = count(j, w[j] > r)") == std::vector<bool>{true});
  CHECK(once("u[i] = w[i] * sum(j, w[j] * w[j])") == std::vector<bool>{true});
  // Two sums, one reading i.
  CHECK(once("u[i] = sum(j, w[j]) + sum(k, w[k] > w[i], 1.0)") == std::vector<bool>{true, false});
  // dx reads p[i]; w[i] in the condition or the body reads i.
  CHECK(once("u[i] = sum(j, |dx| < r, w[j])") == std::vector<bool>{false});
  CHECK(once("u[i] = count(j, true and dx.x > 0)") == std::vector<bool>{false});
  CHECK(once("u[i] = sum(j, w[j] - w[i])") == std::vector<bool>{false});
  CHECK(once("u[i] = max(j, w[j] < w[i], w[j])") == std::vector<bool>{false});
}

namespace {

// The step's statements after fold_zero_terms, as the IR printer writes them
// (the 3-d model above, with const zero = 0).
std::vector<std::string> folded(const std::string& step_body) {
  const partc::Compilation c = compile_text(
      "model m\ndim 3\ndomain lo=(0, 0, 0) hi=(1, 1, 1)\nparam r: real = 0.1\nconst zero = 0\n"
      "particles P(10) {\n  u: real = 0\n  w: real = 1\n  f: vec = 0\n}\n"
      "step P {\n" +
      step_body + "\n}\n");
  std::vector<std::string> out;
  for (const partc::ir::Stage& stage : c.model.stages)
    for (const partc::ir::Statement& st : stage.statements)
      out.push_back(partc::ir::to_string(st.value, c.model, st.labels));
  return out;
}

}  // namespace

TEST_CASE("fold: a term with a constant 0 factor is removed", "[analysis]") {
  CHECK(folded("u[i] += zero * w[i]").empty());  // adds nothing: gone
  CHECK(folded("f[i] += -w[i] * zero * vec(0, 0, 1)").empty());
  CHECK(folded("u[i] = zero * sum(j, |dx| < r, w[j])") == std::vector<std::string>{"0"});
  CHECK(folded("u[i] = sum(j, |dx| < r, zero * w[j]) / w[i]") == std::vector<std::string>{"0"});
  // Not provably 0: kept as written.
  CHECK(folded("u[i] += w[i] / zero").size() == 1);
  CHECK(folded("u[i] += r * w[i]").size() == 1);
  CHECK(folded("u[i] += zero * normal()").size() == 1);  // a draw: its noise stays as it was
  CHECK(folded("u[i] += zero + w[i]").size() == 1);      // a model's own statement is one term
}

namespace {

// After fold_conditions and drop_unread_declarations: the step's statements,
// the functions and consts left, and the conditionals folded (as true or false).
struct ConditionsFolded {
  std::vector<std::string> statements, functions, consts, conditions;
};
ConditionsFolded conditions_folded(const std::string& step_body) {
  const partc::Compilation c = compile_text(
      "model m\ndim 3\ndomain lo=(0, 0, 0) hi=(1, 1, 1)\nparam r: real = 0.1\n"
      "const one = 1\nconst pick = one\nconst spare = 2\n"
      "fn near(x: real) = 2 * x\nfn far(x: real) = 3 * x\nfn idle(x: real) = x\n"
      "particles P(10) {\n  u: real = 0\n  w: real = 1\n}\n"
      "step P {\n" +
      step_body + "\n}\n");
  ConditionsFolded out;
  for (const partc::ir::Stage& stage : c.model.stages)
    for (const partc::ir::Statement& st : stage.statements)
      out.statements.push_back(partc::ir::to_string(st.value, c.model, st.labels));
  for (const partc::ir::UserFn& f : c.model.functions) out.functions.push_back(f.name);
  for (const partc::ir::Const& k : c.model.consts) out.consts.push_back(k.name);
  for (const partc::ir::FoldedCondition& f : c.folded_conditions)
    out.conditions.push_back(f.condition ? "true" : "false");
  return out;
}

using Names = std::vector<std::string>;

}  // namespace

TEST_CASE("fold: a conditional on a constant is the branch it chooses", "[analysis]") {
  // Chosen: the other branch's function goes, and so do the consts only the
  // condition read (pick, and one through pick); what nothing read stays.
  const ConditionsFolded chosen = conditions_folded("u[i] = if(pick == 1, near(w[i]), far(w[i]))");
  CHECK(chosen.statements == Names{"near(w[i])"});
  CHECK(chosen.functions == Names{"near", "idle"});
  CHECK(chosen.consts == Names{"spare"});
  CHECK(chosen.conditions == Names{"true"});
  CHECK(conditions_folded("u[i] = if(not (pick == 1), near(w[i]), far(w[i]))").functions ==
        Names{"far", "idle"});
  // A const read elsewhere too stays.
  const ConditionsFolded read =
      conditions_folded("u[i] = if(pick == 1, near(w[i]), far(w[i])) + pick");
  CHECK(read.functions == Names{"near", "idle"});
  CHECK(read.consts == Names{"one", "pick", "spare"});
  // Inside out: dim is a constant, w[i] > 0 is not.
  const ConditionsFolded nested =
      conditions_folded("u[i] = if(dim == 3, if(w[i] > 0, near(w[i]), 0), far(w[i]))");
  CHECK(nested.statements == Names{"if((w[i] > 0), near(w[i]), 0)"});
  CHECK(nested.conditions == Names{"true"});
  // Not constant: a param; an int branch of a real if is left to the if to convert.
  const ConditionsFolded param = conditions_folded("u[i] = if(r > 0, near(w[i]), far(w[i]))");
  CHECK(param.conditions.empty());
  CHECK(param.functions == Names{"near", "far", "idle"});
  CHECK(param.consts == Names{"one", "pick", "spare"});
  CHECK(conditions_folded("u[i] = if(pick == 1, 1, 2.5) * w[i]").conditions.empty());
}

// The passes statement fusion makes of a step body (over P's u and w),
// each as its members' step indices, and the reasons of its refusals.
struct Passes {
  std::vector<std::vector<int>> passes;
  std::vector<std::string> refused;
};
Passes passes_of(const std::string& step_body) {
  const partc::Compilation c = compile(step_body);
  Passes out;
  for (const partc::FusedPass& pass : c.facts.fusion.passes) {
    out.passes.emplace_back();
    for (const auto& [g, k] : pass.statements) out.passes.back().push_back(k);
  }
  for (const partc::FusionRefusal& r : c.facts.fusion.refused) out.refused.push_back(r.reason);
  return out;
}

TEST_CASE("statement fusion: statements one walk serves share a pass", "[analysis]") {
  const Passes two = passes_of(
      "u[i] = sum(j, |dx| < r, w[j])\n"
      "w[i] = 2 * sum(j, |dx| < r and |dx| > 0, 1 / |dx|)");
  CHECK(two.passes.size() == 0);  // w's pass would write what u's sum reads at j
  REQUIRE(two.refused.size() == 1);
  CHECK_THAT(two.refused[0], Catch::Contains("reads w, which w[i]"));
  // Neither reads the other's target: one pass, even past a statement they commute with.
  const Passes fused = passes_of(
      "u[i] = sum(j, |dx| < r, |dx|)\n"
      "w[i] = sum(j, |dx| < r and |dx| > 0, 1 / |dx|)");
  CHECK(fused.passes == std::vector<std::vector<int>>{{0, 1}});
  CHECK(fused.refused.empty());
}

TEST_CASE("statement fusion: what one walk cannot serve stays apart, with its reason",
          "[analysis]") {
  // A statement between them that the second reads: it cannot be moved up.
  CHECK(passes_of("u[i] = sum(j, |dx| < r, |dx|)\n"
                  "p[i] += vec(0, 0, 1e-3)\n"
                  "w[i] = sum(j, |dx| < r, 1)")
            .passes.empty());
  // Each pair once against both ways (|dx| + p[i].x is neither even nor odd in i, j).
  const Passes ways = passes_of(
      "u[i] = sum(j, |dx| < r, |dx|)\n"
      "w[i] = sum(j, |dx| < r, |dx| + p[i].x)");
  CHECK(ways.passes.empty());
  REQUIRE(ways.refused.size() == 1);
  CHECK_THAT(ways.refused[0], Catch::Contains("one takes each pair once, the other both ways"));
  // Cutoffs far apart get searches of their own (the search plan): no shared walk.
  const Passes apart = passes_of(
      "u[i] = sum(j, |dx| < r, |dx|)\n"
      "w[i] = sum(j, |dx| < 4 * r, |dx|)");
  CHECK(apart.passes.empty());
  REQUIRE(apart.refused.size() == 1);
  CHECK_THAT(apart.refused[0], Catch::Contains("searches of their own"));
}

namespace {

// The vector-term fact of each accumulation, in order, of a 2-d model with
// a float-stored q, under the given schedule block.
std::vector<partc::VectorTermFact> vector_terms_of(const std::string& schedule) {
  const partc::Compilation c = compile_text(
      "model m\ndim 2\ndomain lo=(0, 0) hi=(1, 1) periodic=(x, y)\n"
      "param r: real = 0.1\n"
      "particles P(10) {\n  u: real = 0\n  w: real = 0\n  q: real = 1\n  n: int = 0\n}\n"
      "step {\n"
      "  density: u[i] = sum(j, |dx| < r, (q[i] * q[j]) * exp(-|dx|))\n"
      "  w[i] = sum(j, |dx| < r, |dx|)\n"
      "}\nschedule {\n  P.q: precision = float\n" +
      schedule + "\n}\n");
  std::vector<partc::VectorTermFact> facts;
  for (const auto& [id, fact] : c.facts.vector_terms) facts.push_back(fact);
  return facts;
}

}  // namespace

TEST_CASE("vector terms: the schedule's arithmetic chooses their lanes", "[analysis]") {
  using partc::ir::Precision;
  // A float-stored variable no longer keeps the scalar walk; double by default.
  const auto plain = vector_terms_of("");
  REQUIRE(plain.size() == 2);
  CHECK(plain[0].vector);
  CHECK(plain[0].arithmetic == Precision::Double);
  CHECK_THAT(plain[0].reason, Catch::Contains("arithmetic: double lanes (double, the default)"));
  // Per statement: only the named one.
  const auto named = vector_terms_of("  density: arithmetic = float");
  CHECK(named[0].arithmetic == Precision::Float);
  CHECK_THAT(named[0].reason, Catch::Contains("float lanes"));
  CHECK_THAT(named[0].reason, Catch::Contains("for this statement (line 17)"));
  CHECK(named[1].arithmetic == Precision::Double);
  // The whole model, and a statement's own entry over it.
  const auto model_wide = vector_terms_of("  arithmetic = float\n  density: arithmetic = double");
  CHECK(model_wide[0].arithmetic == Precision::Double);
  CHECK(model_wide[1].arithmetic == Precision::Float);
  CHECK_THAT(model_wide[1].reason, Catch::Contains("for the whole model (line 17)"));
}

TEST_CASE("statement fusion: one pass computes its pair terms in one arithmetic", "[analysis]") {
  const partc::Compilation c = compile_text(
      "model m\ndim 2\ndomain lo=(0, 0) hi=(1, 1) periodic=(x, y)\n"
      "param r: real = 0.1\n"
      "particles P(10) {\n  u: real = 0\n  w: real = 0\n}\n"
      "step {\n"
      "  density: u[i] = sum(j, |dx| < r, exp(-|dx|))\n"
      "  w[i] = sum(j, |dx| < r, |dx|)\n"
      "}\nschedule {\n  density: arithmetic = float\n}\n");
  CHECK(c.facts.fusion.passes.empty());
  REQUIRE(c.facts.fusion.refused.size() == 1);
  CHECK_THAT(c.facts.fusion.refused[0].reason,
             Catch::Contains("one computes its pair terms in float, the other in double"));
}

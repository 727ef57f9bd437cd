// Decides, per accumulation, whether it needs every particle or only those
// near particle i, and how near.
//
// The condition of `sum(j, cond, e)` is split into its top-level `and`
// terms. A term that bounds |dx| from above by a value that is the same for
// every pair (literals, params, consts) makes the sum a neighbourhood sum:
//   |dx| < r, |dx| <= r, r > |dx|, r >= |dx|      (norm(dx) likewise)
//   dot(dx, dx) < r2 (and the other spellings)   -> radius sqrt(r2)
// With several such terms the smallest bound wins. Anything else (no
// condition, a bound under `or`, a bound that reads particle variables) is
// dense: every particle j is visited. The search structure that serves a
// neighbourhood sum is chosen at run time (brute force for few particles,
// a cell list otherwise) by runtime/partc/neighbour_search.hpp.
#include "analysis/neighbourhood.hpp"

#include "ir/visitor.hpp"
#include "ir/constant.hpp"

namespace partc {

namespace {

using ir::Expr;

bool is_dx(const Expr& e) { return ir::as<ir::Dx>(e) != nullptr; }

bool is_norm_of_dx(const Expr& e) {
  auto c = ir::as<ir::Call>(e);
  return c && c->fn == ir::Function::Norm && is_dx(c->args[0]);
}

bool is_squared_norm_of_dx(const Expr& e) {
  auto c = ir::as<ir::Call>(e);
  return c && c->fn == ir::Function::Dot && is_dx(c->args[0]) && is_dx(c->args[1]);
}

void split_conjunction(const Expr& e, std::vector<Expr>& terms) {
  auto b = ir::as<ir::Binary>(e);
  if (b && b->op == ir::BinaryOp::And) {
    split_conjunction(b->lhs, terms);
    split_conjunction(b->rhs, terms);
  } else {
    terms.push_back(e);
  }
}

// The upper bound on |dx| a term states, or null.
Expr bound_of(const Expr& term) {
  auto b = ir::as<ir::Binary>(term);
  if (!b) return nullptr;
  Expr measured, limit;
  if (b->op == ir::BinaryOp::Lt || b->op == ir::BinaryOp::Le) {
    measured = b->lhs, limit = b->rhs;
  } else if (b->op == ir::BinaryOp::Gt || b->op == ir::BinaryOp::Ge) {
    measured = b->rhs, limit = b->lhs;
  } else {
    return nullptr;
  }
  if (!is_uniform(limit)) return nullptr;
  if (is_norm_of_dx(measured)) return limit;
  if (is_squared_norm_of_dx(measured))
    return std::make_shared<ir::Call>(ir::Type::Real, ir::Function::Sqrt,
                                      std::vector<Expr>{limit}, limit->loc);
  return nullptr;
}

class AccumulationFinder : public ir::Visitor {
 public:
  AccumulationFinder(NeighbourhoodReport& report, const std::string& source)
      : report_(report), source_(source) {}

 public:
  using ir::Visitor::visit;

 protected:
  void visit(const ir::Accumulate& acc) override {
    SearchFact fact;
    std::vector<Expr> terms;
    if (acc.condition) split_conjunction(acc.condition, terms);
    for (const Expr& term : terms) {
      Expr bound = bound_of(term);
      if (!bound) continue;
      fact.radius = fact.radius ? std::make_shared<ir::Call>(
                                      ir::Type::Real, ir::Function::Min,
                                      std::vector<Expr>{fact.radius, bound}, bound->loc)
                                : bound;
    }
    if (fact.radius) {
      fact.kind = SearchFact::Kind::Neighbours;
      fact.reason = "the condition bounds |dx| by " +
                    source_.substr(fact.radius->loc.begin,
                                   fact.radius->loc.end - fact.radius->loc.begin) +
                    ": spatial search with that radius";
    } else {
      fact.reason = acc.condition
                        ? "no upper bound on |dx| shared by all pairs in the condition: dense loop"
                        : "no condition: dense loop over every particle";
    }
    report_[acc.id] = std::move(fact);
  }

 private:
  NeighbourhoodReport& report_;
  const std::string& source_;
};

}  // namespace

NeighbourhoodReport find_neighbourhoods(const ir::Model& model, const std::string& source) {
  NeighbourhoodReport report;
  AccumulationFinder finder(report, source);
  for (const ir::Stage& stage : model.stages)
    for (const ir::Statement& st : stage.statements) finder.visit(st.value);
  return report;
}

}  // namespace partc

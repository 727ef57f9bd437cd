// Decides, per accumulation, whether it needs every particle or only those
// near particle i, and how near.
//
// The condition of `sum(j, cond, e)` is split into its top-level `and`
// terms. A term that bounds |dx| from above by a value that is the same for
// every pair (literals, params, consts) makes the sum a neighbourhood sum:
//   |dx| < r, |dx| <= r, r > |dx|, r >= |dx|      (norm(dx) likewise)
//   dot(dx, dx) < r2 (and the other spellings)   -> radius sqrt(r2)
// With several such terms the smallest bound wins. A bound that reads
// particle variables (DEM's |dx| < r[i] + r[j]) also makes a neighbourhood
// sum when it is a sum of terms that each read one particle's variables: the
// search is then sized by the sum of each term's largest value. Anything else
// (no condition, a bound under `or`, r[i] * r[j]) is dense: every particle j
// is visited. The search structure that serves a
// neighbourhood sum is chosen at run time (brute force for few particles,
// a cell list otherwise) by runtime/partc/search/neighbour_search.hpp.
#include "analysis/neighbourhood.hpp"

#include <set>

#include "ir/visitor.hpp"
#include "ir/constant.hpp"

namespace partc {

namespace {

using ir::Expr;

using ir::is_norm_of_dx;
using ir::is_squared_norm_of_dx;

void split_conjunction(const Expr& e, std::vector<Expr>& terms) {
  auto b = ir::as<ir::Binary>(e);
  if (b && b->op == ir::BinaryOp::And) {
    split_conjunction(b->lhs, terms);
    split_conjunction(b->rhs, terms);
  } else {
    terms.push_back(e);
  }
}

// Which labels an expression reads particles through, and whether it holds
// something no largest value over particles can bound (dx, random, sums).
class ParticleReads : public ir::Visitor {
 public:
  std::set<int> labels;
  bool unboundable = false;
  using ir::Visitor::visit;

 protected:
  void visit(const ir::VarRef& n) override { labels.insert(n.label); }
  void visit(const ir::Dx&) override { unboundable = true; }
  void visit(const ir::Random&) override { unboundable = true; }
  void visit(const ir::Accumulate&) override { unboundable = true; }
};

void split_sum(const Expr& e, std::vector<Expr>& terms) {
  auto b = ir::as<ir::Binary>(e);
  if (b && b->op == ir::BinaryOp::Add) {
    split_sum(b->lhs, terms);
    split_sum(b->rhs, terms);
  } else {
    terms.push_back(e);
  }
}

// The terms a per-particle bound splits into, or none if it does not split.
std::vector<Expr> per_particle_terms(const Expr& limit) {
  std::vector<Expr> terms;
  split_sum(limit, terms);
  for (const Expr& t : terms) {
    ParticleReads reads;
    reads.visit(t);
    if (reads.unboundable || reads.labels.size() > 1) return {};
  }
  return terms;
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
  if (!is_uniform(limit) && per_particle_terms(limit).empty()) return nullptr;
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
  using ir::Visitor::visit;

 protected:
  void visit(const ir::Accumulate& acc) override {
    SearchFact fact;
    std::vector<Expr> terms;
    if (acc.condition) split_conjunction(acc.condition, terms);
    Expr per_particle;  // the first bound that varies per particle
    for (const Expr& term : terms) {
      Expr bound = bound_of(term);
      if (!bound) continue;
      if (!is_uniform(bound)) {
        if (!per_particle) per_particle = bound;
        continue;
      }
      fact.radius = fact.radius ? std::make_shared<ir::Call>(
                                      ir::Type::Real, ir::Function::Min,
                                      std::vector<Expr>{fact.radius, bound}, bound->loc)
                                : bound;
    }
    // A uniform bound is exact and cheaper than any per-particle maximum.
    if (fact.radius) {
      fact.radius_terms = {fact.radius};
    } else if (per_particle) {
      fact.radius = per_particle;
      fact.radius_terms = per_particle_terms(per_particle);
    }
    if (fact.radius) {
      const std::string text = source_.substr(fact.radius->loc.begin,
                                              fact.radius->loc.end - fact.radius->loc.begin);
      fact.kind = SearchFact::Kind::Neighbours;
      // A bound on dot(dx, dx) is kept as sqrt(bound), whose text is the bound's.
      const bool squared = ir::as<ir::Call>(fact.radius) &&
                           ir::as<ir::Call>(fact.radius)->fn == ir::Function::Sqrt &&
                           fact.radius->loc.begin == ir::as<ir::Call>(fact.radius)->args[0]->loc.begin;
      const std::string bounded = squared ? "|dx|^2" : "|dx|";
      fact.reason = is_uniform(fact.radius)
                        ? "the condition bounds " + bounded + " by " + text + ": spatial search with that radius"
                        : "the condition bounds " + bounded + " by " + text +
                              ": spatial search sized by its largest value over the particles";
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
    for (const ir::Statement& st : stage.statements) {
      finder.visit(st.value);
      finder.visit(st.solve_operator);
    }
  return report;
}

}  // namespace partc

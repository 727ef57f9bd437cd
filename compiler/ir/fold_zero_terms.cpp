#include "ir/fold_zero_terms.hpp"

#include <memory>

#include "ir/constant.hpp"
#include "ir/terms.hpp"
#include "ir/visitor.hpp"

namespace partc::ir {

namespace {

struct HasRandom : Visitor {
  bool found = false;
  using Visitor::visit;
  void visit(const Random&) override { found = true; }
};

bool has_random(const Expr& e) {
  HasRandom r;
  r.visit(e);
  return r.found;
}

// Whether e is 0 for every value of what it reads: a constant 0, a product
// with such a factor, a quotient with such a numerator, or a vec of them.
bool zero(const Expr& e, const Model& model) {
  if (const auto value = evaluate_constant(e, model)) return *value == 0;
  switch (e->kind) {
    case ExprKind::Unary: return as<Unary>(e)->op == UnaryOp::Neg && zero(as<Unary>(e)->operand, model);
    case ExprKind::Binary: {
      auto b = as<Binary>(e);
      if (b->op == BinaryOp::Mul) return zero(b->lhs, model) || zero(b->rhs, model);
      if (b->op == BinaryOp::Div) return zero(b->lhs, model);
      return false;
    }
    case ExprKind::MakeVec:
      for (const Expr& c : as<MakeVec>(e)->components)
        if (!zero(c, model)) return false;
      return true;
    case ExprKind::Accumulate: {
      auto acc = as<Accumulate>(e);
      return acc->reduction == Reduction::Sum && zero(acc->body, model);
    }
    default: return false;
  }
}

// Whether there is anything to fold: a literal is as plain as 0 gets.
bool plain(const Expr& e) {
  if (e->kind == ExprKind::Literal) return true;
  if (e->kind != ExprKind::MakeVec) return false;
  for (const Expr& c : as<MakeVec>(e)->components)
    if (c->kind != ExprKind::Literal) return false;
  return true;
}

}  // namespace

std::vector<FoldedTerm> fold_zero_terms(Model& model) {
  std::vector<FoldedTerm> folded;
  for (Stage& stage : model.stages) {
    std::vector<Statement> kept;
    std::vector<int> index(stage.statements.size() + 1);  // old position -> new
    for (std::size_t s = 0; s < stage.statements.size(); ++s) {
      index[s] = static_cast<int>(kept.size());
      Statement st = stage.statements[s];
      const bool assigns =
          st.op == AssignOp::Set || st.op == AssignOp::Add || st.op == AssignOp::Sub;
      if (!assigns || st.solve_operator || plain(st.value)) {
        kept.push_back(std::move(st));
        continue;
      }
      // Instantiation joins the contributions of several effects, one per origin.
      const bool own = st.origins.empty();
      const std::size_t n = own ? 1 : st.origins.size();
      const std::vector<Term> terms = split_terms(st.value, n);
      std::vector<Term> live;
      std::vector<Origin> origins;
      for (std::size_t k = 0; k < terms.size(); ++k) {
        if (zero(terms[k].value, model) && !has_random(terms[k].value)) {
          const std::string target =
              st.observable >= 0 ? model.observables[st.observable].name
                                 : model.sets[st.set].name + "." + model.sets[st.set].vars[st.var].name;
          folded.push_back({own ? "" : st.origins[k].effect, own ? st.loc : st.origins[k].loc,
                            target});
          continue;
        }
        live.push_back(terms[k]);
        if (!own) origins.push_back(st.origins[k]);
      }
      if (live.size() == terms.size()) {
        kept.push_back(std::move(st));
        continue;
      }
      if (live.empty()) {
        if (st.op != AssignOp::Set) continue;  // adds nothing
        st.value = zero_of(st.value->type, model.dim, st.value->loc);  // still theirs
      } else {
        st.value = join_terms(live, st.value->loc);
        st.origins = std::move(origins);
      }
      kept.push_back(std::move(st));
    }
    index[stage.statements.size()] = static_cast<int>(kept.size());
    for (Iterate& loop : stage.loops) {
      loop.first = index[loop.first];
      loop.last = index[loop.last];
    }
    stage.statements = std::move(kept);
  }
  return folded;
}

}  // namespace partc::ir

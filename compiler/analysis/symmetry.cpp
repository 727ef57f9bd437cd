// Decides, per accumulation, whether one evaluation of its term per
// unordered pair of particles can serve both particles of the pair
// (Newton's third law).
//
// Exchanging the pair, T: i <-> j with dx -> -dx, turns the term particle i
// receives from j into the term j receives from i. If T leaves the condition
// unchanged and leaves the term unchanged (even) or negates it (odd), a loop
// over pairs {i, j} can add the term to i and +-term to j. Parity is decided
// bottom-up: dx is odd, values common to all pairs (literals, params, consts)
// are even, and the operations combine parities as in algebra (odd * odd is
// even, |odd| is even, even + odd is neither). A particle variable read
// through one label is neither on its own, but a commutative operation on it
// and its twin read through the other label is even -- r[i] + r[j],
// m[i] * m[j], max(h[i], h[j]) -- and a difference of twins, v[j] - v[i], is
// odd. Products are judged whole: k * q[i] * q[j] / r is even although
// (k * q[i]) * q[j] groups q[i] apart from its twin, because factors pair up
// with their twins across the product's grouping. A user function's call is
// judged by its body with the arguments put in (ir/inline_calls.hpp):
// amix(a[i], a[j]) with fn amix(x, y) = sqrt(x * y) is even, because x * y
// becomes a[i] * a[j]; past the inlining budget, a call is even when its
// arguments are. The rules are sound, not complete:
// what they cannot show symmetric is evaluated both ways, which is always
// correct.
//
// Only sums and counts over the statement's own set qualify: a pair's term is
// added into both particles' totals, which a min or max does not do, and a
// particle of another set computes no such total.
#include "analysis/symmetry.hpp"

#include <fmt/format.h>

#include "ir/inline_calls.hpp"
#include "ir/visitor.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace {

using ir::Expr;

enum class Parity { Even, Odd, Neither };

// A product's or quotient's parity.
Parity times(Parity a, Parity b) {
  if (a == Parity::Neither || b == Parity::Neither) return Parity::Neither;
  return a == b ? Parity::Even : Parity::Odd;
}

// A sum's parity, or a vec's: its parts must all change the same way.
Parity alike(Parity a, Parity b) { return a == b ? a : Parity::Neither; }

bool is_commutative(ir::BinaryOp op) {
  using ir::BinaryOp;
  return op == BinaryOp::Add || op == BinaryOp::Mul || op == BinaryOp::Eq || op == BinaryOp::Ne ||
         op == BinaryOp::And || op == BinaryOp::Or;
}

// Parities under the exchange of the statement's label (0) with the label
// `j` of one accumulation.
class PairExchange {
 public:
  PairExchange(const ir::Model& model, int j) : model_(model), j_(j) {}

  // The innermost expression found to be neither, first in evaluation order:
  // where the asymmetry starts, for the reason.
  Expr culprit;

  Parity parity(const Expr& e) {
    switch (e->kind) {
      case ir::ExprKind::Literal:
      case ir::ExprKind::ParamRef:
      case ir::ExprKind::ConstRef:
      case ir::ExprKind::ObservableRef: return Parity::Even;
      case ir::ExprKind::Dx: return Parity::Odd;
      case ir::ExprKind::VarRef:
        return neither(e);  // one particle's value, unless twinned above
      // -x changes as x does; `not b` as b does (a bool is never odd).
      case ir::ExprKind::Unary: return parity(ir::as<ir::Unary>(e)->operand);
      case ir::ExprKind::Binary: return binary(*ir::as<ir::Binary>(e), e);
      case ir::ExprKind::Call: return call(*ir::as<ir::Call>(e), e);
      case ir::ExprKind::MakeVec: {
        const auto& components = ir::as<ir::MakeVec>(e)->components;
        Parity p = parity(components[0]);
        for (std::size_t k = 1; k < components.size(); ++k) p = alike(p, parity(components[k]));
        return found(e, p);
      }
      case ir::ExprKind::Component: return parity(ir::as<ir::Component>(e)->vec);
      case ir::ExprKind::FnCall:
        if (const Expr body = ir::inline_calls(e, model_)) return parity(body);
        return found(e, all_even(ir::as<ir::FnCall>(e)->args));
      // T picks the same branch when it leaves the condition alone.
      case ir::ExprKind::Select: {
        auto s = ir::as<ir::Select>(e);
        if (parity(s->condition) != Parity::Even) return neither(e);
        return found(e, alike(parity(s->then), parity(s->otherwise)));
      }
      // Random draws are rejected in accumulations by sema, nested ones too,
      // and function arguments exist only in function bodies.
      case ir::ExprKind::Random:
      case ir::ExprKind::Accumulate:
      case ir::ExprKind::FnArg: return neither(e);
    }
    internal_error("PairExchange: unknown expression kind");
  }

 private:
  Parity neither(const Expr& e) {
    if (!culprit) culprit = e;
    return Parity::Neither;
  }
  Parity found(const Expr& e, Parity p) { return p == Parity::Neither ? neither(e) : p; }

  // Pure functions of values T leaves alone are left alone too.
  Parity all_even(const std::vector<Expr>& args) {
    Parity p = Parity::Even;
    for (const Expr& a : args)
      if (parity(a) != Parity::Even) p = Parity::Neither;
    return p;
  }

  // The factors of a product: a * b / c gives a and b over c.
  static void factors(const Expr& e, bool over, std::vector<Expr>& up, std::vector<Expr>& down) {
    if (e->kind == ir::ExprKind::Binary) {
      auto b = ir::as<ir::Binary>(e);
      if (b->op == ir::BinaryOp::Mul || b->op == ir::BinaryOp::Div) {
        factors(b->lhs, over, up, down);
        factors(b->rhs, b->op == ir::BinaryOp::Div ? !over : over, up, down);
        return;
      }
    }
    (over ? down : up).push_back(e);
  }

  // A product's parity: each factor with its twin beside it (on the same side
  // of the fraction) is even as a pair; the other factors by their own.
  Parity product(const Expr& self) {
    std::vector<Expr> up, down;
    factors(self, false, up, down);
    Parity p = Parity::Even;
    for (std::vector<Expr>* side : {&up, &down}) {
      std::vector<bool> paired(side->size(), false);
      for (std::size_t a = 0; a < side->size(); ++a) {
        if (paired[a]) continue;
        for (std::size_t b = a + 1; b < side->size() && !paired[a]; ++b)
          if (!paired[b] && twins((*side)[a], (*side)[b])) paired[a] = paired[b] = true;
        if (!paired[a]) p = times(p, parity((*side)[a]));
      }
    }
    return found(self, p);
  }

  Parity binary(const ir::Binary& b, const Expr& self) {
    if (b.op == ir::BinaryOp::Mul || b.op == ir::BinaryOp::Div) return product(self);
    // T turns `a op b` into `b op a` when b is a's twin.
    if (twins(b.lhs, b.rhs)) {
      if (is_commutative(b.op)) return Parity::Even;
      if (b.op == ir::BinaryOp::Sub) return Parity::Odd;
    }
    const Parity l = parity(b.lhs), r = parity(b.rhs);
    switch (b.op) {
      case ir::BinaryOp::Add:
      case ir::BinaryOp::Sub: return found(self, alike(l, r));
      // -a == -b exactly when a == b.
      case ir::BinaryOp::Eq:
      case ir::BinaryOp::Ne:
        return found(self, alike(l, r) == Parity::Neither ? Parity::Neither : Parity::Even);
      // An odd operand would turn < into >; and/or take bools, never odd.
      default:
        return found(self, l == Parity::Even && r == Parity::Even ? Parity::Even : Parity::Neither);
    }
  }

  Parity call(const ir::Call& c, const Expr& self) {
    // T turns min(a, b) into min(b, a) when b is a's twin.
    if ((c.fn == ir::Function::Min || c.fn == ir::Function::Max) && twins(c.args[0], c.args[1]))
      return Parity::Even;
    switch (c.fn) {
      // |-x| = |x|, cos(-x) = cos(x).
      case ir::Function::Norm:
      case ir::Function::Abs:
      case ir::Function::Cos: {
        const Parity p = parity(c.args[0]);
        return found(self, p == Parity::Neither ? Parity::Neither : Parity::Even);
      }
      // Odd functions: sin(-x) = -sin(x), and so on.
      case ir::Function::Sin:
      case ir::Function::Tan:
      case ir::Function::Asin:
      case ir::Function::Atan:
      case ir::Function::Tanh:
      case ir::Function::Sign: return parity(c.args[0]);
      case ir::Function::Dot:
      case ir::Function::Cross: return found(self, times(parity(c.args[0]), parity(c.args[1])));
      default: return found(self, all_even(c.args));
    }
  }

  int exchanged(int label) const { return label == 0 ? j_ : label == j_ ? 0 : label; }

  bool all_twins(const std::vector<Expr>& a, const std::vector<Expr>& b) const {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k)
      if (!twins(a[k], b[k])) return false;
    return true;
  }

  // Whether b is a with labels i and j exchanged, neither holding dx: then
  // T maps a to b and b to a.
  bool twins(const Expr& a, const Expr& b) const {
    if (a->kind != b->kind || a->type != b->type) return false;
    switch (a->kind) {
      case ir::ExprKind::Literal:
        return ir::as<ir::Literal>(a)->value == ir::as<ir::Literal>(b)->value;
      case ir::ExprKind::ParamRef:
        return ir::as<ir::ParamRef>(a)->param == ir::as<ir::ParamRef>(b)->param;
      case ir::ExprKind::ConstRef:
        return ir::as<ir::ConstRef>(a)->constant == ir::as<ir::ConstRef>(b)->constant;
      case ir::ExprKind::ObservableRef:
        return ir::as<ir::ObservableRef>(a)->observable == ir::as<ir::ObservableRef>(b)->observable;
      case ir::ExprKind::VarRef: {
        auto x = ir::as<ir::VarRef>(a), y = ir::as<ir::VarRef>(b);
        return x->set == y->set && x->var == y->var && exchanged(x->label) == y->label;
      }
      case ir::ExprKind::Unary: {
        auto x = ir::as<ir::Unary>(a), y = ir::as<ir::Unary>(b);
        return x->op == y->op && twins(x->operand, y->operand);
      }
      case ir::ExprKind::Binary: {
        auto x = ir::as<ir::Binary>(a), y = ir::as<ir::Binary>(b);
        return x->op == y->op && twins(x->lhs, y->lhs) && twins(x->rhs, y->rhs);
      }
      case ir::ExprKind::Call: {
        auto x = ir::as<ir::Call>(a), y = ir::as<ir::Call>(b);
        return x->fn == y->fn && all_twins(x->args, y->args);
      }
      case ir::ExprKind::MakeVec:
        return all_twins(ir::as<ir::MakeVec>(a)->components, ir::as<ir::MakeVec>(b)->components);
      case ir::ExprKind::Component: {
        auto x = ir::as<ir::Component>(a), y = ir::as<ir::Component>(b);
        return x->index == y->index && twins(x->vec, y->vec);
      }
      case ir::ExprKind::FnCall: {
        auto x = ir::as<ir::FnCall>(a), y = ir::as<ir::FnCall>(b);
        return x->fn == y->fn && all_twins(x->args, y->args);
      }
      case ir::ExprKind::Select: {
        auto x = ir::as<ir::Select>(a), y = ir::as<ir::Select>(b);
        return twins(x->condition, y->condition) && twins(x->then, y->then) &&
               twins(x->otherwise, y->otherwise);
      }
      // T negates dx, so dx has no twin of the same form; the rest cannot
      // occur in an accumulation.
      case ir::ExprKind::Dx:
      case ir::ExprKind::Random:
      case ir::ExprKind::Accumulate:
      case ir::ExprKind::FnArg: return false;
    }
    internal_error("PairExchange: unknown expression kind");
  }

  const ir::Model& model_;
  const int j_;
};

// Why `what` (the condition, the term) is not symmetric, naming the variable
// read without its twin when that is where the asymmetry starts.
std::string asymmetry(const std::string& what, const Expr& culprit, const std::string& exchange,
                      const ir::Model& model, const ir::Statement& st, int j) {
  auto v = ir::as<ir::VarRef>(culprit);
  if (!v) return what + " is not symmetric under " + exchange;
  const std::string& name = model.sets[v->set].vars[v->var].name;
  const int twin = v->label == 0 ? j : 0;
  return fmt::format("{} reads {}[{}] alone, not paired symmetrically with {}[{}]", what, name,
                     st.labels[v->label].name, name, st.labels[twin].name);
}

PairSymmetryFact judge(const ir::Model& model, const ir::Statement& st, const ir::Accumulate& acc) {
  const ir::Label& i = st.labels[0];
  const ir::Label& j = st.labels[acc.label];
  const std::string exchange = i.name + " <-> " + j.name + ", dx -> -dx";
  PairSymmetryFact fact;
  if (acc.reduction == ir::Reduction::Min || acc.reduction == ir::Reduction::Max) {
    fact.reason = std::string(ir::reduction_name(acc.reduction)) +
                  " is not a sum: only sums and counts add a pair's term to both particles";
    return fact;
  }
  if (st.schedule.compensated) {
    fact.reason = "the schedule asks for compensated summation, which each particle does over "
                  "its own terms, in order";
    return fact;
  }
  if (j.set != i.set) {
    fact.reason = fmt::format("{} ranges over {}, not {}: only {} takes the term", j.name,
                              model.sets[j.set].name, model.sets[i.set].name, i.name);
    return fact;
  }
  // No condition: every pair, both ways.
  PairExchange condition(model, acc.label);
  if (acc.condition && condition.parity(acc.condition) != Parity::Even) {
    fact.reason = asymmetry("the condition", condition.culprit, exchange, model, st, acc.label);
    return fact;
  }
  if (acc.reduction == ir::Reduction::Count) {
    fact.newton = true;
    fact.reason = "the condition is symmetric under " + exchange;
    return fact;
  }
  PairExchange term(model, acc.label);
  switch (term.parity(acc.body)) {
    case Parity::Even:
      fact.newton = true;
      fact.reason = "the term and the condition are symmetric under " + exchange + ": " + j.name +
                    " takes +term";
      break;
    case Parity::Odd:
      fact.newton = true;
      fact.sign = -1;
      fact.reason = "the term is antisymmetric and the condition symmetric under " + exchange +
                    ": " + j.name + " takes -term";
      break;
    case Parity::Neither:
      fact.reason = asymmetry("the term", term.culprit, exchange, model, st, acc.label);
      break;
  }
  return fact;
}

}  // namespace

PairSymmetryReport find_pair_symmetry(const ir::Model& model) {
  PairSymmetryReport report;
  for (const ir::Stage& stage : model.stages)
    for (const ir::Statement& st : stage.statements)
      for (const ir::Accumulate* acc : ir::accumulations_in(st))
        report[acc->id] = st.observable >= 0 || st.solve_operator
                              ? PairSymmetryFact{false, 0, "an observable's sum, or a solve's operator"}
                              : judge(model, st, *acc);
  return report;
}

}  // namespace partc

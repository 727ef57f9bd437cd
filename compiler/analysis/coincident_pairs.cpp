// Decides, per accumulation, whether its term is singular where |dx| = 0 and
// whether the condition keeps such pairs out; warns when it does not. A sum
// over j of i's own set includes j = i, where dx = 0 in every run, and any
// two particles may come to share a position: `dx / |dx|` is then 0 / 0, the
// NaN spreads through the sum, and the run stops at the next finite check,
// far from the line that caused it.
//
// Singular at |dx| = 0: a division by something that vanishes there (|dx|,
// dot(dx, dx), a component of dx, a product or positive power of one, a
// user function's argument that is one), a negative power of one, its log.
// Excluded: by an `and` term of the condition that implies |dx| > 0 (|dx| > c
// with c >= 0, |dx| >= c with c > 0, |dx| != 0; and so for anything else 0 at
// |dx| = 0: dot(dx, dx), dx.x, a function's argument r = |dx|); inside
// if(c, a, b), a when c implies |dx| > 0 and b when `not c` does (|dx| < c
// with c > 0, |dx| <= 0, |dx| == 0). A param in a bound is judged by its
// default value, a const by its definition.
//
// Runs after sema, on the typed IR with user functions resolved; nothing
// else depends on it: it adds warnings and --explain facts only.
#include "analysis/coincident_pairs.hpp"

#include <fmt/format.h>

#include <map>
#include <utility>
#include <vector>

#include "ir/visitor.hpp"

namespace partc {

namespace {

using ir::Expr;

// Whether each argument of the user function being read vanishes at |dx| = 0.
using ArgFacts = std::vector<bool>;

struct Singularity {
  const ir::ExprNode* at = nullptr;  // what is 0 at |dx| = 0
  std::string op;                    // "divides by" it, "takes the log of" it, ...
  std::string outer_fn, inner_fn;    // the user functions it is passed through, if any

  // What the term does with it, as "the term ___ it".
  std::string what() const {
    if (outer_fn.empty()) return op;
    return "passes it to " + outer_fn +
           (inner_fn == outer_fn ? "" : " (and on to " + inner_fn + ")") + ", which " + op;
  }
};

class CoincidentTerms {
 public:
  CoincidentTerms(const ir::Model& model, int label) : model_(model), label_(label) {}

  // The label dx starts from, once a vanishing dx has been seen.
  int from() const { return from_; }

  bool vanishes(const Expr& e, const ArgFacts& args) {
    if (!e) return false;
    if (auto d = ir::as<ir::Dx>(e)) {
      if (d->to != label_) return false;
      from_ = d->from;
      return true;
    }
    if (auto a = ir::as<ir::FnArg>(e))
      return static_cast<std::size_t>(a->index) < args.size() && args[a->index];
    if (auto u = ir::as<ir::Unary>(e))
      return u->op == ir::UnaryOp::Neg && vanishes(u->operand, args);
    if (auto b = ir::as<ir::Binary>(e)) {
      switch (b->op) {
        case ir::BinaryOp::Mul: return vanishes(b->lhs, args) || vanishes(b->rhs, args);
        case ir::BinaryOp::Div: return vanishes(b->lhs, args);
        case ir::BinaryOp::Add:
        case ir::BinaryOp::Sub: return vanishes(b->lhs, args) && vanishes(b->rhs, args);
        default: return false;
      }
    }
    if (auto c = ir::as<ir::Call>(e)) {
      switch (c->fn) {
        case ir::Function::Norm:
        case ir::Function::Sqrt:
        case ir::Function::Abs: return vanishes(c->args[0], args);
        case ir::Function::Dot:
        case ir::Function::Cross: return vanishes(c->args[0], args) || vanishes(c->args[1], args);
        case ir::Function::Pow: return sign(c->args[1]) > 0 && vanishes(c->args[0], args);
        default: return false;
      }
    }
    if (auto c = ir::as<ir::Component>(e)) return vanishes(c->vec, args);
    if (auto v = ir::as<ir::MakeVec>(e)) {
      for (const Expr& c : v->components)
        if (!vanishes(c, args)) return false;
      return true;
    }
    if (auto s = ir::as<ir::Select>(e))
      return vanishes(s->then, args) && vanishes(s->otherwise, args);
    if (auto f = ir::as<ir::FnCall>(e)) {
      const Call key{f->fn, facts_of(*f, args)};
      if (auto known = vanishing_calls_.find(key); known != vanishing_calls_.end())
        return known->second;
      return vanishing_calls_[key] = vanishes(model_.functions[f->fn].body, key.second);
    }
    return false;
  }

  // The first place where e is singular at |dx| = 0 and not guarded.
  Singularity singular(const Expr& e, const ArgFacts& args) {
    if (!e || ir::as<ir::Accumulate>(e)) return {};  // an inner sum's dx is its own
    if (auto b = ir::as<ir::Binary>(e)) {
      if (b->op == ir::BinaryOp::Div && vanishes(b->rhs, args))
        return {b->rhs.get(), "divides by", {}, {}};
      return first(singular(b->lhs, args), [&] { return singular(b->rhs, args); });
    }
    if (auto c = ir::as<ir::Call>(e)) {
      if (c->fn == ir::Function::Pow && sign(c->args[1]) < 0 && vanishes(c->args[0], args))
        return {c->args[0].get(), "takes a negative power of", {}, {}};
      if (c->fn == ir::Function::Log && vanishes(c->args[0], args))
        return {c->args[0].get(), "takes the log of", {}, {}};
      for (const Expr& a : c->args)
        if (Singularity s = singular(a, args); s.at) return s;
      return {};
    }
    if (auto s = ir::as<ir::Select>(e)) {
      if (Singularity found = singular(s->condition, args); found.at) return found;
      if (!nonzero_if(s->condition, true, args))
        if (Singularity found = singular(s->then, args); found.at) return found;
      if (!nonzero_if(s->condition, false, args)) return singular(s->otherwise, args);
      return {};
    }
    if (auto f = ir::as<ir::FnCall>(e)) {
      for (const Expr& a : f->args)
        if (Singularity s = singular(a, args); s.at) return s;
      const ir::UserFn& fn = model_.functions[f->fn];
      const Call key{f->fn, facts_of(*f, args)};
      auto known = singular_calls_.find(key);
      if (known == singular_calls_.end())
        known = singular_calls_.emplace(key, singular(fn.body, key.second)).first;
      const Singularity& inner = known->second;
      const ArgFacts& facts = key.second;
      if (!inner.at) return {};
      std::size_t k = 0;  // the argument that is 0 (the first, if several are)
      while (!facts[k]) ++k;
      return {f->args[k].get(), inner.op, fn.name,
              inner.inner_fn.empty() ? fn.name : inner.inner_fn};
    }
    if (auto u = ir::as<ir::Unary>(e)) return singular(u->operand, args);
    if (auto c = ir::as<ir::Component>(e)) return singular(c->vec, args);
    if (auto v = ir::as<ir::MakeVec>(e)) {
      for (const Expr& c : v->components)
        if (Singularity s = singular(c, args); s.at) return s;
    }
    return {};
  }

  // Whether c being `holds` implies |dx| > 0. A comparison of anything that
  // vanishes at |dx| = 0 (|dx|, dx.x, a function's argument r = |dx|) that
  // implies it is not 0 implies |dx| > 0.
  bool nonzero_if(const Expr& c, bool holds, const ArgFacts& args) {
    if (auto u = ir::as<ir::Unary>(c); u && u->op == ir::UnaryOp::Not)
      return nonzero_if(u->operand, !holds, args);
    auto b = ir::as<ir::Binary>(c);
    if (!b) return false;
    // a and b holds: either implies it. a and b fails: both failing must.
    if (b->op == ir::BinaryOp::And)
      return holds ? nonzero_if(b->lhs, true, args) || nonzero_if(b->rhs, true, args)
                   : nonzero_if(b->lhs, false, args) && nonzero_if(b->rhs, false, args);
    if (b->op == ir::BinaryOp::Or)
      return holds ? nonzero_if(b->lhs, true, args) && nonzero_if(b->rhs, true, args)
                   : nonzero_if(b->lhs, false, args) || nonzero_if(b->rhs, false, args);
    // Spelled as "vanishing OP bound".
    ir::BinaryOp op = b->op;
    Expr bound = b->rhs;
    if (b->lhs->type != ir::Type::Real || !vanishes(b->lhs, args)) {
      if (b->rhs->type != ir::Type::Real || !vanishes(b->rhs, args)) return false;
      bound = b->lhs;
      op = mirrored(op);
    }
    if (!holds) op = negated(op);
    const int s = sign(bound);
    switch (op) {
      case ir::BinaryOp::Gt: return s >= 0;
      case ir::BinaryOp::Ge: return s > 0;
      case ir::BinaryOp::Ne: return s == 0;
      default: return false;
    }
  }

 private:
  ArgFacts facts_of(const ir::FnCall& call, const ArgFacts& args) {
    ArgFacts facts;
    for (const Expr& a : call.args) facts.push_back(vanishes(a, args));
    return facts;
  }

  template <class Next>
  static Singularity first(Singularity found, Next next) {
    return found.at ? found : next();
  }

  static ir::BinaryOp mirrored(ir::BinaryOp op) {  // b < a for a > b
    switch (op) {
      case ir::BinaryOp::Lt: return ir::BinaryOp::Gt;
      case ir::BinaryOp::Le: return ir::BinaryOp::Ge;
      case ir::BinaryOp::Gt: return ir::BinaryOp::Lt;
      case ir::BinaryOp::Ge: return ir::BinaryOp::Le;
      default: return op;
    }
  }
  static ir::BinaryOp negated(ir::BinaryOp op) {  // not (a < b) is a >= b
    switch (op) {
      case ir::BinaryOp::Lt: return ir::BinaryOp::Ge;
      case ir::BinaryOp::Le: return ir::BinaryOp::Gt;
      case ir::BinaryOp::Gt: return ir::BinaryOp::Le;
      case ir::BinaryOp::Ge: return ir::BinaryOp::Lt;
      case ir::BinaryOp::Eq: return ir::BinaryOp::Ne;
      case ir::BinaryOp::Ne: return ir::BinaryOp::Eq;
      default: return op;
    }
  }

  // -1, 0 or 1 when the sign of e is known (params at their defaults), else 2.
  int sign(const Expr& e) const {
    constexpr int unknown = 2;
    if (auto l = ir::as<ir::Literal>(e)) return (l->value > 0) - (l->value < 0);
    if (auto p = ir::as<ir::ParamRef>(e)) return sign(model_.params[p->param].default_value);
    if (auto c = ir::as<ir::ConstRef>(e)) return sign(model_.consts[c->constant].value);
    if (auto u = ir::as<ir::Unary>(e)) {
      const int s = sign(u->operand);
      return u->op == ir::UnaryOp::Neg && s != unknown ? -s : unknown;
    }
    if (auto b = ir::as<ir::Binary>(e)) {
      const int l = sign(b->lhs), r = sign(b->rhs);
      if (l == unknown || r == unknown) return unknown;
      if (b->op == ir::BinaryOp::Mul || (b->op == ir::BinaryOp::Div && r != 0)) return l * r;
      if (b->op == ir::BinaryOp::Add && l * r >= 0) return l != 0 ? l : r;
      return unknown;
    }
    if (auto c = ir::as<ir::Call>(e)) {
      if (c->fn == ir::Function::Exp) return 1;
      if (c->fn == ir::Function::Sqrt || c->fn == ir::Function::Abs) {
        const int s = sign(c->args[0]);
        return s == unknown ? unknown : s != 0;
      }
    }
    return unknown;
  }

  const ir::Model& model_;
  const int label_;
  int from_ = -1;
  // A function's body is read once per (function, which arguments vanish):
  // functions calling functions twice each would otherwise cost 2^depth.
  using Call = std::pair<int, ArgFacts>;
  std::map<Call, bool> vanishing_calls_;
  std::map<Call, Singularity> singular_calls_;
};

class AccumulationFinder : public ir::Visitor {
 public:
  AccumulationFinder(const ir::Model& model, const std::string& source, CoincidenceReport& report)
      : model_(model), source_(source), report_(report) {}
  const ir::Statement* statement = nullptr;
  using ir::Visitor::visit;

 protected:
  void visit(const ir::Accumulate& acc) override {
    ir::Visitor::visit(acc);  // inner sums first: each has its own dx
    CoincidenceFact fact;
    CoincidentTerms terms(model_, acc.label);
    const Singularity found = terms.singular(acc.body, {});
    fact.excluded = acc.condition && terms.nonzero_if(acc.condition, true, {});
    if (found.at) {
      fact.singular = true;
      const std::string zero = text(found.at->loc);
      const ir::Label& to = statement->labels[acc.label];
      const bool self = terms.from() >= 0 && statement->labels[terms.from()].set == to.set &&
                        !excludes_self(acc.condition, terms.from(), acc.label);
      const std::string where = self ? "for " + to.name + " = " +
                                           statement->labels[terms.from()].name +
                                           " itself and where particles coincide"
                                     : "where particles coincide";
      fact.reason = fmt::format("{} is 0 {}, and the term {} it: {}", zero, where, found.what(),
                                fact.excluded ? "the condition excludes |dx| = 0"
                                              : "the condition allows |dx| = 0 (warning)");
      if (!fact.excluded)
        fact.warning = Diagnostic{
            found.at->loc,
            fmt::format("{} is 0 {}, and the term {} it: NaN or Inf there", zero, where,
                        found.what()),
            "add '|dx| > 0' to the condition, as in sum(" + to.name +
                ", |dx| < rc and |dx| > 0, ...), or guard the term with if(|dx| > 0, ..., ...)",
            true};
    }
    report_[acc.id] = std::move(fact);
  }

 private:
  // Whether an `and` term of the condition is id[j] != id[i].
  static bool excludes_self(const Expr& condition, int from, int to) {
    auto b = ir::as<ir::Binary>(condition);
    if (!b) return false;
    if (b->op == ir::BinaryOp::And)
      return excludes_self(b->lhs, from, to) || excludes_self(b->rhs, from, to);
    const auto id_of = [](const Expr& e, int label) {
      auto v = ir::as<ir::VarRef>(e);
      return v && v->var == ir::kId && v->label == label;
    };
    return b->op == ir::BinaryOp::Ne && ((id_of(b->lhs, from) && id_of(b->rhs, to)) ||
                                         (id_of(b->lhs, to) && id_of(b->rhs, from)));
  }

  std::string text(Location loc) const { return source_.substr(loc.begin, loc.end - loc.begin); }

  const ir::Model& model_;
  const std::string& source_;
  CoincidenceReport& report_;
};

}  // namespace

CoincidenceReport find_coincident_pairs(const ir::Model& model, const std::string& source) {
  CoincidenceReport report;
  AccumulationFinder finder(model, source, report);
  for (const ir::Stage& stage : model.stages)
    for (const ir::Statement& st : stage.statements) {
      finder.statement = &st;
      finder.visit(st.value);
      finder.visit(st.solve_operator);
    }
  return report;
}

}  // namespace partc

// Decides how each solve's operator becomes a matrix: its terms, each a
// diagonal entry or a sum over j of coefficient(i, j) * w[j], and under which
// conditions on i each applies. Runs after the neighbourhood analysis, whose
// facts say whether every sum has a cutoff (a sparse matrix) or not (dense).
//
// The operator must be linear in w, and homogeneous: every part of it a
// multiple of w[i] or of w[j] inside a sum. Linear forms are recognised as
// algebra builds them: w[i] and w[j] (coefficient 1); a * L and L * a, L / a,
// -L, L + L, L - L where a does not read w; if(c, L1, L2) with c free of w,
// whose branches become guarded terms (a branch 0 contributes nothing); and a
// sum(j, cond, L_j) over the unknown's set with cond free of w. Anything else
// that reads w (w[j] * w[j], exp(w[j]), w[i] inside a sum, a min over j) is an
// error at its place in the .part line: it is not a linear system, or not one
// partc can assemble.
#include "analysis/linear_operator.hpp"

#include "ir/visitor.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace {

using ir::Expr;

class ReadsUnknown : public ir::Visitor {
 public:
  ReadsUnknown(int set, int var) : set_(set), var_(var) {}
  bool found = false;
  using ir::Visitor::visit;

 protected:
  void visit(const ir::VarRef& n) override { found |= n.set == set_ && n.var == var_; }

 private:
  int set_, var_;
};

Expr times(const Expr& a, const Expr& b, ir::BinaryOp op = ir::BinaryOp::Mul) {
  if (!a) return op == ir::BinaryOp::Mul ? b : nullptr;  // callers never divide 1 by b
  if (!b) return a;
  if (auto lit = ir::as<ir::Literal>(a); lit && lit->value == -1 && op == ir::BinaryOp::Mul)
    return std::make_shared<ir::Unary>(ir::Type::Real, ir::UnaryOp::Neg, b, b->loc);
  return std::make_shared<ir::Binary>(ir::Type::Real, op, a, b, a->loc);
}

bool is_zero(const Expr& e) {
  auto lit = ir::as<ir::Literal>(e);
  return lit && lit->value == 0;
}

class Linearise {
 public:
  Linearise(const ir::Statement& st, const std::string& unknown) : st_(st), unknown_(unknown) {}

  // A factor of a term is computed per row, before its sums: no sum in it.
  Expr factor(const Expr& e) const {
    if (!ir::accumulations_in(e).empty())
      not_linear(e, "a sum as a factor: compute it into a variable in a statement before");
    return e;
  }

  bool reads_unknown(const Expr& e) const {
    ReadsUnknown reads(st_.set, st_.var);
    reads.visit(e);
    return reads.found;
  }

  // The terms of a linear form at the top of the operator (over i).
  void terms(const Expr& e, const Expr& scale, std::vector<std::pair<Expr, bool>> guards,
             std::vector<OperatorTerm>& out) {
    if (auto v = ir::as<ir::VarRef>(e); v && reads_unknown(e)) {
      if (v->label != 0)
        not_linear(e, "outside a sum, only " + unknown_ + "[" + label(0) + "] is known");
      out.push_back({std::move(guards), scale, nullptr, nullptr});
      return;
    }
    if (auto acc = ir::as<ir::Accumulate>(e)) {
      if (acc->reduction != ir::Reduction::Sum)
        not_linear(e, std::string(ir::reduction_name(acc->reduction)) + " is not linear");
      if (st_.labels[acc->label].set != st_.set)
        not_linear(e, "the sum runs over another set than " + unknown_ + "'s");
      if (acc->condition && reads_unknown(acc->condition))
        not_linear(acc->condition, "the condition reads " + unknown_);
      out.push_back({std::move(guards), scale, acc, coefficient(acc->body, acc->label)});
      return;
    }
    if (auto b = ir::as<ir::Binary>(e)) {
      const bool l = reads_unknown(b->lhs), r = reads_unknown(b->rhs);
      switch (b->op) {
        case ir::BinaryOp::Add:
        case ir::BinaryOp::Sub:
          if (!l || !r)
            not_linear(!l ? b->lhs : b->rhs,
                       "a term without " + unknown_ + " belongs on the right side");
          terms(b->lhs, scale, guards, out);
          terms(b->rhs, b->op == ir::BinaryOp::Sub ? negated(scale, b->loc) : scale,
                std::move(guards), out);
          return;
        case ir::BinaryOp::Mul:
          if (l && r) not_linear(e, "a product of two values of " + unknown_);
          if (l) return terms(b->lhs, times(scale, factor(b->rhs)), std::move(guards), out);
          if (r) return terms(b->rhs, times(scale, factor(b->lhs)), std::move(guards), out);
          break;
        case ir::BinaryOp::Div:
          if (r) not_linear(b->rhs, "dividing by " + unknown_);
          if (l)
            return terms(b->lhs,
                         times(scale ? scale : one(b->loc), factor(b->rhs), ir::BinaryOp::Div),
                         std::move(guards), out);
          break;
        default: break;
      }
    }
    if (auto u = ir::as<ir::Unary>(e); u && u->op == ir::UnaryOp::Neg)
      return terms(u->operand, negated(scale, u->loc), std::move(guards), out);
    if (auto s = ir::as<ir::Select>(e)) {
      if (reads_unknown(s->condition)) not_linear(s->condition, "the condition reads " + unknown_);
      for (const bool branch : {true, false}) {
        const Expr& part = branch ? s->then : s->otherwise;
        if (is_zero(part)) continue;
        auto guarded = guards;
        guarded.push_back({factor(s->condition), branch});
        terms(part, scale, std::move(guarded), out);
      }
      return;
    }
    not_linear(e, reads_unknown(e) ? "this is not linear in " + unknown_
                                   : "a term without " + unknown_ + " belongs on the right side");
  }

 private:
  // The coefficient of w[j] in a sum's body, linear in w[j]: the body with
  // w[j] replaced by 1 (null when the body is w[j] itself).
  Expr coefficient(const Expr& e, int j) {
    if (auto v = ir::as<ir::VarRef>(e); v && reads_unknown(e)) {
      if (v->label != j)
        not_linear(e, "inside the sum, only " + unknown_ + "[" + label(j) + "] is known");
      return nullptr;
    }
    if (!reads_unknown(e))
      not_linear(e,
                 "each term of the sum must be a multiple of " + unknown_ + "[" + label(j) + "]");
    if (auto b = ir::as<ir::Binary>(e)) {
      const bool l = reads_unknown(b->lhs), r = reads_unknown(b->rhs);
      switch (b->op) {
        case ir::BinaryOp::Mul:
          if (l && r) not_linear(e, "a product of two values of " + unknown_);
          return l ? times(coefficient(b->lhs, j), b->rhs) : times(b->lhs, coefficient(b->rhs, j));
        case ir::BinaryOp::Div:
          if (r) not_linear(b->rhs, "dividing by " + unknown_);
          return times(coefficient(b->lhs, j) ? coefficient(b->lhs, j) : one(b->loc), b->rhs,
                       ir::BinaryOp::Div);
        case ir::BinaryOp::Add:
        case ir::BinaryOp::Sub: {
          if (!l || !r)
            not_linear(!l ? b->lhs : b->rhs, "each term of the sum must be a multiple of " +
                                                 unknown_ + "[" + label(j) + "]");
          Expr a = coefficient(b->lhs, j), c = coefficient(b->rhs, j);
          return std::make_shared<ir::Binary>(ir::Type::Real, b->op, a ? a : one(b->loc),
                                              c ? c : one(b->loc), b->loc);
        }
        default: break;
      }
    }
    if (auto u = ir::as<ir::Unary>(e); u && u->op == ir::UnaryOp::Neg) {
      Expr c = coefficient(u->operand, j);
      return std::make_shared<ir::Unary>(ir::Type::Real, ir::UnaryOp::Neg, c ? c : one(u->loc),
                                         u->loc);
    }
    if (auto s = ir::as<ir::Select>(e)) {
      if (reads_unknown(s->condition)) not_linear(s->condition, "the condition reads " + unknown_);
      auto branch = [&](const Expr& part) {
        if (is_zero(part)) return part;
        Expr c = coefficient(part, j);
        return c ? c : one(part->loc);
      };
      return std::make_shared<ir::Select>(ir::Type::Real, s->condition, branch(s->then),
                                          branch(s->otherwise), s->loc);
    }
    not_linear(e, "this is not linear in " + unknown_);
  }

  [[noreturn]] void not_linear(const Expr& at, const std::string& why) const {
    throw CompileError(Diagnostic{at->loc,
                                  "the left side of solve " + unknown_ + "[" + label(0) +
                                      "] must be linear in " + unknown_ + ": " + why,
                                  "a solve's left side is a sum of terms like a[i] * " + unknown_ +
                                      "[i] and sum(j, ..., c * " + unknown_ + "[j])"});
  }

  std::string label(int k) const { return st_.labels[k].name; }
  static Expr one(Location at) { return std::make_shared<ir::Literal>(ir::Type::Real, 1, at); }
  // -scale, or -1 for no scale.
  static Expr negated(const Expr& scale, Location at) {
    if (!scale) return std::make_shared<ir::Literal>(ir::Type::Real, -1, at);
    return std::make_shared<ir::Unary>(ir::Type::Real, ir::UnaryOp::Neg, scale, at);
  }

  const ir::Statement& st_;
  const std::string& unknown_;
};

}  // namespace

LinearOperatorReport find_linear_operators(const ir::Model& model,
                                           const NeighbourhoodReport& neighbourhoods) {
  LinearOperatorReport report;
  for (std::size_t g = 0; g < model.stages.size(); ++g)
    for (std::size_t k = 0; k < model.stages[g].statements.size(); ++k) {
      const ir::Statement& st = model.stages[g].statements[k];
      if (!st.solve_operator) continue;
      const std::string& unknown = model.sets[st.set].vars[st.var].name;
      Linearise linearise(st, unknown);
      LinearOperatorFact fact;
      linearise.terms(st.solve_operator, nullptr, {}, fact.terms);
      if (linearise.reads_unknown(st.value))
        throw CompileError(Diagnostic{st.value->loc,
                                      "the right side of solve " + unknown + " reads " + unknown,
                                      "move the terms with " + unknown + " to the left side"});
      fact.sparse = true;
      int sums = 0;
      for (const OperatorTerm& t : fact.terms)
        if (t.sum) {
          ++sums;
          fact.sparse &= neighbourhoods.at(t.sum->id).kind == SearchFact::Kind::Neighbours;
        }
      const ir::SolverChoice solver = st.schedule.solver;
      const bool matrix_free = st.schedule.dense == ir::DenseMethod::Fmm;
      if (!fact.sparse && !matrix_free && solver != ir::SolverChoice::Auto &&
          solver != ir::SolverChoice::Lu)
        throw CompileError(Diagnostic{
            st.schedule.loc,
            std::string("solver ") + ir::solver_choice_name(solver) + " needs a sparse operator",
            "an iterative solver here works on neighbours only: give every sum of the solve a "
            "cutoff on |dx|, or use solver = lu"});
      const bool dense = !fact.sparse || solver == ir::SolverChoice::Lu;
      fact.reason = std::to_string(fact.terms.size()) + " term(s), " + std::to_string(sums) +
                    " of them sums over j; " +
                    (matrix_free ? "dense = fmm: no matrix, GMRES whose products are fast "
                                   "sums, preconditioned by blocks of near points"
                     : !fact.sparse ? "a sum without a cutoff: a dense matrix, solved by LU"
                     : dense      ? "every sum has a cutoff, but the schedule says lu: dense LU"
                                  : "every sum has a cutoff: a sparse matrix (neighbours only), "
                                    "solved by an iterative method");
      report[{static_cast<int>(g), static_cast<int>(k)}] = std::move(fact);
    }
  return report;
}

}  // namespace partc

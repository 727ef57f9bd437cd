// Decides, per sum over neighbours, whether its pairs are packed and its term
// computed on vectors of pairs: runs after symmetry, which says how the pairs
// come. A sum taken each pair once (Newton's third law) gets them from the
// search's pair walk or from half Verlet lists alike (both have
// for_each_pair_batch), and from per-particle queries packed the same way
// (NeighbourSearch::for_each_near_batch) when the search walks pairs
// serially; a sum evaluated both ways, over its own set, from those packed
// queries alone. Over another set, with Verlet lists' full lists, or summed
// compensated (each particle's own terms in order, one at a time), a sum
// taken both ways keeps the scalar queries.
//
// A term has a vector form when every node of its condition and body does:
// reals and vecs (a vec is one vector per component), literals and params,
// dx and |dx|, real and vec particle variables of i or j (gathered by index,
// from double or float storage), + - * /, comparisons, and/or/not, if(c, a,
// b) (both sides computed, one kept), and exp, log, sqrt, abs, min, max,
// tanh, sin, cos, dot, norm and pow by an integer constant; a user
// function's call as its body with the arguments put in. Ints, random draws,
// nested sums and the remaining functions keep the scalar walk, and the
// reason names the first such node. Sums only: a count or a min/max per pair
// is not a per-lane term.
//
// The statement's arithmetic (schedule) says which lanes a vector term is
// computed on: double, or float (twice the lanes: the walk's dx and |dx|^2
// and the gathered variables rounded to float, the term's values added into
// the double sums). A scalar term is computed in double whatever it says.
#include "analysis/vector_terms.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "ir/constant.hpp"
#include "ir/inline_calls.hpp"
#include "ir/visitor.hpp"

namespace partc {

namespace {

using namespace ir;

// The first node without a vector form, described; empty when there is none.
class VectorForm : public Visitor {
 public:
  VectorForm(const Model& model, int j_label) : model_(model), j_label_(j_label) {}
  std::string obstacle;

  using Visitor::visit;

 protected:
  void visit(const Literal&) override {}
  void visit(const ParamRef& n) override { scalar_value(model_.params[n.param].type, "param"); }
  void visit(const ConstRef& n) override { scalar_value(model_.consts[n.constant].type, "const"); }
  void visit(const ObservableRef& n) override {
    scalar_value(model_.observables[n.observable].type, "observable");
  }
  void visit(const VarRef& n) override {
    const Variable& var = model_.sets[n.set].vars[n.var];
    if (n.label != 0 && n.label != j_label_)
      refuse("a variable of another sum's particle (" + var.name + ")");
    else if (var.type != Type::Real && var.type != Type::Vec)
      refuse(std::string(type_name(var.type)) + " variable " + var.name);
  }
  void visit(const Dx&) override {}
  void visit(const Random&) override { refuse("a random draw"); }
  void visit(const FnArg&) override { refuse("a user function's argument"); }
  void visit(const FnCall&) override { refuse("a user function's call"); }
  void visit(const Accumulate&) override { refuse("a nested sum"); }
  void visit(const Unary& n) override {
    typed(n.operand, "an operation");
    Visitor::visit(n);
  }
  void visit(const Binary& n) override {
    if (n.op == BinaryOp::FloorDiv) refuse("//");
    const bool logical = n.op == BinaryOp::And || n.op == BinaryOp::Or;
    if (!logical && n.lhs->type == Type::Bool) refuse("a comparison of conditions");
    typed(n.lhs, "an operand");
    typed(n.rhs, "an operand");
    Visitor::visit(n);
  }
  void visit(const Call& n) override {
    switch (n.fn) {
      case Function::Exp:
      case Function::Log:
      case Function::Sqrt:
      case Function::Abs:
      case Function::Min:
      case Function::Max:
      case Function::Tanh:
      case Function::Sin:
      case Function::Cos:
      case Function::Dot:
      case Function::Norm: break;
      case Function::Pow: {
        const std::optional<double> k = evaluate_constant(n.args[1], model_);
        if (!(k && *k == std::floor(*k) && std::abs(*k) <= 32))
          refuse("pow with an exponent that is not a small integer constant");
        typed(n.args[0], "pow's base");
        visit(n.args[0]);
        return;
      }
      default: refuse(std::string(function_name(n.fn)) + "()");
    }
    for (const Expr& a : n.args) typed(a, std::string(function_name(n.fn)) + "'s argument");
    Visitor::visit(n);
  }
  void visit(const Select& n) override {
    typed(n.then, "if's value");
    typed(n.otherwise, "if's value");
    Visitor::visit(n);
  }

 private:
  void refuse(const std::string& what) {
    if (obstacle.empty()) obstacle = what;
  }
  // Values computed per pair are reals, vecs or conditions; an int is one
  // only as a number the same for every pair (3, a param), which converts to
  // a real exactly; int arithmetic stays scalar.
  void typed(const Expr& e, const std::string& what) {
    const bool number = e->kind == ExprKind::Literal || e->kind == ExprKind::ParamRef ||
                        e->kind == ExprKind::ConstRef || e->kind == ExprKind::ObservableRef;
    if (e->type == Type::Int && !number) refuse(what + " of type int");
  }
  // The same for every pair: any number broadcasts; ints convert exactly up to 2^53.
  void scalar_value(Type type, const char* kind) {
    if (type != Type::Real && type != Type::Int && type != Type::Bool)
      refuse(std::string("a vec ") + kind);
  }

  const Model& model_;
  int j_label_;
};

// Why a scalar term ignores the schedule's float arithmetic, when it asks for it.
std::string scalar_arithmetic(const Schedule& schedule) {
  return schedule.arithmetic == Precision::Float
             ? "; computed in double, though the arithmetic is " + schedule.arithmetic_reason +
                   ": float lanes are for vector terms only"
             : "";
}

VectorTermFact judge(const Model& model, const Statement& st, const Accumulate& acc,
                     bool newton, bool queries, bool excludes_coincident) {
  const std::string in_double = scalar_arithmetic(st.schedule);
  if (acc.reduction != Reduction::Sum)
    return {false, std::string("scalar: a ") + reduction_name(acc.reduction) +
                       " is not a sum of per-pair terms" + in_double};
  if (acc.type != Type::Real && acc.type != Type::Vec)
    return {false, "scalar: a sum of ints" + in_double};
  // User functions as their bodies, as codegen/simd_term.cpp emits them.
  VectorForm form(model, acc.label);
  for (const Expr& e : {acc.condition, acc.body}) {
    if (!e) continue;
    const Expr inlined = inline_calls(e, model);
    if (!inlined)
      return {false, "scalar: its user functions call others too many times to inline" + in_double};
    form.visit(inlined);
  }
  if (!form.obstacle.empty()) return {false, "scalar: the term has " + form.obstacle + in_double};
  const bool on_floats = st.schedule.arithmetic == Precision::Float;
  const std::string packed =
      !newton ? std::string("on vectors of neighbours: each particle's neighbours packed, the "
                            "condition and term computed a vector of neighbours at a time, then "
                            "summed into the particle in its query's order")
              : std::string("on vectors of pairs: each point's pairs packed (compress-stores") +
                    (queries ? "; per-particle queries packed alike when the search walks pairs "
                               "serially"
                             : "") +
                    "), the condition and term computed a vector of pairs at a time, then given "
                    "to both particles" +
                    (queries ? " (to i alone from queries)" : "");
  return {true,
          packed +
              (excludes_coincident ? "; i's pair with itself left out, as the condition "
                                     "excludes |dx| = 0"
                                   : "") +
              "; arithmetic: " +
              (on_floats ? "float lanes (twice as many): the walk's dx and |dx|^2 rounded to "
                           "float and the variables read in float, the condition decided in "
                           "double, each term added into double sums"
                         : "double lanes") +
              " (" + st.schedule.arithmetic_reason + ")",
          !excludes_coincident, st.schedule.arithmetic, queries};
}

bool excludes_coincident(const CoincidenceReport& coincident, int id) {
  const auto fact = coincident.find(id);
  return fact != coincident.end() && fact->second.excluded;
}

// Whether a sum taken both ways can be packed from per-particle queries:
// over neighbours of its statement's own set (the query goes by index), from
// a search (Verlet lists' full lists have no packed walk), not compensated.
bool packs_queries(const Statement& st, const Accumulate& acc,
                   const NeighbourhoodReport& neighbourhoods) {
  return st.observable < 0 && !st.solve_operator && !st.schedule.skin &&
         !st.schedule.compensated &&
         st.labels[static_cast<std::size_t>(acc.label)].set == st.set &&
         neighbourhoods.at(acc.id).kind == SearchFact::Kind::Neighbours;
}

// The sums a statement's particle loop takes, not those inside another's term.
std::vector<const Accumulate*> outermost_sums(const Statement& st) {
  std::vector<const Accumulate*> all = accumulations_in(st), nested;
  for (const Accumulate* acc : all)
    for (const Expr& e : {acc->condition, acc->body})
      if (e)
        for (const Accumulate* inner : accumulations_in(e)) nested.push_back(inner);
  std::vector<const Accumulate*> outermost;
  for (const Accumulate* acc : all)
    if (std::find(nested.begin(), nested.end(), acc) == nested.end()) outermost.push_back(acc);
  return outermost;
}

}  // namespace

VectorTermReport find_vector_terms(const Model& model, const NeighbourhoodReport& neighbourhoods,
                                   const PairSymmetryReport& symmetry,
                                   const CoincidenceReport& coincident, bool enabled) {
  VectorTermReport report;
  for (const Stage& stage : model.stages)
    for (const Statement& st : stage.statements)
      for (const Accumulate* acc : outermost_sums(st)) {
        const auto pairs = symmetry.find(acc->id);
        const bool newton = pairs != symmetry.end() && pairs->second.newton;
        const bool queries = packs_queries(st, *acc, neighbourhoods);
        if (!newton && !queries) continue;
        report[acc->id] =
            enabled
                ? judge(model, st, *acc, newton, queries, excludes_coincident(coincident, acc->id))
                : VectorTermFact{false,
                                 "scalar, as --no-simd asks" + scalar_arithmetic(st.schedule)};
      }
  return report;
}

}  // namespace partc

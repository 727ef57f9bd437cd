// Decides which dense sums run by the fast multipole method, and factors
// each into what the method needs: a kernel of |dx| and a charge per j.
//
// It runs after the neighbourhood analysis, which alone knows which sums are
// dense, and after the linear operators' (a solve scheduled dense = fmm is
// solved matrix-free, and each of its terms is factored from its
// coefficient, w[j] taken as 1), and before code generation, which emits the
// charges, the kernel as a function of r = |dx|, and one call of
// partc::fast_sum::Fmm per sum. The term is split at its top-level products
// and quotients; each factor must read either |dx| or dot(dx, dx) (the
// kernel) or particle j (the charge), and at most one factor may be dx
// itself (a field, sum(j, k(|dx|) * dx * q[j])). A sum the schedule asks to
// run fast that does not factor so is an error naming the factor, never a
// silent direct sum: the user asked for a cost and accuracy the direct sum
// does not have.
#include "analysis/fast_sums.hpp"

#include <algorithm>
#include <utility>
#include <vector>

#include "ir/mutator.hpp"
#include "ir/printer.hpp"
#include "ir/visitor.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace {

using ir::Expr;

using ir::is_norm_of_dx;
using ir::is_squared_norm_of_dx;

// dot(dx, dx) as |dx| * |dx|: a kernel is emitted as a function of r = |dx| alone.
class SquaredNormAsProduct : public ir::Mutator {
 public:
  using ir::Mutator::mutate;

 protected:
  Expr mutate(const ir::Call& n, const Expr& self) override {
    if (!is_squared_norm_of_dx(n)) return ir::Mutator::mutate(n, self);
    const Expr norm = std::make_shared<ir::Call>(ir::Type::Real, ir::Function::Norm,
                                                 std::vector<Expr>{n.args[0]}, n.loc);
    return std::make_shared<ir::Binary>(ir::Type::Real, ir::BinaryOp::Mul, norm, norm, n.loc);
  }
};

// What one factor reads.
class FactorReads : public ir::Visitor {
 public:
  explicit FactorReads(int j) : j_(j) {}
  bool norm_of_dx = false, other_dx = false, of_i = false, of_j = false, unfit = false;
  using ir::Visitor::visit;

 protected:
  void visit(const ir::Call& n) override {
    if (is_norm_of_dx(n) || is_squared_norm_of_dx(n))
      norm_of_dx = true;
    else
      ir::Visitor::visit(n);
  }
  void visit(const ir::Dx&) override { other_dx = true; }
  void visit(const ir::VarRef& n) override { (n.label == j_ ? of_j : of_i) = true; }
  void visit(const ir::Random&) override { unfit = true; }
  void visit(const ir::Accumulate&) override { unfit = true; }

 private:
  int j_;
};

struct Factors {
  std::vector<Expr> kernel, kernel_divisors, charge, charge_divisors;
  int dx = 0;
  bool negated = false;
  std::string refused;  // why the term does not factor, in the model's words
  Location refused_at;  // the factor that stops it
};

class Factorer {
 public:
  Factorer(const std::string& source, int j) : source_(source), j_(j) {}
  Factors factors;

  void split(const Expr& e, bool divisor) {
    if (!factors.refused.empty()) return;
    if (auto b = ir::as<ir::Binary>(e);
        b && (b->op == ir::BinaryOp::Mul || b->op == ir::BinaryOp::Div)) {
      split(b->lhs, divisor);
      split(b->rhs, b->op == ir::BinaryOp::Div ? !divisor : divisor);
      return;
    }
    if (auto u = ir::as<ir::Unary>(e); u && u->op == ir::UnaryOp::Neg) {
      factors.negated = !factors.negated;
      split(u->operand, divisor);
      return;
    }
    if (ir::as<ir::Dx>(e)) {
      if (divisor) return refuse(e, "divides by dx");
      if (++factors.dx > 1) return refuse(e, "takes dx twice: only k(|dx|) * dx is a field");
      return;
    }
    FactorReads reads(j_);
    reads.visit(e);
    if (reads.unfit) return refuse(e, "draws random numbers or holds a sum");
    if (reads.other_dx) return refuse(e, "reads dx other than as |dx|, dot(dx, dx) or a factor dx");
    if (reads.of_i)
      return refuse(e,
                    "reads particle i: a fast sum's charges are j's alone (a factor of i "
                    "alone goes outside the sum)");
    if (reads.norm_of_dx && reads.of_j)
      return refuse(e, "reads both |dx| and particle j: write it as k(|dx|) * q[j]");
    if (e->type == ir::Type::Vec) return refuse(e, "is a vec: charges and kernels are reals");
    auto& into = reads.norm_of_dx ? (divisor ? factors.kernel_divisors : factors.kernel)
                                  : (divisor ? factors.charge_divisors : factors.charge);
    into.push_back(e);
  }

 private:
  void refuse(const Expr& e, const std::string& why) {
    factors.refused =
        "its factor " + source_.substr(e->loc.begin, e->loc.end - e->loc.begin) + " " + why;
    factors.refused_at = e->loc;
  }
  const std::string& source_;
  int j_;
};

// The product of `factors` over the product of `divisors` (1 when there are none).
Expr quotient(const std::vector<Expr>& factors, const std::vector<Expr>& divisors, Location at) {
  auto product = [&](const std::vector<Expr>& terms) -> Expr {
    Expr p;
    for (const Expr& t : terms)
      p = p ? std::make_shared<ir::Binary>(ir::Type::Real, ir::BinaryOp::Mul, p, t, at) : t;
    return p;
  };
  Expr top = product(factors);
  if (!top) top = std::make_shared<ir::Literal>(ir::Type::Real, 1.0, at);
  if (Expr bottom = product(divisors))
    top = std::make_shared<ir::Binary>(ir::Type::Real, ir::BinaryOp::Div, top, bottom, at);
  return top;
}

// Whether the condition only keeps coincident pairs out: |dx| > 0, 0 < |dx|, |dx| != 0.
bool excludes_only_coincident(const Expr& condition) {
  auto b = ir::as<ir::Binary>(condition);
  if (!b) return false;
  auto zero = [](const Expr& e) {
    auto l = ir::as<ir::Literal>(e);
    return l && l->value == 0;
  };
  return (b->op == ir::BinaryOp::Gt && is_norm_of_dx(b->lhs) && zero(b->rhs)) ||
         (b->op == ir::BinaryOp::Lt && zero(b->lhs) && is_norm_of_dx(b->rhs)) ||
         (b->op == ir::BinaryOp::Ne && is_norm_of_dx(b->lhs) && zero(b->rhs));
}

// |dx| as r, to print a kernel as the function of r the fast sum calls.
class NormAsR : public ir::Mutator {
 public:
  using ir::Mutator::mutate;

 protected:
  Expr mutate(const ir::Call& n, const Expr& self) override {
    if (is_norm_of_dx(n)) return std::make_shared<ir::FnArg>(ir::Type::Real, 0, "r", n.loc);
    return ir::Mutator::mutate(n, self);
  }
};

// "S.p, S.q": the positions of both sets, then the charge's variables, that
// the schedule stores as float; each once.
std::string float_inputs(const ir::Model& model, const FastSumFact& fact) {
  std::vector<std::pair<int, int>> inputs{{fact.sources, ir::kPosition}};
  if (fact.targets != fact.sources) inputs.emplace_back(fact.targets, ir::kPosition);
  for (const auto& read : ir::variables_read(fact.charge))
    if (std::find(inputs.begin(), inputs.end(), read) == inputs.end()) inputs.push_back(read);
  std::string out;
  for (const auto& [set, var] : inputs) {
    const ir::Variable& v = model.sets[set].vars[var];
    if (v.storage == ir::Precision::Float)
      out += (out.empty() ? "" : ", ") + model.sets[set].name + "." + v.name;
  }
  return out;
}

// Factors the dense sum `acc` of `st`, whose term is `term` (its body; in a
// solve, its coefficient with w[j] taken as 1, which may be null for 1),
// into the fact, or adds the error that stops it.
void factor_sum(const ir::Model& model, const ir::Statement& st, const ir::Accumulate& acc,
                const Expr& term, const std::string& source, std::vector<Diagnostic>& errors,
                FastSumReport& report) {
  const std::string heading = ir::accumulation_heading(model, st, acc);
  if (acc.reduction != ir::Reduction::Sum) {
    errors.push_back({acc.loc, "dense = fmm sums, and this is a " + heading,
                      "schedule min, max and count in a statement of their own"});
    return;
  }
  if (st.observable >= 0) {
    errors.push_back({acc.loc, "dense = fmm gives one sum per particle, not an observable",
                      "compute the sum into a particle variable, then reduce it"});
    return;
  }
  if (acc.condition && !excludes_only_coincident(acc.condition)) {
    errors.push_back({acc.condition->loc,
                      "a fast sum's condition may only leave out coincident pairs",
                      "write |dx| > 0, or no condition"});
    return;
  }
  Factorer factorer(source, acc.label);
  if (term) factorer.split(term, false);
  Factors& f = factorer.factors;
  if (f.refused.empty() && f.kernel.empty() && f.kernel_divisors.empty()) {
    f.refused = "it reads no |dx|: nothing to sum fast";
    f.refused_at = acc.body->loc;
  }
  if (!f.refused.empty()) {
    errors.push_back({f.refused_at, "this term cannot be summed fast: " + f.refused,
                      st.solve_operator
                          ? "a fast solve's term is k(|dx|) * q[j] * w[j], k of |dx| (params, "
                            "consts) alone, q of j alone"
                          : "a fast sum's term is k(|dx|) * q[j] or k(|dx|) * dx * q[j], k of "
                            "|dx| (params, consts) alone, q of j alone"});
    return;
  }
  if (st.solve_operator && f.dx == 1) {
    errors.push_back({acc.body->loc, "a solve's fast sums are potentials, and this is a field",
                      "a vec term has no place in a scalar unknown's equation"});
    return;
  }
  FastSumFact fact;
  fact.kernel = SquaredNormAsProduct().mutate(quotient(f.kernel, f.kernel_divisors, acc.body->loc));
  fact.charge = quotient(f.charge, f.charge_divisors, acc.body->loc);
  if (f.negated)
    fact.charge =
        std::make_shared<ir::Unary>(ir::Type::Real, ir::UnaryOp::Neg, fact.charge, acc.body->loc);
  fact.field = f.dx == 1;
  fact.skips_coincident = acc.condition != nullptr;
  fact.sources = st.labels[acc.label].set;
  fact.targets = st.set;
  fact.in_solve = st.solve_operator != nullptr;
  if (!fact.in_solve) fact.tolerance = st.schedule.tolerance;
  fact.order = st.schedule.order;
  fact.line = st.line;
  fact.float_inputs = float_inputs(model, fact);
  auto text = [&](const Expr& e) {
    return std::string(source.substr(e->loc.begin, e->loc.end - e->loc.begin));
  };
  const std::string knob =
      fact.order ? "order = " + text(fact.order)
      : fact.in_solve
          ? "tol = " + (st.schedule.tolerance ? text(st.schedule.tolerance) : std::string("1e-8")) +
                " / 100, a hundredth of the solver's"
          : "tol = " + (fact.tolerance ? text(fact.tolerance) : std::string("1e-6 (default)"));
  const std::string charge = ir::to_string(fact.charge, model, st.labels);
  fact.reason =
      "fast multipole method (schedule: dense = fmm, " + knob + "): " +
      (fact.in_solve ? "each GMRES product, k(|dx|) * q[j] * x[j] for the Krylov vector x,"
       : fact.field  ? "a field, k(|dx|) * dx * q[j]"
                     : "a potential, k(|dx|) * q[j]") +
      " with k(r) = " + ir::to_string(NormAsR().mutate(fact.kernel), model, st.labels) +
      (fact.skips_coincident ? " (0 at r = 0)" : "") + " and q[j] = " + charge +
      (fact.float_inputs.empty() || fact.order
           ? ""
           : "; it reads " + fact.float_inputs +
                 " stored as float, so a tol below 1e-7 is met for the rounded values only "
                 "(the run warns)");
  report[acc.id] = std::move(fact);
}

}  // namespace

FastSumReport find_fast_sums(const ir::Model& model, const NeighbourhoodReport& neighbourhoods,
                             const LinearOperatorReport& operators, const std::string& source) {
  FastSumReport report;
  std::vector<Diagnostic> errors;
  for (std::size_t g = 0; g < model.stages.size(); ++g)
    for (std::size_t k = 0; k < model.stages[g].statements.size(); ++k) {
      const ir::Statement& st = model.stages[g].statements[k];
      if (st.schedule.dense != ir::DenseMethod::Fmm) continue;
      if (ir::Domain::any(model.domain.periodic)) {
        errors.push_back({st.schedule.loc, "dense = fmm needs a domain without periodic axes",
                          "the fast multipole method does not sum periodic images yet; the "
                          "direct sum (dense = direct) does"});
        continue;
      }
      bool found = false;
      if (st.solve_operator) {
        for (const ir::Accumulate* acc : ir::accumulations_in(st.value))
          if (neighbourhoods.at(acc->id).kind == SearchFact::Kind::Dense)
            errors.push_back({acc->loc, "a matrix-free solve's right side has a dense sum",
                              "compute it into a variable in a statement before the solve"});
        for (const OperatorTerm& t :
             operators.at({static_cast<int>(g), static_cast<int>(k)}).terms) {
          if (!t.sum) continue;
          if (neighbourhoods.at(t.sum->id).kind != SearchFact::Kind::Dense) {
            errors.push_back({t.sum->loc,
                              "a matrix-free solve sums over all pairs, and this "
                              "sum has a cutoff",
                              "its products are fast sums over all pairs; drop dense = fmm to "
                              "assemble the matrix"});
            continue;
          }
          found = true;
          factor_sum(model, st, *t.sum, t.coefficient, source, errors, report);
        }
      } else {
        for (const ir::Accumulate* acc : ir::accumulations_in(st.value)) {
          if (neighbourhoods.at(acc->id).kind != SearchFact::Kind::Dense) continue;
          found = true;
          factor_sum(model, st, *acc, acc->body, source, errors, report);
        }
      }
      if (!found)
        errors.push_back(
            {st.schedule.loc, "statement '" + st.name + "' has no dense sum to run by fmm",
             "dense = fmm is for sums with no bound on |dx|, like sum(j, w[j] / |dx|)"});
    }
  if (!errors.empty()) throw CompileError(errors);
  return report;
}

}  // namespace partc

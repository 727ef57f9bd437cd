// Emits the body of a solve statement's kernel: the linear system's rows,
// assembled in parallel (each row written by one iteration, its entries in
// a fixed order, so the matrix is the same for any thread count), then one
// call of the runtime's dense or sparse solver (runtime/partc/solve/), whose
// solution becomes the unknown's values. The terms of each row are the
// linear-operator analysis's facts (analysis/linear_operator.cpp).
#include <fmt/format.h>

#include "codegen/model_emitter.hpp"

namespace partc::codegen {

ModelEmitter::SolveKind ModelEmitter::solve_kind(std::pair<int, int> position) const {
  const Statement& st = m_.stages.at(position.first).statements.at(position.second);
  if (st.schedule.dense == DenseMethod::Fmm) return SolveKind::matrix_free;
  return !facts_.linear_operators.at(position).sparse || st.schedule.solver == SolverChoice::Lu
             ? SolveKind::dense
             : SolveKind::sparse;
}

void ModelEmitter::solve_body(const Kernel& k, const ExpressionNames& names, NameTable& locals,
                              const std::string& count) {
  const Statement& st = *k.st;
  const SolveKind kind = solve_kind(k.position);
  if (kind == SolveKind::matrix_free) return matrix_free_solve_body(k, names, locals, count);
  const LinearOperatorFact& op = facts_.linear_operators.at(k.position);
  const bool dense = kind == SolveKind::dense;
  const std::string unknown = m_.sets[st.set].vars[st.var].name;
  const std::string i = names.labels[0];
  const std::string matrix = locals.fresh("matrix"), rhs = locals.fresh("rhs");
  const std::string rows = locals.fresh("rows"), row = locals.fresh("row");
  const std::string target = names.array(st.set, st.var);

  if (dense) {
    linef("Eigen::MatrixXd {0} = Eigen::MatrixXd::Zero({1}, {1});", matrix, count);
  } else {
    line("// Row by row, each row's entries in the order the search finds them.");
    linef("std::vector<std::vector<std::pair<std::size_t, double>>> {}({});", rows, count);
  }
  linef("Eigen::VectorXd {}({});", rhs, count);
  line("// Row i of the system: written by one iteration only.");
  linef("partc::parallel_for({}, partc::LoopWork::heavy, [&](std::size_t {}) {{", count, i);
  linef("{}[{}] = {};", rhs, i, expression(st.value, names));
  if (!dense) linef("auto& {} = {}[{}];", row, rows, i);
  auto add = [&](const std::string& column, const std::string& value) {
    return dense ? fmt::format("{}({}, {}) += {};", matrix, i, column, value)
                 : fmt::format("{}.emplace_back({}, {});", row, column, value);
  };
  // Consecutive terms under the same conditions share one if.
  std::string open_guard;
  for (const OperatorTerm& t : op.terms) {
    enter_guard(operator_guard(t, names), open_guard);
    if (!t.sum) {
      line(add(i, t.scale ? emit_operand(t.scale, BinaryOp::Mul, m_, names) : "1.0"));
    } else {
      const Accumulate& acc = *t.sum;
      const std::string j = names.labels[acc.label];
      UsesDx dx;
      dx.visit(acc.condition);
      dx.visit(t.coefficient);
      if (op.sparse)
        linef("{}.for_each_near({}, [&](std::size_t {}, const Vec&{}) {{", search_for(acc.id), i, j,
              dx.dx ? " dx" : "");
      else
        linef("for (std::size_t {0} = 0; {0} < {1}; ++{0}) {{", j, count);
      const std::string value = operator_entry(t, st, names, i, op.sparse ? "" : j);
      const std::string entry = add(j, value);
      if (acc.condition) {
        ExpressionNames inner = names;
        inner.dx_norm = dx.norm ? "dx_norm" : "";
        linef("if ({}) {}", expression(acc.condition, inner), entry);
      } else {
        line(entry);
      }
      line(op.sparse ? "});" : "}");
    }
  }
  if (!open_guard.empty()) line("}");
  line("});");

  const std::string result = solve_results_.at(&st);
  if (!dense) {
    line("// Rows in order; entries of one (row, column) pair add up, as in the sums.");
    linef("partc::SparseMatrixCRS {0}({1}, {1});", matrix, count);
    line("{");
    line("std::vector<Eigen::Triplet<double>> entries;");
    linef("for (std::size_t {0} = 0; {0} < {1}; ++{0})", i, count);
    linef("for (const auto& [column, value] : {}[{}]) entries.emplace_back({}, column, value);",
          rows, i, i);
    linef("{}.setFromTriplets(entries.begin(), entries.end());", matrix);
    line("}");
  }
  linef("if (!matrix_market_.empty()) {{");
  linef("partc::write_matrix_market(matrix_market_ + \"_{}.mtx\", {}, \"{}\");", unknown, matrix,
        "operator of " + source_text(st.loc));
  linef("partc::write_matrix_market(matrix_market_ + \"_{}_rhs.mtx\", {}, \"right side\");",
        unknown, rhs);
  line("}");
  if (dense) {
    linef("{} = partc::solve_dense({}, {}, {{\"{}\"}});", result, matrix, rhs, unknown);
  } else {
    static const char* methods[] = {"bicgstab", "bicgstab", "cg", "bicgstab", "gmres"};
    line("partc::SparseSolveOptions options;");
    linef("options.name = \"{}\";", unknown);
    linef("options.method = partc::KrylovMethod::{};",
          methods[static_cast<int>(st.schedule.solver)]);
    if (st.schedule.tolerance)
      linef("options.tolerance = {};", expression(st.schedule.tolerance, names));
    if (st.schedule.max_iterations)
      linef("options.max_iterations = {};", expression(st.schedule.max_iterations, names));
    linef("{} = partc::solve_sparse({}, {}, options);", result, matrix, rhs);
    linef("if (!{0}.converged) throw partc::NumericalError({0}.warning);", result);
  }
  linef(
      "partc::parallel_for({}, partc::LoopWork::light, [&](std::size_t {}) {{ {}[{}] = {}.x[{}]; "
      "}});",
      count, i, target, i, result, i);
  linef("{}.x = Eigen::VectorXd();  // the values live in {} now", result, unknown);
}

// Closes the if of `open` and opens one for `guard` when they differ.
void ModelEmitter::enter_guard(const std::string& guard, std::string& open) {
  if (guard == open) return;
  if (!open.empty()) line("}");
  if (!guard.empty()) linef("if ({}) {{", guard);
  open = guard;
}

std::string ModelEmitter::operator_guard(const OperatorTerm& t,
                                         const ExpressionNames& names) const {
  std::vector<std::string> guards;
  for (const auto& [condition, wanted] : t.guards)
    guards.push_back(wanted ? emit_operand(condition, BinaryOp::And, m_, names)
                            : "!" + emit_operand(condition, BinaryOp::Mul, m_, names));
  return fmt::format("{}", fmt::join(guards, " && "));
}

// j empty: dx comes from the search (its callback's argument).
std::string ModelEmitter::operator_entry(const OperatorTerm& t, const Statement& st,
                                         const ExpressionNames& names, const std::string& i,
                                         const std::string& j) {
  UsesDx dx;
  dx.visit(t.sum->condition);
  dx.visit(t.coefficient);
  if (dx.dx && !j.empty()) {
    const std::string p = names.array(st.set, kPosition);
    linef("const Vec dx = domain_.minimum_image({} - {});",
          emit_load(m_, st.set, kPosition, p + "[" + j + "]"),
          emit_load(m_, st.set, kPosition, p + "[" + i + "]"));
  }
  if (dx.norm) line("const double dx_norm = partc::norm(dx);");
  ExpressionNames inner = names;
  inner.dx_norm = dx.norm ? "dx_norm" : "";
  std::string value = t.coefficient ? emit_operand(t.coefficient, BinaryOp::Mul, m_, inner) : "";
  const std::string scale = t.scale ? emit_operand(t.scale, BinaryOp::Mul, m_, names) : "";
  if (!scale.empty()) value = value.empty() ? scale : scale + " * " + value;
  return value.empty() ? "1.0" : value;
}

}  // namespace partc::codegen

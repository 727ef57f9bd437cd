// Emits a solve statement scheduled `dense = fmm`: no matrix is assembled.
// Each dense term of the operator (analysis/linear_operator.cpp), factored
// into a kernel of |dx| and a coefficient of j (analysis/fast_sums.cpp),
// gets one fast multipole plan on the positions; the product A x is those
// fast sums, combined per row under the terms' conditions, and the
// preconditioner's blocks come from single entries A(i, j), the same terms
// evaluated pair by pair. The runtime's solve_matrix_free runs GMRES
// (runtime/partc/solve/matrix_free_solve.hpp). The fast sums' tolerance is a
// hundredth of the solver's: a residual below the product's own error means
// nothing, and a looser product stalls the solver. With --check-accuracy the
// contract is the user's tolerance on the residual against the direct sums
// (runtime/partc/solve/direct_residual.hpp); the products' own errors are
// reported beside it.
#include <fmt/format.h>

#include "codegen/model_emitter.hpp"

namespace partc::codegen {

void ModelEmitter::matrix_free_solve_body(const Kernel& k, const ExpressionNames& names,
                                          NameTable& locals, const std::string& count) {
  const Statement& st = *k.st;
  const LinearOperatorFact& op = facts_.linear_operators.at(k.position);
  const std::string unknown = m_.sets[st.set].vars[st.var].name;
  const std::string i = names.labels[0];
  const std::string& set = set_member_[st.set];
  const std::string rhs = locals.fresh("rhs"), tol = locals.fresh("tol");
  const std::string result = solve_results_.at(&st);

  linef("Eigen::VectorXd {}({});", rhs, count);
  linef("partc::parallel_for({}, partc::LoopWork::heavy, [&](std::size_t {}) {{", count, i);
  linef("{}[{}] = {};", rhs, i, expression(st.value, names));
  line("});");
  linef("const double {} = {};  // the solver's", tol,
        st.schedule.tolerance ? expression(st.schedule.tolerance, names) : "1e-8");

  // Per fast term: its charge factors q[j], kernel, plan and record.
  struct FastTerm {
    const OperatorTerm* term;
    std::string coefficient, kernel, accuracy, fmm, record, sum;
  };
  std::vector<FastTerm> fast;
  for (const OperatorTerm& t : op.terms) {
    if (!t.sum) continue;
    const FastSumFact& fact = facts_.fast_sums.at(t.sum->id);
    const std::string j = names.labels[t.sum->label];
    FastTerm f{&t,
               "",
               locals.fresh("kernel_" + j),
               locals.fresh("accuracy_" + j),
               locals.fresh("fmm_" + j),
               fmt::format("fast_sums_[{}]", fast_sum_records_.at(t.sum->id)),
               locals.fresh("sum_" + j)};
    linef("// {}: k(r) and q[j] of each product's fast sum.", accumulation_heading(m_, st, *t.sum));
    const auto literal = ir::as<ir::Literal>(fact.charge);
    if (!literal || literal->value != 1) {
      f.coefficient = locals.fresh("coefficient_" + j);
      linef("std::vector<double> {}({});", f.coefficient, count);
      linef("partc::parallel_for({}, partc::LoopWork::light, [&](std::size_t {}) {{", count, j);
      linef("{}[{}] = {};", f.coefficient, j, expression(fact.charge, names));
      line("});");
    }
    ExpressionNames of_r = names;
    of_r.dx_norm = "r";
    const std::string value = expression(fact.kernel, of_r);
    linef("const auto {} = [&](double r) {{ return {}; }};", f.kernel,
          fact.skips_coincident ? fmt::format("r > 0 ? {} : 0.0", value) : value);
    const std::string order = !fact.order ? "0"
                              : ir::as<ir::Literal>(fact.order)
                                  ? expression(fact.order, names)
                                  : "static_cast<int>(" + expression(fact.order, names) + ")";
    linef("const partc::fast_sum::Accuracy {}{{{}, {}, false}};  // tol, order, field", f.accuracy,
          fact.order ? "0.0" : tol + " / 100", order);
    linef("const partc::fast_sum::Fmm {}({}.positions(), {}.positions(), {}, {});", f.fmm, set, set,
          f.kernel, f.accuracy);
    fast.push_back(std::move(f));
  }

  // The product, one fast sum per term, then each row's combination.
  const std::string product = locals.fresh("product"), x = locals.fresh("x"), y = locals.fresh("y");
  const std::string charges = locals.fresh("charges");
  line("// A x: the fast sums, then each row from the terms that apply to it.");
  linef("const auto {} = [&](const Eigen::VectorXd& {}, Eigen::VectorXd& {}) {{", product, x, y);
  for (const FastTerm& f : fast) {
    linef("std::vector<double> {}({});", f.sum, count);
    line("{");
    line("const auto started = std::chrono::steady_clock::now();");
    if (f.coefficient.empty()) {
      linef("{}.potential({}.data(), {}.data());", f.fmm, x, f.sum);
    } else {
      linef("std::vector<double> {}({});", charges, count);
      linef(
          "partc::parallel_for({0}, partc::LoopWork::light, [&](std::size_t k) {{ {1}[k] = {2}[k] "
          "* {3}[k]; }});",
          count, charges, f.coefficient, x);
      linef("{}.potential({}.data(), {}.data());", f.fmm, charges, f.sum);
    }
    linef("{}.evaluated({}, {}, started);", f.record, f.accuracy, f.fmm);
    line("}");
  }
  linef("partc::parallel_for({}, partc::LoopWork::light, [&](std::size_t {}) {{", count, i);
  line("double row = 0;");
  std::size_t next = 0;
  std::string open_guard;  // consecutive terms under the same conditions share one if
  for (const OperatorTerm& t : op.terms) {
    enter_guard(operator_guard(t, names), open_guard);
    const std::string scale = t.scale ? emit_operand(t.scale, BinaryOp::Mul, m_, names) : "";
    const std::string value =
        t.sum ? fast[next++].sum + "[" + i + "]" : x + "[static_cast<Eigen::Index>(" + i + ")]";
    linef("row += {};", scale.empty() ? value : scale + " * " + value);
  }
  if (!open_guard.empty()) line("}");
  linef("{}[static_cast<Eigen::Index>({})] = row;", y, i);
  line("});");
  line("};");

  // Single entries, for the preconditioner's blocks.
  const std::string entry = locals.fresh("entry"), column = locals.fresh("column");
  line("// A(i, j), for the preconditioner's blocks of near points.");
  linef("const auto {} = [&](std::size_t {}, std::size_t {}) {{", entry, i, column);
  line("double a = 0;");
  for (const OperatorTerm& t : op.terms) {
    const std::string guard = operator_guard(t, names);
    if (!t.sum) {
      linef("if ({}{} == {}) a += {};", guard.empty() ? "" : guard + " && ", i, column,
            t.scale ? emit_operand(t.scale, BinaryOp::Mul, m_, names) : "1.0");
      continue;
    }
    line(guard.empty() ? "{" : fmt::format("if ({}) {{", guard));
    const std::string j = names.labels[t.sum->label];
    linef("const std::size_t {} = {};", j, column);
    const std::string value = operator_entry(t, st, names, i, j);
    if (t.sum->condition) {
      UsesDx dx;
      dx.visit(t.sum->condition);
      dx.visit(t.coefficient);
      ExpressionNames inner = names;
      inner.dx_norm = dx.norm ? "dx_norm" : "";
      linef("if ({}) a += {};", expression(t.sum->condition, inner), value);
    } else {
      linef("a += {};", value);
    }
    line("}");
  }
  line("return a;");
  line("};");

  line("partc::MatrixFreeSolveOptions options;");
  linef("options.name = \"{}\";", unknown);
  linef("options.tolerance = {};", tol);
  if (st.schedule.max_iterations)
    linef("options.max_iterations = {};", expression(st.schedule.max_iterations, names));
  linef("{} = partc::solve_matrix_free({}.positions(), {}, {}, {}, options);", result, set, product,
        entry, rhs);
  linef("if (!{0}.converged) throw partc::NumericalError({0}.warning);", result);
  line("// No matrix exists to write: the right side alone, and the summary says why.");
  line("if (!matrix_market_.empty()) {");
  linef("partc::write_matrix_market(matrix_market_ + \"_{}_rhs.mtx\", {}, \"right side\");",
        unknown, rhs);
  linef(
      "{0}.warning += ({0}.warning.empty() ? \"\" : \"; \") + std::string(\"solve {1}: "
      "matrix-free (dense = fmm), so no {1}.mtx was written, only its right side\");",
      result, unknown);
  line("}");
  // The check: the answer's residual against the direct sums (the solve's
  // contract), then each fast sum once more on the answer's charges (reported).
  line("if (check_accuracy_) {");
  linef("Eigen::VectorXd fast_ax({});", count);
  linef("{}({}.x, fast_ax);", product, result);
  std::string orders;  // the highest order of the products
  for (const FastTerm& f : fast)
    orders = orders.empty() ? f.fmm + ".order()"
                            : fmt::format("std::max({}, {}.order())", orders, f.fmm);
  linef("partc::check_direct_residual({}, {}, fast_ax, {}, {}, {});", result, entry, rhs, tol,
        orders);
  for (const FastTerm& f : fast) {
    line("{");
    linef("std::vector<double> {}({}), {}({});", charges, count, f.sum, count);
    linef("for (std::size_t k = 0; k < {}; ++k) {}[k] = {}{}.x[static_cast<Eigen::Index>(k)];",
          count, charges, f.coefficient.empty() ? "" : f.coefficient + "[k] * ", result);
    linef("{}.potential({}.data(), {}.data());", f.fmm, charges, f.sum);
    linef("{}.check({}, {}, {}.positions(), {}.positions(), {}, {});", f.record, f.fmm, f.kernel,
          set, set, charges, f.sum);
    line("}");
  }
  line("}");
  linef(
      "partc::parallel_for({}, partc::LoopWork::light, [&](std::size_t {}) {{ {}[{}] = {}.x[{}]; "
      "}});",
      count, i, names.array(st.set, st.var), i, result, i);
  linef("{}.x = Eigen::VectorXd();  // the values live in {} now", result, unknown);
}

}  // namespace partc::codegen

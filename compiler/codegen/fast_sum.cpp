// Emits a dense sum the schedule runs by the fast multipole method
// (analysis/fast_sums.cpp): its charges q[j] in one pass over the sources,
// its kernel as a lambda of r = |dx|, one partc::fast_sum::Fmm planned on
// the positions as they are and evaluated for every target at once, before
// the statement's particle loop reads the results. Each sum keeps a record
// (runtime/partc/fast_sum/contract.hpp) for the run's summary, and is
// checked against the direct sum on a sample of targets when the run asks.
#include <fmt/format.h>

#include <algorithm>

#include "codegen/model_emitter.hpp"

namespace partc::codegen {

void ModelEmitter::fast_sum(const Accumulate& acc, const Statement& st, ExpressionNames& names,
                            NameTable& locals, const std::string& count) {
  const FastSumFact& fact = facts_.fast_sums.at(acc.id);
  const std::string j = names.labels[acc.label];
  const std::string& sources = set_member_[fact.sources];
  const std::string charge = locals.fresh("charge_" + j), kernel = locals.fresh("kernel_" + j);
  const std::string fmm = locals.fresh("fmm_" + j), accuracy = locals.fresh("accuracy_" + j);
  const std::string started = locals.fresh("started");
  const std::string result = names.accumulators.at(acc.id);
  const std::string record = fmt::format("fast_sums_[{}]", fast_sum_records_.at(acc.id));

  linef("// {}: its charges, then the fast sum for every particle at once.",
        accumulation_heading(m_, st, acc));
  linef("std::vector<double> {}({}.size());  // the charges", charge, sources);
  linef("partc::parallel_for({}.size(), partc::LoopWork::light, [&](std::size_t {}) {{", sources,
        j);
  linef("{}[{}] = {};", charge, j, expression(fact.charge, names));
  line("});");
  ExpressionNames of_r = names;
  of_r.dx_norm = "r";
  const std::string value = expression(fact.kernel, of_r);
  linef("const auto {} = [&](double r) {{ return {}; }};", kernel,
        fact.skips_coincident ? fmt::format("r > 0 ? {} : 0.0", value) : value);
  // An order fixed by the schedule asks no tolerance; an int param is 64-bit.
  std::string tol = "0.0", order = "0";
  if (fact.order)
    order = ir::as<ir::Literal>(fact.order)
                ? expression(fact.order, names)
                : "static_cast<int>(" + expression(fact.order, names) + ")";
  else
    tol = fact.tolerance ? expression(fact.tolerance, names) : "1e-6";
  linef("const partc::fast_sum::Accuracy {}{{{}, {}, {}}};  // tol, order, field", accuracy, tol,
        order, fact.field ? "true" : "false");
  linef("const auto {} = std::chrono::steady_clock::now();", started);
  linef("const partc::fast_sum::Fmm {}({}.positions(), {}.positions(), {}, {});", fmm, sources,
        set_member_[fact.targets], kernel, accuracy);
  linef("std::vector<{}> {}({});", fact.field ? "Vec" : "double", result, count);
  linef("{}.{}({}.data(), {}.data());", fmm, fact.field ? "field" : "potential", charge, result);
  linef("{}.evaluated({}, {}, {});", record, accuracy, fmm, started);
  linef("if (check_accuracy_) {}.check({}, {}, {}.positions(), {}.positions(), {}, {});", record,
        fmm, kernel, sources, set_member_[fact.targets], charge, result);
  names.accumulators[acc.id] = result + "[" + names.labels[0] + "]";
}

// The fast sums' records, for the driver's summary; and whether each
// evaluation is checked against the direct sum (--check-accuracy).
void ModelEmitter::fast_sum_report() {
  if (fast_sum_records_.empty()) return;
  line("// Each fast sum: the order its tolerance chose, its predicted and measured error.");
  line("std::vector<std::string> fast_sum_report() const {");
  line("std::vector<std::string> report;");
  const bool warns = std::any_of(facts_.fast_sums.begin(), facts_.fast_sums.end(),
                                 [](const auto& sum) { return !sum.second.float_inputs.empty(); });
  line("for (const auto& record : fast_sums_) {");
  line("if (record.evaluations() > 0) report.push_back(record.summary());");
  if (warns)
    line("if (!record.warning().empty()) report.push_back(\"warning: \" + record.warning());");
  line("}");
  line("return report;");
  line("}");
  line("// From now on, every fast sum is checked against the direct sum on a sample of");
  line("// targets; an error above its tolerance stops the run (partc::NumericalError).");
  line("void set_check_accuracy(bool check) { check_accuracy_ = check; }");
}

}  // namespace partc::codegen

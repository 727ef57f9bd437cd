// partc/fast_sum/contract.hpp: the accuracy contract of a model's fast sums.
//
//   partc::fast_sum::FastSumRecord record{"sum at model.part:17"};
//   record.evaluated(accuracy, fmm, started);        // after each evaluation
//   if (check) record.check(fmm, kernel, sources, targets, charges, result);
//   record.summary();  // "sum at model.part:17: fmm order 7 for tol 1e-06, ..."
//   record.warning();  // "" unless the tolerance is finer than float inputs carry
//
// A generated model keeps one record per sum its schedule runs fast
// (`dense = fmm`): what was asked (a tolerance, or an order), the order the
// cost model chose and the error it predicted, how often the sum ran and for
// how long, and, when the run checks accuracy (--check-accuracy; the tests
// always do), the largest error measured against the direct sum on a sample
// of targets. A measured relative L2 error above the tolerance stops the run
// with a NumericalError (exit 3) that says which sum, what was asked, what
// was measured and what order would meet it, as Polatory raises an error
// when no order meets the requested accuracy: a result less accurate than
// asked is never returned silently. A tolerance no order is predicted to
// meet stops the run at the first evaluation, checked or not. An order fixed
// by the schedule asks no tolerance, so its check reports and never stops
// the run; nor does the check of a matrix-free solve's products, whose
// tolerance partc chose, not the user: the solve's residual against the
// direct sums is that contract (solve/direct_residual.hpp).
//
// Inputs stored as float (positions or charges; schedule: precision = float)
// are rounded to about 6e-8 relative, which moves a sum by about as much: a
// tolerance below float_inputs_tol is met for the rounded inputs (the direct
// sum the check compares with reads them too), not for the double values
// they were rounded from. The record warns of it once, as a line of the
// summary, rather than refusing: the fast sum still does what was asked.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "partc/errors.hpp"
#include "partc/fast_sum/accuracy.hpp"
#include "partc/fast_sum/fmm.hpp"
#include "partc/vec.hpp"

namespace partc::fast_sum {

// Below this a tolerance asks more than float-stored inputs resolve.
constexpr double float_inputs_tol = 1e-7;

class FastSumRecord {
 public:
  enum class Role { sum, solve_products };
  // float_inputs: the float-stored variables the sum reads ("V.p, V.q"), if any.
  explicit FastSumRecord(std::string where, Role role = Role::sum, std::string float_inputs = {})
      : where_(std::move(where)), role_(role), float_inputs_(std::move(float_inputs)) {}

  // After an evaluation planned at `started` (plan and evaluation timed
  // together). Throws NumericalError when even the highest order the plan
  // knows is predicted to miss the tolerance asked.
  template <int D, class Kernel>
  void evaluated(const Accuracy& asked, const Fmm<D, Kernel>& fmm,
                 std::chrono::steady_clock::time_point started) {
    asked_ = asked;
    order_ = fmm.order();
    predicted_ = fmm.predicted_error();
    ++evaluations_;
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (!float_inputs_.empty() && asked.order == 0 && asked.tol < float_inputs_tol &&
        warning_.empty())
      warning_ = where_ + ": tol " + number(asked.tol) +
                 " is finer than its float-stored inputs (" + float_inputs_ +
                 ") resolve, about 1e-7 relative: it is met for the rounded inputs, not for the "
                 "values they were rounded from; store them as double (schedule: precision = "
                 "double) for a tighter sum";
    if (asked.order == 0 && predicted_ > asked.tol)
      throw NumericalError(where_ + ": no order meets tol " + number(asked.tol) +
                           ": the highest, " + std::to_string(order_) + ", is predicted to give " +
                           number(predicted_) +
                           " (relative L2); ask a larger tol, or the direct "
                           "sum (dense = direct)");
  }

  // Measures the evaluation's error on a sample of targets against the direct
  // sum; throws NumericalError when it exceeds the tolerance asked.
  template <int D, class Kernel, class T, class Result>
  void check(const Fmm<D, Kernel>& fmm, const Kernel& kernel, const std::vector<Vec<D, T>>& sources,
             const std::vector<Vec<D, T>>& targets, const std::vector<double>& charges,
             const std::vector<Result>& result) {
    MeasuredError measured;
    if constexpr (std::is_same_v<Result, double>)
      measured = measure_potential(sources, targets, kernel, charges.data(), result.data());
    else
      measured = measure_field(sources, targets, kernel, charges.data(), result.data());
    worst_l2_ = std::max(worst_l2_, measured.rel_l2);
    worst_max_ = std::max(worst_max_, measured.max_rel);
    sampled_ = measured.targets;
    if (role_ == Role::solve_products || asked_.order > 0 || !(measured.rel_l2 > asked_.tol))
      return;
    const int order = order_to_meet(fmm, asked_.tol, measured.rel_l2);
    throw NumericalError(
        where_ + ": asked tol " + number(asked_.tol) + ", measured " + number(measured.rel_l2) +
        " (relative L2 over " + std::to_string(measured.targets) +
        " targets, against the direct sum) with order " + std::to_string(order_) + "; " +
        (order > order_ ? "order " + std::to_string(order) +
                              " would meet it (schedule: order = " + std::to_string(order) + ")"
                        : std::string("no order the cost model knows meets it")));
  }

  std::int64_t evaluations() const { return evaluations_; }
  const std::string& warning() const { return warning_; }  // "" when all is well
  double worst_measured_l2() const { return worst_l2_; }   // -1: never checked

  std::string summary() const {
    std::string text = where_ + ": fmm order " + std::to_string(order_) +
                       (asked_.order > 0 ? " (schedule)" : " for tol " + number(asked_.tol)) +
                       (role_ == Role::solve_products ? " (a solve's products)" : "") +
                       ", predicted " + number(predicted_) + " relative L2";
    if (worst_l2_ >= 0)
      text += ", measured " + number(worst_l2_) + " (max " + number(worst_max_) + ", " +
              std::to_string(sampled_) + " targets)";
    return text + "; " + std::to_string(evaluations_) +
           (evaluations_ == 1 ? " evaluation, " : " evaluations, ") + number(seconds_) + " s";
  }

 private:
  static std::string number(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2g", x);
    return text;
  }
  std::string where_;
  Role role_;
  std::string float_inputs_;
  std::string warning_;
  Accuracy asked_;
  int order_ = 0;
  double predicted_ = 0;
  std::int64_t evaluations_ = 0;
  double seconds_ = 0;
  double worst_l2_ = -1, worst_max_ = -1;
  std::size_t sampled_ = 0;
};

}  // namespace partc::fast_sum

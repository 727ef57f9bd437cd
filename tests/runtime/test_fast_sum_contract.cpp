// The accuracy contract of a model's fast sums (partc/fast_sum/contract.hpp):
// a measured error above the tolerance stops the run naming the sum, what was
// asked and measured and what order would meet it; a tolerance no order
// meets stops it at once; an order fixed by the schedule is reported, never
// refused; the summary says what was predicted and measured; a tolerance
// finer than float-stored inputs resolve is warned of.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "fast_sum_cases.hpp"
#include "partc/errors.hpp"
#include "partc/fast_sum/contract.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::Matches;
using fast_sum_cases::Coulomb;
using partc::Vec;
using partc::fast_sum::Accuracy;
using partc::fast_sum::FastSumRecord;
using partc::fast_sum::Fmm;

namespace {

std::vector<Vec<3>> cloud(std::size_t n) { return fast_sum_cases::uniform_points<3>(n, 3); }

}  // namespace

TEST_CASE(
    "fast sum contract: an error above the tolerance stops the run, saying what would meet it",
    "[fast_sum][contract]") {
  const auto x = cloud(6000);
  const std::vector<double> q(x.size(), 1.0);
  const Accuracy asked{1e-3, 0, false};
  const Fmm fmm(x, x, Coulomb{}, asked);
  std::vector<double> phi(x.size());
  fmm.potential(q.data(), phi.data());
  FastSumRecord record{"sum at model.part:7"};
  record.evaluated(asked, fmm, std::chrono::steady_clock::now());
  CHECK_THAT(record.summary(), !Contains("measured"));

  record.check(fmm, Coulomb{}, x, x, q, phi);  // as computed: within tol
  CHECK(record.worst_measured_l2() <= 1e-3);
  CHECK(record.worst_measured_l2() > 0);
  CHECK_THAT(record.summary(),
             Matches("sum at model\\.part:7: fmm order \\d+ for tol 0\\.001, predicted .* relative "
                     "L2, measured .* \\(max .*, 500 targets\\); 1 evaluation, .* s"));

  for (double& v : phi) v *= 1 + 1e-2;  // a result 1% off
  try {
    record.check(fmm, Coulomb{}, x, x, q, phi);
    FAIL("a result 10x less accurate than asked passed the check");
  } catch (const partc::NumericalError& e) {
    CHECK_THAT(std::string(e.what()),
               Matches("sum at model\\.part:7: asked tol 0\\.001, measured 0\\.01 \\(relative L2 "
                       "over 500 targets, against the direct sum\\) with order \\d+; .*"));
  }
}

TEST_CASE("fast sum contract: a tolerance no order meets stops the run at once",
          "[fast_sum][contract]") {
  const auto x = cloud(20000);  // enough for far pairs, whose error is not 0
  const Accuracy asked{1e-30, 0, false};
  const Fmm fmm(x, x, Coulomb{}, asked);
  FastSumRecord record{"sum at model.part:9"};
  CHECK_THROWS_WITH(record.evaluated(asked, fmm, std::chrono::steady_clock::now()),
                    Matches("sum at model\\.part:9: no order meets tol 1e-30: the highest, \\d+, "
                            "is predicted to give .*"));
}

TEST_CASE("fast sum contract: an order the schedule fixes is reported, never refused",
          "[fast_sum][contract]") {
  const auto x = cloud(6000);
  const std::vector<double> q(x.size(), 1.0);
  const Accuracy asked{0, 2, false};
  const Fmm fmm(x, x, Coulomb{}, asked);
  std::vector<double> phi(x.size());
  fmm.potential(q.data(), phi.data());
  FastSumRecord record{"sum at model.part:11"};
  record.evaluated(asked, fmm, std::chrono::steady_clock::now());
  for (double& v : phi) v *= 1.5;
  CHECK_NOTHROW(record.check(fmm, Coulomb{}, x, x, q, phi));
  CHECK_THAT(record.summary(), Contains("fmm order 2 (schedule)"));
  CHECK(record.worst_measured_l2() > 0.4);
}

TEST_CASE("fast sum contract: a tolerance finer than float-stored inputs is warned of",
          "[fast_sum][contract]") {
  const auto x = cloud(6000);
  auto warning = [&](const Accuracy& asked, std::string float_inputs) {
    const Fmm fmm(x, x, Coulomb{}, asked);
    FastSumRecord record{"sum at model.part:5", FastSumRecord::Role::sum, std::move(float_inputs)};
    record.evaluated(asked, fmm, std::chrono::steady_clock::now());
    record.evaluated(asked, fmm, std::chrono::steady_clock::now());
    return record.warning();
  };
  CHECK_THAT(warning({1e-9, 0, false}, "S.p, S.q"),
             Matches("sum at model\\.part:5: tol 1e-09 is finer than its float-stored inputs "
                     "\\(S\\.p, S\\.q\\) resolve, about 1e-7 relative: .*precision = double.*"));
  CHECK(warning({1e-6, 0, false}, "S.p").empty());  // float resolves it
  CHECK(warning({1e-9, 0, false}, "").empty());     // inputs in double
  CHECK(warning({0, 9, false}, "S.p").empty());     // an order asks no tolerance
}

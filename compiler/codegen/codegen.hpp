// C++ code generation: one self-contained translation unit per model.
#pragma once

#include <string>

#include "analysis/aliasing.hpp"
#include "analysis/fast_sums.hpp"
#include "analysis/linear_operator.hpp"
#include "analysis/neighbourhood.hpp"
#include "analysis/observed_steps.hpp"
#include "analysis/search_plan.hpp"
#include "analysis/statement_fusion.hpp"
#include "analysis/symmetry.hpp"
#include "analysis/uniform_sums.hpp"
#include "analysis/vector_terms.hpp"
#include "ir/ir.hpp"
#include "support/source.hpp"

namespace partc {

struct CodegenOptions {
  bool driver_main = false;   // also emit int main() running partc::run_driver
  std::string source_name;    // how the .part file is named in comments
  bool profile = false;       // time step kernels and searches per effect (partc::Profile)
};

// The facts lowering acts on, computed by the analyses.
struct ModelFacts {
  AliasReport aliasing;
  NeighbourhoodReport neighbourhoods;
  PairSymmetryReport symmetry;
  UniformSumReport uniform_sums;
  LinearOperatorReport linear_operators;
  SearchPlan searches;
  ObservedStepReport observed_steps;
  StatementFusion fusion;
  FastSumReport fast_sums;
  VectorTermReport vector_terms;
};

// Unformatted C++ for the model: a class named after it (md -> Md) with
// its parameters, particle storage, init(), step() and accessors.
std::string generate_cpp(const ir::Model& model, const ModelFacts& facts, const SourceFile& file,
                         const CodegenOptions& options);

// The same text laid out by clang-format (LLVM style, 100 columns).
// Throws InternalError if clang cannot lex it.
std::string format_cpp(const std::string& code, const std::string& file_name);

}  // namespace partc

// The story of the compiler: the passes, in the order they run.
#pragma once

#include <string>

#include "analysis/coincident_pairs.hpp"
#include "ast/ast.hpp"
#include "codegen/codegen.hpp"
#include "ir/declarations_read.hpp"
#include "ir/fold_conditions.hpp"
#include "ir/fold_zero_terms.hpp"
#include "ir/inline_single_use.hpp"
#include "ir/ir.hpp"
#include "sema/scene.hpp"
#include "support/diagnostics.hpp"
#include "support/source.hpp"

namespace partc {

struct Compilation {
  SceneReport scene;  // the effects used, for --explain
  ast::Program ast;   // the model itself: a scene with its effects instantiated
  ir::Model model;
  ModelFacts facts;
  std::vector<ir::FoldedCondition> folded_conditions;  // if(c, a, b) with c a constant
  std::vector<ir::FoldedTerm> folded;  // terms a constant 0 removed
  std::vector<ir::DroppedDeclaration> unread;  // functions and consts only folded code read
  ir::SingleUseReport single_use;  // variables computed in their reader, not stored
  CoincidenceReport coincident;    // for warnings, --explain and vector_terms
  std::vector<Diagnostic> warnings;
};

// Choices of the passes that change no result, only how it is computed.
struct PassOptions {
  // false (--no-fuse): every statement a pass of its own, to measure what
  // fusion across statements buys; the sums of one statement still share a walk.
  bool fuse_statements = true;
  // false (--no-simd): every pair term computed pair by pair, to measure what
  // the vector form buys or to compare with it.
  bool simd = true;
  // --schedule TEXT: schedule entries over the model's own (ast/schedule_overrides.hpp).
  std::vector<std::string> schedule;
};

// Front end and analyses; throws CompileError for a bad model, and
// std::invalid_argument for a --drop the scene cannot take. Modules a scene
// uses are appended to `file`.
Compilation analyse(SourceFile& file, const SceneOptions& scene = {},
                    const PassOptions& passes = {});

// --explain: per statement, what was decided and why.
std::string explain(const Compilation& c, const SourceFile& file);
// --explain=json: the same facts as one JSON document (explain_json.cpp).
std::string explain_json(const Compilation& c, const SourceFile& file);

}  // namespace partc

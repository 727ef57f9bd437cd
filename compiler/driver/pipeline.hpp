// The story of the compiler: the passes, in the order they run.
#pragma once

#include <string>

#include "analysis/coincident_pairs.hpp"
#include "ast/ast.hpp"
#include "codegen/codegen.hpp"
#include "ir/ir.hpp"
#include "support/diagnostics.hpp"
#include "support/source.hpp"

namespace partc {

struct Compilation {
  ast::Program ast;
  ir::Model model;
  ModelFacts facts;
  CoincidenceReport coincident;  // for warnings and --explain only
  std::vector<Diagnostic> warnings;
};

// Front end and analyses; throws CompileError for a bad model.
Compilation analyse(const SourceFile& file);

// --explain: per statement, what was decided and why.
std::string explain(const Compilation& c, const SourceFile& file);

}  // namespace partc

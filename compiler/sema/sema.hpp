// Semantic analysis: from the AST of a .part file to the typed IR.
//
// Decides what every name means (param, const, particle set, variable,
// label, builtin function), the type of every expression, and rejects
// models that cannot mean anything: unknown names, type and dimension
// mismatches, dx outside an accumulation, labels nobody bound, writes to
// read-only or j-indexed variables. All errors found are reported together.
#pragma once

#include "ast/ast.hpp"
#include "ir/ir.hpp"
#include "support/diagnostics.hpp"
#include "support/source.hpp"

namespace partc {

// Throws CompileError with every problem found; appends warnings (likely
// mistakes that still mean something) to `warnings`.
ir::Model build_ir(const ast::Program& program, const SourceFile& file,
                   std::vector<Diagnostic>& warnings);

}  // namespace partc

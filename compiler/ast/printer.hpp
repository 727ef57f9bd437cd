// Text form of the AST, for --emit=ast: an S-expression per declaration,
// each with the line:column where it starts.
#pragma once

#include <string>

#include "ast/ast.hpp"
#include "support/source.hpp"

namespace partc::ast {

std::string to_string(const Program& program, const SourceFile& file);

}  // namespace partc::ast

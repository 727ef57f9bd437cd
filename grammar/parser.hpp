// The entry point of the front end: .part text in, AST out.
#pragma once

#include "ast/ast.hpp"
#include "support/source.hpp"

namespace partc {

// Parses a whole file. Throws CompileError (with the position of the first
// syntax error and what was expected there) when the text does not parse.
// `segment` is the file of `file` to parse (0: the model's own; a module
// appended to it when a scene opens one).
ast::Program parse_program(const SourceFile& file, int segment = 0);

}  // namespace partc

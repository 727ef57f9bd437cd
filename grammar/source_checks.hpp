// Checks on the raw text before the grammar runs: the characters the
// language is written in, and a bound on nesting that keeps the recursive
// parser (and every recursive pass after it) within its stack.
#pragma once

#include "support/source.hpp"

namespace partc {

// Deepest nesting of ( and [, and the longest run of prefix operators
// (- + not) or norm bars, that a .part file may use.
constexpr int kMaxNesting = 256;

// Throws CompileError at the first byte outside ASCII that is not in a
// comment, or where nesting goes beyond kMaxNesting, in one file of `file`.
void check_source_text(const SourceFile& file, int segment);

}  // namespace partc

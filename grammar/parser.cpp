// Runs the X3 grammar over a file and turns syntax errors into diagnostics.
#include "grammar/parser.hpp"

#include <cctype>

#include "grammar/rules_def.hpp"
#include "grammar/source_checks.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace {

// Skips blanks and comments, as the grammar's skipper does, so an error
// points at the next token rather than at the whitespace before it.
grammar::Iterator skip_blanks(grammar::Iterator it, grammar::Iterator end) {
  while (it != end) {
    if (std::isspace(static_cast<unsigned char>(*it))) {
      ++it;
    } else if (*it == '#') {
      while (it != end && *it != '\n') ++it;
    } else {
      break;
    }
  }
  return it;
}

// The token at `it`, for "found ..." in messages, and how long it is.
std::pair<std::string, std::uint32_t> token_at(grammar::Iterator it, grammar::Iterator end) {
  if (it == end) return {"end of file", 1};
  auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  grammar::Iterator stop = it;
  if (word_char(*it)) {
    while (stop != end && word_char(*stop)) ++stop;
  } else {
    ++stop;
  }
  return {"'" + std::string(it, stop) + "'", static_cast<std::uint32_t>(stop - it)};
}

// What a C or Python habit at `it` is written as in .part.
std::string habit_note(grammar::Iterator it, grammar::Iterator end) {
  const std::string next(it, end - it >= 2 ? it + 2 : end);
  if (next == "&&") return "write 'and' for &&";
  if (next == "||") return "write 'or' for ||";
  if (next[0] == '!' && next != "!=") return "write 'not' for !";
  if (next[0] == '%') return "write mod(a, b) for a % b";
  if (next[0] == '^') return "write pow(a, b) for a power";
  return {};
}

}  // namespace

ast::Program parse_program(const SourceFile& file, int segment) {
  check_source_text(file, segment);
  const std::string& text = file.text();
  // Offsets count from the start of all the text, so a location names its file.
  const grammar::Iterator begin = text.begin();
  grammar::Iterator first = text.begin() + file.extent(segment).begin;
  const grammar::Iterator last = text.begin() + file.extent(segment).end;
  ast::Program program;
  try {
    namespace x3 = boost::spirit::x3;
    x3::phrase_parse(first, last,
                     x3::with<grammar::source_begin_tag>(begin)[grammar::program], grammar::skipper,
                     program.declarations);
  } catch (const boost::spirit::x3::expectation_failure<grammar::Iterator>& failure) {
    const grammar::Iterator at = skip_blanks(failure.where(), last);
    const auto [found, length] = token_at(at, last);
    const auto offset = static_cast<std::uint32_t>(at - begin);
    throw CompileError(Diagnostic{{offset, offset + length},
                                  "expected " + failure.which() + ", found " + found,
                                  habit_note(at, last)});
  }
  return program;
}

}  // namespace partc

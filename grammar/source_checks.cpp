// Why before parsing: the X3 character classes take a char, and a byte of
// 0x80 or more is a negative char, outside what isalnum may be given (an
// assertion in debug builds); and the parser recurses once per level of
// nesting, so 3000 unclosed '(' overflowed its stack.
#include "grammar/source_checks.hpp"

#include <cstdint>
#include <cstdio>
#include <string>

#include "support/diagnostics.hpp"

namespace partc {

namespace {

// "U+00E9 'é'" for a well-formed UTF-8 sequence at text[k], else "byte 0xC3".
std::string describe_non_ascii(const std::string& text, std::size_t k, std::size_t& length) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(k);
  length = lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 1;
  bool valid = length > 1 && lead < 0xF5 && k + length <= text.size();
  std::uint32_t code = lead & (0x7F >> length);
  for (std::size_t i = 1; valid && i < length; ++i) {
    valid = (byte(k + i) & 0xC0) == 0x80;
    code = (code << 6) | (byte(k + i) & 0x3F);
  }
  char hex[16];
  if (!valid) {
    length = 1;
    std::snprintf(hex, sizeof hex, "byte 0x%02X", lead);
    return hex;
  }
  std::snprintf(hex, sizeof hex, "U+%04X", static_cast<unsigned>(code));
  return std::string(hex) + " '" + text.substr(k, length) + "'";
}

[[noreturn]] void fail(std::size_t at, std::size_t length, std::string message, std::string note) {
  const auto begin = static_cast<std::uint32_t>(at);
  throw CompileError(Diagnostic{{begin, static_cast<std::uint32_t>(at + length)},
                                std::move(message), std::move(note)});
}

bool word_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

}  // namespace

void check_source_text(const SourceFile& file, int segment) {
  const std::string& text = file.text();
  const Location extent = file.extent(segment);
  int depth = 0;   // of ( and [
  int prefix = 0;  // consecutive prefix operators or bars, blanks between them
  for (std::size_t k = extent.begin; k < extent.end; ++k) {
    const char c = text[k];
    if (c == '#') {
      while (k < text.size() && text[k] != '\n') ++k;  // comments may hold any bytes
      continue;
    }
    if (static_cast<unsigned char>(c) >= 0x80) {
      std::size_t length = 1;
      const std::string what = describe_non_ascii(text, k, length);
      fail(k, length, what + " outside a comment",
           "names, numbers and operators are ASCII; other characters may appear in # comments");
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
    const bool prefix_word = c == 'n' && text.compare(k, 3, "not") == 0 &&
                             (k == 0 || !word_char(text[k - 1])) &&
                             (k + 3 == text.size() || !word_char(text[k + 3]));
    if (c == '-' || c == '+' || c == '|' || prefix_word) {
      if (++prefix > kMaxNesting)
        fail(k, 1, "more than " + std::to_string(kMaxNesting) + " prefix operators or bars in a row",
             "partc bounds nesting to keep its recursion within the stack");
      if (prefix_word) k += 2;
      continue;
    }
    if (c == '(' || c == '[') {
      if (++depth > kMaxNesting)
        fail(k, 1, "nesting deeper than " + std::to_string(kMaxNesting) + " levels of ( and [",
             "split the expression with intermediate variables or functions");
    } else if ((c == ')' || c == ']') && depth > 0) {
      --depth;
    }
    if (c != '(') prefix = 0;  // -(-(-x)) is nesting, counted by depth
    while (word_char(c) && k + 1 < text.size() && word_char(text[k + 1])) ++k;
  }
}

}  // namespace partc

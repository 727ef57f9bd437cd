#include "codegen/names.hpp"

#include <cctype>

namespace partc::codegen {

namespace {
const std::set<std::string> kCppKeywords = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break",
    "case", "catch", "char", "char8_t", "char16_t", "char32_t", "class", "compl", "concept",
    "const", "consteval", "constexpr", "constinit", "const_cast", "continue", "co_await",
    "co_return", "co_yield", "decltype", "default", "delete", "do", "double", "dynamic_cast",
    "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto",
    "if", "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq",
    "nullptr", "operator", "or", "or_eq", "private", "protected", "public", "register",
    "reinterpret_cast", "requires", "return", "short", "signed", "sizeof", "static",
    "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local",
    "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using",
    "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq", "std", "partc", "main",
    "Vec"};
}  // namespace

std::string cpp_name(const std::string& qualified) {
  std::string name = qualified;
  for (char& c : name)
    if (c == '.') c = '_';
  const bool reserved = kCppKeywords.count(name) || name.find("__") != std::string::npos ||
                        (name.size() > 1 && name[0] == '_' && std::isupper(name[1]));
  return reserved ? name + "_" : name;
}

std::uint64_t fnv1a64(const std::string& name) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : name) hash = (hash ^ c) * 0x100000001b3ULL;
  return hash;
}

std::string upper_case(const std::string& name) {
  std::string out;
  for (char c : name) out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string class_name(const std::string& model_name) {
  std::string out;
  bool upper = true;
  for (char c : model_name) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return cpp_name(out.empty() ? "Model" : out);
}

std::string NameTable::fresh(const std::string& wanted) {
  std::string name = wanted;
  for (int k = 2; taken_.count(name); ++k) name = wanted + "_" + std::to_string(k);
  taken_.insert(name);
  return name;
}

}  // namespace partc::codegen

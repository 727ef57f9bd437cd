// A libFuzzer target for the whole front end and code generation: parse,
// sema, the analyses and C++ emission (not clang-format, whose own fuzzing is
// LLVM's) on arbitrary bytes. Every input must end in generated C++ or in
// diagnostics that each name the file (or a module of stdlib/ that a scene
// opened), a line and a column; anything else -
// a crash, a sanitizer report, an InternalError or another exception - is a
// find. Built by .ci/fuzz with clang's -fsanitize=fuzzer; replay_main.cpp
// runs it over the saved corpus in the ordinary test suite.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>

#include "codegen/codegen.hpp"
#include "driver/pipeline.hpp"
#include "support/diagnostics.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  partc::SourceFile file("fuzz.part", std::string(reinterpret_cast<const char*>(data), size));
  try {
    // Scenes open the standard library's modules, so instantiation is fuzzed too.
    partc::SceneOptions scene;
    scene.roots.push_back({PARTC_STDLIB_DIR, "stdlib"});
    const partc::Compilation c = partc::analyse(file, scene);
    partc::CodegenOptions options;
    options.driver_main = true;
    options.source_name = "fuzz.part";
    if (partc::generate_cpp(c.model, c.facts, file, options).empty()) std::abort();
  } catch (const partc::CompileError& e) {
    if (e.diagnostics().empty()) std::abort();
    for (const partc::Diagnostic& d : e.diagnostics()) {
      const std::string text = partc::format_diagnostic(file, d);
      if (text.rfind("fuzz.part:", 0) != 0 && text.rfind("stdlib/", 0) != 0) {
        std::cerr << "a diagnostic without its place:\n" << text;
        std::abort();
      }
    }
  }
  return 0;  // InternalError and every other exception escape: a find
}

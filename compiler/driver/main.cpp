// partc: compiles a .part model into a C++ translation unit.
//
//   partc model.part -o model.cpp [--main] [--emit=ast|ir|cpp] [--explain]
//         [--drop NAME] [--stdlib DIR] [--no-fuse] [--no-simd] [--schedule ENTRIES]
//
// Exit status: 0 success, 1 the model has errors, 2 bad command line,
// 3 an I/O failure or a partc bug. Output files are written whole or not at
// all: the text goes to a temporary file renamed into place at the end (a
// link, pipe or device is written in place); the input is never the output.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "ast/printer.hpp"
#include "driver/pipeline.hpp"
#include "grammar/parser.hpp"
#include "ir/printer.hpp"
#include "partc/io/output_file.hpp"
#include "support/diagnostics.hpp"

namespace {

const char* const kUsage =
    "usage: partc MODEL.part [-o OUTPUT] [--main] [--emit=ast|ir|cpp] [--explain]\n"
    "             [--drop NAME]... [--stdlib DIR]... [--no-fuse] [--no-simd]\n"
    "             [--schedule ENTRIES]...\n"
    "\n"
    "Compiles a particle model into one C++17 translation unit.\n"
    "\n"
    "  -o OUTPUT         write to OUTPUT (default: standard output)\n"
    "  --main            also emit main(): the command-line driver (see --help of the model)\n"
    "  --profile         time each step per effect instance: the model's run ends with a\n"
    "                    table of ms a step per effect and what --drop NAME would save\n"
    "  --emit=WHAT       ast: the syntax tree; ir: the typed IR; cpp: C++ (the default)\n"
    "  --explain         print, per statement, the search structure chosen for each\n"
    "                    accumulation and whether the update is buffered, and why; for a\n"
    "                    scene, the effects kept, the modules opened, liveness and fusion\n"
    "  --explain=json    the same facts as one JSON document\n"
    "  --drop NAME       compile a scene without its effect instance NAME, as if its\n"
    "                    use line were deleted (repeatable)\n"
    "  --depfile FILE    also write a make-style dependency file: the output depends on\n"
    "                    the model and every module it opened (with -o)\n"
    "  --no-fuse         every statement a pass of its own: no fusion across statements,\n"
    "                    to measure what it saves (the sums of one statement still share\n"
    "                    a walk)\n"
    "  --no-simd         every pair term computed pair by pair, none on vectors of pairs,\n"
    "                    to measure what vectors buy or to compare with them\n"
    "  --schedule ENTRIES  schedule entries over the model's own, as its schedule block\n"
    "                    writes them: --schedule 'force: dense = fmm, tol = 1e-8' replaces\n"
    "                    the options it names of the entry for force (repeatable)\n"
    "  --stdlib DIR      look for modules in DIR before the standard library (the\n"
    "                    scene's own folder is searched first); repeatable\n"
    "  --version         print the version\n"
    "  --help            print this help\n";

struct Options {
  std::string input;
  std::optional<std::string> output;
  bool driver_main = false;
  bool profile = false;
  bool fuse = true;
  bool simd = true;
  bool explain = false;
  bool explain_json = false;
  std::string emit = "cpp";
  std::vector<std::string> drop;
  std::vector<std::string> schedule;
  std::vector<std::string> module_folders;
  std::optional<std::string> depfile;
};

struct UsageError {
  std::string message;
};

Options parse_options(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "-o") {
      if (k + 1 >= argc) throw UsageError{"-o needs a file name"};
      o.output = argv[++k];
    } else if (arg == "--main") {
      o.driver_main = true;
    } else if (arg == "--profile") {
      o.profile = true;
    } else if (arg == "--no-fuse") {
      o.fuse = false;
    } else if (arg == "--no-simd") {
      o.simd = false;
    } else if (arg == "--depfile") {
      if (k + 1 >= argc) throw UsageError{"--depfile needs a file name"};
      o.depfile = argv[++k];
    } else if (arg == "--drop" || arg == "--stdlib" || arg == "--schedule") {
      if (k + 1 >= argc || argv[k + 1][0] == '\0')
        throw UsageError{arg + (arg == "--drop"       ? " needs an effect instance's name"
                                : arg == "--schedule" ? " needs schedule entries, as in "
                                                        "'force: skin = 0.4'"
                                                      : " needs a folder")};
      const std::string value = argv[++k];
      if (arg == "--drop") {
        o.drop.push_back(value);
      } else if (arg == "--schedule") {
        o.schedule.push_back(value);
      } else {
        std::error_code error;
        if (!std::filesystem::is_directory(value, error))
          throw UsageError{"--stdlib " + value + ": no such folder"};
        o.module_folders.push_back(value);
      }
    } else if (arg == "--explain") {
      o.explain = true;
    } else if (arg == "--explain=json") {
      o.explain = o.explain_json = true;
    } else if (arg.rfind("--emit=", 0) == 0) {
      o.emit = arg.substr(7);
      if (o.emit != "ast" && o.emit != "ir" && o.emit != "cpp")
        throw UsageError{"--emit takes ast, ir or cpp, not '" + o.emit + "'"};
    } else if (!arg.empty() && arg[0] == '-' && arg != "-") {
      throw UsageError{"unknown option '" + arg + "'"};
    } else if (o.input.empty()) {
      o.input = arg;
    } else {
      throw UsageError{"more than one input file ('" + o.input + "' and '" + arg + "')"};
    }
  }
  if (o.input.empty()) throw UsageError{"no input file"};
  if (o.depfile && (!o.output || *o.output == "-"))
    throw UsageError{"--depfile needs -o: a dependency file names the output it is for"};
  // Through links too: -o m.part, or a link to it, would replace the model.
  std::error_code ignored;
  if (o.output && *o.output != "-" && std::filesystem::equivalent(o.input, *o.output, ignored))
    throw UsageError{"the output '" + *o.output + "' is the input file"};
  return o;
}

// Writes the whole text or nothing (a regular file through a temporary; a
// link, pipe or device in place: runtime/partc/io/output_file.hpp).
void write_output(const std::optional<std::string>& path, const std::string& text) {
  if (!path || *path == "-") {
    std::cout << text;
    return;
  }
  const std::filesystem::path folder = std::filesystem::path(*path).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder))
    throw std::runtime_error("cannot write '" + *path + "': folder '" + folder.string() +
                             "' does not exist");
  // The same text already there is left alone, so a build that reruns
  // partc (a new partc, a touched module) recompiles only what changed.
  std::error_code error;
  if (std::filesystem::is_regular_file(*path, error) &&
      std::filesystem::file_size(*path, error) == text.size()) {
    std::ifstream in(*path, std::ios::binary);
    std::string existing(text.size(), '\0');
    if (in.read(existing.data(), static_cast<std::streamsize>(existing.size())) && existing == text)
      return;
  }
  partc::detail::write_file_atomically(*path, [&](std::ostream& out) { out << text; });
}

}  // namespace

int main(int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    }
    if (arg == "--version") {
      std::cout << "partc " << PARTC_VERSION << "\n";
      return 0;
    }
  }
  Options options;
  try {
    options = parse_options(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "partc: error: " << e.message << "\n(run 'partc --help' for usage)\n";
    return 2;
  }

  std::optional<partc::SourceFile> file;
  try {
    file = partc::read_source_file(options.input);
  } catch (const std::exception& e) {
    std::cerr << "partc: error: " << e.what() << "\n";
    return 2;
  }

  try {
    if (options.emit == "ast") {
      write_output(options.output, partc::ast::to_string(partc::parse_program(*file), *file));
      return 0;
    }
    // Modules: the scene's own folder, then --stdlib folders, then the standard library.
    partc::SceneOptions scene;
    const std::string folder = std::filesystem::path(options.input).parent_path().string();
    scene.roots.push_back({folder.empty() ? "." : folder, folder});
    for (const std::string& dir : options.module_folders) scene.roots.push_back({dir, dir});
    scene.roots.push_back({PARTC_STDLIB_DIR, "stdlib"});
    scene.drop = options.drop;
    const partc::Compilation c = partc::analyse(*file, scene, {options.fuse, options.simd, options.schedule});
    for (const partc::Diagnostic& d : c.warnings) std::cerr << partc::format_diagnostic(*file, d);
    if (options.explain)
      std::cout << (options.explain_json ? partc::explain_json(c, *file) : partc::explain(c, *file));
    if (options.emit == "ir") {
      write_output(options.output, partc::ir::to_string(c.model));
      return 0;
    }
    if (options.explain && !options.output) return 0;
    partc::CodegenOptions codegen;
    codegen.driver_main = options.driver_main;
    codegen.profile = options.profile;
    codegen.source_name = std::filesystem::path(options.input).filename().string();
    const std::string code = partc::generate_cpp(c.model, c.facts, *file, codegen);
    const std::string name = options.output ? *options.output : "model.cpp";
    write_output(options.output, partc::format_cpp(code, name));
    if (options.depfile) {
      // Spaces in a make rule are escaped with a backslash.
      auto escaped = [](const std::string& path) {
        std::string out;
        for (char ch : path) out += ch == ' ' ? std::string("\\ ") : std::string(1, ch);
        return out;
      };
      std::string rule = escaped(*options.output) + ": " + escaped(options.input);
      for (const std::string& module : c.scene.module_files) rule += " \\\n  " + escaped(module);
      write_output(options.depfile, rule + "\n");
    }
    return 0;
  } catch (const partc::CompileError& e) {
    std::size_t errors = 0;
    for (const partc::Diagnostic& d : e.diagnostics()) {
      std::cerr << partc::format_diagnostic(*file, d);
      errors += !d.warning;
    }
    if (errors > 1) std::cerr << errors << " errors\n";
    return 1;
  } catch (const std::invalid_argument& e) {  // a --drop the scene cannot take
    std::cerr << "partc: error: " << e.what() << "\n";
    return 2;
  } catch (const partc::InternalError& e) {
    std::cerr << "partc: internal error: partc bug: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "partc: error: " << e.what() << "\n";
    return 3;
  }
}

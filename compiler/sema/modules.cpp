// Scene instantiation: finding a module by its name and parsing it.
//
// `use pair.lj` reads FOLDER/pair/lj.part from the first root that has it
// (the scene's own folder, then the standard library). The module's text is
// appended to the compilation's source, so every later message and comment
// can point into it. `import sph.kernels` opens a module for its functions
// and constants alone (a module may hold no effect); imports are opened as
// they are met, so a cycle is found while its chain is open.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "grammar/parser.hpp"
#include "sema/checker.hpp"
#include "sema/scene_parts.hpp"

namespace partc::scene {

namespace {

// What a module file may hold besides its `module` line and its effect.
const char* declaration_kind(const ast::Declaration& decl) {
  struct Kind {
    const char* operator()(const ast::ModelDecl&) const { return "a model declaration"; }
    const char* operator()(const ast::DimDecl&) const { return "a dim declaration"; }
    const char* operator()(const ast::DomainDecl&) const { return "a domain"; }
    const char* operator()(const ast::ParamDecl&) const {
      return "a param (an effect's parameters go in its header)";
    }
    const char* operator()(const ast::ConstDecl&) const { return nullptr; }
    const char* operator()(const ast::ObservableDecl&) const {
      return "an observable (an effect says: provides NAME: TYPE)";
    }
    const char* operator()(const ast::TimestepDecl&) const {
      return "a timestep (an integrator's effect says it)";
    }
    const char* operator()(const ast::OutputDecl&) const { return "an output declaration"; }
    const char* operator()(const ast::FnDecl&) const { return nullptr; }
    const char* operator()(const ast::ParticlesDecl&) const {
      return "a particle set (effects act on the sets a scene gives them)";
    }
    const char* operator()(const ast::StageBlock&) const {
      return "a stage block (an effect places statements with: at SLOT: ...)";
    }
    const char* operator()(const ast::ScheduleBlock&) const { return "a schedule"; }
    const char* operator()(const ast::ModuleDecl&) const { return "a second module declaration"; }
    const char* operator()(const ast::EffectDecl&) const { return nullptr; }
    const char* operator()(const ast::UseDecl&) const {
      return "a use (modules do not use other modules yet)";
    }
    const char* operator()(const ast::OrderDecl&) const { return "an order declaration"; }
    const char* operator()(const ast::ImportDecl&) const { return nullptr; }
  };
  return boost::apply_visitor(Kind{}, decl);
}

Location location(const ast::Declaration& decl) {
  return boost::apply_visitor([](const auto& d) { return d.loc; }, decl);
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

Location span(const std::vector<ast::Identifier>& name) {
  return {name.front().loc.begin, name.back().loc.end};
}

}  // namespace

const Module& ModuleLibrary::open(const ast::UseDecl& use) {
  const Module& module = open(use.module);
  if (!module.effect)
    throw CompileError(Diagnostic{span(use.module),
                                  "module " + module.name + " holds functions, not an effect",
                                  "import it for its functions: import " + module.name});
  return module;
}

const Module& ModuleLibrary::open(const ast::ImportDecl& import) {
  const std::string name = ast::dotted(import.module);
  if (std::count(opening_.begin(), opening_.end(), name)) {
    std::string chain;
    for (auto it = std::find(opening_.begin(), opening_.end(), name); it != opening_.end(); ++it)
      chain += *it + " imports ";
    throw CompileError(Diagnostic{span(import.module), "modules import each other: " + chain + name,
                                  "move what both need to a module of its own"});
  }
  return open(import.module);
}

const Module& ModuleLibrary::open(const std::vector<ast::Identifier>& dotted) {
  const std::string name = ast::dotted(dotted);
  if (auto it = modules_.find(name); it != modules_.end()) return *it->second;

  std::filesystem::path relative;
  for (const ast::Identifier& part : dotted) relative /= part.name;
  relative += ".part";
  const Location at = span(dotted);
  std::string looked;
  for (const ModuleRoot& root : roots_) {
    const std::filesystem::path path = std::filesystem::path(root.folder) / relative;
    const std::string shown = (std::filesystem::path(root.display) / relative).generic_string();
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
      looked += (looked.empty() ? "" : ", ") + shown;
      continue;
    }
    auto module = std::make_unique<Module>();
    module->name = name;
    module->path = shown;
    const int segment = file_.append(shown, read_text(path));
    report_.modules_opened.push_back(shown);
    report_.module_files.push_back(path.string());
    module->program = parse_program(file_, segment);

    std::vector<Diagnostic> problems;
    const auto& decls = module->program.declarations;
    const auto* header = decls.empty() ? nullptr : boost::get<ast::ModuleDecl>(&decls.front());
    const Location start{file_.extent(segment).begin, file_.extent(segment).begin + 1};
    if (!header)
      problems.push_back({decls.empty() ? start : location(decls.front()),
                          "a module begins with its name: module " + name});
    else if (ast::dotted(header->name) != name)
      problems.push_back(
          {header->loc,
           "this file is module " + name + " (from its path), not " + ast::dotted(header->name),
           "rename the file or write: module " + name});
    for (std::size_t k = header ? 1 : 0; k < decls.size(); ++k) {
      if (const char* what = declaration_kind(decls[k]))
        problems.push_back({location(decls[k]), std::string("a module cannot hold ") + what,
                            "a module holds imports, fn and const declarations and one effect"});
      if (auto effect = boost::get<ast::EffectDecl>(&decls[k])) {
        if (module->effect)
          problems.push_back({effect->loc, "a second effect in module " + name,
                              "one effect per module: move it to a file of its own"});
        else
          module->effect = effect;
      }
    }
    if (!problems.empty()) throw CompileError(problems);
    opening_.push_back(name);
    for (const ast::Declaration& decl : decls)
      if (auto import = boost::get<ast::ImportDecl>(&decl)) module->imports.push_back(&open(*import));
    opening_.pop_back();
    return *(modules_[name] = std::move(module));
  }
  // On the error path only: the modules there are, for a suggestion.
  std::vector<std::string> known;
  for (const ModuleRoot& root : roots_) {
    std::error_code error;
    for (auto it = std::filesystem::recursive_directory_iterator(root.folder, error);
         !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
      if (it->path().extension() != ".part") continue;
      std::string module = std::filesystem::relative(it->path(), root.folder, error)
                               .replace_extension()
                               .generic_string();
      std::replace(module.begin(), module.end(), '/', '.');
      known.push_back(module);
    }
  }
  throw CompileError(
      Diagnostic{at, "no module " + name + sema::suggestion(name, known), "looked for " + looked});
}

}  // namespace partc::scene

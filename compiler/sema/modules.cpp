// Scene instantiation: finding a module by its name and parsing it.
//
// `use pair.lj` reads FOLDER/pair/lj.part from the first root that has it
// (the scene's own folder, then the standard library). The module's text is
// appended to the compilation's source, so every later message and comment
// can point into it.
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

}  // namespace

const Module& ModuleLibrary::open(const ast::UseDecl& use) {
  const std::string name = ast::dotted(use.module);
  if (auto it = modules_.find(name); it != modules_.end()) return *it->second;

  std::filesystem::path relative;
  for (const ast::Identifier& part : use.module) relative /= part.name;
  relative += ".part";
  const Location at{use.module.front().loc.begin, use.module.back().loc.end};
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
                            "a module holds fn and const declarations and one effect"});
      if (auto effect = boost::get<ast::EffectDecl>(&decls[k])) {
        if (module->effect)
          problems.push_back({effect->loc, "a second effect in module " + name,
                              "one effect per module: move it to a file of its own"});
        else
          module->effect = effect;
      }
    }
    if (!module->effect && problems.empty())
      problems.push_back({start, "module " + name + " has no effect",
                          "declare one: effect NAME(PARAMS) on P { ... }"});
    if (!problems.empty()) throw CompileError(problems);
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

// Scenes: a model that `use`s effects from modules, turned into a plain model.
//
// Runs first in sema, before names and types, because an effect is text
// written against an interface: once its parameters are namespaced, its
// sets bound and its statements placed at the slots of its set's integrator,
// the result is an ordinary model that the rest of sema checks as if the
// user had written it. Only the modules a scene uses are opened; an
// instance left out with --drop is never instantiated, so the model is the
// one its `use` line's deletion would give.
#pragma once

#include <string>
#include <vector>

#include "ast/ast.hpp"
#include "support/diagnostics.hpp"
#include "support/source.hpp"

namespace partc {

struct ModuleRoot {
  std::string folder;   // where to look: FOLDER/pair/lj.part for pair.lj
  std::string display;  // how messages and comments name files there ("stdlib")
};

struct SceneOptions {
  std::vector<ModuleRoot> roots;  // searched in order
  std::vector<std::string> drop;  // instance names left out (--drop)
};

// What instantiation decided, for --explain.
struct SceneReport {
  struct Instance {
    std::string name, module;
    std::string path;  // the module's file, as messages name it
    std::vector<std::string> sets;
    Location use;
  };
  std::vector<Instance> kept;
  std::vector<std::string> dropped;
  std::vector<std::string> modules_opened;  // file names, in the order opened
  std::vector<std::string> module_files;    // the same, as paths to read (for --depfile)
  // One line per statement placed: slot, set, target and the effects merged into it.
  struct Placement {
    std::string statement;  // its name, as liveness reports it
    std::string text;
  };
  std::vector<Placement> placements;
  // Liveness: each statement dropped, and each variable, observable and
  // function an effect declared, kept or not and why.
  struct DroppedStatement {
    std::string name, target;
    Location loc;
  };
  std::vector<DroppedStatement> dropped_statements;
  struct Decision {
    std::string what;
    bool kept;
    std::string why;
  };
  std::vector<Decision> variables;
  // The liveness drop of a placed statement, by its name; null when kept.
  const DroppedStatement* dropped_statement(const std::string& name) const {
    for (const DroppedStatement& d : dropped_statements)
      if (d.name == name) return &d;
    return nullptr;
  }
  bool is_scene() const { return !kept.empty() || !dropped.empty() || !modules_opened.empty(); }
};

// The model with every `use` instantiated. A model with no `use` comes back
// as it is. Appends each module opened to `file`. Throws CompileError.
ast::Program instantiate_scene(const ast::Program& scene, SourceFile& file,
                               const SceneOptions& options, SceneReport& report);

// Says, for each diagnostic in a module's text, which instances use it and
// where their use lines are (a module's mistake shows in every scene using it).
void add_scene_context(std::vector<Diagnostic>& diagnostics, const SceneReport& report,
                       const SourceFile& file);

// --explain's account of a scene: effects kept and dropped, modules opened,
// where each statement went. Empty for a model that uses no effects.
std::string explain_scene(const SceneReport& report, const SourceFile& file);

}  // namespace partc

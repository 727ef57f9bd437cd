// The pieces scene instantiation is made of, shared by its three files:
// modules.cpp (finding and parsing modules), interfaces.cpp (checking effect
// bodies against their interfaces, and instances against each other) and
// instantiate.cpp (renaming, placing at slots, merging channels).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sema/scene.hpp"

namespace partc::scene {

// A parsed module: `module NAME`, the modules it imports, functions and
// constants, and at most one effect (none: a module of functions, imported).
struct Module {
  std::string name;
  std::string path;  // as messages name it
  ast::Program program;
  const ast::EffectDecl* effect = nullptr;
  std::vector<const Module*> imports;
};

// Opens modules on first use, each once; a module never used is never read.
class ModuleLibrary {
 public:
  ModuleLibrary(SourceFile& file, const std::vector<ModuleRoot>& roots, SceneReport& report)
      : file_(file), roots_(roots), report_(report) {}
  const Module& open(const ast::UseDecl& use);          // a module with an effect
  const Module& open(const ast::ImportDecl& import);    // any module, for its functions

 private:
  const Module& open(const std::vector<ast::Identifier>& name);
  SourceFile& file_;
  const std::vector<ModuleRoot>& roots_;
  SceneReport& report_;
  std::map<std::string, std::unique_ptr<Module>> modules_;
  std::vector<std::string> opening_;  // the chain of imports being opened, for cycles
};

// One `use`: an effect instantiated on actual sets.
struct Instance {
  std::string name;
  const ast::UseDecl* use = nullptr;
  const Module* module = nullptr;
  std::map<std::string, std::string> sets;  // formal -> actual
  std::vector<std::string> actual_sets;
  std::map<std::string, std::string> locals;  // `owns local u` -> lj_u
  // The variable a name in the effect's body stands for.
  std::string var(const std::string& name) const {
    auto it = locals.find(name);
    return it == locals.end() ? name : it->second;
  }
  const ast::EffectDecl& effect() const { return *module->effect; }
  const std::string& home() const { return actual_sets.front(); }
  bool integrator() const;
  std::vector<std::string> slots(const char* kind) const;  // "slots" or "prime"
};

// Every variable of a set and who declared it: the scene or an effect's `owns`.
struct Owner {
  std::string type;
  bool channel = false;
  const Instance* instance = nullptr;  // null: the scene
  Location loc;
};
using Owners = std::map<std::pair<std::string, std::string>, Owner>;  // (set, var)

// Checks every instance's body against its interface and the instances
// against each other (owners, integrators, writers at a slot, order);
// returns the owners. Throws CompileError with every conflict found.
Owners check_interfaces(const std::vector<Instance>& instances, const ast::Program& scene,
                        const SourceFile& file);

// Integrators of each set, by set name (after check_interfaces: at most one).
std::map<std::string, const Instance*> integrators(const std::vector<Instance>& instances);

// What the instances add to the scene, before it is assembled.
struct Instantiated {
  std::vector<ast::Declaration> declared;                  // params, consts, fns, observables
  std::map<std::string, std::vector<ast::VarDecl>> owned;  // set -> its effects' variables
  std::vector<ast::StageBlock> init, step;                 // primed slots; the step's slots
  std::vector<ast::Requirement> requirements;              // each instance's requires items
};

// Removes from `made` every statement, variable, observable and function
// that nothing the scene keeps needs (liveness.cpp).
void drop_dead(const ast::Program& scene, Instantiated& made, SceneReport& report);

// Calls seen(name) on every name `value` reads: variables, observables,
// functions, consts and params, as written (liveness.cpp).
void for_each_name_read(const ast::Chain& value,
                        const std::function<void(const ast::Identifier&)>& seen);

// The C++ name a qualified name becomes (lj.eps -> lj_eps).
std::string mangled(const std::string& qualified);

}  // namespace partc::scene

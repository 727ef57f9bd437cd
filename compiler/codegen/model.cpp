// Emits the C++ class for a model.
//
// Layout of the generated class, in order: the parameter struct, one tag
// per particle variable (the runtime's SoA ParticleSet is keyed by them),
// the public API (init, load, step, accessors, what the driver needs), one
// private kernel per statement, then the state. Each kernel is one pass
// over its particle set, preceded by the .part line it implements and the
// facts that shaped it (buffered or in place, how neighbours are found).
// Only what the model uses is emitted: no search structure for a set no
// accumulation searches, no buffer for a statement that updates in place.
#include <fmt/format.h>

#include <set>

#include "codegen/codegen.hpp"
#include "codegen/expression.hpp"
#include "codegen/names.hpp"
#include "ir/visitor.hpp"
#include "ir/constant.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace {

using namespace ir;
using codegen::cpp_name;
using codegen::cpp_type;
using codegen::emit_expression;
using codegen::emit_literal;
using codegen::ExpressionNames;
using codegen::NameTable;

// What one statement's kernel touches.
class StatementUses : public Visitor {
 public:
  std::set<std::pair<int, int>> arrays;  // (set, var) read
  std::vector<int> labels;               // through these labels, in order of reading
  std::vector<const Accumulate*> accumulations;
  std::set<int> params, consts;
  bool random = false;

 public:
  using Visitor::visit;

 protected:
  void visit(const VarRef& n) override {
    arrays.insert({n.set, n.var});
    labels.push_back(n.label);
  }
  void visit(const ParamRef& n) override { params.insert(n.param); }
  void visit(const ConstRef& n) override { consts.insert(n.constant); }
  void visit(const Random&) override { random = true; }
  void visit(const Accumulate& n) override {
    accumulations.push_back(&n);
    Visitor::visit(n);
  }
};

// Whether an expression reads any variable through one label (j).
class ReadsLabel : public Visitor {
 public:
  explicit ReadsLabel(int label) : label_(label) {}
  bool found = false;

 public:
  using Visitor::visit;

 protected:
  void visit(const VarRef& n) override { found |= n.label == label_; }

 private:
  int label_;
};

class UsesDx : public Visitor {
 public:
  bool dx = false, norm = false;

 public:
  using Visitor::visit;

 protected:
  void visit(const Dx&) override { dx = true; }
  void visit(const Call& n) override {
    if (n.fn == Function::Norm && as<Dx>(n.args[0])) norm = true;
    Visitor::visit(n);
  }
};

std::string one_line(std::string_view text) {
  std::string out;
  bool space = false;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
      space = !out.empty();
      continue;
    }
    if (space) out += ' ';
    space = false;
    out += c;
  }
  return out;
}

class ModelEmitter {
 public:
  ModelEmitter(const Model& model, const ModelFacts& facts, const SourceFile& file,
               const CodegenOptions& options)
      : m_(model), facts_(facts), file_(file), options_(options) {
    cls_ = codegen::class_name(m_.name);
    for (const char* fixed : {"params_", "rng_", "step_", "domain_"}) members_.reserve(fixed);
    for (const ParticleSet& s : m_.sets) {
      set_member_.push_back(members_.fresh(cpp_name(s.name) + "_"));
      epoch_.push_back(members_.fresh(s.name + "_epoch_"));
      set_type_.push_back(members_.fresh(s.name + "Set"));
    }
    for (const Const& c : m_.consts) const_member_.push_back(members_.fresh(cpp_name(c.name) + "_"));
    for (const char* api : {"params", "set_seed", "step_count", "param_info", "set_param", "init",
                            "load", "step", "for_each_set", "search_report", "check_finite",
                            "compute_constants"})
      members_.reserve(api);
    for (const ParticleSet& s : m_.sets) members_.reserve(cpp_name(s.name));
    for (const UserFn& f : m_.functions) function_member_.push_back(members_.fresh(cpp_name(f.name)));
    plan_searches();
  }

  std::string run() {
    header();
    line("class " + cls_ + " {");
    line("public:");
    public_types();
    public_api();
    line("private:");
    helpers();
    kernels();
    state();
    line("};");
    if (options_.driver_main) {
      line("");
      line("int main(int argc, char** argv) { return partc::run_driver<" + cls_ +
           ">(argc, argv); }");
    }
    line("");
    line("#endif");
    return out_;
  }

 private:
  // ---- output -----------------------------------------------------------

  // A comment, wrapped by words at 96 columns; continuation lines indented.
  void comment(const std::string& text) {
    std::string current = "//";
    std::size_t start = 0;
    while (start < text.size()) {
      std::size_t end = text.find(' ', start);
      if (end == std::string::npos) end = text.size();
      const std::string word = text.substr(start, end - start);
      if (current.size() + 1 + word.size() > 96 && current.size() > 4) {
        line(current);
        current = "//  ";
      }
      current += " " + word;
      start = end + 1;
    }
    line(current);
  }

  void line(const std::string& text) {
    out_ += text;
    out_ += '\n';
  }
  template <class... Args>
  void linef(fmt::format_string<Args...> f, Args&&... args) {
    line(fmt::format(f, std::forward<Args>(args)...));
  }

  std::string source_line(Location loc) const {
    return fmt::format("{}:{}", options_.source_name, file_.line_column(loc.begin).line);
  }
  std::string source_text(Location loc) const { return one_line(file_.slice(loc)); }

  // ---- searches: one per set that neighbourhood sums run over, and per
  // search structure the schedule forces on some of them -----------------

  using SearchKey = std::pair<int, SearchChoice>;  // (set searched, structure)

  void plan_searches() {
    for (const Stage& stage : m_.stages)
      for (const Statement& st : stage.statements) {
        StatementUses uses;
        uses.visit(st.value);
        for (const Accumulate* acc : uses.accumulations) {
          if (facts_.neighbourhoods.at(acc->id).kind != SearchFact::Kind::Neighbours) continue;
          if (st.schedule.skin) {
            if (!lists_.count(&st))
              lists_[&st] = members_.fresh(
                  (st.name.empty() ? m_.sets[st.set].name : st.name) + "_lists_");
            continue;
          }
          const SearchKey key{st.labels[acc->label].set, st.schedule.search};
          if (searches_.count(key)) continue;
          const std::string& set = m_.sets[key.first].name;
          searches_[key] = members_.fresh(key.second == SearchChoice::Auto
                                              ? set + "_search_"
                                              : set + "_" + search_choice_name(key.second) + "_");
        }
      }
  }

  const std::string& search_for(int set, const Statement& st) const {
    return searches_.at({set, st.schedule.search});
  }

  // ---- header -----------------------------------------------------------

  void header() {
    linef("// {}: generated by partc {} from {}.", cls_, PARTC_VERSION, options_.source_name);
    line("// Do not edit: change the .part file and run partc again.");
    // A guard, not #pragma once: the file is also compiled as a main file.
    const std::string guard = "PARTC_GENERATED_" + fmt::format("{}", codegen::upper_case(cls_));
    linef("#ifndef {0}\n#define {0}", guard);
    std::vector<std::string> extent;
    for (int k = 0; k < m_.dim; ++k)
      extent.push_back(fmt::format("[{}, {}]", emit_literal(Type::Real, m_.domain.lo[k]),
                                   emit_literal(Type::Real, m_.domain.hi[k])));
    std::vector<std::string> periodic;
    static const char* axes[] = {"x", "y", "z", "w"};
    for (int k = 0; k < m_.dim; ++k)
      if (m_.domain.periodic[k]) periodic.push_back(axes[k]);
    linef("// Model {}: {} dimensions, domain {}, {}.", m_.name, m_.dim, fmt::join(extent, " x "),
          periodic.empty() ? std::string("not periodic")
                           : "periodic in " + fmt::format("{}", fmt::join(periodic, ", ")));
    std::vector<std::string> std_headers = {"algorithm", "cmath",  "cstdint", "limits",
                                            "map",       "string", "vector"};
    if (!lists_.empty()) std_headers.push_back("optional");
    std::sort(std_headers.begin(), std_headers.end());
    for (const std::string& h : std_headers) linef("#include <{}>", h);
    line("");
    std::vector<std::string> headers = {"csv.hpp",          "domain.hpp",   "errors.hpp",
                                        "finite.hpp",       "math.hpp", "model_support.hpp", "parallel.hpp",
                                        "particle_set.hpp", "rng.hpp",      "vec.hpp"};
    if (!searches_.empty()) headers.push_back("neighbour_search.hpp");
    if (!lists_.empty()) headers.push_back("verlet_list.hpp");
    if (options_.driver_main) headers.push_back("driver.hpp");
    std::sort(headers.begin(), headers.end());
    for (const std::string& h : headers) linef("#include <partc/{}>", h);
    line("");
  }

  // ---- public types -----------------------------------------------------

  std::string tag(int set, int var) const {
    return cpp_name(m_.sets[set].name + "_" + m_.sets[set].vars[var].name);
  }

  void public_types() {
    linef("static constexpr const char* model_name = \"{}\";", m_.name);
    linef("static constexpr int dim = {};", m_.dim);
    linef("using Vec = partc::Vec<{}>;", m_.dim);
    line("");
    line("// Parameters: set them before init(), or with --set NAME=VALUE.");
    line("struct Params {");
    for (const Param& p : m_.params)
      linef("{} {} = {};  // {}", cpp_type(p.type), cpp_name(p.name),
            emit_literal(p.type, as<Literal>(p.default_value)->value), source_line(p.loc));
    line("};");
    for (std::size_t s = 0; s < m_.sets.size(); ++s) {
      const ParticleSet& set = m_.sets[s];
      line("");
      linef("// Particle set {} ({}): p, id, alive and its variables.", set.name,
            source_line(set.loc));
      std::vector<std::string> tags;
      for (std::size_t v = kFirstUserVar; v < set.vars.size(); ++v) {
        const Variable& var = set.vars[v];
        tags.push_back(tag(s, v));
        linef("struct {} {{ using type = {}; static constexpr const char* name = \"{}\"; }};",
              tags.back(), var.type == Type::Vec ? "Vec" : cpp_type(var.type), var.name);
      }
      linef("using {} = partc::ParticleSet<{}{}{}>;", set_type_[s], m_.dim, tags.empty() ? "" : ", ",
            fmt::join(tags, ", "));
    }
    line("");
  }

  // ---- public API -------------------------------------------------------

  void public_api() {
    line("Params& params() { return params_; }");
    line("const Params& params() const { return params_; }");
    line("void set_seed(std::uint64_t seed) { rng_ = partc::CounterRng(seed); }");
    line("std::int64_t step_count() const { return step_; }");
    for (std::size_t s = 0; s < m_.sets.size(); ++s) {
      linef("{0}& {1}() {{ return {2}; }}", set_type_[s], cpp_name(m_.sets[s].name), set_member_[s]);
      linef("const {0}& {1}() const {{ return {2}; }}", set_type_[s], cpp_name(m_.sets[s].name),
            set_member_[s]);
    }
    line("");
    param_info();
    set_param();
    init();
    load();
    step();
    for_each_set();
    search_report();
    line("");
    line("// Throws partc::NumericalError naming the first NaN or Inf found.");
    line("void check_finite() const {");
    for (std::size_t s = 0; s < m_.sets.size(); ++s)
      linef("partc::check_finite({}, \"{}\", step_);", set_member_[s], m_.sets[s].name);
    line("}");
    line("");
  }

  void param_info() {
    line("static std::vector<partc::ParamInfo> param_info() {");
    line("return {");
    for (const Param& p : m_.params)
      linef("{{\"{}\", \"{}\", \"{}\"}},", p.name, type_name(p.type),
            emit_literal(p.type, as<Literal>(p.default_value)->value));
    line("};");
    line("}");
    line("");
  }

  void set_param() {
    line("// Sets a parameter from text, as the driver's --set does.");
    linef("void set_param(const std::string& name, const std::string&{}) {{",
          m_.params.empty() ? "" : " value");
    std::vector<std::string> names;
    for (const Param& p : m_.params) {
      names.push_back(p.name);
      linef("if (name == \"{0}\") {{ params_.{1} = partc::parse_param<{2}>(\"{0}\", value); return; }}",
            p.name, cpp_name(p.name), cpp_type(p.type));
    }
    const std::string listed = names.empty() ? "this model has none" : fmt::format("parameters: {}", fmt::join(names, ", "));
    linef("throw partc::UsageError(\"unknown parameter '\" + name + \"' ({})\");", listed);
    line("}");
    line("");
  }

  void init() {
    line("// Computes the constants, creates every set's particles with their");
    line("// declared initial values, then runs the init blocks.");
    line("void init() {");
    line("compute_constants();");
    line("step_ = 0;");
    for (std::size_t s = 0; s < m_.sets.size(); ++s) linef("create_{}();", m_.sets[s].name);
    for (const std::string& k : kernel_names(StageKind::Init)) linef("{}();", k);
    line("}");
    line("");
  }

  void load() {
    line("// Instead of init(): particles come from tables (CSV files), one per");
    line("// named set; sets not named start empty. Variables a table lacks take");
    line("// their declared initial values.");
    line("void load(const std::map<std::string, partc::CsvTable>& tables) {");
    line("compute_constants();");
    line("step_ = 0;");
    std::vector<std::string> names;
    for (std::size_t s = 0; s < m_.sets.size(); ++s) {
      const std::string& name = m_.sets[s].name;
      names.push_back(name);
      linef("{}.clear();", set_member_[s]);
      linef("if (auto t = tables.find(\"{}\"); t != tables.end())", name);
      linef("partc::load_set({0}, t->second, domain_, [this](std::size_t i) {{ initialise_{1}(i); }});",
            set_member_[s], name);
      linef("++{};", epoch_[s]);
    }
    line("for (const auto& [name, table] : tables)");
    linef("if ({}) throw partc::UsageError(\"no particle set '\" + name + \"' in model {} (sets: {})\");",
          fmt::join(set_comparisons(names), " && "), m_.name, fmt::join(names, ", "));
    line("}");
    line("");
  }

  static std::vector<std::string> set_comparisons(const std::vector<std::string>& names) {
    std::vector<std::string> out;
    for (const std::string& n : names) out.push_back("name != \"" + n + "\"");
    return out;
  }

  void step() {
    line("// One time step: every step block, in order.");
    line("void step() {");
    for (const std::string& k : kernel_names(StageKind::Step)) linef("{}();", k);
    line("++step_;");
    line("}");
    line("");
  }

  void for_each_set() {
    line("// f(name, set) for every particle set, in declaration order.");
    line("template <class F> void for_each_set(F&& f) const {");
    for (std::size_t s = 0; s < m_.sets.size(); ++s)
      linef("f(\"{}\", {});", m_.sets[s].name, set_member_[s]);
    line("}");
  }

  void search_report() {
    line("// Each neighbour search: what it serves, its structure, its builds so far.");
    line("std::vector<partc::SearchReport> search_report() const {");
    line("std::vector<partc::SearchReport> report;");
    for (const auto& [key, search] : searches_)
      linef("report.push_back({{\"sums over {0}{1}\", {2}.describe(), {2}.build_count()}});",
            m_.sets[key.first].name,
            key.second == SearchChoice::Auto ? ""
                                             : std::string(" (schedule: ") +
                                                   search_choice_name(key.second) + ")",
            search);
    for (const auto& [st, lists] : lists_)
      linef("if ({0}) report.push_back({{\"{1}\", {0}->describe(), {0}->rebuild_count()}});", lists,
            (st->name.empty() ? "" : st->name + " at ") + source_line(st->loc));
    line("return report;");
    line("}");
  }

  // ---- private helpers --------------------------------------------------

  void helpers() {
    for (std::size_t f = 0; f < m_.functions.size(); ++f) user_function(static_cast<int>(f));
    line("// Constants that depend on parameters, computed once they are known.");
    line("void compute_constants() {");
    for (std::size_t c = 0; c < m_.consts.size(); ++c)
      if (!evaluate_constant(m_.consts[c].value, m_))
        linef("{} = {};  // {}", const_member_[c], expression(m_.consts[c].value, initialiser_names(0)),
              source_line(m_.consts[c].loc));
    line("}");
    line("");
    for (std::size_t s = 0; s < m_.sets.size(); ++s) {
      create_set(static_cast<int>(s));
      initialise_particle(static_cast<int>(s));
    }
  }

  void user_function(int f) {
    const UserFn& fn = m_.functions[f];
    std::vector<std::string> args;
    for (std::size_t k = 0; k < fn.arg_names.size(); ++k)
      args.push_back((fn.arg_types[k] == Type::Vec ? "const Vec& " : cpp_type(fn.arg_types[k]) + " ") +
                     cpp_name(fn.arg_names[k]));
    linef("// {}", source_line(fn.loc));
    linef("//   {}", source_text(fn.loc));
    linef("{} {}({}) const {{ return {}; }}", cpp_type(fn.body->type), function_member_[f],
          fmt::join(args, ", "), expression(fn.body, base_names()));
    line("");
  }

  // Names every expression may use: consts and functions.
  ExpressionNames base_names() const {
    ExpressionNames names;
    for (const Param& param : m_.params) names.params.push_back("params_." + cpp_name(param.name));
    names.consts = const_member_;
    names.functions = function_member_;
    return names;
  }

  void create_set(int s) {
    const ParticleSet& set = m_.sets[s];
    linef("// Creates the {} particles of {} ({}).", source_text(set.initial_count->loc), set.name,
          source_line(set.loc));
    linef("void create_{}() {{", set.name);
    linef("const std::int64_t count = {};", expression(set.initial_count, initialiser_names(s)));
    linef("if (count < 0) throw partc::UsageError(\"particle set {} would have \" + std::to_string(count) + \" particles\");",
          set.name);
    linef("{}.clear();", set_member_[s]);
    linef("{}.reserve(static_cast<std::size_t>(count));", set_member_[s]);
    line("for (std::int64_t k = 0; k < count; ++k)");
    linef("initialise_{}({}.push_back(Vec::zero()));", set.name, set_member_[s]);
    linef("++{};", epoch_[s]);
    line("}");
    line("");
  }

  void initialise_particle(int s) {
    const ParticleSet& set = m_.sets[s];
    linef("// The declared initial values of particle i of {}.", set.name);
    bool any = false;
    for (const Variable& v : set.vars) any |= v.initial != nullptr;
    linef("void initialise_{}(std::size_t{}) {{", set.name, any ? " i" : "");
    if (any) {
      ExpressionNames names = initialiser_names(s);
      std::set<std::pair<int, int>> arrays;
      bool random = false;
      for (const Variable& v : set.vars) {
        if (!v.initial) continue;
        StatementUses uses;
        uses.visit(v.initial);
        random |= uses.random;
      }
      if (random) linef("const auto& id = {}.ids();", set_member_[s]);
      for (std::size_t v = 0; v < set.vars.size(); ++v) {
        const Variable& var = set.vars[v];
        if (!var.initial) continue;
        linef("{}[i] = {};  // {}", array_access(s, static_cast<int>(v)),
              expression(var.initial, names), source_line(var.loc));
      }
    }
    line("}");
    line("");
  }

  // `P_.get<P_v>()`, `P_.positions()`, ...: a set's array of one variable.
  std::string array_access(int s, int var) const {
    switch (var) {
      case kPosition: return set_member_[s] + ".positions()";
      case kId: return set_member_[s] + ".ids()";
      case kAlive: return set_member_[s] + ".alive()";
      default: return set_member_[s] + ".get<" + tag(s, var) + ">()";
    }
  }

  ExpressionNames initialiser_names(int s) const {
    ExpressionNames names = base_names();
    names.home_set = s;
    names.labels = {"i"};
    names.array = [](int, int var) { return var == kId ? std::string("id") : std::string("?"); };
    return names;
  }

  std::string expression(const Expr& e, const ExpressionNames& names) const {
    return emit_expression(e, m_, names);
  }

  // ---- kernels ----------------------------------------------------------

  struct Kernel {
    std::string name;
    const Statement* st;
    const AliasFact* alias;
  };

  void plan_kernels() {
    if (!kernels_.empty()) return;
    for (std::size_t g = 0; g < m_.stages.size(); ++g) {
      const Stage& stage = m_.stages[g];
      for (std::size_t k = 0; k < stage.statements.size(); ++k) {
        const Statement& st = stage.statements[k];
        const std::string stage_name = stage.kind == StageKind::Init ? "init" : "step";
        const std::string set_part = m_.sets.size() > 1 ? m_.sets[st.set].name + "_" : "";
        kernels_.push_back({members_.fresh(stage_name + "_" + set_part + m_.sets[st.set].vars[st.var].name),
                            &st, &facts_.aliasing[g][k]});
        kernel_stage_.push_back(stage.kind);
      }
    }
  }

  std::vector<std::string> kernel_names(StageKind kind) {
    plan_kernels();
    std::vector<std::string> out;
    for (std::size_t k = 0; k < kernels_.size(); ++k)
      if (kernel_stage_[k] == kind) out.push_back(kernels_[k].name);
    return out;
  }

  void kernels() {
    plan_kernels();
    for (const Kernel& k : kernels_) kernel(k);
  }

  void kernel(const Kernel& k) {
    const Statement& st = *k.st;
    const int home = st.set;
    StatementUses uses;
    uses.visit(st.value);

    // Names local to this kernel: the model's own, then ours.
    NameTable locals;
    for (const Label& l : st.labels) locals.reserve(cpp_name(l.name));
    for (std::size_t s = 0; s < m_.sets.size(); ++s)
      for (std::size_t v = kFirstUserVar; v < m_.sets[s].vars.size(); ++v)
        locals.reserve(tag(static_cast<int>(s), static_cast<int>(v)));
    std::map<std::pair<int, int>, std::string> arrays;
    auto array_name = [&](int s, int var) -> std::string {
      auto key = std::make_pair(s, var);
      auto it = arrays.find(key);
      if (it != arrays.end()) return it->second;
      // Another set's arrays are named "<var>_<set>" (strength_O): never a tag name.
      const std::string wanted = cpp_name(s == home ? m_.sets[s].vars[var].name
                                                    : m_.sets[s].vars[var].name + "_" + m_.sets[s].name);
      return arrays[key] = locals.fresh(wanted);
    };
    std::set<std::pair<int, int>> needed = uses.arrays;
    needed.insert({home, st.var});
    if (uses.random) needed.insert({home, kId});
    for (const Accumulate* acc : uses.accumulations) {
      UsesDx dx;
      dx.visit(acc->condition);
      dx.visit(acc->body);
      const SearchFact& fact = facts_.neighbourhoods.at(acc->id);
      // A search over another set is asked from p[i]; one over the home set and Verlet
      // lists by i alone; a dense loop computes dx itself.
      if (fact.kind == SearchFact::Kind::Neighbours && !st.schedule.skin &&
          st.labels[acc->label].set != home)
        needed.insert({home, kPosition});
      if (fact.kind == SearchFact::Kind::Dense && dx.dx) {
        needed.insert({home, kPosition});
        needed.insert({st.labels[acc->label].set, kPosition});
      }
    }
    for (const auto& [s, var] : needed) array_name(s, var);

    ExpressionNames names = base_names();
    names.home_set = home;
    for (const Label& l : st.labels) names.labels.push_back(cpp_name(l.name));
    names.array = array_name;
    for (const Accumulate* acc : uses.accumulations)
      names.accumulators[acc->id] =
          locals.fresh(std::string(reduction_name(acc->reduction)) + "_" + names.labels[acc->label]);
    const std::string count = locals.fresh("n");
    // A fused loop has one index: every label it serves is named after the first.
    const std::vector<Loop> loops = fuse_loops(uses.accumulations, st);
    for (const Loop& l : loops)
      for (const Accumulate* acc : l.members)
        names.labels[acc->label] = names.labels[l.members.front()->label];
    const std::string i = names.labels[0];

    // The comment: the .part line and the decisions behind the kernel.
    linef("// {}", source_line(st.loc));
    linef("//   {}", source_text(st.loc));
    for (const Accumulate* acc : uses.accumulations) {
      comment(fmt::format("{}({}): {}", reduction_name(acc->reduction), st.labels[acc->label].name,
                          facts_.neighbourhoods.at(acc->id).reason));
      if (newton_pairs(st) && facts_.neighbourhoods.at(acc->id).kind == SearchFact::Kind::Neighbours)
        comment((st.schedule.skin ? "  each pair once, from half Verlet lists: "
                                  : "  each pair once when the search can walk pairs: ") +
                facts_.symmetry.at(acc->id).reason);
      if (facts_.uniform_sums.at(acc->id).once)
        comment("  " + facts_.uniform_sums.at(acc->id).reason);
    }
    comment(k.alias->reason);
    linef("void {}() {{", k.name);
    kernel_constants(st, uses, names, locals);

    // Bring every search this statement needs up to date before any index
    // is taken: a rebuild may reorder its set.
    std::map<int, std::vector<std::string>> radii;  // set -> radius expressions
    for (const Accumulate* acc : uses.accumulations) {
      const SearchFact& fact = facts_.neighbourhoods.at(acc->id);
      if (fact.kind != SearchFact::Kind::Neighbours) continue;
      auto& list = radii[st.labels[acc->label].set];
      const std::string radius = radius_expression(fact, st, names);
      if (std::find(list.begin(), list.end(), radius) == list.end()) list.push_back(radius);
    }
    for (const auto& [s, list] : radii) {
      if (st.schedule.skin)
        refresh_lists(st, list, locals.fresh("radius"), names);
      else
        refresh_search(s, search_for(s, st), list, locals.fresh("radius"));
    }

    for (const auto& [key, name] : arrays) {
      const bool written = key.first == home && key.second == st.var;
      linef("{}auto& {} = {};", written ? "" : "const ", name, array_access(key.first, key.second));
    }
    linef("const std::size_t {} = {}.size();", count, set_member_[home]);
    std::string buffer;
    if (k.alias->buffered) {
      buffer = buffer_member(home, st.var);
      linef("{}.resize({});", buffer, count);
    }
    std::vector<const Loop*> per_particle;
    std::string pairs_once;  // names the run-time choice of a search's pair walk
    for (const Loop& l : loops) {
      if (l.once) {
        loop(l, st, names);
      } else if (l.kind == SearchFact::Kind::Neighbours && half_lists(st)) {
        pair_pass(l, names, count, locals, lists_.at(&st) + "->for_each_pair");
        for (const Accumulate* acc : l.members)
          names.accumulators[acc->id] = pair_sums_.at(acc->id).first + "[" + i + "]";
      } else if (l.kind == SearchFact::Kind::Neighbours && newton_pairs(st)) {
        const std::string& search = search_for(l.set, st);
        pairs_once = locals.fresh("pairs_once");
        line("// Each pair once when the search walks pairs in parallel, or the set is small.");
        linef("const bool {} = {}.pairs_once();", pairs_once, search);
        linef("if ({}) {{", pairs_once);
        pair_pass(l, names, count, locals, search + ".for_each_pair");
        line("}");
        per_particle.push_back(&l);
      } else {
        per_particle.push_back(&l);
      }
    }
    // Every iteration writes only particle i's value (aliasing saw to that).
    linef("partc::parallel_for({}, partc::LoopWork::{}, [&](std::size_t {}) {{", count,
          per_particle.empty() ? "light" : "heavy", i);
    for (const Loop* l : per_particle)
      loop(*l, st, names, l->kind == SearchFact::Kind::Neighbours ? pairs_once : "");
    assignment(st, names, buffer);
    line("});");
    const std::string target_array = array_name(home, st.var);
    if (!buffer.empty()) linef("{}.swap({});", target_array, buffer);
    if (st.var == kAlive) linef("{}.erase_dead();", set_member_[home]);
    if (st.var == kPosition || st.var == kAlive) linef("++{};", epoch_[home]);
    line("}");
    line("");
  }

  // The params and computed consts a kernel reads, as local constants named
  // after them: the kernel reads like the model, and the C++ compiler need not
  // reload them after every call it cannot see into (exp in a pair loop;
  // the seed kernel at N = 20 timed alone: 4% faster).
  void kernel_constants(const Statement& st, StatementUses uses, ExpressionNames& names,
                        NameTable& locals) {
    if (st.schedule.skin) uses.visit(st.schedule.skin);
    for (int p : uses.params) {
      const Param& param = m_.params[p];
      names.params[p] = locals.fresh(cpp_name(param.name));
      linef("const {} {} = params_.{};", cpp_type(param.type), names.params[p], cpp_name(param.name));
    }
    for (int c : uses.consts) {
      if (evaluate_constant(m_.consts[c].value, m_)) continue;  // a static constexpr member already
      names.consts[c] = locals.fresh(cpp_name(m_.consts[c].name));
      linef("const {} {} = {};", cpp_type(m_.consts[c].type), names.consts[c], const_member_[c]);
    }
  }

  std::string buffer_member(int s, int var) {
    auto key = std::make_pair(s, var);
    auto it = buffers_.find(key);
    if (it != buffers_.end()) return it->second.first;
    const ParticleSet& set = m_.sets[s];
    const std::string name =
        members_.fresh((m_.sets.size() > 1 ? set.name + "_" : "") + set.vars[var].name + "_next_");
    const Type type = set.vars[var].type;
    const std::string element = type == Type::Bool ? "std::uint8_t" : cpp_type(type);
    buffers_[key] = {name, element};
    return name;
  }

  void refresh_search(int s, const std::string& search, const std::vector<std::string>& radii,
                      const std::string& local) {
    std::string radius = radii.front();
    for (std::size_t k = 1; k < radii.size(); ++k) radius = "std::max(" + radius + ", " + radii[k] + ")";
    linef("const double {} = {};", local, radius);
    linef("if ({0}epoch_ != {1} || {0}radius_ != {2}) {{", search, epoch_[s], local);
    linef("{}.build(domain_, {}, {});", search, local, set_member_[s]);
    linef("{}epoch_ = ++{};  // the build may reorder {}", search, epoch_[s], m_.sets[s].name);
    linef("{}radius_ = {};", search, local);
    line("}");
  }

  // The search radius: the bound itself when it is uniform, else the sum of
  // each term's largest value over the particles it reads (max r + max r for
  // r[i] + r[j]), kept positive so coincident particles are still found.
  std::string radius_expression(const SearchFact& fact, const Statement& st,
                                const ExpressionNames& names) const {
    if (fact.radius_terms.size() == 1 && is_uniform(fact.radius_terms.front()))
      return expression(fact.radius_terms.front(), names);
    std::vector<std::string> parts;
    for (const Expr& term : fact.radius_terms) {
      StatementUses reads;
      reads.visit(term);
      if (reads.arrays.empty()) {
        parts.push_back(expression(term, names));
        continue;
      }
      const int label = reads.labels.front();
      const int set = st.labels[label].set;
      ExpressionNames over_k = names;
      over_k.labels[label] = "k";
      over_k.array = [this](int s, int var) { return array_access(s, var); };
      parts.push_back(fmt::format("partc::max_over({}.size(), [&](std::size_t k) {{ return {}; }})",
                                  set_member_[set], expression(term, over_k)));
    }
    return fmt::format("std::max({}, std::numeric_limits<double>::min())", fmt::join(parts, " + "));
  }

  // Newton's third law: a statement whose every neighbour sum gives j the term
  // i gets, or its negative (analysis/symmetry.cpp), can take each pair once:
  // from half lists with Verlet lists (half_lists), else from the search's pair
  // walk when NeighbourSearch::pairs_once says it pays (else per-particle queries).
  bool half_lists(const Statement& st) const { return st.schedule.skin && newton_pairs(st); }
  bool newton_pairs(const Statement& st) const {
    StatementUses uses;
    uses.visit(st.value);
    bool any = false;
    for (const Accumulate* acc : uses.accumulations) {
      if (facts_.neighbourhoods.at(acc->id).kind != SearchFact::Kind::Neighbours) continue;
      if (!facts_.symmetry.at(acc->id).newton) return false;
      any = true;
    }
    return any;
  }

  // Verlet lists: reused while no particle has moved half the skin since
  // they were built; a rebuild may reorder the set, like a search build.
  void refresh_lists(const Statement& st, const std::vector<std::string>& radii,
                     const std::string& local, const ExpressionNames& names) {
    std::string radius = radii.front();
    for (std::size_t k = 1; k < radii.size(); ++k) radius = "std::max(" + radius + ", " + radii[k] + ")";
    const std::string& lists = lists_.at(&st);
    const std::string skin = expression(st.schedule.skin, names);
    linef("const double {} = {};", local, radius);
    linef("if (!{0} || {0}->skin() != {1}) {0}.emplace({1}{2});", lists, skin,
          half_lists(st) ? ", partc::VerletPairs::half" : "");
    linef("if ({}->update(domain_, {}, {})) ++{};  // rebuilt: {} may be reordered", lists, local,
          set_member_[st.set], epoch_[st.set], m_.sets[st.set].name);
  }

  // Accumulations of one statement over the same set, found the same way
  // (the same search, or the same dense loop), share one pass: SPH's
  // density and its normalisation cost one neighbour walk, not two.
  struct Loop {
    int set;
    SearchFact::Kind kind;
    bool once;  // the same for every i (uniform_sums.cpp): run before the particle loop
    std::vector<const Accumulate*> members;
  };

  std::vector<Loop> fuse_loops(const std::vector<const Accumulate*>& accumulations,
                               const Statement& st) const {
    std::vector<Loop> loops;
    for (const Accumulate* acc : accumulations) {
      const int set = st.labels[acc->label].set;
      const SearchFact::Kind kind = facts_.neighbourhoods.at(acc->id).kind;
      const bool once = facts_.uniform_sums.at(acc->id).once;
      auto same = std::find_if(loops.begin(), loops.end(), [&](const Loop& l) {
        return l.set == set && l.kind == kind && l.once == once;
      });
      if (same == loops.end())
        loops.push_back({set, kind, once, {acc}});
      else
        same->members.push_back(acc);
    }
    return loops;
  }

  std::string identity(const Accumulate& acc) const {
    switch (acc.reduction) {
      case Reduction::Sum:
        return acc.type == Type::Vec ? "Vec::zero()" : emit_literal(acc.type, 0);
      case Reduction::Count: return "0";
      case Reduction::Min:
        return acc.type == Type::Real ? "std::numeric_limits<double>::infinity()"
                                      : "std::numeric_limits<std::int64_t>::max()";
      case Reduction::Max:
        return acc.type == Type::Real ? "-std::numeric_limits<double>::infinity()"
                                      : "std::numeric_limits<std::int64_t>::min()";
    }
    internal_error("identity: unknown reduction");
  }

  std::string update(const Accumulate& acc, const ExpressionNames& names) const {
    const std::string& name = names.accumulators.at(acc.id);
    std::string step;
    switch (acc.reduction) {
      case Reduction::Sum: step = name + " += " + expression(acc.body, names) + ";"; break;
      case Reduction::Count: step = "++" + name + ";"; break;
      case Reduction::Min:
      case Reduction::Max:
        step = fmt::format("{0} = std::{1}<{2}>({0}, {3});", name, reduction_name(acc.reduction),
                           cpp_type(acc.type), expression(acc.body, names));
        break;
    }
    if (always_true(acc)) return step;
    return "if (" + expression(acc.condition, names) + ") " + step;
  }

  // No condition, or one always true (sum(j, true, ...)): no test.
  bool always_true(const Accumulate& acc) const {
    const std::optional<double> constant =
        acc.condition ? evaluate_constant(acc.condition, m_) : std::optional<double>(1.0);
    return constant && *constant != 0;
  }

  std::string accumulator_type(const Accumulate& acc) const {
    return acc.reduction == Reduction::Count ? "std::int64_t" : cpp_type(acc.type);
  }

  // The loop of one particle i over its partners; with pairs_once (the name of
  // the run-time choice) the totals come from the pair walk's sums instead.
  void loop(const Loop& l, const Statement& st, const ExpressionNames& names,
            const std::string& pairs_once = "") {
    UsesDx dx;
    bool reads_j = false;
    for (const Accumulate* acc : l.members) {
      linef("{} {} = {};", accumulator_type(*acc), names.accumulators.at(acc->id), identity(*acc));
      dx.visit(acc->condition);
      dx.visit(acc->body);
      ReadsLabel reads(acc->label);
      reads.visit(acc->condition);
      reads.visit(acc->body);
      reads_j |= reads.found;
    }
    ExpressionNames inner = names;
    inner.dx_norm = dx.norm ? "dx_norm" : "";
    std::string body;
    if (dx.norm) body += "const double dx_norm = partc::norm(dx);\n";
    for (const Accumulate* acc : l.members) body += update(*acc, inner) + "\n";

    const std::string j = names.labels[l.members.front()->label];
    const std::string i = names.labels[0];
    const std::string home_p = names.array(st.set, kPosition);
    if (!pairs_once.empty()) {
      linef("if ({}) {{", pairs_once);
      for (const Accumulate* acc : l.members)
        linef("{} = {}[{}];", names.accumulators.at(acc->id), pair_sums_.at(acc->id).first, i);
      line("} else {");
    }
    if (l.kind == SearchFact::Kind::Neighbours) {
      if (st.schedule.skin)
        linef("{}->for_each_near({}, [&](std::size_t{}, const Vec&{}) {{", lists_.at(&st), i,
              reads_j ? " " + j : "", dx.dx ? " dx" : "");
      else  // a query from the searched set itself goes by index: the search knows its cell
        linef("{}.for_each_near({}, [&](std::size_t{}, const Vec&{}) {{", search_for(l.set, st),
              l.set == st.set ? i : fmt::format("{}[{}]", home_p, i), reads_j ? " " + j : "",
              dx.dx ? " dx" : "");
      out_ += body;
      line("});");
      if (!pairs_once.empty()) line("}");
    } else {
      linef("for (std::size_t {0} = 0; {0} < {1}.size(); ++{0}) {{", j, set_member_[l.set]);
      if (dx.dx)
        linef("const Vec dx = domain_.minimum_image({}[{}] - {}[{}]);", names.array(l.set, kPosition),
              j, home_p, i);
      out_ += body;
      line("}");
    }
  }

  // The sums of a loop over pairs (walk: half lists' or a search's
  // for_each_pair), pair by pair, into per-particle member vectors (kept
  // between steps for their memory) that the particle loop reads.
  void pair_pass(const Loop& l, const ExpressionNames& names, const std::string& count,
                 NameTable& locals, const std::string& walk) {
    const std::string i = names.labels[0];
    const std::string j = names.labels[l.members.front()->label];
    UsesDx dx;
    for (const Accumulate* acc : l.members) {
      dx.visit(acc->condition);
      dx.visit(acc->body);
      linef("{}.assign({}, {});", pair_sums_member(*acc), count, identity(*acc));
    }
    ExpressionNames inner = names;
    inner.dx_norm = dx.norm ? "dx_norm" : "";
    // i's terms go to locals, stored once per group of i's pairs; j's straight to j.
    std::map<int, std::string> of_i;
    for (const Accumulate* acc : l.members)
      of_i[acc->id] = locals.fresh(std::string(reduction_name(acc->reduction)) + "_" + i);
    const std::string term = locals.fresh("term"), pairs = locals.fresh("pairs_of_" + i);
    line("// Each pair once (Newton's third law): i and j get the same term, or opposite ones.");
    linef("{}([&](std::size_t {}, const auto& {}) {{", walk, i, pairs);
    for (const Accumulate* acc : l.members)
      linef("{} {} = {};", accumulator_type(*acc), of_i.at(acc->id), identity(*acc));
    linef("{}([&](std::size_t {}, const Vec&{}) {{", pairs, j, dx.dx ? " dx" : "");
    if (dx.norm) line("const double dx_norm = partc::norm(dx);");
    for (const Accumulate* acc : l.members) {
      const std::string& sums = pair_sums_.at(acc->id).first;
      const bool test = !always_true(*acc);
      if (test) linef("if ({}) {{", expression(acc->condition, inner));
      if (acc->reduction == Reduction::Count) {
        linef("++{};", of_i.at(acc->id));
        linef("if ({1} != {2}) ++{0}[{2}];", sums, i, j);
      } else {
        linef("const {} {} = {};", cpp_type(acc->type), term, expression(acc->body, inner));
        linef("{} += {};", of_i.at(acc->id), term);
        linef("if ({2} != {1}) {0}[{2}] {3}= {4};", sums, i, j,
              facts_.symmetry.at(acc->id).sign > 0 ? "+" : "-", term);
      }
      if (test) line("}");
    }
    line("});");
    for (const Accumulate* acc : l.members)
      linef("{}[{}] += {};", pair_sums_.at(acc->id).first, i, of_i.at(acc->id));
    line("});");
  }

  std::string pair_sums_member(const Accumulate& acc) {
    auto it = pair_sums_.find(acc.id);
    if (it != pair_sums_.end()) return it->second.first;
    const std::string name = members_.fresh(std::string(reduction_name(acc.reduction)) + "_pairs_");
    pair_sums_[acc.id] = {name, accumulator_type(acc)};
    return name;
  }

  void assignment(const Statement& st, const ExpressionNames& names, const std::string& buffer) {
    const std::string target = names.array(st.set, st.var) + "[" + names.labels[0] + "]";
    const bool wrap = st.var == kPosition &&
                      std::find(m_.domain.periodic.begin(), m_.domain.periodic.end(), true) !=
                          m_.domain.periodic.end();
    const std::string value = expression(st.value, names);
    if (buffer.empty() && !wrap) {
      linef("{} {} {};", target, assign_op_spelling(st.op), value);
      return;
    }
    // The new value as one expression: target op value.
    std::string updated = value;
    if (st.op != AssignOp::Set) {
      static const BinaryOp ops[] = {BinaryOp::Add, BinaryOp::Add, BinaryOp::Sub, BinaryOp::Mul,
                                     BinaryOp::Div};
      const BinaryOp op = ops[static_cast<int>(st.op)];
      updated = fmt::format("{} {} {}", target, binary_op_spelling(op),
                            codegen::emit_operand(st.value, op, m_, names));
    }
    if (wrap) updated = "domain_.wrap(" + updated + ")";
    linef("{} = {};", buffer.empty() ? target : buffer + "[" + names.labels[0] + "]", updated);
  }

  // ---- state ------------------------------------------------------------

  void state() {
    line("Params params_;");
    for (std::size_t c = 0; c < m_.consts.size(); ++c) {
      const Const& k = m_.consts[c];
      if (auto value = evaluate_constant(k.value, m_))
        linef("static constexpr {} {} = {};  // {}", cpp_type(k.type), const_member_[c],
              emit_literal(k.type, *value), source_text(k.loc));
      else
        linef("{} {}{{}};  // {}", cpp_type(k.type), const_member_[c], source_text(k.loc));
    }
    std::vector<std::string> lo, hi, periodic;
    for (int k = 0; k < m_.dim; ++k) {
      lo.push_back(emit_literal(Type::Real, m_.domain.lo[k]));
      hi.push_back(emit_literal(Type::Real, m_.domain.hi[k]));
      periodic.push_back(m_.domain.periodic[k] ? "true" : "false");
    }
    linef("partc::Domain<{}> domain_{{Vec{{{{{}}}}}, Vec{{{{{}}}}}, {{{{{}}}}}}};", m_.dim,
          fmt::join(lo, ", "), fmt::join(hi, ", "), fmt::join(periodic, ", "));
    line("partc::CounterRng rng_;");
    line("std::int64_t step_ = 0;");
    for (std::size_t s = 0; s < m_.sets.size(); ++s) {
      linef("{} {};", set_type_[s], set_member_[s]);
      linef("std::uint64_t {} = 0;  // bumped whenever {}'s positions or order change", epoch_[s],
            m_.sets[s].name);
    }
    for (const auto& [key, search] : searches_) {
      if (key.second == SearchChoice::Auto)
        linef("partc::NeighbourSearch<{}> {};  // over {}", m_.dim, search, m_.sets[key.first].name);
      else
        linef("partc::NeighbourSearch<{0}> {1}{{partc::NeighbourSearch<{0}>::Kind::{2}}};  // schedule",
              m_.dim, search, search_choice_name(key.second));
      linef("std::uint64_t {}epoch_ = std::numeric_limits<std::uint64_t>::max();", search);
      linef("double {}radius_ = 0;", search);
    }
    for (const auto& [st, lists] : lists_)
      linef("std::optional<partc::VerletList<{}>> {};  // schedule: skin {}", m_.dim, lists,
            source_text(st->schedule.skin->loc));
    for (const auto& [id, sums] : pair_sums_)
      linef("std::vector<{}> {};  // per particle, a sum over each pair once", sums.second, sums.first);
    for (const auto& [key, buffer] : buffers_)
      linef("std::vector<{}> {};  // new values of {}, for buffered updates", buffer.second, buffer.first,
            m_.sets[key.first].vars[key.second].name);
  }

  const Model& m_;
  const ModelFacts& facts_;
  const SourceFile& file_;
  const CodegenOptions& options_;
  std::string out_;
  std::string cls_;
  NameTable members_;
  std::vector<std::string> set_member_, epoch_, set_type_, const_member_, function_member_;
  std::map<SearchKey, std::string> searches_;
  std::map<const Statement*, std::string> lists_;  // Verlet lists of statements with a skin
  std::vector<Kernel> kernels_;
  std::vector<StageKind> kernel_stage_;
  std::map<std::pair<int, int>, std::pair<std::string, std::string>> buffers_;  // -> name, element
  std::map<int, std::pair<std::string, std::string>> pair_sums_;  // Accumulate::id -> name, element
};

}  // namespace

std::string generate_cpp(const Model& model, const ModelFacts& facts, const SourceFile& file,
                         const CodegenOptions& options) {
  return ModelEmitter(model, facts, file, options).run();
}

}  // namespace partc

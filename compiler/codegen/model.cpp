// Emits the C++ class for a model.
//
// Layout of the generated class, in order: the parameter struct, one tag
// per particle variable (the runtime's SoA ParticleSet is keyed by them),
// the public API (init, load, step, accessors, what the driver needs), one
// private kernel per statement (codegen/kernel.cpp), then the state. Each
// kernel is one pass over its particle set, preceded by the .part line it
// implements and the facts that shaped it (buffered or in place, how
// neighbours are found).
// Only what the model uses is emitted: no search structure for a set no
// accumulation searches, no buffer for a statement that updates in place.
#include <fmt/format.h>

#include <algorithm>

#include "codegen/model_emitter.hpp"
#include "ir/constant.hpp"
#include "ir/terms.hpp"
#include "support/diagnostics.hpp"

namespace partc {

namespace codegen {

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

ModelEmitter::ModelEmitter(const Model& model, const ModelFacts& facts, const SourceFile& file,
                           const CodegenOptions& options)
    : m_(model), facts_(facts), file_(file), options_(options) {
  cls_ = codegen::class_name(m_.name);
  members_.reserve(cls_);  // a member or nested type named like the class would be its constructor
  observables_type_ = members_.fresh("Observables");
  for (const char* fixed :
       {"params_", "rng_", "step_", "t_", "observables_", "observed_", "domain_", "faces_"})
    members_.reserve(fixed);
  for (const ParticleSet& s : m_.sets) {
    set_member_.push_back(members_.fresh(cpp_name(s.name) + "_"));
    epoch_.push_back(members_.fresh(s.name + "_epoch_"));
    set_type_.push_back(members_.fresh(s.name + "Set"));
    if (Domain::any(m_.domain.open)) left_.push_back(members_.fresh(s.name + "_left_"));
  }
  for (const Const& c : m_.consts) const_member_.push_back(members_.fresh(cpp_name(c.name) + "_"));
  for (const char* api : {"params",
                          "set_seed",
                          "step_count",
                          "param_info",
                          "set_param",
                          "init",
                          "load",
                          "step",
                          "for_each_set",
                          "search_report",
                          "check_finite",
                          "compute_constants",
                          "observables",
                          "time",
                          "log_columns",
                          "log_every",
                          "log_row",
                          "solve_report",
                          "boundary_report",
                          "frames",
                          "set_matrix_market",
                          "matrix_market_",
                          "stage_names",
                          "run_stage",
                          "fast_sum_report",
                          "set_check_accuracy",
                          "fast_sums_",
                          "check_accuracy_"})
    members_.reserve(api);
  for (const auto& [id, fact] : facts_.fast_sums) {
    const std::size_t index = fast_sum_records_.size();
    fast_sum_records_[id] = index;
  }
  for (const Stage& stage : m_.stages)
    if (stage.kind == StageKind::Named)
      stage_methods_[stage.name] = members_.fresh(cpp_name(stage.name));
  for (const ParticleSet& s : m_.sets) members_.reserve(cpp_name(s.name));
  for (const UserFn& f : m_.functions) function_member_.push_back(members_.fresh(cpp_name(f.name)));
  plan_searches();
  for (const auto& [position, fact] : facts_.observed_steps) {
    const Statement& st = m_.stages[position.first].statements[position.second];
    const std::string target = target_name(m_, st);
    if (!fact.observed_only || std::find(observed_only_targets_.begin(), observed_only_targets_.end(),
                                         target) != observed_only_targets_.end())
      continue;
    observed_only_targets_.push_back(target);
    if (st.observable >= 0) observed_only_.insert(st.observable);
  }
}

std::string ModelEmitter::run() {
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
    line("int main(int argc, char** argv) { return partc::run_driver<" + cls_ + ">(argc, argv); }");
  }
  line("");
  line("#endif");
  return out_;
}

// A comment, wrapped by words at 96 columns; continuation lines indented.
void ModelEmitter::comment(const std::string& text) {
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

void ModelEmitter::line(const std::string& text) {
  out_ += text;
  out_ += '\n';
}

// The model's own lines by the name it was given; a module's by its path.
std::string ModelEmitter::source_line(Location loc) const {
  return fmt::format("{}:{}",
                     file_.file_of(loc.begin) == 0 ? options_.source_name : file_.path_of(loc.begin),
                     file_.output_line(loc.begin));
}

std::vector<std::pair<std::string, std::vector<const Statement*>>> ModelEmitter::lists_served()
    const {
  std::vector<std::pair<std::string, std::vector<const Statement*>>> out;
  for (const Stage& stage : m_.stages)
    for (const Statement& st : stage.statements) {
      auto it = lists_.find(&st);
      if (it == lists_.end()) continue;
      auto same = std::find_if(out.begin(), out.end(),
                               [&](const auto& entry) { return entry.first == it->second; });
      if (same == out.end())
        out.push_back({it->second, {&st}});
      else
        same->second.push_back(&st);
    }
  return out;
}

void ModelEmitter::plan_searches() {
  // Statements with lists of one set and one skin share them, built at the
  // largest of their radii (each sum keeps its own cutoff test) and holding
  // half lists, full lists or both as their statements take pairs: a step
  // builds them once, and no rebuild reorders the set under another
  // statement's lists (which would then rebuild too, every step, as two lists
  // at two radii did, and half and full lists of one set did).
  std::map<std::string, std::string> shared;  // that key -> the lists' member
  for (const Stage& stage : m_.stages)
    for (const Statement& st : stage.statements) {
      StatementUses uses;
      uses.visit(st.value);
      uses.visit(st.solve_operator);
      if (st.solve_operator)
        solve_results_[&st] = members_.fresh(
            (st.name.empty() ? m_.sets[st.set].vars[st.var].name : st.name) + "_solve_");
      const bool neighbours =
          std::any_of(uses.accumulations.begin(), uses.accumulations.end(), [&](const auto* acc) {
            return facts_.neighbourhoods.at(acc->id).kind == SearchFact::Kind::Neighbours;
          });
      if (!st.schedule.skin || !neighbours) continue;
      const std::string key =
          fmt::format("{} {}", st.set, source_text(st.schedule.skin->loc));
      auto [it, fresh] = shared.insert({key, ""});
      if (fresh)
        it->second = members_.fresh((st.name.empty() ? m_.sets[st.set].name : st.name) + "_lists_");
      lists_[&st] = it->second;
    }
  // The plan's searches: P_search_, or P_kd_tree_ when forced; a set's second
  // search of one structure P_search_2_ (sums apart from the first's).
  std::map<std::pair<int, SearchChoice>, int> seen;
  for (const PlannedSearch& search : facts_.searches.searches) {
    const std::string& set = m_.sets[search.set].name;
    const int n = ++seen[{search.set, search.structure}];
    searches_.push_back(members_.fresh((search.structure == SearchChoice::Auto
                                            ? set + "_search"
                                            : set + "_" + search_choice_name(search.structure)) +
                                       (n > 1 ? "_" + std::to_string(n) : "") + "_"));
  }
}

std::string ModelEmitter::lists_pairs(const std::string& lists) const {
  bool half = false, full = false;
  for (const auto& [member, statements] : lists_served())
    if (member == lists)
      for (const Statement* st : statements) (half_lists(*st) ? half : full) = true;
  return half && full ? "partc::VerletPairs::both"
         : half       ? "partc::VerletPairs::half"
                      : "partc::VerletPairs::full";
}

const std::string& ModelEmitter::search_for(int sum) const {
  const int group = facts_.searches.group_of.at(sum);
  if (auto chosen = walked_search_.find(group); chosen != walked_search_.end())
    return chosen->second;
  return searches_.at(facts_.searches.groups.at(group).search);
}

void ModelEmitter::header() {
  linef("// {}: generated by partc {} from {}.", cls_, PARTC_VERSION, options_.source_name);
  line("// Do not edit: change the .part file and run partc again.");
  // A guard, not #pragma once: the file is also compiled as a main file.
  const std::string guard = "PARTC_GENERATED_" + fmt::format("{}", codegen::upper_case(cls_));
  linef("#ifndef {0}\n#define {0}", guard);
  std::vector<std::string> extent;
  for (int k = 0; k < m_.dim; ++k)
    extent.push_back(fmt::format("[{}, {}]", emit_literal(Type::Real, m_.domain.lo[k]),
                                 emit_literal(Type::Real, m_.domain.hi[k])));
  std::vector<std::string> faces;
  static const char* axes[] = {"x", "y", "z", "w"};
  for (const auto& [kind, which] : {std::pair{"periodic", &m_.domain.periodic},
                                    std::pair{"reflecting", &m_.domain.reflect},
                                    std::pair{"open", &m_.domain.open}}) {
    std::vector<std::string> in;
    for (int k = 0; k < m_.dim; ++k)
      if ((*which)[k]) in.push_back(axes[k]);
    if (!in.empty()) faces.push_back(fmt::format("{} in {}", kind, fmt::join(in, ", ")));
  }
  linef("// Model {}: {} dimensions, domain {}, {}.", m_.name, m_.dim, fmt::join(extent, " x "),
        faces.empty() ? std::string("not periodic") : fmt::format("{}", fmt::join(faces, "; ")));
  std::vector<std::string> std_headers = {"algorithm", "cmath",  "cstdint", "limits",
                                          "map",       "string", "vector"};
  if (!lists_.empty()) std_headers.push_back("optional");
  if (!fast_sum_records_.empty()) std_headers.push_back("chrono");
  std::sort(std_headers.begin(), std_headers.end());
  for (const std::string& h : std_headers) linef("#include <{}>", h);
  line("");
  std::vector<std::string> headers = {
      "domain.hpp",   "errors.hpp",       "finite.hpp", "io/csv.hpp", "math.hpp",
      "model_support.hpp", "parallel.hpp", "particle_set.hpp", "rng.hpp", "vec.hpp"};
  if (!searches_.empty()) headers.push_back("search/neighbour_search.hpp");
  if (std::any_of(facts_.searches.groups.begin(), facts_.searches.groups.end(),
                  [](const SearchGroup& g) { return !g.chosen_at_run_time.empty(); }))
    headers.push_back("search/search_sharing.hpp");
  if (Domain::any(m_.domain.reflect) || Domain::any(m_.domain.open)) headers.push_back("faces.hpp");
  if (!lists_.empty()) headers.push_back("search/verlet_list.hpp");
  if (options_.driver_main) headers.push_back("driver.hpp");
  if (options_.profile) headers.push_back("profile.hpp");
  if (!m_.frames.empty()) headers.push_back("io/vtk.hpp");
  // Each solve's own solver (Eigen's dense LU, its sparse Krylov methods and
  // the matrix-free GMRES take seconds each to compile), and Matrix Market
  // output for --matrix-market.
  if (!solve_results_.empty()) headers.push_back("solve/matrix_market.hpp");
  for (const auto& solve : facts_.linear_operators) {
    switch (solve_kind(solve.first)) {
      case SolveKind::dense: headers.push_back("solve/dense_solve.hpp"); break;
      case SolveKind::sparse: headers.push_back("solve/sparse_solve.hpp"); break;
      case SolveKind::matrix_free:
        headers.push_back("solve/direct_residual.hpp");
        headers.push_back("solve/matrix_free_solve.hpp");
        break;
    }
  }
  if (!fast_sum_records_.empty())
    for (const char* h : {"fast_sum/contract.hpp", "fast_sum/fmm.hpp"}) headers.push_back(h);
  std::sort(headers.begin(), headers.end());
  headers.erase(std::unique(headers.begin(), headers.end()), headers.end());
  for (const std::string& h : headers) linef("#include <partc/{}>", h);
  line("");
}

std::string ModelEmitter::tag(int set, int var) const {
  return cpp_name(m_.sets[set].name + "_" + m_.sets[set].vars[var].name);
}

void ModelEmitter::public_types() {
  linef("static constexpr const char* model_name = \"{}\";", m_.name);
  linef("static constexpr int dim = {};", m_.dim);
  linef("using Vec = partc::Vec<{}>;", m_.dim);
  line("");
  line("// Parameters: set them before init(), or with --set NAME=VALUE.");
  line("struct Params {");
  for (const Param& p : m_.params)
    linef("{} {} = {};  // {}", cpp_type(p.type), cpp_name(p.name),
          emit_literal(p.type, *as<Literal>(p.default_value)), source_line(p.loc));
  line("};");
  if (has_user_observables()) {
    line("");
    line("// Observables: model-level values that statements assign, read with observables().");
    linef("struct {} {{", observables_type_);
    for (std::size_t o = kFirstUserObservable; o < m_.observables.size(); ++o)
      linef("{} {}{{}};  // {}", cpp_type(m_.observables[o].type), cpp_name(m_.observables[o].name),
            source_line(m_.observables[o].loc));
    line("};");
  }
  for (std::size_t s = 0; s < m_.sets.size(); ++s) {
    const ParticleSet& set = m_.sets[s];
    line("");
    linef("// Particle set {} ({}): p, id, alive and its variables.", set.name,
          source_line(set.loc));
    // A variable stored as float says so here, once; kernels widen its loads.
    const auto stored_as = [&](const Variable& var) -> std::string {
      if (var.storage == Precision::Float)
        return var.type == Type::Vec ? fmt::format("partc::Vec<{}, float>", m_.dim) : "float";
      return var.type == Type::Vec ? "Vec" : cpp_type(var.type);
    };
    std::vector<std::string> tags;
    for (std::size_t v = kFirstUserVar; v < set.vars.size(); ++v) {
      const Variable& var = set.vars[v];
      tags.push_back(tag(s, v));
      if (var.storage == Precision::Float) linef("// {}: stored as float (schedule)", var.name);
      linef("struct {} {{ using type = {}; static constexpr const char* name = \"{}\"; }};",
            tags.back(), stored_as(var), var.name);
    }
    const Variable& p = set.vars[kPosition];
    const std::string listed = tags.empty() ? "" : fmt::format(", {}", fmt::join(tags, ", "));
    if (p.storage == Precision::Float) {
      line("// p: stored as float (schedule)");
      linef("using {} = partc::BasicParticleSet<{}{}>;", set_type_[s], stored_as(p), listed);
    } else {
      linef("using {} = partc::ParticleSet<{}{}>;", set_type_[s], m_.dim, listed);
    }
  }
  line("");
}

void ModelEmitter::public_api() {
  line("Params& params() { return params_; }");
  line("const Params& params() const { return params_; }");
  line("void set_seed(std::uint64_t seed) { rng_ = partc::CounterRng(seed); }");
  line("std::int64_t step_count() const { return step_; }");
  if (m_.timestep) line("double time() const { return t_; }");
  if (has_user_observables())
    linef("const {0}& observables() const {{ return observables_; }}", observables_type_);
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
  named_stages();
  for_each_set();
  search_report();
  if (options_.profile) profile_api();
  boundary_report();
  solve_report();
  fast_sum_report();
  log();
  frames();
  line("");
  line("// Throws partc::NumericalError naming the first NaN or Inf found.");
  line("void check_finite() const {");
  for (std::size_t s = 0; s < m_.sets.size(); ++s)
    linef("partc::check_finite({}, \"{}\", step_);", set_member_[s], m_.sets[s].name);
  if (m_.timestep) line("partc::check_finite_observable(t_, \"t\", step_);");
  // Then those the last step computed only if observed: a value it did not
  // compute was checked when it was.
  for (bool observed_only : {false, true}) {
    if (observed_only && !observed_only_.empty()) line("if (observed_) {");
    for (std::size_t o = kFirstUserObservable; o < m_.observables.size(); ++o)
      if ((m_.observables[o].type == Type::Real || m_.observables[o].type == Type::Vec) &&
          (observed_only_.count(static_cast<int>(o)) > 0) == observed_only)
        linef("partc::check_finite_observable(observables_.{}, \"{}\", step_);",
              cpp_name(m_.observables[o].name), m_.observables[o].name);
    if (observed_only && !observed_only_.empty()) line("}");
  }
  line("}");
  line("");
}

void ModelEmitter::param_info() {
  line("static std::vector<partc::ParamInfo> param_info() {");
  line("return {");
  for (const Param& p : m_.params)
    linef("{{\"{}\", \"{}\", \"{}\"}},", p.name, type_name(p.type),
          emit_literal(p.type, *as<Literal>(p.default_value)));
  line("};");
  line("}");
  line("");
}

void ModelEmitter::set_param() {
  line("// Sets a parameter from text, as the driver's --set does.");
  linef("void set_param(const std::string& name, const std::string&{}) {{",
        m_.params.empty() ? "" : " value");
  std::vector<std::string> names;
  for (const Param& p : m_.params) {
    names.push_back(p.name);
    linef(
        "if (name == \"{0}\") {{ params_.{1} = partc::parse_param<{2}>(\"{0}\", value); return; }}",
        p.name, cpp_name(p.name), cpp_type(p.type));
  }
  const std::string listed =
      names.empty() ? "this model has none" : fmt::format("parameters: {}", fmt::join(names, ", "));
  linef("throw partc::UsageError(\"unknown parameter '\" + name + \"' ({})\");", listed);
  line("}");
  line("");
}

void ModelEmitter::init() {
  line("// Computes the constants, creates every set's particles with their");
  line("// declared initial values, then runs the init blocks.");
  line("void init() {");
  line("compute_constants();");
  start_clock();
  for (std::size_t s = 0; s < m_.sets.size(); ++s) linef("create_{}();", m_.sets[s].name);
  stage_calls(StageKind::Init);
  line("}");
  line("");
}

void ModelEmitter::load() {
  line("// Instead of init(): particles come from tables (CSV files), one per");
  line("// named set; sets not named start empty. Variables a table lacks take");
  line("// their declared initial values.");
  line("void load(const std::map<std::string, partc::CsvTable>& tables) {");
  line("compute_constants();");
  start_clock();
  std::vector<std::string> names;
  for (std::size_t s = 0; s < m_.sets.size(); ++s) {
    const std::string& name = m_.sets[s].name;
    names.push_back(name);
    linef("{}.clear();", set_member_[s]);
    linef("if (auto t = tables.find(\"{}\"); t != tables.end())", name);
    const bool faces = Domain::any(m_.domain.reflect) || Domain::any(m_.domain.open);
    linef(
        "partc::load_set({0}, t->second, domain_, {2}[this](std::size_t i) {{ initialise_{1}(i); "
        "}});",
        set_member_[s], name, faces ? "faces_, " : "");
    linef("++{};", epoch_[s]);
  }
  line("for (const auto& [name, table] : tables)");
  linef(
      "if ({}) throw partc::UsageError(\"no particle set '\" + name + \"' in model {} (sets: "
      "{})\");",
      fmt::join(set_comparisons(names), " && "), m_.name, fmt::join(names, ", "));
  // An integrator's primed slots (the forces of the state loaded) end load as they end init.
  stage_calls(StageKind::Init, "", true);
  line("}");
  line("");
}

std::vector<std::string> ModelEmitter::set_comparisons(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const std::string& n : names) out.push_back("name != \"" + n + "\"");
  return out;
}

// Step 0, time 0 and each observable's initial value, as init and load begin.
void ModelEmitter::start_clock() {
  line("step_ = 0;");
  if (m_.timestep) line("t_ = 0;");
  if (!observed_only_targets_.empty()) line("observed_ = true;");
  for (std::size_t o = kFirstUserObservable; o < m_.observables.size(); ++o) {
    const Observable& obs = m_.observables[o];
    const Literal* literal = as<Literal>(obs.initial);
    linef("observables_.{} = {};", cpp_name(obs.name),
          literal ? emit_literal(obs.type, *literal)
                  : expression(obs.initial, initialiser_names(0)));
  }
}

void ModelEmitter::step() {
  line(m_.timestep ? "// One time step: every step block, in order; then t advances."
                   : "// One time step: every step block, in order.");
  if (observed_only_targets_.empty()) {
    line("void step() {");
  } else {
    comment(fmt::format(
        "observed = false: the state after this step will not be read, so what only it needs "
        "is not computed: {} keep{} the value{} of the last observed step. The driver observes "
        "the steps it logs or writes and the last one.",
        fmt::join(observed_only_targets_, ", "), observed_only_targets_.size() == 1 ? "s" : "",
        observed_only_targets_.size() == 1 ? "" : "s"));
    line("void step(bool observed = true) {");
    line("observed_ = observed;");
  }
  if (options_.profile) line("const partc::ProfileTimer step_timer(profile_, profile_.step_slot());");
  stage_calls(StageKind::Step);
  if (m_.timestep)
    linef("t_ += {};  // {}", expression(m_.timestep, initialiser_names(0)),
          source_line(m_.timestep->loc));
  line("++step_;");
  line("}");
  line("");
}

void ModelEmitter::for_each_set() {
  line("// f(name, set) for every particle set, in declaration order.");
  line("template <class F> void for_each_set(F&& f) const {");
  for (std::size_t s = 0; s < m_.sets.size(); ++s)
    linef("f(\"{}\", {});", m_.sets[s].name, set_member_[s]);
  line("}");
}

void ModelEmitter::search_report() {
  line("// Each neighbour search: what it serves, its structure, its builds so far.");
  line("std::vector<partc::SearchReport> search_report() const {");
  line("std::vector<partc::SearchReport> report;");
  // A set's searches of one structure are told apart by the lines they serve.
  std::map<std::pair<int, SearchChoice>, int> alike;
  for (const PlannedSearch& search : facts_.searches.searches)
    ++alike[{search.set, search.structure}];
  for (std::size_t k = 0; k < searches_.size(); ++k) {
    const PlannedSearch& search = facts_.searches.searches[k];
    std::set<int> lines;
    for (const SearchGroup& group : facts_.searches.groups)
      if (group.search == static_cast<int>(k))
        for (const auto& [g, s] : group.statements) lines.insert(m_.stages[g].statements[s].line);
    const std::string at =
        alike[{search.set, search.structure}] == 1
            ? ""
            : fmt::format(" at line{} {}", lines.size() > 1 ? "s" : "", fmt::join(lines, ", "));
    linef(
        "report.push_back({{\"sums over {}{}{}\", {}.describe(), {}.build_count(), "
        "{}.walk_count()}});",
        m_.sets[search.set].name, at,
        search.structure == SearchChoice::Auto
            ? ""
            : std::string(" (schedule: ") + search_choice_name(search.structure) + ")",
        searches_[k], searches_[k], searches_[k]);
  }
  for (const auto& [lists, statements] : lists_served()) {
    std::vector<std::string> served;
    for (const Statement* st : statements)
      served.push_back((st->name.empty() ? "" : st->name + " at ") + source_line(st->loc));
    linef(
        "if ({0}) report.push_back({{\"{1}\", {0}->describe(), {0}->rebuild_count(), "
        "{0}->walk_count()}});",
        lists, fmt::format("{}", fmt::join(served, ", ")));
  }
  line("return report;");
  line("}");
}

// --profile: the profile, and the calibration the driver runs after the run.
void ModelEmitter::profile_api() {
  line("const partc::Profile& profile() const { return profile_; }");
  line("// Times each kernel of several effects whole and without each effect's term, into");
  line("// buffers nobody reads: the model's state stays as it is.");
  line("void calibrate_profile([[maybe_unused]] int rounds) {");
  for (const Calibration& c : calibrations_) {
    build_calibration_searches(c);
    std::vector<std::string> calls;
    for (const std::string& v : c.variants) calls.push_back(fmt::format("[this] {{ {}(); }}", v));
    linef("profile_.calibrate({}, rounds, {{{}}});", c.profiled, fmt::join(calls, ", "));
  }
  line("}");
}

// --profile: what each slot of the profile times, in the order of the slots.
void ModelEmitter::profile_state() {
  auto quoted = [](const std::vector<std::string>& names) {
    std::vector<std::string> out;
    for (const std::string& n : names) out.push_back("\"" + n + "\"");
    return fmt::format("{{{}}}", fmt::join(out, ", "));
  };
  auto effects_of = [](const std::vector<const Statement*>& statements) {
    std::vector<std::string> effects;
    for (const Statement* st : statements) {
      if (st->origins.empty()) effects.push_back("");
      for (const Origin& o : st->origins)
        if (std::find(effects.begin(), effects.end(), o.effect) == effects.end())
          effects.push_back(o.effect);
    }
    return effects;
  };
  std::vector<std::string> kernels, searches;
  for (const Kernel* k : profiled_) {
    std::vector<std::string> effects, leaves_out;
    for (const Origin& o : k->st->origins) effects.push_back(o.effect);
    for (const auto& [member, alias] : k->fused)
      for (const Origin& o : member->origins) effects.push_back(o.effect);
    for (const Calibration& c : calibrations_)
      if (c.profiled == k->profiled)
        for (const std::vector<std::size_t>& origins : c.leaves_out)
          leaves_out.push_back(fmt::format("{{{}}}", fmt::join(origins, ", ")));
    kernels.push_back(fmt::format("{{\"{}\", {}, \"line {}\", {{{}}}}}", k->name, quoted(effects),
                                  file_.output_line(k->st->loc.begin),
                                  fmt::join(leaves_out, ", ")));
  }
  // A search serves the effects whose terms hold its sums, not every effect
  // merged into their statement: a search of one effect's sums alone is
  // that effect's (--drop removes it).
  for (std::size_t k = 0; k < searches_.size(); ++k) {
    std::vector<std::string> effects;
    auto serves = [&](const std::string& effect) {
      if (std::find(effects.begin(), effects.end(), effect) == effects.end())
        effects.push_back(effect);
    };
    for (const SearchGroup& group : facts_.searches.groups) {
      if (group.search != static_cast<int>(k)) continue;
      for (std::size_t n = 0; n < group.sums.size(); ++n) {
        const Statement& owner =
            m_.stages[group.statements[n].first].statements[group.statements[n].second];
        if (owner.origins.empty()) serves("");
        for (std::size_t o : origins_of_sum(owner, group.sums[n])) serves(owner.origins[o].effect);
      }
    }
    searches.push_back(fmt::format("{{\"{} of {}\", {}}}", searches_[k],
                                   m_.sets[facts_.searches.searches[k].set].name, quoted(effects)));
  }
  for (const auto& [lists, statements] : lists_served())
    searches.push_back(fmt::format("{{\"{}\", {}}}", lists, quoted(effects_of(statements))));
  linef("partc::Profile profile_{{{{{}}}, {{{}}}}};  // --profile: step kernels, then searches",
        fmt::join(kernels, ", "), fmt::join(searches, ", "));
  calibration_search_members();
}

// How many particles of each set left through open faces (the driver's summary).
void ModelEmitter::boundary_report() {
  if (left_.empty()) return;
  line("std::vector<std::string> boundary_report() const {");
  line("std::vector<std::string> report;");
  for (std::size_t s = 0; s < m_.sets.size(); ++s)
    linef("report.push_back(\"{}: \" + std::to_string({}) + \" particles left through open faces\");",
          m_.sets[s].name, left_[s]);
  line("return report;");
  line("}");
}

// A method per named stage, and the stages by name (for the driver's --stage).
void ModelEmitter::named_stages() {
  if (stage_methods_.empty()) return;
  for (const Stage& stage : m_.stages) {
    if (stage.kind != StageKind::Named) continue;
    linef("// Stage {} ({}): its statements, in order.", stage.name, source_line(stage.loc));
    linef("void {}() {{", stage_methods_.at(stage.name));
    stage_calls(StageKind::Named, stage.name);
    line("}");
  }
  std::vector<std::string> quoted, names;
  for (const auto& [name, method] : stage_methods_) {
    quoted.push_back("\"" + name + "\"");
    names.push_back(name);
  }
  linef("static std::vector<std::string> stage_names() {{ return {{{}}}; }}",
        fmt::join(quoted, ", "));
  line("// Runs a named stage, as the driver's --stage does.");
  line("void run_stage(const std::string& name) {");
  for (const auto& [name, method] : stage_methods_)
    linef("if (name == \"{}\") return {}();", name, method);
  linef("throw partc::UsageError(\"no stage '\" + name + \"' in model {} (stages: {})\");", m_.name,
        fmt::join(names, ", "));
  line("}");
  line("");
}

// Each solve's last result, for the driver's summary; where to write the
// assembled systems (Matrix Market), for users who solve them elsewhere.
void ModelEmitter::solve_report() {
  if (solve_results_.empty()) return;
  line("// Each solve's last result: method, size, condition or iterations, residual, time.");
  line("std::vector<std::string> solve_report() const {");
  line("std::vector<std::string> report;");
  for (const auto& [st, result] : solve_results_) {
    linef("if ({0}.n > 0) report.push_back({0}.summary());", result);
    linef("if (!{0}.warning.empty()) report.push_back(\"warning: \" + {0}.warning);", result);
  }
  line("return report;");
  line("}");
  line("// Solves from now on also write their matrix and right side to PREFIX_w.mtx and");
  line("// PREFIX_w_rhs.mtx (Matrix Market); \"\" stops it.");
  line("void set_matrix_market(std::string prefix) { matrix_market_ = std::move(prefix); }");
}

bool ModelEmitter::has_user_observables() const {
  return m_.observables.size() > static_cast<std::size_t>(kFirstUserObservable);
}

// What the driver logs (`output ...`): columns, interval and one row; step
// first, t next when the model has a timestep. Vecs take one column each
// component, named as CSV files name them (p_tot_0, p_tot_1).
// What VTK frames hold (`output SET: ...`), for the driver.
void ModelEmitter::frames() {
  if (m_.frames.empty()) return;
  const ExpressionNames names = base_names();
  line("// The VTK frames the model asks for: each set's variables and interval.");
  line("std::vector<partc::FrameSpec> frames() const {");
  line("return {");
  for (const Frames& f : m_.frames) {
    std::vector<std::string> vars;
    for (int v : f.vars) vars.push_back("\"" + m_.sets[f.set].vars[v].name + "\"");
    linef("{{\"{}\", {{{}}}, {}}},  // {}", m_.sets[f.set].name, fmt::join(vars, ", "),
          f.every ? expression(f.every, names) : "1", source_line(f.loc));
  }
  line("};");
  line("}");
}

void ModelEmitter::log() {
  if (m_.log.observables.empty()) return;
  std::vector<int> logged = {kStep};
  if (m_.timestep) logged.push_back(kTime);
  for (int o : m_.log.observables)
    if (std::find(logged.begin(), logged.end(), o) == logged.end()) logged.push_back(o);
  std::vector<std::string> columns, values;
  const ExpressionNames names = base_names();
  for (int o : logged) {
    const Observable& obs = m_.observables[o];
    const std::string value = names.observables[o];
    if (obs.type == Type::Vec) {
      for (int k = 0; k < m_.dim; ++k) {
        columns.push_back(fmt::format("\"{}_{}\"", obs.name, k));
        values.push_back(fmt::format("{}[{}]", value, k));
      }
    } else {
      columns.push_back("\"" + obs.name + "\"");
      values.push_back(obs.type == Type::Real ? value : "static_cast<double>(" + value + ")");
    }
  }
  line("");
  linef("// The observables the run logs ({}), and how often.", source_line(m_.log.loc));
  linef("static std::vector<std::string> log_columns() {{ return {{{}}}; }}",
        fmt::join(columns, ", "));
  linef("std::int64_t log_every() const {{ return {}; }}",
        m_.log.every ? expression(m_.log.every, names) : "1");
  linef("std::vector<double> log_row() const {{ return {{{}}}; }}", fmt::join(values, ", "));
}

void ModelEmitter::helpers() {
  for (std::size_t f = 0; f < m_.functions.size(); ++f) user_function(static_cast<int>(f));
  line("// Constants that depend on parameters, computed once they are known.");
  line("void compute_constants() {");
  for (std::size_t c = 0; c < m_.consts.size(); ++c)
    if (!evaluate_constant(m_.consts[c].value, m_))
      linef("{} = {};  // {}", const_member_[c],
            expression(m_.consts[c].value, initialiser_names(0)), source_line(m_.consts[c].loc));
  line("}");
  line("");
  for (std::size_t s = 0; s < m_.sets.size(); ++s) {
    create_set(static_cast<int>(s));
    initialise_particle(static_cast<int>(s));
  }
}

void ModelEmitter::user_function(int f) {
  const UserFn& fn = m_.functions[f];
  std::vector<std::string> args;
  for (std::size_t k = 0; k < fn.arg_names.size(); ++k)
    args.push_back(
        (fn.arg_types[k] == Type::Vec ? "const Vec& " : cpp_type(fn.arg_types[k]) + " ") +
        cpp_name(fn.arg_names[k]));
  linef("// {}", source_line(fn.loc));
  linef("//   {}", source_text(fn.loc));
  linef("{} {}({}) const {{ return {}; }}", cpp_type(fn.body->type), function_member_[f],
        fmt::join(args, ", "), expression(fn.body, base_names()));
  line("");
}

// Names every expression may use: consts and functions.
ExpressionNames ModelEmitter::base_names() const {
  ExpressionNames names;
  for (const Param& param : m_.params) names.params.push_back("params_." + cpp_name(param.name));
  names.consts = const_member_;
  for (const Observable& o : m_.observables)
    names.observables.push_back(&o == &m_.observables[kStep] ? "step_"
                                : &o == &m_.observables[kTime]
                                    ? "t_"
                                    : "observables_." + cpp_name(o.name));
  names.functions = function_member_;
  return names;
}

void ModelEmitter::create_set(int s) {
  const ParticleSet& set = m_.sets[s];
  linef("// Creates the {} particles of {} ({}).", source_text(set.initial_count->loc), set.name,
        source_line(set.loc));
  linef("void create_{}() {{", set.name);
  linef("const std::int64_t count = {};", expression(set.initial_count, initialiser_names(s)));
  // A constant count is checked by partc; one from params only now.
  if (!evaluate_constant(set.initial_count, m_))
    linef(
        "if (count < 0) throw partc::UsageError(\"{}: particle set {} would have \" + "
        "std::to_string(count) + \" particles ({})\");",
        source_line(set.loc), set.name, source_text(set.initial_count->loc));
  linef("{}.clear();", set_member_[s]);
  linef("{}.reserve(static_cast<std::size_t>(count));", set_member_[s]);
  line("for (std::int64_t k = 0; k < count; ++k)");
  linef("initialise_{}({}.push_back(Vec::zero()));", set.name, set_member_[s]);
  linef("++{};", epoch_[s]);
  line("}");
  line("");
}

void ModelEmitter::initialise_particle(int s) {
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
std::string ModelEmitter::array_access(int s, int var) const {
  switch (var) {
    case kPosition: return set_member_[s] + ".positions()";
    case kId: return set_member_[s] + ".ids()";
    case kAlive: return set_member_[s] + ".alive()";
    default: return set_member_[s] + ".get<" + tag(s, var) + ">()";
  }
}

ExpressionNames ModelEmitter::initialiser_names(int s) const {
  ExpressionNames names = base_names();
  names.home_set = s;
  names.labels = {"i"};
  names.array = [](int, int var) { return var == kId ? std::string("id") : std::string("?"); };
  return names;
}

std::string ModelEmitter::expression(const Expr& e, const ExpressionNames& names) const {
  return emit_expression(e, m_, names);
}

void ModelEmitter::state() {
  line("Params params_;");
  for (std::size_t c = 0; c < m_.consts.size(); ++c) {
    const Const& k = m_.consts[c];
    if (auto value = evaluate_constant(k.value, m_))
      linef("static constexpr {} {} = {};  // {}", cpp_type(k.type), const_member_[c],
            as<Literal>(k.value) ? emit_literal(k.type, *as<Literal>(k.value))
                                 : emit_literal(k.type, *value),
            source_text(k.loc));
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
  if (Domain::any(m_.domain.reflect) || Domain::any(m_.domain.open)) {
    std::vector<std::string> reflect, open;
    for (int k = 0; k < m_.dim; ++k) {
      reflect.push_back(m_.domain.reflect[k] ? "true" : "false");
      open.push_back(m_.domain.open[k] ? "true" : "false");
    }
    linef("partc::Faces<{}> faces_{{domain_.lo, domain_.hi, {{{{{}}}}}, {{{{{}}}}}}};", m_.dim,
          fmt::join(reflect, ", "), fmt::join(open, ", "));
  }
  line("partc::CounterRng rng_;");
  line("std::int64_t step_ = 0;");
  if (m_.timestep) line("double t_ = 0;  // advanced by the timestep");
  if (has_user_observables()) linef("{} observables_;", observables_type_);
  if (!observed_only_targets_.empty())
    line("bool observed_ = true;  // whether the last step computed everything (step(observed))");
  for (std::size_t s = 0; s < m_.sets.size(); ++s) {
    linef("{} {};", set_type_[s], set_member_[s]);
    linef("std::uint64_t {} = 0;  // bumped whenever {}'s positions or order change", epoch_[s],
          m_.sets[s].name);
    if (!left_.empty())
      linef("std::int64_t {} = 0;  // particles of {} that left through an open face", left_[s],
            m_.sets[s].name);
  }
  for (std::size_t k = 0; k < searches_.size(); ++k) {
    const PlannedSearch& search = facts_.searches.searches[k];
    const std::string type = fmt::format("partc::NeighbourSearch<{}>", m_.dim);
    std::vector<std::string> arguments;
    if (search.structure != SearchChoice::Auto)
      arguments.push_back(type + "::Kind::" + search_choice_name(search.structure));
    else if (!search.reorders)
      arguments.push_back(type + "::default_margin");
    if (!search.reorders) arguments.push_back(type + "::Order::keep");
    linef("{} {}{};  // over {}{}", type, searches_[k],
          arguments.empty() ? "" : fmt::format("{{{}}}", fmt::join(arguments, ", ")),
          m_.sets[search.set].name, search.structure == SearchChoice::Auto ? "" : ", schedule");
    linef("std::uint64_t {}epoch_ = std::numeric_limits<std::uint64_t>::max();", searches_[k]);
    linef("double {}radius_ = 0;", searches_[k]);
  }
  for (const auto& [lists, statements] : lists_served())
    linef("std::optional<partc::VerletList<{}>> {};  // schedule: skin {}", m_.dim, lists,
          source_text(statements.front()->schedule.skin->loc));
  for (const auto& [st, result] : solve_results_)
    linef("partc::SolveResult {};  // the last solve of {}", result, source_line(st->loc));
  if (!solve_results_.empty()) line("std::string matrix_market_;  // \"\": no Matrix Market files");
  if (!fast_sum_records_.empty()) {
    std::vector<std::string> records(fast_sum_records_.size());
    for (const auto& [id, index] : fast_sum_records_) {
      const FastSumFact& fact = facts_.fast_sums.at(id);
      // FastSumRecord(where, role = sum, float_inputs = ""): what differs from the defaults.
      std::vector<std::string> args{fmt::format("\"sum at {}:{}\"", options_.source_name, fact.line)};
      if (fact.in_solve || !fact.float_inputs.empty())
        args.push_back(std::string("partc::fast_sum::FastSumRecord::Role::") +
                       (fact.in_solve ? "solve_products" : "sum"));
      if (!fact.float_inputs.empty()) args.push_back("\"" + fact.float_inputs + "\"");
      records[index] = fmt::format("partc::fast_sum::FastSumRecord{{{}}}", fmt::join(args, ", "));
    }
    linef("std::vector<partc::fast_sum::FastSumRecord> fast_sums_{{{}}};", fmt::join(records, ", "));
    line("bool check_accuracy_ = false;  // --check-accuracy");
  }
  for (const auto& [id, sums] : pair_sums_)
    linef("std::vector<{}> {};  // per particle, a sum its walk fills", sums.second,
          sums.first);
  for (const auto& [key, buffer] : buffers_)
    linef("std::vector<{}> {};  // new values of {}, {}", buffer.second, buffer.first,
          m_.sets[std::get<0>(key)].vars[std::get<1>(key)].name,
          std::get<2>(key) ? "for --profile's calibration (nobody reads them)"
                           : "for buffered updates");
  if (options_.profile) profile_state();
}

}  // namespace codegen

std::string generate_cpp(const ir::Model& model, const ModelFacts& facts, const SourceFile& file,
                         const CodegenOptions& options) {
  return codegen::ModelEmitter(model, facts, file, options).run();
}

}  // namespace partc

// ModelEmitter, which writes the C++ class of a model: the class around the
// kernels in codegen/model.cpp, the kernels (one per statement) in
// codegen/kernel.cpp. Also the IR visitors both use. Internal to codegen/.
#pragma once

#include <fmt/format.h>

#include <deque>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "codegen/codegen.hpp"
#include "codegen/expression.hpp"
#include "codegen/names.hpp"
#include "ir/visitor.hpp"

namespace partc::codegen {

using namespace ir;

// What one statement's kernel touches.
class StatementUses : public Visitor {
 public:
  std::set<std::pair<int, int>> arrays;  // (set, var) read
  std::vector<int> labels;               // through these labels, in order of reading
  std::vector<const Accumulate*> accumulations;
  std::set<int> params, consts, observables;
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
  void visit(const ObservableRef& n) override { observables.insert(n.observable); }
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
    if (is_norm_of_dx(n)) norm = true;
    Visitor::visit(n);
  }
};

// The text on one line: each run of whitespace becomes one space.
std::string one_line(std::string_view text);

class ModelEmitter {
 public:
  ModelEmitter(const Model& model, const ModelFacts& facts, const SourceFile& file,
               const CodegenOptions& options);
  std::string run();

 private:
  // ---- output -----------------------------------------------------------

  void comment(const std::string& text);
  void line(const std::string& text);
  template <class... Args>
  void linef(fmt::format_string<Args...> f, Args&&... args) {
    line(fmt::format(f, std::forward<Args>(args)...));
  }

  std::string source_line(Location loc) const;
  std::string source_text(Location loc) const { return one_line(file_.slice(loc)); }

  // ---- searches: as the search plan says (analysis/search_plan.cpp) -----

  void plan_searches();
  // The search an Accumulate id's sum walks: a member, or in a kernel the local
  // that names the one chosen at run time.
  const std::string& search_for(int sum) const;

  // ---- header -----------------------------------------------------------

  void header();

  // ---- public types -----------------------------------------------------

  std::string tag(int set, int var) const;
  void public_types();

  // ---- public API -------------------------------------------------------

  void public_api();
  void param_info();
  void set_param();
  void init();
  void load();
  static std::vector<std::string> set_comparisons(const std::vector<std::string>& names);
  void step();
  void for_each_set();
  void search_report();
  void boundary_report();
  void frames();
  void solve_report();
  void start_clock();
  bool has_user_observables() const;
  void log();

  // ---- private helpers --------------------------------------------------

  void helpers();
  void user_function(int f);
  ExpressionNames base_names() const;
  void create_set(int s);
  void initialise_particle(int s);
  std::string array_access(int s, int var) const;
  ExpressionNames initialiser_names(int s) const;
  std::string expression(const Expr& e, const ExpressionNames& names) const;

  // ---- kernels ----------------------------------------------------------

  struct Kernel {
    Kernel(std::string n, const Statement* s, const AliasFact* a, std::pair<int, int> p,
           std::string into = "")
        : name(std::move(n)), st(s), alias(a), position(p), sink(std::move(into)) {}
    std::string name;
    const Statement* st;
    const AliasFact* alias;
    std::pair<int, int> position;  // (stage, statement)
    // --profile: a calibration variant, which writes this member instead of
    // its target and leaves the model's state as it was.
    std::string sink;
    int profiled = -1;  // --profile: a step kernel's index in partc::Profile
    // --profile, a variant: search group -> the calibration search it walks
    // instead of the group's, when calibrate_profile built one.
    std::map<int, std::string> calibration_searches;
    // A fused pass (facts_.fusion): its later members, relabelled to name
    // their sums with st's labels (st then a copy with all of them), each
    // with its aliasing; the pass's index.
    std::vector<std::pair<const Statement*, const AliasFact*>> fused;
    int pass = -1;
    // A pass of members that run every step and members that run only on
    // observed steps: 1, its kernel then (all of them); 0, on the others.
    int observed = -1;
    // st and the fused members, each with its aliasing: what the kernel computes.
    std::vector<std::pair<const Statement*, const AliasFact*>> members() const {
      std::vector<std::pair<const Statement*, const AliasFact*>> all{{st, alias}};
      all.insert(all.end(), fused.begin(), fused.end());
      return all;
    }
  };
  Kernel pass_kernel(const std::vector<std::pair<int, int>>& positions,
                     const std::string& stage_name, int pass);
  std::string target(const Statement& st) const;
  bool observed_only(std::pair<int, int> position) const;
  // --profile: a kernel of several effects' terms, and its variants: whole,
  // then without some of its origins each (Profile::calibrate).
  // A variant whose sums reach less far than its statement's walks a search
  // of its own (codegen/calibration_search.cpp).
  struct CalibrationSearch {
    std::string member;  // std::optional<NeighbourSearch>: built when radius < whole
    int group;           // the search group whose walk it stands in for
    std::size_t part;           // the variant's index in Calibration::leaves_out
    std::string variant;        // the variant's kernel, for people
    std::string radius, whole;  // the variant's largest radius and the group's
  };
  struct Calibration {
    int profiled;
    std::vector<std::string> variants;
    std::vector<std::vector<std::size_t>> leaves_out;  // per variant after the whole
    std::vector<CalibrationSearch> searches;
  };
  void plan_calibration(const Kernel k);  // a copy: kernels_ grows
  void plan_calibration_searches(Kernel& variant, const Statement& whole,
                                 const std::vector<std::size_t>& leaves_out,
                                 Calibration& calibration);
  void build_calibration_searches(const Calibration& calibration);
  void calibration_search_members();
  std::string group_radius(const SearchGroup& group, const std::vector<std::size_t>& sums) const;
  void profile_api();
  void profile_state();
  void plan_kernels();
  // after_load: only the init stages that also end load().
  void stage_calls(StageKind kind, const std::string& name = "", bool after_load = false);
  void named_stages();
  void kernels();
  void kernel(const Kernel& k);
  void kernel_comment(const Kernel& k, const StatementUses& uses);
  void kernel_constants(const Statement& st, StatementUses uses, ExpressionNames& names,
                        NameTable& locals);
  std::string buffer_member(int s, int var, bool sink = false);
  void refresh_search(int group, const Statement& st, const ExpressionNames& names,
                      NameTable& locals, bool walked = true);
  void choose_search(int group, const Statement& st, const ExpressionNames& names,
                     NameTable& locals, bool walked);
  std::string group_radius(const SearchGroup& group, const Statement& st,
                           const ExpressionNames& names) const;
  void build_if_stale(int search, const std::string& radius, const std::string& chosen);
  std::string radius_expression(const SearchFact& fact, const Statement& st,
                                const ExpressionNames& names) const;

  // Newton's third law: a statement whose every neighbour sum gives j the term
  // i gets, or its negative (analysis/symmetry.cpp), can take each pair once:
  // from half lists with Verlet lists (half_lists), else from the search's pair
  // walk when NeighbourSearch::pairs_once says it pays (else per-particle queries).
  bool half_lists(const Statement& st) const { return st.schedule.skin && newton_pairs(st); }
  bool newton_pairs(const Statement& st) const;
  bool walks_pairs(const Statement& st) const;
  void refresh_lists(const Statement& st, const std::string& local, const ExpressionNames& names);
  ExpressionNames names_outside(const Statement& owner) const;

  // Accumulations of one statement over the same set, found the same way
  // (the same search, or the same dense loop), share one pass: SPH's
  // density and its normalisation cost one neighbour walk, not two.
  struct Loop {
    int set;
    SearchFact::Kind kind;
    bool once;  // the same for every i (uniform_sums.cpp): run before the particle loop
    int search;  // Neighbours: SearchPlan::searches index; sums apart are not fused
    std::string searched;  // Neighbours without a skin: the search it walks, named by kernel()
    std::vector<const Accumulate*> members;
  };
  std::vector<Loop> fuse_loops(const std::vector<const Accumulate*>& accumulations,
                               const Statement& st) const;
  std::string identity(const Accumulate& acc) const;
  std::string update(const Accumulate& acc, const ExpressionNames& names, bool compensated) const;
  bool always_true(const Accumulate& acc) const;
  std::string accumulator_type(const Accumulate& acc) const;
  void loop(const Loop& l, const Statement& st, const ExpressionNames& names,
            const std::string& pairs_once = "");
  void pair_pass(const Loop& l, const ExpressionNames& names, const std::string& count,
                 NameTable& locals, const std::string& walk, const std::string& kernel);
  std::string pair_sums_member(const Accumulate& acc, const std::string& kernel);
  // codegen/pair_batch_pass.cpp: the sums of a loop whose every sum has a
  // vector form (vector_terms), on vectors of pairs: a lambda, named by the
  // return value, for the walks that will call it (each pair once, packed
  // queries, or either, chosen at run time), which fill the loop's members
  // (pair_sums_); whether those walks must give i's pair with itself.
  bool vector_terms(const Loop& l) const;
  enum class BatchWalks { pairs, pairs_or_queries, queries };
  std::string batch_kernel(const Loop& l, const ExpressionNames& names, const std::string& count,
                           NameTable& locals, const std::string& kernel, BatchWalks walks);
  bool batch_self_pair(const Loop& l) const;
  // Whether every sum of the loop can take packed per-particle queries
  // (VectorTermFact::packed_queries).
  bool packed_queries(const Loop& l) const;
  void assignment(const Statement& st, const ExpressionNames& names, const std::string& buffer);
  // codegen/fast_sum.cpp: a dense sum by the fast multipole method, before the
  // particle loop; its result read as names.accumulators[acc.id].
  void fast_sum(const Accumulate& acc, const Statement& st, ExpressionNames& names,
                NameTable& locals, const std::string& count);
  void fast_sum_report();
  // codegen/solve.cpp: a solve statement's system, assembled and solved.
  // How the solve at `position` (stage, statement) runs: what it calls in the
  // runtime, and so which of its headers the file includes.
  enum class SolveKind { dense, sparse, matrix_free };
  SolveKind solve_kind(std::pair<int, int> position) const;
  void solve_body(const Kernel& k, const ExpressionNames& names, NameTable& locals,
                  const std::string& count);
  // The conditions on i under which an operator term applies ("" for always).
  std::string operator_guard(const OperatorTerm& t, const ExpressionNames& names) const;
  // Consecutive terms under the same conditions share one if: closes the
  // open one and opens one for `guard` when they differ.
  void enter_guard(const std::string& guard, std::string& open);
  // Emits the locals a sum term's coefficient reads (dx, dx_norm) for row i
  // and column j, and returns the coefficient times the term's scale.
  std::string operator_entry(const OperatorTerm& t, const Statement& st,
                             const ExpressionNames& names, const std::string& i,
                             const std::string& j);
  // codegen/matrix_free_solve.cpp: a solve with dense = fmm, by GMRES whose
  // products are fast sums.
  void matrix_free_solve_body(const Kernel& k, const ExpressionNames& names, NameTable& locals,
                              const std::string& count);

  // ---- state ------------------------------------------------------------

  void state();

  // The emitter's own state: what it reads, what it has written and named.
  const Model& m_;
  const ModelFacts& facts_;
  const SourceFile& file_;
  const CodegenOptions& options_;
  std::string out_;
  std::string cls_, observables_type_;
  NameTable members_;
  std::vector<std::string> set_member_, epoch_, set_type_, const_member_, function_member_;
  std::vector<std::string> left_;  // per set, with open faces: how many left
  std::map<int, std::string> compensation_;  // accumulation id -> its Neumaier error's local
  std::vector<std::string> searches_;        // per SearchPlan::searches
  // In the kernel being emitted: each search group chosen at run time ->
  // the local naming the search its sums walk (choose_search).
  std::map<int, std::string> walked_search_;
  std::map<const Statement*, std::string> lists_;  // Verlet lists of statements with a skin
  // Each lists member and the statements it serves, in program order.
  std::vector<std::pair<std::string, std::vector<const Statement*>>> lists_served() const;
  // The VerletPairs a lists member keeps: half, full, or both when it serves both.
  std::string lists_pairs(const std::string& lists) const;
  std::map<const Statement*, std::string> solve_results_;  // the last result of each solve
  std::map<int, std::size_t> fast_sum_records_;  // Accumulate::id -> its index in fast_sums_
  std::vector<Kernel> kernels_;
  // Statements codegen made: calibration variants, fused passes' members.
  std::deque<Statement> variants_;
  std::vector<Calibration> calibrations_;
  std::vector<const Kernel*> profiled_;  // --profile: the step kernels, in order
  std::map<std::string, std::string> stage_methods_;  // named stage -> its method
  // (set, var, sink) -> name, element: a buffered update's, or a variant's sink
  std::map<std::tuple<int, int, bool>, std::pair<std::string, std::string>> buffers_;
  std::map<int, std::pair<std::string, std::string>> pair_sums_;  // Accumulate::id -> name, element
  // What the step computes only when step(observed) is told so
  // (analysis/observed_steps.cpp): targets in order, and the observables
  // among them. None: step() takes no argument.
  std::vector<std::string> observed_only_targets_;
  std::set<int> observed_only_;
};

}  // namespace partc::codegen

// partc/driver.hpp: the command-line program around a generated model.
//
//   int main(int argc, char** argv) { return partc::run_driver<md>(argc, argv); }
//
// Options (also --help): --steps K, --seed S, --set NAME=VALUE, --input
// [SET=]FILE.csv, --output FILE.csv, --vtk PREFIX, --every M, --check-every M,
// --last-finite FILE.csv, --log FILE.csv, --log-every M, --log-file-every M, --quiet,
// and for models that have them --stage NAME[:K], --matrix-market PREFIX (solves) and
// --check-accuracy (fast sums); "--option=value" works too. Exit status: 0 success, 1 bad input
// file or I/O failure, 2 bad arguments, 3 numerical blow-up (NaN/Inf).
//
// Surprises:
// - Every argument is checked before any work, including the parameter
//   values (through the model's set_param) and that output directories exist:
//   a typo costs a second, not a run.
// - With --check-every M > 0 the final state is always checked too, and so
//   is every state written as a VTK frame (no frame holds a NaN); a NaN found
//   more than a step after the last clean check says since when it may be
//   there. --output never holds a NaN; on a blow-up no output file is written (VTK
//   frames of earlier steps stay: they are complete and help to find the cause).
// - Instead, the last state found finite is written (last_finite.hpp), to
//   --last-finite FILE.csv, by default OUTPUT.last-finite.csv beside --output,
//   else MODEL.last-finite.csv here; the message says where and of which step.
// - The model's sets are discovered through for_each_set on a freshly
//   constructed model, before init or load: generated models hold their sets
//   as members, so this needs no extra API.
// - VTK "time" is the model's t when it has a timestep, else the step number.
// - VTK frames hold every set and variable, unless the model says
//   `output SET: v, rho every K`: then only the sets it names, with id, the
//   points and those variables, every K steps (--every overrides K).
//   --output always writes the whole state, so that --input can read it back.
// - A model with `output NAME, ...` logs those observables (thermo_log.hpp):
//   a progress row on the terminal every few steps (the model's interval, or
//   --log-every; not with --quiet), and every step into --log FILE.csv
//   (every M steps with --log-file-every M; the first and last always).
// - What only the state after a step needs (an observable nothing in a step
//   reads, and what only it reads) is computed only on the steps the log
//   shows or writes, VTK frames are written, and the last (a model's
//   step(observed)): the fewer rows logged, the less a run computes. A
//   --last-finite state may hold such variables from an earlier step.
// - The summary says how many particles left through open faces, if any are
//   open, each solve's and each fast sum's figures (a fast sum's order, its
//   predicted error and, with --check-accuracy, the error measured against
//   the direct sum), and ends with the model's search_report(): each neighbour search
//   or set of Verlet lists, its structure and how often it was built.
// - The command line, --help and the exit statuses (driver.cpp), and the
//   run loop with its checks, files and summary (run_model.cpp), are the
//   same code for every model, compiled once in the runtime library: a model
//   is seen through RunnableModel, which ModelAdapter<Model> implements with
//   a few lines per member. Link partc_runtime.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "partc/errors.hpp"
#include "partc/io/csv.hpp"
#include "partc/io/set_view.hpp"
#include "partc/io/vtk.hpp"            // FrameSpec
#include "partc/model_support.hpp"  // ParamInfo, SearchReport: a model used as a library needs them too

namespace partc {

namespace detail {

struct DriverOptions {
  std::int64_t steps = 10;
  std::uint64_t seed = 0;
  std::vector<std::pair<std::string, std::string>> inputs;  // (set, file)
  std::string output;                                       // "" = no CSV output
  std::string vtk_prefix;                                   // "" = no VTK output
  std::optional<std::int64_t> every;  // VTK interval; default: the model's, else 1
  std::int64_t check_every = 1;
  std::string last_finite;    // "" = the default path (last_finite_path)
  std::string log;            // "" = no CSV time series
  std::string matrix_market;  // "" = no Matrix Market files of solves
  std::vector<std::pair<std::string, std::int64_t>> stages;  // (named stage, runs), in order
  std::optional<std::int64_t> log_every;                     // overrides the model's interval
  std::int64_t log_file_every = 1;                           // --log's rows
  bool quiet = false;
  bool check_accuracy = false;  // fast sums checked against the direct sum
};

// Models that log observables (`output ...`) have log_columns(), log_every()
// and log_row(); others have none of them.
template <class Model, class = void>
struct logs_observables : std::false_type {};
template <class Model>
struct logs_observables<Model, std::void_t<decltype(Model::log_columns())>> : std::true_type {};

// Models with named stages run them by name.
template <class Model, class = void>
struct has_stages : std::false_type {};
template <class Model>
struct has_stages<Model, std::void_t<decltype(Model::stage_names())>> : std::true_type {};

// Models with solve statements report them, and can write their systems.
template <class Model, class = void>
struct has_solves : std::false_type {};
template <class Model>
struct has_solves<Model, std::void_t<decltype(std::declval<const Model&>().solve_report())>>
    : std::true_type {};

// Models with fast sums (dense = fmm) report them, and can check their accuracy.
template <class Model, class = void>
struct has_fast_sums : std::false_type {};
template <class Model>
struct has_fast_sums<Model, std::void_t<decltype(std::declval<const Model&>().fast_sum_report())>>
    : std::true_type {};

// Models with open faces count the particles that left through them.
template <class Model, class = void>
struct has_open_faces : std::false_type {};
template <class Model>
struct has_open_faces<Model, std::void_t<decltype(std::declval<const Model&>().boundary_report())>>
    : std::true_type {};

// Models with `output SET: ...` say which sets and variables VTK frames hold.
template <class Model, class = void>
struct has_frames : std::false_type {};
template <class Model>
struct has_frames<Model, std::void_t<decltype(std::declval<const Model&>().frames())>>
    : std::true_type {};

template <class Model, class = void>
struct has_profile : std::false_type {};
template <class Model>
struct has_profile<Model, std::void_t<decltype(std::declval<const Model&>().profile())>>
    : std::true_type {};

// Models with observables only the state after a step reads take step(observed).
template <class Model, class = void>
struct has_observed_steps : std::false_type {};
template <class Model>
struct has_observed_steps<Model, std::void_t<decltype(std::declval<Model&>().step(true))>>
    : std::true_type {};

template <class Model, class = void>
struct has_time : std::false_type {};
template <class Model>
struct has_time<Model, std::void_t<decltype(std::declval<const Model&>().time())>>
    : std::true_type {};

// What the options and --help need to know of a model, gathered once from it,
// so that parsing them and writing the help are compiled once (driver.cpp).
struct ModelFacts {
  std::string name;
  std::vector<std::string> sets;
  std::vector<std::string> stages;       // named stages, if any
  std::vector<std::string> log_columns;  // observables logged, if any
  std::int64_t log_every = 0;            // the model's progress interval, when it logs
  bool logs = false, solves = false, fast_sums = false;
  bool named_frames = false;  // `output SET: ...` says what VTK frames hold
  bool profiles = false;      // compiled with --profile
  std::vector<ParamInfo> params;
  // Model::set_param: checks and sets a parameter (--set).
  std::function<void(const std::string& name, const std::string& value)> set_param;
};

// A model as the run loop (run_model.cpp) sees it, whatever its type: one
// virtual call per step or per file written, none inside a step, so that the
// loop, the writers and the summary are compiled once for every model.
// ModelAdapter<Model> implements it; a model lacking an optional part (the
// traits above) gets what its absence means.
class RunnableModel {
 public:
  virtual ~RunnableModel() = default;
  virtual ModelFacts facts() = 0;
  // The seed, and the options of the model's solves and fast sums.
  virtual void configure(const DriverOptions& options) = 0;
  virtual void init() = 0;
  virtual void load(const std::map<std::string, CsvTable>& tables) = 0;
  // Per set, what its frames hold, when the model says (`output SET: ...`,
  // facts().named_frames); else every variable of every set.
  virtual std::vector<FrameSpec> frames() const = 0;
  virtual void run_stage(const std::string& name) = 0;
  virtual void step(bool observed) = 0;
  virtual std::int64_t step_count() const = 0;
  // VTK's time: the model's t when it has a timestep, else the step number.
  virtual double time() const = 0;
  // The logged observables: the progress interval (once the parameters are
  // known) and a row of values.
  virtual std::int64_t log_every() const = 0;
  virtual std::vector<double> log_row() const = 0;
  virtual void check_finite() const = 0;
  // Points `views` at every set, in declaration order, reusing their
  // storage (they are stale after the next step).
  virtual void view_sets(std::vector<SetView>& views) const = 0;
  // The summary's lines on open faces, solves and fast sums, and the searches.
  virtual std::vector<std::string> reports() const = 0;
  virtual std::vector<SearchReport> search_report() const = 0;
  // --profile: calibrates the kernels' timers, then reports them.
  virtual void report_profile(std::ostream& out, std::int64_t steps) = 0;
};

template <class Model>
class ModelAdapter final : public RunnableModel {
 public:
  explicit ModelAdapter(Model& model) : model_(model) {}

  ModelFacts facts() override {
    ModelFacts facts;
    facts.name = Model::model_name;
    model_.for_each_set([&](const char* name, const auto&) { facts.sets.emplace_back(name); });
    if constexpr (has_stages<Model>::value) facts.stages = Model::stage_names();
    if constexpr (logs_observables<Model>::value) {
      facts.logs = true;
      facts.log_columns = Model::log_columns();
      facts.log_every = log_every();
    }
    facts.solves = has_solves<Model>::value;
    facts.fast_sums = has_fast_sums<Model>::value;
    facts.named_frames = has_frames<Model>::value;
    facts.profiles = has_profile<Model>::value;
    facts.params = Model::param_info();
    facts.set_param = [this](const std::string& name, const std::string& value) {
      model_.set_param(name, value);
    };
    return facts;
  }
  void configure(const DriverOptions& options) override {
    model_.set_seed(options.seed);
    if constexpr (has_solves<Model>::value) model_.set_matrix_market(options.matrix_market);
    if constexpr (has_fast_sums<Model>::value) model_.set_check_accuracy(options.check_accuracy);
  }
  void init() override { model_.init(); }
  void load(const std::map<std::string, CsvTable>& tables) override { model_.load(tables); }
  std::vector<FrameSpec> frames() const override {
    if constexpr (has_frames<Model>::value) return model_.frames();
    return {};
  }
  void run_stage([[maybe_unused]] const std::string& name) override {
    if constexpr (has_stages<Model>::value) model_.run_stage(name);
  }
  void step([[maybe_unused]] bool observed) override {
    if constexpr (has_observed_steps<Model>::value)
      model_.step(observed);
    else
      model_.step();
  }
  std::int64_t step_count() const override { return model_.step_count(); }
  double time() const override {
    if constexpr (has_time<Model>::value) return model_.time();
    return static_cast<double>(model_.step_count());
  }
  std::int64_t log_every() const override {
    if constexpr (logs_observables<Model>::value) return model_.log_every();
    return 0;
  }
  std::vector<double> log_row() const override {
    if constexpr (logs_observables<Model>::value) return model_.log_row();
    return {};
  }
  void check_finite() const override { model_.check_finite(); }
  void view_sets(std::vector<SetView>& views) const override {
    std::size_t k = 0;
    model_.for_each_set([&](const char* name, const auto& set) {
      if (k == views.size()) views.emplace_back();
      view_into(views[k++], name, set);
    });
    views.resize(k);
  }
  std::vector<std::string> reports() const override {
    std::vector<std::string> lines;
    const auto add = [&](const std::vector<std::string>& more) {
      lines.insert(lines.end(), more.begin(), more.end());
    };
    if constexpr (has_open_faces<Model>::value) add(model_.boundary_report());
    if constexpr (has_solves<Model>::value) add(model_.solve_report());
    if constexpr (has_fast_sums<Model>::value) add(model_.fast_sum_report());
    return lines;
  }
  std::vector<SearchReport> search_report() const override { return model_.search_report(); }
  void report_profile([[maybe_unused]] std::ostream& out,
                      [[maybe_unused]] std::int64_t steps) override {
    if constexpr (has_profile<Model>::value) {
      model_.calibrate_profile(9);
      model_.profile().report(out, steps);
    }
  }

 private:
  Model& model_;
};

std::string usage_line(const std::string& model);

// "out.csv" for set P -> "out_P.csv", when a model has several sets.
std::string path_for_set(const std::string& path, const std::string& set);

// The command line (the arguments after the program's name), every value
// checked (the parameters' through facts.set_param, which sets them).
DriverOptions parse_driver_options(const ModelFacts& facts, const std::vector<std::string>& args);

void print_help(std::ostream& out, const ModelFacts& facts);

// Where the last finite state goes: --last-finite, else beside --output, else
// here, named after the model.
std::string last_finite_path(const std::string& model, const DriverOptions& options);

// Runs the model as the options say (run_model.cpp): init or load, the
// stages, the steps with their checks, frames and log, the output, the summary.
void run_model(RunnableModel& model, const ModelFacts& facts, const DriverOptions& options,
               std::ostream& out);

// --help, or the options parsed and the model run.
void drive(RunnableModel& model, const std::vector<std::string>& args, std::ostream& out);

// run(), with the errors it throws written to err and mapped to the exit
// status (see the top of this file); 0 when it returns.
int exit_status_of(const std::string& model, std::ostream& err, const std::function<void()>& run);

}  // namespace detail

// The whole program; out receives --help and the summary, err the errors.
template <class Model>
int run_driver(int argc, char** argv, std::ostream& out, std::ostream& err) {
  const std::vector<std::string> args(argv + std::min(argc, 1), argv + argc);
  return detail::exit_status_of(Model::model_name, err, [&] {
    Model model;
    detail::ModelAdapter<Model> adapter(model);
    detail::drive(adapter, args, out);
  });
}

template <class Model>
int run_driver(int argc, char** argv) {
  return run_driver<Model>(argc, argv, std::cout, std::cerr);
}

}  // namespace partc

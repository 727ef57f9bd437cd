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
// - The command line, --help and the exit statuses are the same code for
//   every model, compiled once in the runtime library (driver.cpp), from
//   the ModelFacts a model gives: link partc_runtime.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "partc/csv.hpp"
#include "partc/errors.hpp"
#include "partc/finite.hpp"
#include "partc/last_finite.hpp"
#include "partc/model_support.hpp"  // ParamInfo: a model used as a library needs it too
#include "partc/thermo_log.hpp"
#include "partc/vec.hpp"
#include "partc/vtk.hpp"

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

template <class Model>
void take_step(Model& model, bool observed) {
  if constexpr (has_observed_steps<Model>::value)
    model.step(observed);
  else
    model.step();
}

template <class Model, class = void>
struct has_time : std::false_type {};
template <class Model>
struct has_time<Model, std::void_t<decltype(std::declval<const Model&>().time())>>
    : std::true_type {};

template <class Model>
std::vector<std::string> set_names(const Model& model) {
  std::vector<std::string> names;
  model.for_each_set([&](const char* name, const auto&) { names.emplace_back(name); });
  return names;
}

// What the options and --help need to know of a model, gathered once from it,
// so that parsing them and writing the help are compiled once (driver.cpp).
struct ModelFacts {
  std::string name;
  std::vector<std::string> sets;
  std::vector<std::string> stages;       // named stages, if any
  std::vector<std::string> log_columns;  // observables logged, if any
  std::int64_t log_every = 0;            // the model's progress interval, when it logs
  bool logs = false, solves = false, fast_sums = false;
  std::vector<ParamInfo> params;
  // Model::set_param: checks and sets a parameter (--set).
  std::function<void(const std::string& name, const std::string& value)> set_param;
};

template <class Model>
ModelFacts facts_of(Model& model) {
  ModelFacts facts;
  facts.name = Model::model_name;
  facts.sets = set_names(model);
  if constexpr (has_stages<Model>::value) facts.stages = Model::stage_names();
  if constexpr (logs_observables<Model>::value) {
    facts.logs = true;
    facts.log_columns = Model::log_columns();
    facts.log_every = model.log_every();
  }
  facts.solves = has_solves<Model>::value;
  facts.fast_sums = has_fast_sums<Model>::value;
  facts.params = Model::param_info();
  facts.set_param = [&model](const std::string& name, const std::string& value) {
    model.set_param(name, value);
  };
  return facts;
}

std::string usage_line(const std::string& model);

// "out.csv" for set P -> "out_P.csv", when a model has several sets.
std::string path_for_set(const std::string& path, const std::string& set);

// The command line (the arguments after the program's name), every value
// checked (the parameters' through facts.set_param, which sets them).
DriverOptions parse_driver_options(const ModelFacts& facts, const std::vector<std::string>& args);

void print_help(std::ostream& out, const ModelFacts& facts);

// Per set: particle count, then min/mean/max of each variable (of |v| for a vec).
template <class Model>
void print_summary(std::ostream& out, const Model& model, const DriverOptions& options,
                   double seconds) {
  std::ostringstream text;
  text << Model::model_name << ": " << model.step_count() << " steps, seed " << options.seed << ", "
       << seconds << " s\n";
  model.for_each_set([&](const char* set_name, const auto& set) {
    text << set_name << ": " << set.size() << (set.size() == 1 ? " particle, " : " particles, ")
         << std::decay_t<decltype(set)>::bytes_per_particle << " bytes each\n";
    if (set.empty()) return;
    text << "  " << std::left << std::setw(12) << "variable" << std::right << std::setw(14) << "min"
         << std::setw(14) << "mean" << std::setw(14) << "max"
         << "\n";
    set.for_each_variable([&](const char* name, const auto& values) {
      using S = typename std::decay_t<decltype(values)>::value_type;
      double low = std::numeric_limits<double>::infinity(), high = -low, sum = 0;
      for (const S& value : values) {
        double x;
        if constexpr (StorageTraits<S>::is_vec)
          x = norm(value);
        else
          x = static_cast<double>(value);
        low = std::min(low, x);
        high = std::max(high, x);
        sum += x;
      }
      const std::string label = StorageTraits<S>::is_vec ? "|" + std::string(name) + "|" : name;
      text << "  " << std::left << std::setw(12) << label << std::right << std::setw(14) << low
           << std::setw(14) << sum / static_cast<double>(values.size()) << std::setw(14) << high
           << "\n";
    });
  });
  if constexpr (has_open_faces<Model>::value)
    for (const std::string& line : model.boundary_report()) text << line << "\n";
  if constexpr (has_solves<Model>::value)
    for (const std::string& line : model.solve_report()) text << line << "\n";
  if constexpr (has_fast_sums<Model>::value)
    for (const std::string& line : model.fast_sum_report()) text << line << "\n";
  const std::vector<SearchReport> searches = model.search_report();
  if (!searches.empty()) text << "neighbour searches:\n";
  for (const SearchReport& s : searches)
    text << "  " << s.serves << ": " << s.structure << "; built " << s.builds
         << (s.builds == 1 ? " time" : " times") << ", walked " << s.walks
         << (s.walks == 1 ? " time\n" : " times\n");
  out << text.str();
}

// Where the last finite state goes: --last-finite, else beside --output, else
// here, named after the model.
std::string last_finite_path(const std::string& model, const DriverOptions& options);

// When a run writes, logs and checks, the same for every model: run_model
// asks it at each step. Frames are due for a set every --every steps, else
// its own interval; a step is observed when something reads the state after
// it (a frame, a log row, or it is the last).
class RunPlan {
 public:
  // frames: one per set; named: the model names their variables (`output
  // SET: ...`), else frames hold every variable.
  RunPlan(const DriverOptions& options, std::vector<FrameSpec> frames, bool named,
          std::optional<ThermoLog> log);

  bool observed(std::int64_t step) const;
  // Whether the state of `step` is checked for NaN and Inf: every
  // --check-every steps, and whenever a frame is written (unless checks are off).
  bool check_due(std::int64_t step) const;
  void found_finite(std::int64_t step) { clean_ = step; }
  // In a handler of the NumericalError e of the check at `step`: rethrows it,
  // or, when the last clean check was more than a step before, an error that
  // says since when the value may be there.
  [[noreturn]] void rethrow_with_last_clean(const NumericalError& e, std::int64_t step) const;

  // The series the set's frame of `step` goes to, or null when none is due.
  VtkSeries* frame_due(const std::string& set, std::int64_t step);
  // The variables the set's frames hold (null: all of them).
  const std::vector<std::string>* frame_variables(const std::string& set) const;

  void log_row(std::int64_t step, const std::vector<double>& values) { log_->row(step, values); }
  void close_log() {
    if (log_) log_->close();
  }

 private:
  bool any_frame_due(std::int64_t step) const;
  std::int64_t every(const FrameSpec& frame) const;

  const DriverOptions& options_;
  std::map<std::string, FrameSpec> frames_;
  bool named_;
  std::map<std::string, VtkSeries> series_;  // empty without --vtk
  std::optional<ThermoLog> log_;
  std::int64_t clean_ = -1;  // the last step found finite
};

// Writes the kept state after a blow-up; returns what to add to its message.
template <class Model>
std::string keep_last_finite(const LastFinite& kept, const Model& model,
                             const DriverOptions& options) {
  if (kept.empty()) return "no state was found finite before it, so none is written";
  const std::string path = last_finite_path(Model::model_name, options);
  const bool several = set_names(model).size() > 1;
  try {
    const std::vector<std::string> paths = kept.write(
        [&](const std::string& set) { return several ? path_for_set(path, set) : path; });
    return "the last state found finite, at step " + std::to_string(kept.step()) + ", is in " +
           join(paths) + " (--input reads it back)";
  } catch (const std::exception& e) {
    return "the last state found finite, at step " + std::to_string(kept.step()) +
           ", could not be written: " + e.what();
  }
}

template <class Model>
void run_model(Model& model, const DriverOptions& options, std::ostream& out) {
  const auto start = std::chrono::steady_clock::now();
  model.set_seed(options.seed);
  if constexpr (has_solves<Model>::value) model.set_matrix_market(options.matrix_market);
  if constexpr (has_fast_sums<Model>::value) model.set_check_accuracy(options.check_accuracy);
  if (options.inputs.empty()) {
    model.init();
  } else {
    std::map<std::string, CsvTable> tables;
    for (const auto& [set, file] : options.inputs) tables.emplace(set, read_csv(file));
    model.load(tables);
  }

  const std::vector<std::string> sets = set_names(model);
  // Per set: its frames' variables (all of them without `output SET: ...`).
  std::vector<FrameSpec> frames;
  if constexpr (has_frames<Model>::value) {
    frames = model.frames();
  } else {
    for (const auto& set : sets) frames.push_back(FrameSpec{set, {}, 1});
  }

  if constexpr (has_stages<Model>::value)
    for (const auto& [name, runs] : options.stages)
      for (std::int64_t k = 0; k < runs; ++k) model.run_stage(name);

  std::optional<ThermoLog> log;
  if constexpr (logs_observables<Model>::value)
    log.emplace(Model::log_columns(), options.quiet ? nullptr : &out,
                options.log_every.value_or(model.log_every()), options.log, options.log_file_every);
  RunPlan plan(options, std::move(frames), has_frames<Model>::value, std::move(log));

  // Step 0 (the state after init or load) is checked and written like any other.
  // A step that writes a VTK frame is checked too, so no frame holds a NaN.
  bool checked = false;
  [[maybe_unused]] std::chrono::duration<double> stepping{0};  // in step(), for --profile
  LastFinite kept(model);
  const auto check = [&](std::int64_t step) {
    try {
      model.check_finite();
    } catch (const NumericalError& e) {
      plan.rethrow_with_last_clean(e, step);
    }
    plan.found_finite(step);
    kept.take(model, step);
  };
  try {
    for (std::int64_t k = 0; k <= options.steps; ++k) {
      if (k > 0) {
        if constexpr (has_profile<Model>::value) {
          const auto before = std::chrono::steady_clock::now();
          take_step(model, plan.observed(k));
          stepping += std::chrono::steady_clock::now() - before;
        } else {
          take_step(model, plan.observed(k));
        }
      }
      const std::int64_t step = model.step_count();
      checked = plan.check_due(step);
      if (checked) check(step);
      if constexpr (logs_observables<Model>::value)
        if (plan.observed(k)) plan.log_row(step, model.log_row());
      double time = static_cast<double>(step);
      if constexpr (has_time<Model>::value) time = model.time();
      model.for_each_set([&](const char* name, const auto& set) {
        if (VtkSeries* series = plan.frame_due(name, step))
          series->write(set, step, time, plan.frame_variables(name));
      });
    }
    if (options.check_every > 0 && !checked) check(model.step_count());
  } catch (const NumericalError& e) {
    throw NumericalError(std::string(e.what()) + "\n" + Model::model_name +
                         ": note: " + keep_last_finite(kept, model, options));
  }
  plan.close_log();

  if (!options.output.empty())
    model.for_each_set([&](const char* name, const auto& set) {
      write_csv(sets.size() > 1 ? path_for_set(options.output, name) : options.output, set);
    });
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  if (!options.quiet) print_summary(out, model, options, elapsed.count());
  // After the output and the summary: the calibration runs kernels again.
  if constexpr (has_profile<Model>::value) {
    if (options.quiet) return;
    model.calibrate_profile(9);
    model.profile().report(out, options.steps);
    out << "  the driver's clock around step(): "
        << (options.steps > 0 ? 1e3 * stepping.count() / static_cast<double>(options.steps) : 0)
        << " ms a step\n";
  }
}

}  // namespace detail

namespace detail {

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
    if (std::find(args.begin(), args.end(), "--help") != args.end())
      return detail::print_help(out, detail::facts_of(model));
    const detail::DriverOptions options =
        detail::parse_driver_options(detail::facts_of(model), args);
    detail::run_model(model, options, out);
  });
}

template <class Model>
int run_driver(int argc, char** argv) {
  return run_driver<Model>(argc, argv, std::cout, std::cerr);
}

}  // namespace partc

// partc/run_model.cpp: the driver's run loop, the same for every model
// (driver.hpp says what the options do): a model is a RunnableModel here,
// its sets SetViews, so this is compiled once, in the runtime library.
#include <chrono>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include "partc/driver.hpp"
#include "partc/finite.hpp"
#include "partc/io/last_finite.hpp"
#include "partc/io/thermo_log.hpp"

namespace partc {

namespace detail {

namespace {

bool due(std::int64_t step, std::int64_t every) { return every > 0 && step % every == 0; }

// When a run writes, logs and checks: run_model asks it at each step. Frames
// are due for a set every --every steps, else its own interval; a step is
// observed when something reads the state after it (a frame, a log row, or
// it is the last).
class RunPlan {
 public:
  // frames: one per set; named: the model names their variables (`output
  // SET: ...`), else frames hold every variable.
  RunPlan(const DriverOptions& options, std::vector<FrameSpec> frames, bool named,
          std::optional<ThermoLog> log)
      : options_(options), named_(named), log_(std::move(log)) {
    for (FrameSpec& f : frames) frames_.emplace(f.set, std::move(f));
    if (!options.vtk_prefix.empty())
      for (const auto& [set, unused] : frames_)
        series_.emplace(set, options.vtk_prefix + "_" + set);
  }

  bool observed(std::int64_t step) const {
    return step == options_.steps || any_frame_due(step) || (log_ && log_->uses(step));
  }
  // Whether the state of `step` is checked for NaN and Inf: every
  // --check-every steps, and whenever a frame is written (unless checks are off).
  bool check_due(std::int64_t step) const {
    return due(step, options_.check_every) || (any_frame_due(step) && options_.check_every > 0);
  }
  void found_finite(std::int64_t step) { clean_ = step; }
  // In a handler of the NumericalError e of the check at `step`: rethrows it,
  // or, when the last clean check was more than a step before, an error that
  // says since when the value may be there.
  [[noreturn]] void rethrow_with_last_clean(const NumericalError& e, std::int64_t step) const {
    if (clean_ < 0 || step - clean_ <= 1) throw;
    throw NumericalError(std::string(e.what()) + " (checked every " +
                         std::to_string(options_.check_every) + " steps: it arose after step " +
                         std::to_string(clean_) + ", the last found finite; --check-every 1 " +
                         "finds the step)");
  }

  bool any_frame_due(std::int64_t step) const {
    return std::any_of(series_.begin(), series_.end(),
                       [&](const auto& s) { return due(step, every(frames_.at(s.first))); });
  }
  // The series the set's frame of `step` goes to, or null when none is due.
  VtkSeries* frame_due(const std::string& set, std::int64_t step) {
    const auto s = series_.find(set);
    if (s == series_.end() || !due(step, every(frames_.at(set)))) return nullptr;
    return &s->second;
  }
  // The variables the set's frames hold (null: all of them).
  const std::vector<std::string>* frame_variables(const std::string& set) const {
    return named_ ? &frames_.at(set).variables : nullptr;
  }

  void log_row(std::int64_t step, const std::vector<double>& values) { log_->row(step, values); }
  void close_log() {
    if (log_) log_->close();
  }

 private:
  std::int64_t every(const FrameSpec& frame) const { return options_.every.value_or(frame.every); }

  const DriverOptions& options_;
  std::map<std::string, FrameSpec> frames_;
  bool named_;
  std::map<std::string, VtkSeries> series_;  // empty without --vtk
  std::optional<ThermoLog> log_;
  std::int64_t clean_ = -1;  // the last step found finite
};

// Per set (sets: views of the final state): particle count, then
// min/mean/max of each variable (of |v| for a vec).
void print_summary(std::ostream& out, RunnableModel& model, const ModelFacts& facts,
                   const DriverOptions& options, double seconds, const std::vector<SetView>& sets) {
  std::ostringstream text;
  text << facts.name << ": " << model.step_count() << " steps, seed " << options.seed << ", "
       << seconds << " s\n";
  for (const SetView& set : sets) {
    text << set.name << ": " << set.size << (set.size == 1 ? " particle, " : " particles, ")
         << set.bytes_per_particle << " bytes each\n";
    if (set.size == 0) continue;
    text << "  " << std::left << std::setw(12) << "variable" << std::right << std::setw(14) << "min"
         << std::setw(14) << "mean" << std::setw(14) << "max"
         << "\n";
    for (const ColumnView& column : set.columns) {
      double low = std::numeric_limits<double>::infinity(), high = -low, sum = 0;
      visit_column(column, [&](const auto* values) {
        using S = std::remove_const_t<std::remove_pointer_t<decltype(values)>>;
        for (std::size_t i = 0; i < set.size; ++i) {
          double x;
          if constexpr (StorageTraits<S>::is_vec)
            x = norm(values[i]);  // in the vec's own precision, as a model would
          else
            x = static_cast<double>(values[i]);
          low = std::min(low, x);
          high = std::max(high, x);
          sum += x;
        }
      });
      const std::string label = column.is_vec ? "|" + std::string(column.name) + "|" : column.name;
      text << "  " << std::left << std::setw(12) << label << std::right << std::setw(14) << low
           << std::setw(14) << sum / static_cast<double>(set.size) << std::setw(14) << high
           << "\n";
    }
  }
  for (const std::string& line : model.reports()) text << line << "\n";
  const std::vector<SearchReport> searches = model.search_report();
  if (!searches.empty()) text << "neighbour searches:\n";
  for (const SearchReport& s : searches)
    text << "  " << s.serves << ": " << s.structure << "; built " << s.builds
         << (s.builds == 1 ? " time" : " times") << ", walked " << s.walks
         << (s.walks == 1 ? " time\n" : " times\n");
  out << text.str();
}

// Writes the kept state after a blow-up; returns what to add to its message.
std::string keep_last_finite(const LastFinite& kept, const ModelFacts& facts,
                             const DriverOptions& options) {
  if (kept.empty()) return "no state was found finite before it, so none is written";
  const std::string path = last_finite_path(facts.name, options);
  const bool several = facts.sets.size() > 1;
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

}  // namespace

std::string last_finite_path(const std::string& model, const DriverOptions& options) {
  if (!options.last_finite.empty()) return options.last_finite;
  if (options.output.empty()) return model + ".last-finite.csv";
  const std::filesystem::path p(options.output);
  return (p.parent_path() / (p.stem().string() + ".last-finite" + p.extension().string())).string();
}

void run_model(RunnableModel& model, const ModelFacts& facts, const DriverOptions& options,
               std::ostream& out) {
  const auto start = std::chrono::steady_clock::now();
  model.configure(options);
  if (options.inputs.empty()) {
    model.init();
  } else {
    std::map<std::string, CsvTable> tables;
    for (const auto& [set, file] : options.inputs) tables.emplace(set, read_csv(file));
    model.load(tables);
  }

  for (const auto& [name, runs] : options.stages)
    for (std::int64_t k = 0; k < runs; ++k) model.run_stage(name);

  std::optional<ThermoLog> log;
  if (facts.logs)
    log.emplace(facts.log_columns, options.quiet ? nullptr : &out,
                options.log_every.value_or(model.log_every()), options.log, options.log_file_every);
  std::vector<FrameSpec> frames = model.frames();
  if (!facts.named_frames)
    for (const std::string& set : facts.sets) frames.push_back(FrameSpec{set, {}, 1});
  RunPlan plan(options, std::move(frames), facts.named_frames, std::move(log));

  // Step 0 (the state after init or load) is checked and written like any other.
  // A step that writes a VTK frame is checked too, so no frame holds a NaN.
  bool checked = false;
  std::chrono::duration<double> stepping{0};  // in step(), for --profile
  LastFinite kept;
  std::vector<SetView> views;  // of the sets, refreshed before each use
  const auto check = [&](std::int64_t step) {
    try {
      model.check_finite();
    } catch (const NumericalError& e) {
      plan.rethrow_with_last_clean(e, step);
    }
    plan.found_finite(step);
    model.view_sets(views);
    kept.take(views, step);
  };
  try {
    for (std::int64_t k = 0; k <= options.steps; ++k) {
      if (k > 0) {  // the clock read only for --profile: a small model's step is a microsecond
        const auto before = facts.profiles ? std::chrono::steady_clock::now()
                                           : std::chrono::steady_clock::time_point();
        model.step(plan.observed(k));
        if (facts.profiles) stepping += std::chrono::steady_clock::now() - before;
      }
      const std::int64_t step = model.step_count();
      checked = plan.check_due(step);
      if (checked) check(step);
      if (facts.logs && plan.observed(k)) plan.log_row(step, model.log_row());
      if (plan.any_frame_due(step)) {
        const double time = model.time();
        model.view_sets(views);
        for (const SetView& set : views)
          if (VtkSeries* series = plan.frame_due(set.name, step))
            series->write(set, step, time, plan.frame_variables(set.name));
      }
    }
    if (options.check_every > 0 && !checked) check(model.step_count());
  } catch (const NumericalError& e) {
    throw NumericalError(std::string(e.what()) + "\n" + facts.name +
                         ": note: " + keep_last_finite(kept, facts, options));
  }
  plan.close_log();

  model.view_sets(views);
  if (!options.output.empty())
    for (const SetView& set : views)
      write_csv(facts.sets.size() > 1 ? path_for_set(options.output, set.name) : options.output,
                set);
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  if (options.quiet) return;
  print_summary(out, model, facts, options, elapsed.count(), views);
  // After the output and the summary: the calibration runs kernels again.
  if (facts.profiles) {
    model.report_profile(out, options.steps);
    out << "  the driver's clock around step(): "
        << (options.steps > 0 ? 1e3 * stepping.count() / static_cast<double>(options.steps) : 0)
        << " ms a step\n";
  }
}

void drive(RunnableModel& model, const std::vector<std::string>& args, std::ostream& out) {
  const ModelFacts facts = model.facts();
  if (std::find(args.begin(), args.end(), "--help") != args.end())
    return print_help(out, facts);
  run_model(model, facts, parse_driver_options(facts, args), out);
}

}  // namespace detail

}  // namespace partc

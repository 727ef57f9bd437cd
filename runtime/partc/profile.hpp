// partc/profile.hpp: where a generated model's step time goes, per effect
// instance, for models compiled with `partc --profile`.
//
//   partc::Profile profile({{"step_f", {"lj", "coulomb"}, "", {{0}, {1}}},
//                           {"step_v", {"verlet"}, ""}},
//                          {{"sums over A", {"lj", "coulomb"}}});
//   { const partc::ProfileTimer t(profile, profile.step_slot()); ...
//     { const partc::ProfileTimer k(profile, profile.kernel_slot(0)); step_f(); } ... }
//   profile.calibrate(0, 5, {full, without_lj, without_coulomb});  // after the run
//   profile.report(std::cout, steps);
//
// Surprises:
// - Times are exclusive: a timer's time is taken off the timer open around
//   it, so a search built inside a kernel counts for the search, not for the
//   kernel that happened to need it first. Every slot together is step()'s
//   time, exactly; nothing is counted twice.
// - A kernel of several effects (their contributions merged into one
//   statement, one pair walk; or a variable computed where it is read) is
//   split by a calibration after the run: the statement computed whole, then
//   without some of its effects' terms in turn, into a buffer nobody reads.
//   Part o's marginal cost is m_o = full - without_o; what the variants
//   leave in (a fused pass's reader, the integrator that reads the force) is
//   the rest, full - sum(m). A part's share of the kernel's time T is
//   T m_o / sum(m, rest) (the shared walk split in proportion), and what
//   dropping it would save is T m_o / full; the rest's saving is not known.
// - A kernel of several effects that is not calibrated is shown as their
//   joint row: no split is claimed.
// - A search's builds count towards an effect's saving only when that effect
//   alone uses the search; otherwise they are a shared row.
// - Without an effect, a shared search may be built at a smaller radius (its
//   far sums gone): calibrate_build times a build at either radius, and the
//   difference, times the search's builds in the run, is that part's too. It
//   may be negative: a cell list of many more cells than particles builds
//   slower than one of few.
// - Timers are opened on the thread that calls step(), never inside a
//   parallel loop: the profile holds no locks and no global state.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace partc {

// One step kernel: its name and the effect instances its terms come from
// (none: a statement the scene or model wrote itself, named by where).
struct ProfiledKernel {
  std::string name;
  std::vector<std::string> effects;
  std::string where;  // "line 12": for statements of no effect
  // The effects (indices) each calibration variant after the whole leaves
  // out; none: the kernel is not calibrated.
  std::vector<std::vector<std::size_t>> leaves_out;
};

// One search or set of Verlet lists: what it serves, and the effects of the
// statements it serves ("" for a statement of no effect).
struct ProfiledSearch {
  std::string serves;
  std::vector<std::string> effects;
};

// An effect's (or a joint row's) time per step and what dropping it saves.
struct EffectTime {
  std::string name;
  double seconds = 0;   // over the run
  double saving = 0;    // predicted, over the run
  bool effect = false;  // an effect instance's row (or several's, joint)
  // Why no saving is predicted; empty when one is.
  std::string unpredicted;
};

class Profile {
 public:
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();

  Profile(std::vector<ProfiledKernel> kernels, std::vector<ProfiledSearch> searches)
      : kernels_(std::move(kernels)),
        searches_(std::move(searches)),
        seconds_(1 + kernels_.size() + searches_.size(), 0.0),
        calls_(seconds_.size(), 0),
        calibration_(kernels_.size()),
        build_saving_(kernels_.size()) {}

  std::size_t step_slot() const { return 0; }
  std::size_t kernel_slot(std::size_t k) const { return 1 + k; }
  std::size_t search_slot(std::size_t s) const { return 1 + kernels_.size() + s; }

  // Adds seconds to a slot (a timer's time; tests give times directly).
  void add(std::size_t slot, double seconds) { seconds_.at(slot) += seconds; }
  // Counts a call of a slot (a timer's: a kernel's call, a search's build).
  void count(std::size_t slot) { ++calls_.at(slot); }
  std::size_t calls(std::size_t slot) const { return calls_.at(slot); }

  // Exclusive seconds of a slot so far.
  double seconds(std::size_t slot) const { return seconds_.at(slot); }
  // step()'s time: every slot together.
  double step_seconds() const {
    double total = 0;
    for (double s : seconds_) total += s;
    return total;
  }

  // Times each variant `rounds` times, interleaved so that a loaded machine
  // slows them alike: variants[0] computes the kernel's statement whole,
  // variants[1 + v] without the effects leaves_out[v]. Each timing repeats a variant
  // for at least min_seconds (a clock tick is not a cost); keeps the fastest
  // per call.
  void calibrate(std::size_t kernel, int rounds, const std::vector<std::function<void()>>& variants,
                 double min_seconds = 20e-3) {
    if (variants.size() != kernels_.at(kernel).leaves_out.size() + 1)
      throw std::invalid_argument("Profile::calibrate: one variant per part left out, and the whole");
    const std::vector<double> step = seconds_;
    set_calibration(kernel, fastest(rounds, variants, min_seconds));
    seconds_ = step;  // a variant's search checks are not the step's
  }

  // Times builds of one search at the whole statement's radius and at the
  // smaller one variant leaves_out[variant] leaves (in searches of their own,
  // so that the set's order stays as it is), as calibrate does; the
  // difference per build, times the run's builds of search s, adds to what
  // dropping that part saves.
  void calibrate_build(std::size_t kernel, std::size_t variant, std::size_t s, int rounds,
                       const std::function<void()>& at_whole,
                       const std::function<void()>& at_variant, double min_seconds = 20e-3) {
    const std::vector<double> t = fastest(rounds, {at_whole, at_variant}, min_seconds);
    set_build_saving(kernel, variant,
                     static_cast<double>(calls_.at(search_slot(s))) * (t[0] - t[1]));
  }

  // As calibrate_build measured: over the run, what variant's builds save.
  void set_build_saving(std::size_t kernel, std::size_t variant, double seconds) {
    std::vector<double>& saving = build_saving_.at(kernel);
    saving.resize(std::max(saving.size(), variant + 1), 0.0);
    saving[variant] += seconds;
  }

  // As calibrate measured: [0] the whole statement, [1 + v] without leaves_out[v].
  void set_calibration(std::size_t kernel, std::vector<double> seconds) {
    calibration_.at(kernel) = std::move(seconds);
  }

  // Per effect instance, then the scene's own statements, shared searches
  // and step() outside kernels: the rows sum to step_seconds().
  std::vector<EffectTime> attribute() const {
    std::vector<EffectTime> rows;
    auto row = [&](const std::string& name, bool effect = true) -> EffectTime& {
      for (EffectTime& r : rows)
        if (r.name == name) return r;
      EffectTime r;
      r.name = name;
      r.effect = effect;
      rows.push_back(r);
      return rows.back();
    };
    for (std::size_t k = 0; k < kernels_.size(); ++k) {
      const ProfiledKernel& kernel = kernels_[k];
      const double t = seconds_[kernel_slot(k)];
      if (kernel.effects.empty()) {
        row("scene, " + kernel.where, false).seconds += t;
      } else if (kernel.effects.size() == 1) {
        EffectTime& r = row(kernel.effects.front());
        r.seconds += t;
        r.saving += t;
      } else if (calibration_[k].empty()) {
        EffectTime& r = row(joined(kernel, all(kernel)));
        r.seconds += t;
        r.unpredicted = "joint: not split";
      } else {
        split(kernel, t, calibration_[k], build_saving_[k], row);
      }
    }
    for (std::size_t s = 0; s < searches_.size(); ++s) {
      const ProfiledSearch& search = searches_[s];
      const double t = seconds_[search_slot(s)];
      const bool alone = !search.effects.empty() && !search.effects.front().empty() &&
                         std::all_of(search.effects.begin(), search.effects.end(),
                                     [&](const std::string& e) { return e == search.effects[0]; });
      EffectTime& r = row(alone ? search.effects.front() : "search: " + search.serves, alone);
      r.seconds += t;
      if (alone) r.saving += t;
    }
    row("step() outside kernels", false).seconds += seconds_[step_slot()];
    return rows;
  }

  // The table: per row, ms a step, its share of the step, and the predicted
  // saving of dropping it (--drop NAME), effects only.
  void report(std::ostream& out, std::int64_t steps) const {
    const double total = step_seconds();
    const double per = steps > 0 ? 1e3 / static_cast<double>(steps) : 0;
    std::ostringstream text;
    text << std::fixed << std::setprecision(4);
    text << "profile: " << steps << " steps, " << total * per << " ms a step in step()\n";
    text << "  " << std::left << std::setw(36) << "effect" << std::right << std::setw(12)
         << "ms/step" << std::setw(8) << "share" << std::setw(26) << "--drop saves (ms/step)"
         << "\n";
    for (const EffectTime& r : attribute()) {
      text << "  " << std::left << std::setw(36) << r.name << std::right << std::setw(12)
           << r.seconds * per << std::setw(7) << std::setprecision(1)
           << (total > 0 ? 100 * r.seconds / total : 0) << "%" << std::setprecision(4);
      if (r.effect && !r.unpredicted.empty())
        text << std::setw(26) << r.unpredicted;
      else if (r.effect)
        text << std::setw(26) << r.saving * per;
      text << "\n";
    }
    out << text.str();
  }

 private:
  friend class ProfileTimer;

  static std::vector<std::size_t> all(const ProfiledKernel& kernel) {
    std::vector<std::size_t> out(kernel.effects.size());
    for (std::size_t o = 0; o < out.size(); ++o) out[o] = o;
    return out;
  }

  // "pressure+viscosity": the effects' names, each once.
  static std::string joined(const ProfiledKernel& kernel, const std::vector<std::size_t>& part) {
    std::vector<std::string> names;
    for (std::size_t o : part)
      if (std::find(names.begin(), names.end(), kernel.effects.at(o)) == names.end())
        names.push_back(kernel.effects[o]);
    std::string out = names.front();
    for (std::size_t n = 1; n < names.size(); ++n) out += "+" + names[n];
    return out;
  }

  // Per function, the fastest over rounds of its time per call, interleaved
  // so that a loaded machine slows them alike; each timing repeats a function
  // for at least min_seconds (a clock tick is not a cost). The fastest, not
  // the median: a shared machine only ever adds time, and a marginal is the
  // small difference of two such times (the fused bench scene, 3 runs: drag's
  // 0 to 0.53 ms a step by medians of 5 ms timings, 0 each time by the
  // fastest of 20 ms ones).
  static std::vector<double> fastest(int rounds, const std::vector<std::function<void()>>& fs,
                                     double min_seconds) {
    auto time = [](const std::function<void()>& f, int calls) {
      const auto start = std::chrono::steady_clock::now();
      for (int c = 0; c < calls; ++c) f();
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const double once = std::max(time(fs.front(), 1), 1e-9);
    const int calls = static_cast<int>(std::clamp(std::ceil(min_seconds / once), 1.0, 1e6));
    std::vector<std::vector<double>> times(fs.size());
    for (int r = 0; r < rounds; ++r)
      for (std::size_t f = 0; f < fs.size(); ++f) times[f].push_back(time(fs[f], calls) / calls);
    std::vector<double> out;
    for (std::vector<double>& t : times) out.push_back(*std::min_element(t.begin(), t.end()));
    return out;
  }

  // A calibrated kernel's time t, by its parts' marginal costs; builds: what
  // each part's searches at a smaller radius save (calibrate_build).
  template <class Row>
  static void split(const ProfiledKernel& kernel, double t, const std::vector<double>& c,
                    const std::vector<double>& builds, Row& row) {
    std::vector<std::vector<std::size_t>> parts = kernel.leaves_out;
    std::vector<double> marginal;
    double total = 0;
    for (std::size_t v = 0; v < parts.size(); ++v) {
      marginal.push_back(std::max(0.0, c[0] - c[1 + v]));
      total += marginal.back();
    }
    std::vector<std::size_t> rest;
    for (std::size_t o : all(kernel))
      if (std::none_of(parts.begin(), parts.end(), [&](const std::vector<std::size_t>& part) {
            return std::find(part.begin(), part.end(), o) != part.end();
          }))
        rest.push_back(o);
    const std::size_t left_out = parts.size();
    if (!rest.empty()) {
      parts.push_back(rest);
      marginal.push_back(std::max(0.0, c[0] - total));
      total += marginal.back();
    }
    for (std::size_t p = 0; p < parts.size(); ++p) {
      const std::string name = joined(kernel, parts[p]);
      EffectTime& r = row(name);
      r.seconds += total > 0 ? t * marginal[p] / total : t / static_cast<double>(parts.size());
      if (p >= left_out)
        r.unpredicted = "rest of a fused pass";
      else if (name.find('+') != std::string::npos)
        r.unpredicted = "joint: not split";
      else if (c[0] > 0)
        r.saving += t * marginal[p] / c[0] + (p < builds.size() ? builds[p] : 0.0);
    }
  }

  std::vector<ProfiledKernel> kernels_;
  std::vector<ProfiledSearch> searches_;
  std::vector<double> seconds_;  // exclusive, per slot
  std::vector<std::size_t> calls_;  // per slot, in step()
  std::vector<std::vector<double>> calibration_;
  std::vector<std::vector<double>> build_saving_;  // per kernel, per variant after the whole
  std::size_t open_ = none;  // the slot whose timer is running, innermost
};

// Times a scope into one slot of a profile, exclusive of the timers opened
// inside it; outside step() (a search built by init), nothing.
class ProfileTimer {
 public:
  ProfileTimer(Profile& profile, std::size_t slot)
      : profile_(profile), slot_(slot), parent_(profile.open_),
        counts_(slot == profile.step_slot() || parent_ != Profile::none),
        start_(std::chrono::steady_clock::now()) {
    profile_.open_ = slot_;
  }
  ~ProfileTimer() {
    profile_.open_ = parent_;
    if (!counts_) return;
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    profile_.add(slot_, s);
    profile_.count(slot_);
    if (parent_ != Profile::none) profile_.add(parent_, -s);
  }
  ProfileTimer(const ProfileTimer&) = delete;
  ProfileTimer& operator=(const ProfileTimer&) = delete;

 private:
  Profile& profile_;
  std::size_t slot_, parent_;
  bool counts_;  // only in a step: a search built by init is not the step's
  std::chrono::steady_clock::time_point start_;
};

}  // namespace partc

// bench_compose: two pair effects on one force, LJ and Coulomb, composed
// into one pair walk against the same physics as two walks (issue 10), next
// to LAMMPS doing the same: pair_style lj/cut/coul/cut (one pair loop)
// against hybrid/overlay lj/cut coul/cut (one loop per sub-style).
//
// The system: LAMMPS's melt (lj_melt_setup.hpp: 32000 LJ atoms, fcc at
// density 0.8442, T = 3.0, zero momentum; velocity Verlet, dt = 0.005, 100
// steps) with charges +q and -q alternating by id (id k: +q for even k; 16000
// of each, q = 0.2), LJ truncated at 2.5 and Coulomb (LJ units: E = qi qj / r)
// truncated at 2.5, then at 3.0. The partc models (tests/bench/compose_*.part.in):
//   one sum     f = sum(j, r < max(rc_lj, rc_coul), if(lj) + if(coulomb)): one walk
//   fused       f = sum(j, r < rc_lj, lj) + sum(j, r < rc_coul, coulomb), one
//               statement: fuse_loops makes it one walk at the larger radius
//   separate    f_lj = sum(lj) and f_coulomb = sum(coulomb), two statements,
//               the kicks add them: statement fusion makes them one pass, one
//               walk, where their sums share one search or one set of lists;
//               compiled --no-fuse (lists only), two walks of one set of
//               lists: what composing is measured against
//   one radius  separate, with the LJ sum bounded by the larger cutoff (its
//               term masked by its own), so both statements search one radius;
//               run only when the cutoffs differ
//   LJ alone, Coulomb alone: one walk each
// each with Verlet lists (skin 0.3, rebuilt when some atom moved half the
// skin), as examples/lj_melt.part, and fused, separate and one radius also
// with a cell list built every step. The walks column counts the walks a step
// that the models' search_report() recorded, not what the names promise:
// separate is two walks only where the search plan gave its sums two searches.
//
// In order:
// 1. physics, untimed: every variant from the same start; its forces after
//    one step against the one-sum model's (same terms, other order: ~1e-15
//    relative) and against hand-written ones (a plain cell list here, not
//    partc), and its total energy after 10 steps against the one-sum
//    model's; then 100 steps of the one-sum model with energies every 10
//    steps computed by the hand-written code, beside LAMMPS's thermo.
// 2. timing: every variant, `repetitions` runs of the 100 steps from the same
//    start, one thread (OMP_NUM_THREADS=1 from .ci/bench), median loop time;
//    the variants take turns, run by run, so that a load that comes and goes
//    on a shared machine falls on all of them alike. With the model's
//    search_report() after the run: list sets or searches, their structure
//    and builds.
// The LAMMPS runs (optional) start from the very same state: bench_compose
// --lammps-data FILE writes it as a LAMMPS data file, .ci/bench runs lmp on
// it, and the logs (arguments) are matched to their pair style by the
// pair_style line they echo. Their neighbour settings are partc's: neighbor
// 0.3 bin, neigh_modify every 1 delay 0 check yes; thermo every 10 steps
// (energies on those steps only; partc computes none).
//
// Usage: bench_compose --lammps-data FILE
//        bench_compose [LAMMPS_LOG]...
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "compose_coulomb_lists.hpp"
#include "compose_fused_cells.hpp"
#include "compose_fused_lists.hpp"
#include "compose_lj_lists.hpp"
#include "compose_one_sum_lists.hpp"
#include "compose_separate_cells.hpp"
#include "compose_separate_lists.hpp"
#include "compose_separate_lists_unfused.hpp"
#include "compose_separate_one_radius_cells.hpp"
#include "compose_separate_one_radius_lists.hpp"
#include "lammps_log.hpp"
#include "lj_melt_setup.hpp"
#include "timing.hpp"

namespace {

using lj_melt_bench::Vec3;

constexpr double charge = 0.2;
constexpr double rc_lj = 2.5;
constexpr double coulomb_cutoffs[] = {2.5, 3.0};
constexpr int steps = lj_melt_bench::steps;
constexpr int repetitions = 3;
constexpr int thermo_every = 10;
// Composed against separate: the same pair terms, added in another order.
constexpr double same_physics_tolerance = 1e-12;
// Against the hand-written forces: s = 1/r^2 powers against r^-6 ones too.
constexpr double reference_tolerance = 1e-10;

enum class Physics { both, lj, coulomb };

// The system at one moment, by id: what the models load and what the checks compare.
struct State {
  std::vector<Vec3> position, velocity, f_lj, f_coulomb;
  std::vector<double> q;
  double e_lj = 0.0, e_coulomb = 0.0, kinetic = 0.0;

  std::size_t size() const { return position.size(); }
  double potential() const { return e_lj + e_coulomb; }
  double temperature() const { return 2.0 * kinetic / (3.0 * static_cast<double>(size()) - 3.0); }
  Vec3 force(std::size_t i, Physics physics) const {
    Vec3 f{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      f[k] = (physics != Physics::coulomb ? f_lj[i][k] : 0.0) +
             (physics != Physics::lj ? f_coulomb[i][k] : 0.0);
    return f;
  }
};

// Hand-written forces and energies: LJ truncated at rc_lj (lj/cut) and
// Coulomb truncated at rc_coul (coul/cut), each pair from both sides, through
// lj_melt_setup.hpp's cell list at the larger cutoff. Plain: it runs a few
// times, not per step.
void compute_forces(State& s, double rc_coul) {
  s.f_lj.assign(s.size(), Vec3{0, 0, 0});
  s.f_coulomb.assign(s.size(), Vec3{0, 0, 0});
  double e_lj = 0.0, e_coulomb = 0.0;  // every pair twice
  const auto add = [&](std::size_t i, std::size_t j, const Vec3& d, double r2) {
    if (r2 < rc_lj * rc_lj) {
      const lj_melt_bench::LjTerm lj = lj_melt_bench::lj_term(r2);
      e_lj += lj.energy;
      for (int k = 0; k < 3; ++k) s.f_lj[i][k] -= lj.f_over_r * d[k];
    }
    if (r2 < rc_coul * rc_coul) {
      const double r = std::sqrt(r2);
      e_coulomb += s.q[i] * s.q[j] / r;
      const double f_over_r = s.q[i] * s.q[j] / (r2 * r);
      for (int k = 0; k < 3; ++k) s.f_coulomb[i][k] -= f_over_r * d[k];
    }
  };
  lj_melt_bench::for_each_pair_within(s.position, std::max(rc_lj, rc_coul), add);
  s.e_lj = 0.5 * e_lj;
  s.e_coulomb = 0.5 * e_coulomb;
  double twice = 0.0;
  for (const Vec3& v : s.velocity) twice += v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  s.kinetic = 0.5 * twice;
}

// bench_lj's start (lattice, velocities at T = 3) with the charges, forces computed.
State start_state(double rc_coul) {
  const lj_melt_bench::MeltState melt = lj_melt_bench::melt_start();
  State s;
  s.position = melt.position;
  s.velocity = melt.velocity;
  for (std::size_t i = 0; i < s.size(); ++i) s.q.push_back(i % 2 == 0 ? charge : -charge);
  compute_forces(s, rc_coul);
  return s;
}

// The separate model keeps two force variables, the others one.
template <class Model, class = void>
struct SplitForce : std::false_type {};
template <class Model>
struct SplitForce<Model, std::void_t<typename Model::A_f_lj>> : std::true_type {};

// One model through the calls bench_compose makes, whichever model it is.
class Run {
 public:
  virtual ~Run() = default;
  virtual void step() = 0;
  // Positions, velocities, charges and the model's own force (for `physics`) by id.
  virtual State state(std::vector<Vec3>& model_force) const = 0;
  virtual std::vector<partc::SearchReport> search_report() const = 0;
};

template <class Model>
class ModelRun final : public Run {
 public:
  ModelRun(const State& s, Physics physics, double rc_coul) {
    model_.params().rc_lj = rc_lj;
    model_.params().rc_coul = rc_coul;
    partc::CsvTable table;
    table.header = {"id", "p_0", "p_1", "p_2", "v_0", "v_1", "v_2", "q"};
    for (const char* f : SplitForce<Model>::value ? std::vector<const char*>{"f_lj", "f_coulomb"}
                                                  : std::vector<const char*>{"f"})
      for (const char* k : {"_0", "_1", "_2"}) table.header.push_back(std::string(f) + k);
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Vec3 &p = s.position[i], &v = s.velocity[i];
      std::vector<double> row = {
          static_cast<double>(i), p[0], p[1], p[2], v[0], v[1], v[2], s.q[i]};
      const auto put = [&row](const Vec3& f) { row.insert(row.end(), f.begin(), f.end()); };
      if constexpr (SplitForce<Model>::value) {
        put(s.f_lj[i]);
        put(s.f_coulomb[i]);
      } else {
        put(s.force(i, physics));
      }
      table.rows.push_back(std::move(row));
    }
    model_.load({{"A", table}});
  }

  void step() override { model_.step(); }

  State state(std::vector<Vec3>& model_force) const override {
    const auto& set = model_.A();
    const auto& v = set.template get<typename Model::A_v>();
    const auto& q = set.template get<typename Model::A_q>();
    State s;
    s.position.resize(set.size());
    s.velocity.resize(set.size());
    s.q.resize(set.size());
    model_force.resize(set.size());
    for (std::size_t k = 0; k < set.size(); ++k) {
      const auto i = static_cast<std::size_t>(set.ids()[k]);
      const auto& p = set.positions()[k];
      s.position[i] = {p[0], p[1], p[2]};
      s.velocity[i] = {v[k][0], v[k][1], v[k][2]};
      s.q[i] = q[k];
      if constexpr (SplitForce<Model>::value) {
        const auto& a = set.template get<typename Model::A_f_lj>();
        const auto& b = set.template get<typename Model::A_f_coulomb>();
        model_force[i] = {a[k][0] + b[k][0], a[k][1] + b[k][1], a[k][2] + b[k][2]};
      } else {
        const auto& f = set.template get<typename Model::A_f>();
        model_force[i] = {f[k][0], f[k][1], f[k][2]};
      }
    }
    return s;
  }

  std::vector<partc::SearchReport> search_report() const override { return model_.search_report(); }

 private:
  Model model_;
};

// Pair walks a step, as search_report() counted them over the run.
std::string fmt_walks(double per_step) {
  char text[32];
  std::snprintf(text, sizeof text, per_step == std::round(per_step) ? "%.0f" : "%.2f", per_step);
  return text;
}

struct Variant {
  const char* name;
  Physics physics;
  bool two_radii_only;  // the same as another variant when the cutoffs are equal
  std::function<std::unique_ptr<Run>(const State&, double)> make;
};

template <class Model>
Variant variant(const char* name, Physics physics, bool two_radii_only = false) {
  return {name, physics, two_radii_only, [physics](const State& s, double rc_coul) {
            return std::unique_ptr<Run>(new ModelRun<Model>(s, physics, rc_coul));
          }};
}

const std::vector<Variant>& variants() {
  static const std::vector<Variant> all = {
      variant<ComposeOneSumLists>("partc one sum, lists", Physics::both),
      variant<ComposeFusedLists>("partc fused, lists", Physics::both),
      variant<ComposeSeparateLists>("partc separate, lists", Physics::both),
      variant<ComposeSeparateListsUnfused>("partc separate --no-fuse, lists", Physics::both),
      variant<ComposeLjLists>("partc LJ alone, lists", Physics::lj),
      variant<ComposeCoulombLists>("partc Coulomb alone, lists", Physics::coulomb),
      variant<ComposeFusedCells>("partc fused, cells", Physics::both),
      variant<ComposeSeparateCells>("partc separate, cells", Physics::both),
      variant<ComposeSeparateOneRadiusLists>("partc one radius, lists", Physics::both, true),
      variant<ComposeSeparateOneRadiusCells>("partc one radius, cells", Physics::both, true),
  };
  return all;
}

// The variants worth running at a Coulomb cutoff.
std::vector<const Variant*> variants_at(double rc_coul) {
  std::vector<const Variant*> chosen;
  for (const Variant& v : variants())
    if (!v.two_radii_only || rc_coul != rc_lj) chosen.push_back(&v);
  return chosen;
}

// max_i |a_i - b_i| / max_i |b_i|
double relative_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::hypot(a[i][0] - b[i][0], a[i][1] - b[i][1], a[i][2] - b[i][2]));
    scale = std::max(scale, std::hypot(b[i][0], b[i][1], b[i][2]));
  }
  return worst / scale;
}

std::vector<Vec3> reference_force(const State& s, Physics physics) {
  std::vector<Vec3> f(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) f[i] = s.force(i, physics);
  return f;
}

// Thermo rows, LAMMPS's and partc's (computed here) alike: E_vdwl is LJ, E_coul Coulomb.
using bench::Thermo;

Thermo thermo_of(int step, const State& s) {
  const double n = static_cast<double>(s.size());
  return {step,       s.temperature(), s.potential() / n,
          s.e_lj / n, s.e_coulomb / n, (s.kinetic + s.potential()) / n};
}

struct Timed {
  double loop_seconds = 0.0, first_step_seconds = 0.0;
  std::vector<partc::SearchReport> searches;
};

Timed time_run(const Variant& v, const State& start, double rc_coul) {
  const std::unique_ptr<Run> run = v.make(start, rc_coul);
  Timed t;
  for (int step = 1; step <= steps; ++step) {
    const double seconds = bench::seconds([&] { run->step(); });
    t.loop_seconds += seconds;
    if (step == 1) t.first_step_seconds = seconds;
  }
  t.searches = run->search_report();
  return t;
}

std::vector<std::string> words_of(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// Two pair_style argument lists alike, numbers compared as numbers ("3" and "3.0").
bool same_style(const std::string& a, const std::string& b) {
  const std::vector<std::string> x = words_of(a), y = words_of(b);
  if (x.size() != y.size()) return false;
  for (std::size_t k = 0; k < x.size(); ++k) {
    char *end_x = nullptr, *end_y = nullptr;
    const double u = std::strtod(x[k].c_str(), &end_x), w = std::strtod(y[k].c_str(), &end_y);
    const bool numbers = *end_x == '\0' && *end_y == '\0' && !x[k].empty() && !y[k].empty();
    if (numbers ? u != w : x[k] != y[k]) return false;
  }
  return true;
}

// The logs of one pair style.
struct LammpsStyle {
  bench::LammpsLog first;
  std::vector<double> loop_seconds;
};

// The LAMMPS pair styles of one Coulomb cutoff, as .ci/bench writes them.
struct LammpsRow {
  std::string label, pair_style;
};

std::vector<LammpsRow> lammps_rows(double rc_coul) {
  char combined[64], overlay[96], coulomb[64], lj[64];
  std::snprintf(combined, sizeof combined, "lj/cut/coul/cut %g %g", rc_lj, rc_coul);
  std::snprintf(overlay, sizeof overlay, "hybrid/overlay lj/cut %g coul/cut %g", rc_lj, rc_coul);
  std::snprintf(coulomb, sizeof coulomb, "coul/cut %g", rc_coul);
  std::snprintf(lj, sizeof lj, "lj/cut %g", rc_lj);
  return {{"LAMMPS lj/cut/coul/cut", combined},
          {"LAMMPS hybrid/overlay", overlay},
          {"LAMMPS lj/cut alone", lj},
          {"LAMMPS coul/cut alone", coulomb}};
}

// The starting state as a LAMMPS data file (atom_style charge), ids 1..N in id order.
int write_lammps_data(const char* path) {
  const State s = start_state(coulomb_cutoffs[0]);
  std::FILE* out = std::fopen(path, "w");
  if (!out) {
    std::fprintf(stderr, "bench_compose: cannot write %s\n", path);
    return 2;
  }
  const double L = lj_melt_bench::box_length();
  std::fprintf(out,
               "bench_compose: LJ melt with charges +-%g (atom_style charge)\n\n%zu atoms\n"
               "1 atom types\n\n0 %.17g xlo xhi\n0 %.17g ylo yhi\n0 %.17g zlo zhi\n\n"
               "Masses\n\n1 1.0\n\nAtoms # charge\n\n",
               charge, s.size(), L, L, L);
  for (std::size_t i = 0; i < s.size(); ++i)
    std::fprintf(out, "%zu 1 %.17g %.17g %.17g %.17g\n", i + 1, s.q[i], s.position[i][0],
                 s.position[i][1], s.position[i][2]);
  std::fprintf(out, "\nVelocities\n\n");
  for (std::size_t i = 0; i < s.size(); ++i)
    std::fprintf(out, "%zu %.17g %.17g %.17g\n", i + 1, s.velocity[i][0], s.velocity[i][1],
                 s.velocity[i][2]);
  return std::fclose(out) == 0 ? 0 : 2;
}

std::string cell(const char* format, double value) {
  if (std::isnan(value)) return "-";
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

void physics_check(const State& start, double rc_coul) {
  std::printf(
      "\nEach variant from the start: its forces after one step, max |f - g| / max |g|, against\n"
      "the one-sum model's and the hand-written ones at its positions; its total energy\n"
      "(hand-written) after %d steps against the one-sum model's, relative\n",
      thermo_every);
  std::printf("%-32s %16s %18s %18s\n", "", "f vs one sum", "f vs hand-written",
              "E_tot vs one sum");
  std::vector<Vec3> one_sum_force;
  double one_sum_energy = 0.0;
  for (const Variant* chosen : variants_at(rc_coul)) {
    const Variant& v = *chosen;
    const std::unique_ptr<Run> run = v.make(start, rc_coul);
    run->step();
    std::vector<Vec3> force;
    State now = run->state(force);
    compute_forces(now, rc_coul);
    const double reference = relative_difference(force, reference_force(now, v.physics));
    for (int step = 2; step <= thermo_every; ++step) run->step();
    std::vector<Vec3> unused;
    State later = run->state(unused);
    compute_forces(later, rc_coul);
    const double energy = later.kinetic + later.potential();
    if (one_sum_force.empty()) {  // the first variant: the one-sum model
      one_sum_force = force;
      one_sum_energy = energy;
    }
    const bool both = v.physics == Physics::both;
    const double same_force = both ? relative_difference(force, one_sum_force) : std::nan("");
    const double same_energy =
        both ? std::abs(energy - one_sum_energy) / std::abs(one_sum_energy) : std::nan("");
    std::printf("%-32s %16s %18s %18s\n", v.name, cell("%.2e", same_force).c_str(),
                cell("%.2e", reference).c_str(), cell("%.2e", same_energy).c_str());
    if (!(reference <= reference_tolerance) || (both && !(same_force <= same_physics_tolerance &&
                                                          same_energy <= same_physics_tolerance))) {
      std::fprintf(stderr,
                   "bench_compose: %s disagrees (tolerance %g against the one-sum model, %g "
                   "against the hand-written forces)\n",
                   v.name, same_physics_tolerance, reference_tolerance);
      std::exit(1);
    }
  }
}

// 100 steps of one variant, untimed, with thermo by the hand-written code.
std::vector<Thermo> thermo_run(const Variant& v, const State& start, double rc_coul) {
  const std::unique_ptr<Run> run = v.make(start, rc_coul);
  std::vector<Thermo> thermo = {thermo_of(0, start)};
  for (int step = 1; step <= steps; ++step) {
    run->step();
    if (step % thermo_every) continue;
    std::vector<Vec3> force;
    State now = run->state(force);
    compute_forces(now, rc_coul);
    thermo.push_back(thermo_of(step, now));
  }
  return thermo;
}

void cutoff_section(double rc_coul, const std::vector<LammpsStyle>& lammps) {
  std::printf("\n==== LJ cutoff %g, Coulomb cutoff %g\n", rc_lj, rc_coul);
  const State start = start_state(rc_coul);
  physics_check(start, rc_coul);

  struct Row {
    std::string name;
    double per_step_ms, without_first_ms;
    std::string walks, structures, builds;
  };
  std::vector<Row> rows;
  std::map<std::string, double> per_step;  // ms, by variant name or LAMMPS label
  const std::vector<const Variant*> chosen = variants_at(rc_coul);
  std::vector<std::vector<Timed>> runs(chosen.size());
  for (int r = 0; r < repetitions; ++r)
    for (std::size_t k = 0; k < chosen.size(); ++k)
      runs[k].push_back(time_run(*chosen[k], start, rc_coul));
  std::vector<std::string> structures;  // of the median runs, for the list below the table
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const Variant& v = *chosen[k];
    std::sort(runs[k].begin(), runs[k].end(),
              [](const Timed& a, const Timed& b) { return a.loop_seconds < b.loop_seconds; });
    const Timed& t = runs[k][runs[k].size() / 2];
    for (const partc::SearchReport& s : t.searches)
      structures.push_back(std::string(v.name) + ": " + s.serves + ": " + s.structure + ", " +
                           std::to_string(s.builds) + " builds");
    std::size_t builds = 0, walks = 0;
    for (const partc::SearchReport& s : t.searches) {
      builds += s.builds;
      walks += s.walks;
    }
    rows.push_back({v.name, 1e3 * t.loop_seconds / steps,
                    1e3 * (t.loop_seconds - t.first_step_seconds) / (steps - 1),
                    fmt_walks(static_cast<double>(walks) / steps),
                    std::to_string(t.searches.size()),
                    std::to_string(builds)});
    per_step[v.name] = rows.back().per_step_ms;
  }
  for (const LammpsRow& l : lammps_rows(rc_coul)) {
    const auto style = std::find_if(lammps.begin(), lammps.end(), [&](const LammpsStyle& s) {
      return same_style(s.first.pair_style, l.pair_style);
    });
    if (style == lammps.end()) continue;
    const double ms = 1e3 * bench::median(style->loop_seconds) / steps;
    per_step[l.label] = ms;
    rows.push_back({l.label + " (" + std::to_string(style->loop_seconds.size()) + " runs)", ms,
                    std::nan(""), l.label == "LAMMPS hybrid/overlay" ? "2" : "1", "-",
                    std::to_string(style->first.builds)});
  }

  std::printf(
      "\nTime per step, median of %d runs of %d steps (LAMMPS: its loop time); walks: pair\n"
      "walks a step (search_report()'s count); structures: its entries (sets of Verlet\n"
      "lists, or searches); builds: theirs in the %d steps (LAMMPS: neighbour list builds)\n",
      repetitions, steps, steps);
  std::printf("%-36s %10s %14s %6s %11s %7s\n", "", "ms/step", "ms, steps 2-", "walks",
              "structures", "builds");
  for (const Row& r : rows)
    std::printf("%-36s %10s %14s %6s %11s %7s\n", r.name.c_str(),
                cell("%.2f", r.per_step_ms).c_str(), cell("%.2f", r.without_first_ms).c_str(),
                r.walks.c_str(), r.structures.c_str(), r.builds.c_str());
  const auto ms = [&](const char* name) {
    const auto it = per_step.find(name);
    return it == per_step.end() ? std::nan("") : it->second;
  };
  const auto ratio = [&](const char* a, const char* b) { return cell("%.2f", ms(a) / ms(b)); };
  std::printf("\nsearch_report() of the median runs:\n");
  for (const std::string& s : structures) std::printf("  %s\n", s.c_str());

  std::printf(
      "\npartc composed / two walks (separate, --no-fuse), lists: one sum %s, fused %s, separate "
      "%s (issue 10's target: <= 0.65)\n",
      ratio("partc one sum, lists", "partc separate --no-fuse, lists").c_str(),
      ratio("partc fused, lists", "partc separate --no-fuse, lists").c_str(),
      ratio("partc separate, lists", "partc separate --no-fuse, lists").c_str());
  std::printf("partc composed / separate, lists: one sum %s, fused %s\n",
              ratio("partc one sum, lists", "partc separate, lists").c_str(),
              ratio("partc fused, lists", "partc separate, lists").c_str());
  std::printf("partc composed / separate, cells: fused %s\n",
              ratio("partc fused, cells", "partc separate, cells").c_str());
  if (rc_coul != rc_lj)
    std::printf("partc composed / one radius: lists, one sum %s, fused %s; cells, fused %s\n",
                ratio("partc one sum, lists", "partc one radius, lists").c_str(),
                ratio("partc fused, lists", "partc one radius, lists").c_str(),
                ratio("partc fused, cells", "partc one radius, cells").c_str());
  std::printf("partc composed / (LJ alone + Coulomb alone), lists: one sum %s\n",
              cell("%.2f", ms("partc one sum, lists") /
                               (ms("partc LJ alone, lists") + ms("partc Coulomb alone, lists")))
                  .c_str());
  std::printf("LAMMPS hybrid/overlay / lj/cut/coul/cut %s; lj/cut/coul/cut / hybrid/overlay %s\n",
              ratio("LAMMPS hybrid/overlay", "LAMMPS lj/cut/coul/cut").c_str(),
              ratio("LAMMPS lj/cut/coul/cut", "LAMMPS hybrid/overlay").c_str());
  std::printf("partc one sum, lists / LAMMPS lj/cut/coul/cut %s\n",
              ratio("partc one sum, lists", "LAMMPS lj/cut/coul/cut").c_str());

  // Energies: partc's by the hand-written code, LAMMPS's own thermo, same start.
  const std::vector<Thermo> ours = thermo_run(variants().front(), start, rc_coul);
  const auto theirs = std::find_if(lammps.begin(), lammps.end(), [&](const LammpsStyle& s) {
    return same_style(s.first.pair_style, lammps_rows(rc_coul).front().pair_style);
  });
  std::printf(
      "\nEnergies per atom, partc one sum with lists (computed here, by the hand-written code)%s\n",
      theirs == lammps.end() ? "" : " beside LAMMPS lj/cut/coul/cut (its thermo)");
  std::printf("%5s %10s %16s %16s %18s %18s %10s\n", "step", "T", "E_lj", "E_coulomb", "E_tot",
              "LAMMPS E_tot", "diff");
  for (const Thermo& t : ours) {
    const Thermo* l =
        theirs == lammps.end() ? nullptr : bench::at_step(theirs->first.thermo, t.step);
    std::printf("%5d %10.6f %16.10f %16.10f %18.12f %18s %10s\n", t.step, t.temperature, t.e_vdwl,
                t.e_coul, t.total, l ? cell("%.12f", l->total).c_str() : "-",
                l ? cell("%+.1e", t.total - l->total).c_str() : "-");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "--lammps-data") == 0) return write_lammps_data(argv[2]);
  std::vector<LammpsStyle> lammps;
  for (int a = 1; a < argc; ++a) {
    const std::optional<bench::LammpsLog> log = bench::read_lammps_log(argv[a]);
    if (!log || log->pair_style.empty()) {
      std::fprintf(stderr,
                   "bench_compose: %s: not a LAMMPS log with a pair_style, a thermo table and a "
                   "loop time\n",
                   argv[a]);
      return 2;
    }
    auto same = std::find_if(lammps.begin(), lammps.end(), [&](const LammpsStyle& s) {
      return same_style(s.first.pair_style, log->pair_style);
    });
    if (same == lammps.end()) same = lammps.insert(lammps.end(), {*log, {}});
    same->loop_seconds.push_back(log->loop_seconds);
  }
  std::printf(
      "LJ + Coulomb on the LJ melt: %zu atoms, fcc at density %g, T %g, charges +-%g alternating\n"
      "by id, dt 0.005, %d steps, one thread. Compiler: %s\n",
      lj_melt_bench::atom_count, lj_melt_bench::density, lj_melt_bench::initial_temperature, charge,
      steps, __VERSION__);
  if (lammps.empty()) std::printf("(no LAMMPS logs given: no LAMMPS rows)\n");
  for (const double rc_coul : coulomb_cutoffs) cutoff_section(rc_coul, lammps);
  return 0;
}

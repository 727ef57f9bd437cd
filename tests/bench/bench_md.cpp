// bench_md: the molecular-dynamics benchmark of the Aboria paper (Robinson &
// Bruna, 2017), timing the velocity update
//
//   v[i] += c * sum(j, |dx| < rc and |dx| > 0, -exp(-|dx|) * dx / |dx|)
//
// of N uniform random particles in the periodic unit square, c = 1e-3, as
// compiled by partc (md_velocity.part.in) and as written by hand below, in one
// run, on identical positions, with identical compiler flags (one translation
// unit). As in the paper, positions do not move and the neighbour structure is
// built before timing starts; Te is the mean time of one update over a batch
// of floor(1000/N)+1 updates. Two cutoffs:
//   rc = sqrt(3/N)    about 3*pi neighbours per particle whatever N: N/Te flat;
//   rc = sqrt(3/500)  the neighbour count grows with N: N/Te falls like 1/N.
// The force is odd in dx, so partc takes each pair once (Newton's third law:
// j gets the opposite of i's term). Te_hand is the paper's kernel, a sum per
// particle over its neighbours; Te_pairs the same hand-written cell list
// taking each pair once, for a like-for-like ratio. A last column times the
// hand-written O(N^2) loop over all pairs, for small N only, to show where
// brute force beats a cell list.
//
// Then, against the strongest hand-written kernels: the project owner's
// hand-vectorised ones (floor/floor_kernels.hpp, from shared/floor), a sum
// per particle each, on the same positions, taking turns with the others:
// compact_simd (the cell grid, an AVX2 filter packing the real neighbours,
// then packed arithmetic) and sell4 (a precomputed SELL-4 neighbour list,
// pure pair arithmetic: the floor). Their structures are built before timing,
// as the floor does. They are compiled with the floor's flags (-march=native),
// and only where that gives AVX2. Beside them, partc's update with Verlet
// lists of skin 0 (md_velocity_lists: half lists at the cutoff, built by its
// first step), the like of sell4's precomputed list.
//
// Usage: bench_md [--max-n N]   (sizes up to N only, for a quick check; the
// default, the full run, is what .ci/bench runs)
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "timing.hpp"
#include "md_velocity.hpp"
#include "md_velocity_lists.hpp"
#ifdef PARTC_BENCH_FLOOR
#include "floor_kernels.hpp"
#endif

namespace {

constexpr double force_strength = 1e-3;  // c
constexpr double box = 1.0;              // side of the periodic square [0, 1)^2

// A batch is timed this many times and the median kept: unlike the mean it
// ignores the odd interruption by the operating system.
constexpr int repetitions = 5;
// The O(N^2) kernel takes seconds beyond this size and has long lost by then.
constexpr std::size_t brute_force_max_n = 2000;
// A (size, cutoff) whose measurement is estimated to take longer is skipped.
constexpr double seconds_per_size_budget = 60.0;
// Two kernels summing the same terms in a different order agree to rounding,
// about 1e-16 times the number of neighbours; a missed or extra pair would
// change v by a whole term, about the size of v itself.
// The floor's kernels use a hand-written exp (about 1 ulp), a rounding's
// worth per term more: they agree to 1.1e-14 at worst (N <= 2e4), as partc
// does (1e-14).
constexpr double agreement_tolerance = 1e-12;

using Vec2 = std::array<double, 2>;

// Structure of arrays, as the kernels want them.
struct Positions {
  std::vector<double> x, y;
  std::size_t size() const { return x.size(); }
};

Positions uniform_positions(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  // The top 53 bits of a 64-bit draw: uniform doubles in [0, 1), never 1.
  const auto uniform = [&random] { return static_cast<double>(random() >> 11) * 0x1p-53; };
  Positions p;
  p.x.resize(n);
  p.y.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.x[i] = box * uniform();
    p.y[i] = box * uniform();
  }
  return p;
}

// The seed's pair force -exp(-r) dx / r for 0 < r < rc, added to (fx, fy):
// the hand-written kernels share it, as a hand-writer would. With (gx, gy),
// each pair once (Newton's third law): j gets the opposite force.
inline void add_pair_force(double dx, double dy, double r2, double rc2, double& fx, double& fy) {
  if (r2 < rc2 && r2 > 0.0) {
    const double r = std::sqrt(r2);
    const double s = -std::exp(-r) / r;
    fx += s * dx;
    fy += s * dy;
  }
}
inline void add_pair_force(double dx, double dy, double r2, double rc2, double& fx, double& fy,
                           double& gx, double& gy) {
  if (r2 < rc2 && r2 > 0.0) {
    const double r = std::sqrt(r2);
    const double s = -std::exp(-r) / r;
    fx += s * dx;
    fy += s * dy;
    gx -= s * dx;
    gy -= s * dy;
  }
}

// The hand-written kernel with a cell list: square cells at least rc wide,
// particles stored sorted by cell (a counting sort), so that a cell is one
// contiguous range and the neighbours of a particle lie in its own cell and
// the 8 around it. A neighbour cell across the box edge is the cell on the far
// side, its particles seen shifted by one box length. The 3x3 stencil needs
// at least 3 cells per side, or one cell would be visited twice.
class HandCellList {
 public:
  static std::size_t cells_per_side(double rc) { return static_cast<std::size_t>(box / rc); }
  static bool applicable(double rc) { return cells_per_side(rc) >= 3; }

  HandCellList(const Positions& input, double rc, double c)
      : n_side_(cells_per_side(rc)), rc2_(rc * rc), c_(c) {
    const std::size_t n = input.size();
    std::vector<std::size_t> cell(n);
    cell_start_.assign(n_side_ * n_side_ + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      cell[i] = cell_of(input.x[i], input.y[i]);
      ++cell_start_[cell[i] + 1];
    }
    for (std::size_t k = 1; k < cell_start_.size(); ++k) cell_start_[k] += cell_start_[k - 1];
    std::vector<std::size_t> next(cell_start_.begin(), cell_start_.end() - 1);
    x_.resize(n);
    y_.resize(n);
    input_index_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t k = next[cell[i]]++;
      x_[k] = input.x[i];
      y_[k] = input.y[i];
      input_index_[k] = i;
    }
    vx_.assign(n, 0.0);
    vy_.assign(n, 0.0);
  }

  void update_velocities() {
    const double rc2 = rc2_, c = c_;
    for_each_particle([&](std::size_t i, const Stencil& around) {
      double fx = 0.0, fy = 0.0;
      for (const NeighbourCell& nc : around) {
        // Shifting particle i once per cell, not every neighbour.
        const double xi = x_[i] - nc.shift_x, yi = y_[i] - nc.shift_y;
        for (std::size_t j = nc.first; j < nc.last; ++j) {
          const double dx = x_[j] - xi, dy = y_[j] - yi;
          const double r2 = dx * dx + dy * dy;
          add_pair_force(dx, dy, r2, rc2, fx, fy);
        }
      }
      vx_[i] += c * fx;
      vy_[i] += c * fy;
    });
  }

  // The same, each pair once (Newton's third law): a cell meets its own pairs
  // j > i and the 4 cells after it in the stencil (the other 4 meet it from
  // their side); the force goes to i, and its opposite to j.
  void update_velocities_pairs() {
    const double rc2 = rc2_, c = c_;
    fx_.assign(x_.size(), 0.0);
    fy_.assign(x_.size(), 0.0);
    for_each_particle([&](std::size_t i, const Stencil& around) {
      double fx = 0.0, fy = 0.0;
      for (std::size_t k = own_cell; k < around.size(); ++k) {
        const NeighbourCell& nc = around[k];
        const double xi = x_[i] - nc.shift_x, yi = y_[i] - nc.shift_y;
        for (std::size_t j = k == own_cell ? i + 1 : nc.first; j < nc.last; ++j) {
          const double dx = x_[j] - xi, dy = y_[j] - yi;
          add_pair_force(dx, dy, dx * dx + dy * dy, rc2, fx, fy, fx_[j], fy_[j]);
        }
      }
      fx_[i] += fx;
      fy_[i] += fy;
    });
    for (std::size_t i = 0; i < x_.size(); ++i) {
      vx_[i] += c * fx_[i];
      vy_[i] += c * fy_[i];
    }
  }

  // Pairs (i, j) with 0 < |dx| < rc, divided by N.
  double mean_neighbours() const {
    std::size_t pairs = 0;
    for_each_particle([&](std::size_t i, const Stencil& around) {
      for (const NeighbourCell& nc : around)
        for (std::size_t j = nc.first; j < nc.last; ++j) {
          const double dx = x_[j] - (x_[i] - nc.shift_x), dy = y_[j] - (y_[i] - nc.shift_y);
          const double r2 = dx * dx + dy * dy;
          pairs += r2 < rc2_ && r2 > 0.0;
        }
    });
    return static_cast<double>(pairs) / static_cast<double>(x_.size());
  }

  // In the order of the input positions.
  std::vector<Vec2> velocities() const {
    std::vector<Vec2> v(vx_.size());
    for (std::size_t k = 0; k < v.size(); ++k) v[input_index_[k]] = {vx_[k], vy_[k]};
    return v;
  }

 private:
  struct NeighbourCell {
    std::size_t first, last;  // the cell's particles: first .. last-1
    double shift_x, shift_y;  // added to their coordinates: 0 or +-box
  };

  // Coordinates lie in [0, box); the min() guards x * n / box rounding up to n.
  std::size_t cell_of(double x, double y) const {
    const double scale = static_cast<double>(n_side_) / box;
    const auto cx = std::min(static_cast<std::size_t>(x * scale), n_side_ - 1);
    const auto cy = std::min(static_cast<std::size_t>(y * scale), n_side_ - 1);
    return cy * n_side_ + cx;
  }

  // neighbour_cells' stencil, rows y - 1, y, y + 1: the cell itself is the 5th.
  using Stencil = std::array<NeighbourCell, 9>;
  static constexpr std::size_t own_cell = 4;

  // f(i, stencil of i's cell) for every particle i, cell by cell.
  template <class F>
  void for_each_particle(F&& f) const {
    for (std::size_t cy = 0; cy < n_side_; ++cy)
      for (std::size_t cx = 0; cx < n_side_; ++cx) {
        const Stencil around = neighbour_cells(cx, cy);
        const std::size_t cell = cy * n_side_ + cx;
        for (std::size_t i = cell_start_[cell]; i < cell_start_[cell + 1]; ++i) f(i, around);
      }
  }

  Stencil neighbour_cells(std::size_t cx, std::size_t cy) const {
    // Cell c + offset along one axis, wrapped, and the shift its particles need.
    const auto wrapped = [n = n_side_](std::size_t c, int offset) -> std::pair<std::size_t, double> {
      if (offset < 0 && c == 0) return {n - 1, -box};
      if (offset > 0 && c == n - 1) return {0, box};
      return {c + offset, 0.0};
    };
    Stencil around;
    std::size_t k = 0;
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        const auto [nx, shift_x] = wrapped(cx, ox);
        const auto [ny, shift_y] = wrapped(cy, oy);
        const std::size_t cell = ny * n_side_ + nx;
        around[k++] = {cell_start_[cell], cell_start_[cell + 1], shift_x, shift_y};
      }
    return around;
  }

  std::size_t n_side_;
  double rc2_, c_;
  std::vector<std::size_t> cell_start_;  // cell k holds particles cell_start_[k] .. cell_start_[k+1]-1
  std::vector<double> x_, y_, vx_, vy_;  // sorted by cell
  std::vector<double> fx_, fy_;          // update_velocities_pairs: the forces
  std::vector<std::size_t> input_index_;  // particle k of the sorted order is input particle input_index_[k]
};

// The hand-written O(N^2) kernel: every pair, with the minimum image.
class HandBruteForce {
 public:
  HandBruteForce(const Positions& input, double rc, double c)
      : x_(input.x), y_(input.y), vx_(input.size(), 0.0), vy_(input.size(), 0.0),
        rc2_(rc * rc), c_(c), images_(rc >= 0.5 * box) {}

  void update_velocities() {
    if (images_) return update_velocities_with_images();
    const double rc2 = rc2_, c = c_;
    const std::size_t n = x_.size();
    for (std::size_t i = 0; i < n; ++i) {
      const double xi = x_[i], yi = y_[i];
      double fx = 0.0, fy = 0.0;
      for (std::size_t j = 0; j < n; ++j) {
        double dx = x_[j] - xi, dy = y_[j] - yi;
        // Coordinates lie in [0, box), so one shift gives the minimum image;
        // arithmetic rather than a branch, which would be mispredicted half the time.
        dx -= box * ((dx > 0.5 * box) - (dx < -0.5 * box));
        dy -= box * ((dy > 0.5 * box) - (dy < -0.5 * box));
        const double r2 = dx * dx + dy * dy;
        add_pair_force(dx, dy, r2, rc2, fx, fy);
      }
      vx_[i] += c * fx;
      vy_[i] += c * fy;
    }
  }

  // rc >= box/2 (N <= 12 with rc = sqrt(3/N)): a particle can feel two images of
  // another along an axis, and itself across the box; the differences of
  // coordinates in [0, box) lie in (-box, box), so the shifts -box, 0, box
  // give every image within rc < box.
  void update_velocities_with_images() {
    const double rc2 = rc2_, c = c_;
    const std::size_t n = x_.size();
    for (std::size_t i = 0; i < n; ++i) {
      double fx = 0.0, fy = 0.0;
      for (std::size_t j = 0; j < n; ++j)
        for (int sx = -1; sx <= 1; ++sx)
          for (int sy = -1; sy <= 1; ++sy) {
            const double dx = x_[j] - x_[i] + sx * box, dy = y_[j] - y_[i] + sy * box;
            add_pair_force(dx, dy, dx * dx + dy * dy, rc2, fx, fy);
          }
      vx_[i] += c * fx;
      vy_[i] += c * fy;
    }
  }

  // The same, each pair once (Newton's third law): pairs j > i, the force to
  // i and its opposite to j. (i's own images lie a box length away, beyond rc.)
  void update_velocities_pairs() {
    const double rc2 = rc2_, c = c_;
    const std::size_t n = x_.size();
    fx_.assign(n, 0.0);
    fy_.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      double fx = 0.0, fy = 0.0;
      for (std::size_t j = i + 1; j < n; ++j) {
        if (images_) {
          for (int sx = -1; sx <= 1; ++sx)
            for (int sy = -1; sy <= 1; ++sy) {
              const double dx = x_[j] - x_[i] + sx * box, dy = y_[j] - y_[i] + sy * box;
              add_pair_force(dx, dy, dx * dx + dy * dy, rc2, fx, fy, fx_[j], fy_[j]);
            }
          continue;
        }
        double dx = x_[j] - x_[i], dy = y_[j] - y_[i];
        dx -= box * ((dx > 0.5 * box) - (dx < -0.5 * box));
        dy -= box * ((dy > 0.5 * box) - (dy < -0.5 * box));
        add_pair_force(dx, dy, dx * dx + dy * dy, rc2, fx, fy, fx_[j], fy_[j]);
      }
      vx_[i] += c * (fx + fx_[i]);
      vy_[i] += c * (fy + fy_[i]);
    }
  }

  // Pairs (i, j) with 0 < |dx| < rc, every image counted, divided by N.
  double mean_neighbours() const {
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < x_.size(); ++i)
      for (std::size_t j = 0; j < x_.size(); ++j)
        for (int sx = -1; sx <= 1; ++sx)
          for (int sy = -1; sy <= 1; ++sy) {
            const double dx = x_[j] - x_[i] + sx * box, dy = y_[j] - y_[i] + sy * box;
            const double r2 = dx * dx + dy * dy;
            pairs += r2 < rc2_ && r2 > 0.0;
          }
    return static_cast<double>(pairs) / static_cast<double>(x_.size());
  }

  std::vector<Vec2> velocities() const {
    std::vector<Vec2> v(vx_.size());
    for (std::size_t k = 0; k < v.size(); ++k) v[k] = {vx_[k], vy_[k]};
    return v;
  }

 private:
  std::vector<double> x_, y_, vx_, vy_;
  std::vector<double> fx_, fy_;  // update_velocities_pairs: forces from the j < i
  double rc2_, c_;
  bool images_;
};

// The partc model, its particles loaded from a table built in memory: ids
// 0..N-1 in input order, so results can be matched whatever order partc's
// cell list sorts the particles into.
template <class Model>
void load_positions(Model& model, const Positions& input, double rc) {
  model.params().N = static_cast<std::int64_t>(input.size());
  model.params().c = force_strength;
  model.params().rc = rc;
  partc::CsvTable table;
  table.header = {"id", "p_0", "p_1"};
  table.rows.reserve(input.size());
  for (std::size_t i = 0; i < input.size(); ++i)
    table.rows.push_back({static_cast<double>(i), input.x[i], input.y[i]});
  model.load({{"P", table}});
}

template <class Model>
std::vector<Vec2> velocities(const Model& model) {
  const auto& set = model.P();
  const auto& v = set.template get<typename Model::P_v>();
  std::vector<Vec2> by_id(set.size());
  for (std::size_t k = 0; k < set.size(); ++k)
    by_id[static_cast<std::size_t>(set.ids()[k])] = {v[k][0], v[k][1]};
  return by_id;
}

// max_i |a_i - b_i| / max_i |b_i|: relative to the scale of v, since single
// particles may have a v near zero from cancelling forces.
double relative_difference(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::hypot(a[i][0] - b[i][0], a[i][1] - b[i][1]));
    scale = std::max(scale, std::hypot(b[i][0], b[i][1]));
  }
  return worst == 0.0 ? 0.0 : worst / scale;
}

void require_agreement(const char* name, const std::vector<Vec2>& v, const char* reference_name,
                       const std::vector<Vec2>& reference, std::size_t n, double rc) {
  const double difference = relative_difference(v, reference);
  if (!(difference <= agreement_tolerance)) {
    std::fprintf(stderr,
                 "bench_md: N = %zu, rc = %.17g: the %s kernel's v differs from the %s kernel's "
                 "by %.3g relative (tolerance %g); timings would compare different work\n",
                 n, rc, name, reference_name, difference, agreement_tolerance);
    std::exit(1);
  }
}

// The paper's batch: floor(1000/N)+1 updates.
int batch_size(std::size_t n) { return static_cast<int>(1000 / n) + 1; }

template <class Update>
double seconds_per_update(Update&& update, int batch) {
  const auto start = std::chrono::steady_clock::now();
  for (int e = 0; e < batch; ++e) update();
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  return elapsed.count() / batch;
}

struct Cutoff {
  const char* description;
  double (*rc)(std::size_t n);
};

struct Row {
  double neighbours;
  double te_partc, te_hand, te_pairs, te_brute;  // te_brute < 0: not measured
  bool hand_is_brute_force;            // too few cells for the hand-written cell list
  double te_compact, te_sell4;         // the floor's kernels; < 0: not measured
  double te_lists;                     // partc with Verlet lists (skin 0); < 0: not measured
};

Row measure(std::size_t n, double rc) {
  const Positions positions = uniform_positions(n, 2017);
  MdVelocity partc_model;
  load_positions(partc_model, positions, rc);
  std::optional<HandCellList> cells;
  if (HandCellList::applicable(rc)) cells.emplace(positions, rc, force_strength);
  // Brute force: the third column, and the hand-written kernel where cells cannot be used.
  std::optional<HandBruteForce> brute;
  if (n <= brute_force_max_n || !cells) brute.emplace(positions, rc, force_strength);
  // The hand-written kernel taking each pair once, as partc does for this
  // force: with the cell list, or by brute force where cells cannot be used.
  std::optional<HandCellList> cell_pairs = cells;
  std::optional<HandBruteForce> brute_pairs;
  if (!cells) brute_pairs = brute;
  const auto update_pairs = [&] {
    if (cell_pairs)
      cell_pairs->update_velocities_pairs();
    else
      brute_pairs->update_velocities_pairs();
  };
#ifdef PARTC_BENCH_FLOOR
  // The floor's kernels need its cell grid (3 cells a side), and the SELL-4
  // list its memory guard.
  std::optional<floor_ref::VelocityUpdate> floor;
  const bool with_sell4 = floor_ref::VelocityUpdate::sell4_fits(static_cast<int>(n), rc);
  if (floor_ref::VelocityUpdate::applicable(rc))
    floor.emplace(positions.x.data(), positions.y.data(), static_cast<int>(n), rc,
                  force_strength, with_sell4);
  // partc's lists where sell4 has its list: beside it, within its memory guard.
  std::optional<MdVelocityLists> lists_model;
  if (floor && with_sell4) {
    lists_model.emplace();
    load_positions(*lists_model, positions, rc);
  }
#endif

  // One update each from v = 0, compared before anything is timed. partc's
  // first step() also builds its neighbour search, which the paper leaves out of Te.
  partc_model.step();
  if (cells) cells->update_velocities();
  if (brute) brute->update_velocities();
  update_pairs();
  const std::vector<Vec2> v_reference = cells ? cells->velocities() : brute->velocities();
  const char* reference_name = cells ? "hand-written cell list" : "hand-written brute force";
  require_agreement("partc", velocities(partc_model), reference_name, v_reference, n, rc);
  if (cells && brute)
    require_agreement("hand-written brute force", brute->velocities(), reference_name,
                      v_reference, n, rc);
  require_agreement("hand-written each-pair-once",
                    cell_pairs ? cell_pairs->velocities() : brute_pairs->velocities(),
                    reference_name, v_reference, n, rc);
#ifdef PARTC_BENCH_FLOOR
  if (floor) {
    floor->update_compact();
    require_agreement("floor compact_simd", floor->velocities_compact(), reference_name,
                      v_reference, n, rc);
    if (with_sell4) {
      floor->update_sell4();
      require_agreement("floor sell4", floor->velocities_sell4(), reference_name, v_reference,
                        n, rc);
    }
  }
  if (lists_model) {
    lists_model->step();
    require_agreement("partc with Verlet lists", velocities(*lists_model), reference_name,
                      v_reference, n, rc);
  }
#endif

  // The kernels take turns, so that a slow spell of the (shared) machine hits
  // them alike; each timed batch follows an untimed one of the same kernel,
  // which warms caches and branch predictors up again after the others ran.
  const int batch = batch_size(n);
  const auto time_batch = [batch](auto&& update) {
    seconds_per_update(update, batch);
    return seconds_per_update(update, batch);
  };
  std::vector<double> partc_times, hand_times, pairs_times, brute_times, compact_times,
      sell4_times, lists_times;
  for (int r = 0; r < repetitions; ++r) {
    partc_times.push_back(time_batch([&] { partc_model.step(); }));
    if (cells) hand_times.push_back(time_batch([&] { cells->update_velocities(); }));
    pairs_times.push_back(time_batch(update_pairs));
    if (brute) brute_times.push_back(time_batch([&] { brute->update_velocities(); }));
#ifdef PARTC_BENCH_FLOOR
    if (floor) {
      compact_times.push_back(time_batch([&] { floor->update_compact(); }));
      if (with_sell4) sell4_times.push_back(time_batch([&] { floor->update_sell4(); }));
    }
    if (lists_model) lists_times.push_back(time_batch([&] { lists_model->step(); }));
#endif
  }

  Row row{};
  row.neighbours = cells ? cells->mean_neighbours() : brute->mean_neighbours();
  row.te_partc = bench::median(partc_times);
  row.te_brute = brute ? bench::median(brute_times) : -1.0;
  row.te_hand = cells ? bench::median(hand_times) : row.te_brute;
  row.te_pairs = bench::median(pairs_times);
  row.hand_is_brute_force = !cells;
  row.te_compact = compact_times.empty() ? -1.0 : bench::median(compact_times);
  row.te_sell4 = sell4_times.empty() ? -1.0 : bench::median(sell4_times);
  row.te_lists = lists_times.empty() ? -1.0 : bench::median(lists_times);
  return row;
}

// What a measurement costs, up to a constant: updates done times the pairs
// examined per update (N particles, each with its neighbours and itself).
double expected_work(std::size_t n, double rc) {
  constexpr double pi = 3.14159265358979323846;
  const double neighbours = std::min(pi * rc * rc, box * box) * static_cast<double>(n - 1);
  const double updates = 1 + 2 * repetitions * batch_size(n);
  return updates * static_cast<double>(n) * (1.0 + neighbours);
}

#ifdef PARTC_BENCH_FLOOR
// The same rows against the floor's kernels, from the same run: a second
// table rather than a wider first one.
void print_against_floor(const std::vector<std::pair<std::size_t, Row>>& rows) {
  std::printf(
      "\nThe same run against the strongest hand-written kernels (shared/floor); lists: partc\n"
      "with Verlet lists of skin 0 (half lists, each pair once) where sell4 has its list:\n");
  std::printf("%9s %11s %12s %11s %11s %12s %11s %13s %11s %11s %11s\n", "N", "Te_partc/s",
              "Te_compact/s", "Te_sell4/s", "N/Te_partc", "N/Te_compact", "N/Te_sell4",
              "partc/compact", "partc/sell4", "N/Te_lists", "lists/sell4");
  // A measured time (or N/Te), or, where negative (not measured), why not.
  const auto cell = [](double te, const char* why) {
    char text[16];
    std::snprintf(text, sizeof text, "%.3e", te);
    return std::string(te >= 0 ? text : why);
  };
  const auto ratio = [](double a, double b) {
    char text[16];
    std::snprintf(text, sizeof text, "%.2f", a / b);
    return std::string(b >= 0 ? text : "-");
  };
  bool few_cells = false, over_guard = false;
  for (const auto& [n, row] : rows) {
    const double size = static_cast<double>(n);
    const char* no_sell4 = row.te_compact < 0 ? "cells" : "memory";
    few_cells |= row.te_compact < 0;
    over_guard |= row.te_compact >= 0 && row.te_sell4 < 0;
    std::printf("%9zu %11.3e %12s %11s %11.3e %12s %11s %13s %11s %11s %11s\n", n, row.te_partc,
                cell(row.te_compact, "cells").c_str(), cell(row.te_sell4, no_sell4).c_str(),
                size / row.te_partc, cell(size / row.te_compact, "-").c_str(),
                cell(size / row.te_sell4, "-").c_str(),
                ratio(row.te_partc, row.te_compact).c_str(),
                ratio(row.te_partc, row.te_sell4).c_str(),
                cell(size / row.te_lists, "-").c_str(), ratio(row.te_lists, row.te_sell4).c_str());
  }
  if (few_cells)
    std::printf("  cells: rc > 1/3, fewer than 3 cells a side for the floor's grid: not measured\n");
  if (over_guard)
    std::printf("  memory: over the floor's memory guard for neighbour lists (%.2g pairs): no SELL-4\n",
                floor_ref::VelocityUpdate::sell4_max_pairs);
}
#endif

void run(const Cutoff& cutoff, const std::vector<std::size_t>& sizes) {
  std::printf("\n%s\n", cutoff.description);
  std::printf("%9s %10s %11s %11s %11s %11s %10s %11s %11s %11s\n", "N", "neighbours",
              "Te_partc/s", "Te_hand/s", "N/Te_partc", "N/Te_hand", "partc/hand", "Te_pairs/s",
              "partc/pairs", "Te_brute/s");
  bool hand_fell_back = false;
  double seconds_per_work = 0.0;  // of the last size measured
  std::vector<std::pair<std::size_t, Row>> rows;
  for (const std::size_t n : sizes) {
    const double rc = cutoff.rc(n);
    const double estimate = seconds_per_work * expected_work(n, rc);
    if (estimate > seconds_per_size_budget) {
      std::printf("%9zu skipped: estimated %.0f s, over the %.0f s budget\n", n, estimate,
                  seconds_per_size_budget);
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    const Row row = measure(n, rc);
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    seconds_per_work = elapsed.count() / expected_work(n, rc);

    hand_fell_back |= row.hand_is_brute_force;
    char brute[16] = "-";
    if (row.te_brute >= 0) std::snprintf(brute, sizeof brute, "%.3e", row.te_brute);
    std::printf("%9zu %10.1f %11.3e %10.3e%s %11.3e %11.3e %10.2f %11.3e %11.2f %11s\n", n,
                row.neighbours, row.te_partc, row.te_hand, row.hand_is_brute_force ? "*" : " ",
                static_cast<double>(n) / row.te_partc, static_cast<double>(n) / row.te_hand,
                row.te_partc / row.te_hand, row.te_pairs, row.te_partc / row.te_pairs, brute);
    rows.emplace_back(n, row);
  }
  if (hand_fell_back)
    std::printf("  * rc > 1/3: too few cells for the 3x3 stencil; Te_hand is the brute-force kernel\n"
                "    (and Te_pairs brute force taking each pair once)\n");
#ifdef PARTC_BENCH_FLOOR
  print_against_floor(rows);
#endif
}

// Small N on static points lets the branch predictor learn a whole update's
// pattern of hits and misses, which favours branchy loops (the hand-written
// ones) over branch-free filtering (partc's cell list). Cycling one update at
// a time over many independent position sets, as a simulation's moving
// particles would, takes that away: Te per update, rc = sqrt(3/N).
void run_unlearnt(const std::vector<std::size_t>& sizes) {
  constexpr int sets = 64;
  std::printf("\nSmall N, no learnt branch pattern: updates cycle over %d independent position sets\n"
              "(rc = sqrt(3/N)); Te per update, median of %d rounds\n", sets, repetitions);
  std::printf("%9s %11s %11s %11s %10s %11s\n", "N", "Te_partc/s", "Te_hand/s", "Te_pairs/s",
              "partc/hand", "partc/pairs");
  for (const std::size_t n : sizes) {
    const double rc = std::sqrt(3.0 / static_cast<double>(n));
    std::vector<MdVelocity> models(sets);
    std::vector<HandCellList> hands, pairs;
    for (int k = 0; k < sets; ++k) {
      const Positions positions = uniform_positions(n, 2017 + static_cast<std::uint64_t>(k));
      load_positions(models[k], positions, rc);
      models[k].step();  // builds the search
      hands.emplace_back(positions, rc, force_strength);
      pairs.emplace_back(positions, rc, force_strength);
    }
    const int rounds = static_cast<int>(20000 / n) + 1;
    const auto time = [&](auto&& update_set) {
      std::vector<double> times;
      for (int r = 0; r < repetitions; ++r)
        times.push_back(seconds_per_update(
                            [&] {
                              for (int k = 0; k < sets; ++k) update_set(k);
                            },
                            rounds) /
                        sets);
      return bench::median(times);
    };
    const double te_partc = time([&](int k) { models[k].step(); });
    const double te_hand = time([&](int k) { hands[k].update_velocities(); });
    const double te_pairs = time([&](int k) { pairs[k].update_velocities_pairs(); });
    std::printf("%9zu %11.3e %11.3e %11.3e %10.2f %11.2f\n", n, te_partc, te_hand, te_pairs,
                te_partc / te_hand, te_partc / te_pairs);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t max_n = 1000000;
  if (argc == 3 && std::string(argv[1]) == "--max-n") {
    max_n = std::strtoull(argv[2], nullptr, 10);
  } else if (argc != 1) {
    std::fprintf(stderr, "usage: bench_md [--max-n N]\n");
    return 2;
  }
  const auto up_to_max = [max_n](std::vector<std::size_t> sizes) {
    sizes.erase(std::remove_if(sizes.begin(), sizes.end(), [&](std::size_t n) { return n > max_n; }),
                sizes.end());
    return sizes;
  };
  const std::vector<std::size_t> sizes =
      up_to_max({10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000, 50000, 100000, 200000,
                 500000, 1000000});
  std::printf("md velocity update (Aboria paper): Te = mean time of one update in a batch of\n"
              "floor(1000/N)+1 (each after an untimed batch), median of %d batches; positions\n"
              "static, search built before. partc searches by brute force when a cell list would\n"
              "save a query fewer than %g pair tests. The force is odd in dx, so partc takes each\n"
              "pair once (Newton's third law); Te_hand is the paper's per-particle kernel, Te_pairs\n"
              "the same hand-written cell list taking each pair once too.\n",
              repetitions, partc::NeighbourSearch<2>::default_margin);
#ifdef PARTC_BENCH_FLOOR
  std::printf("Each table is followed by the same run against the project owner's hand-vectorised\n"
              "kernels (shared/floor), a sum per particle each, their structures built before\n"
              "timing: compact_simd (cell grid, AVX2 filter, packed arithmetic) and sell4 (a\n"
              "precomputed SELL-4 neighbour list: pure pair arithmetic, the floor). They are\n"
              "built with -O3 -march=native -fno-math-errno -fopenmp-simd, the rest with the\n"
              "Release flags and the runtime's (-O3 -march=native, CMake's PARTC_NATIVE).\n");
#else
  std::printf("The floor's hand-vectorised kernels (shared/floor) are not built here: -march=native\n"
              "gives no AVX2 on this compiler or machine, so there is no comparison with them.\n");
#endif
  std::printf("Compiler: %s\n", __VERSION__);
  run({"rc = sqrt(3/N): about 3*pi neighbours per particle, N/Te should be flat",
       [](std::size_t n) { return std::sqrt(3.0 / static_cast<double>(n)); }},
      sizes);
  run({"rc = sqrt(3/500): neighbours grow with N",
       [](std::size_t) { return std::sqrt(3.0 / 500.0); }},
      sizes);
  run_unlearnt(up_to_max({50, 100, 200, 500}));
}

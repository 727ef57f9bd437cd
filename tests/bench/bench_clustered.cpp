// bench_clustered: neighbour search on clustered particles, where a cell list
// degrades and partc's k-d tree should not. The kernel is a density sum
//
//   rho[i] = sum(j, |dx| < h, W(|dx|))      (clustered_density.part.in)
//
// over N points in the periodic unit square, compiled three times with the
// search forced to a cell list, forced to a k-d tree, and left to the runtime
// (auto), loaded with identical positions. Distributions: uniform (the control,
// where the cell list should win), and 5 Gaussian blobs of standard deviation
// sigma around uniform random centres. h gives about `target_neighbours`
// neighbours per particle: N pi h^2 = 20 for uniform points, and for a blob of
// M = N/5 points, whose mean density seen from its own points is M/(4 pi sigma^2),
// h = 2 sigma sqrt(20/M). The grid of a cell list is capped at 2N + 64 cells,
// so its cells are much wider than h and a blob fills a few of them.
//
// Te is the time of one evaluation with the search already built (positions
// never move), the median of `repetitions` batches each after an untimed one,
// the models taking turns, as in bench_md. Builds are timed apart, calling the
// runtime's NeighbourSearch::build as the generated code does. Columns also
// give the points a cell-list query examines (OrderedCellList::mean_examined,
// the figure auto decides by: a tree above NeighbourSearch::kd_tree_above_examined)
// and which structure auto chose. The generated class does not expose its
// search, so the choice is read from the particle order: each structure sorts
// the particles in its own deterministic order, and auto's order equals the
// order of the model forced to the structure it picked.
//
// Usage: bench_clustered (no arguments; see .ci/bench).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "timing.hpp"
#include "clustered_density_auto.hpp"
#include "clustered_density_cell_list.hpp"
#include "clustered_density_kd_tree.hpp"

namespace {

constexpr double target_neighbours = 20.0;
constexpr int blob_count = 5;
constexpr int repetitions = 3;
// A timed batch lasts at least this long (at least one evaluation), so that
// fast evaluations are not timed one by one near the clock's resolution.
constexpr double min_batch_seconds = 0.05;
// The three models sum the same terms in different orders.
constexpr double agreement_tolerance = 1e-12;

struct Points {
  std::vector<double> x, y;
  std::size_t size() const { return x.size(); }
};

// sigma <= 0: uniform.
Points make_points(std::size_t n, double sigma, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  const auto uniform = [&random] { return (static_cast<double>(random() >> 11) + 0.5) * 0x1p-53; };
  constexpr double two_pi = 6.283185307179586;
  const auto normal = [&] {
    return std::sqrt(-2.0 * std::log(uniform())) * std::cos(two_pi * uniform());
  };
  const auto wrap = [](double c) { return c - std::floor(c); };
  double cx[blob_count], cy[blob_count];
  for (int b = 0; b < blob_count; ++b) {
    cx[b] = uniform();
    cy[b] = uniform();
  }
  Points p;
  for (std::size_t i = 0; i < n; ++i) {
    if (sigma <= 0) {
      p.x.push_back(uniform());
      p.y.push_back(uniform());
    } else {
      const std::size_t b = i % blob_count;
      p.x.push_back(wrap(cx[b] + sigma * normal()));
      p.y.push_back(wrap(cy[b] + sigma * normal()));
    }
  }
  return p;
}

double smoothing_length(std::size_t n, double sigma) {
  constexpr double pi = 3.141592653589793;
  if (sigma <= 0) return std::sqrt(target_neighbours / (pi * static_cast<double>(n)));
  const double per_blob = static_cast<double>(n) / blob_count;
  return 2.0 * sigma * std::sqrt(target_neighbours / per_blob);
}

partc::Domain<2> unit_square() {
  return {partc::Vec<2>{{0.0, 0.0}}, partc::Vec<2>{{1.0, 1.0}}, {{true, true}}};
}

std::vector<partc::Vec<2>> as_vecs(const Points& p) {
  std::vector<partc::Vec<2>> v(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) v[i] = partc::Vec<2>{{p.x[i], p.y[i]}};
  return v;
}

// Mean number of other points within h (with a k-d tree of the runtime: cheap
// whatever the clustering).
double mean_neighbours(const Points& p, double h) {
  const auto points = as_vecs(p);
  partc::KdTree<2> tree;
  tree.build(unit_square(), h, points);
  std::size_t pairs = 0;
  for (const auto& q : points)
    tree.for_each_near(
        q, [&](std::size_t, const partc::Vec<2>& dx) { pairs += partc::squared_norm(dx) < h * h; });
  return static_cast<double>(pairs - p.size()) / static_cast<double>(p.size());
}

double cell_list_examined(const Points& p, double h) {
  partc::OrderedCellList<2> cells;
  cells.build(unit_square(), h, as_vecs(p));
  return cells.mean_examined();
}

template <class Model>
void load_points(Model& model, const Points& p, double h) {
  model.params().N = static_cast<std::int64_t>(p.size());
  model.params().h = h;
  partc::CsvTable table;
  table.header = {"id", "p_0", "p_1"};
  for (std::size_t i = 0; i < p.size(); ++i)
    table.rows.push_back({static_cast<double>(i), p.x[i], p.y[i]});
  model.load({{"P", table}});
}

template <class Model>
std::vector<double> rho_by_id(const Model& model) {
  const auto& set = model.P();
  const auto& rho = set.template get<typename Model::P_rho>();
  std::vector<double> by_id(set.size());
  for (std::size_t k = 0; k < set.size(); ++k)
    by_id[static_cast<std::size_t>(set.ids()[k])] = rho[k];
  return by_id;
}

// Te of each model (its step()), in seconds. The first step() builds the
// search; the models then take turns, each timed batch after an untimed one
// of the same model, so that a slow spell of the machine hits them alike (as
// bench_md).
std::vector<double> time_evaluations(const std::vector<std::function<void()>>& steps) {
  std::vector<int> batch;
  for (const auto& step : steps) {
    step();
    batch.push_back(std::max(1, static_cast<int>(min_batch_seconds / bench::seconds(step))));
  }
  std::vector<std::vector<double>> te(steps.size());
  for (int r = 0; r < repetitions; ++r)
    for (std::size_t k = 0; k < steps.size(); ++k) {
      bench::seconds(steps[k], batch[k]);
      te[k].push_back(bench::seconds(steps[k], batch[k]) / batch[k]);
    }
  std::vector<double> result;
  for (const auto& times : te) result.push_back(bench::median(times));
  return result;
}

// The build alone, as the generated code does it (NeighbourSearch::build on
// the particle set, which it reorders), on a fresh copy each time; median of
// `repetitions`. Timed apart from the models because a build is milliseconds
// and the noise of a clustered cell-list evaluation is more.
double build_seconds(const Points& p, double h,
                     std::optional<partc::NeighbourSearch<2>::Kind> kind) {
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r) {
    partc::ParticleSet<2> set;
    for (const auto& q : as_vecs(p)) set.push_back(q);
    partc::NeighbourSearch<2> search =
        kind ? partc::NeighbourSearch<2>(*kind) : partc::NeighbourSearch<2>();
    times.push_back(bench::seconds([&] { search.build(unit_square(), h, set); }));
  }
  return bench::median(times);
}

struct Distribution {
  const char* name;
  double sigma;  // <= 0: uniform
};

void measure(const Distribution& d, std::size_t n) {
  const Points points = make_points(n, d.sigma, 2024);
  const double h = smoothing_length(n, d.sigma);

  ClusteredDensityCellList cells;
  ClusteredDensityKdTree tree;
  ClusteredDensityAuto automatic;
  load_points(cells, points, h);
  load_points(tree, points, h);
  load_points(automatic, points, h);
  const std::vector<std::int64_t> input_order = automatic.P().ids();
  const std::vector<double> te =
      time_evaluations({[&] { cells.step(); }, [&] { tree.step(); }, [&] { automatic.step(); }});
  const double te_cells = te[0], te_tree = te[1], te_auto = te[2];
  using Kind = partc::NeighbourSearch<2>::Kind;
  const double build_cells = build_seconds(points, h, Kind::cell_list);
  const double build_tree = build_seconds(points, h, Kind::kd_tree);
  const double build_auto = build_seconds(points, h, std::nullopt);

  const std::vector<double> reference = rho_by_id(tree);
  double scale = 0.0;
  for (const double r : reference) scale = std::max(scale, std::abs(r));
  for (const auto& [name, rho] :
       {std::pair{"cell_list", rho_by_id(cells)}, std::pair{"auto", rho_by_id(automatic)}}) {
    double worst = 0.0;
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, std::abs(rho[i] - reference[i]));
    if (!(worst <= agreement_tolerance * scale)) {
      std::fprintf(stderr,
                   "bench_clustered: %s, N = %zu: the %s model's rho differs from the kd_tree "
                   "model's by %.3g relative\n",
                   d.name, n, name, worst / scale);
      std::exit(1);
    }
  }

  const auto& order = automatic.P().ids();
  const char* choice = order == tree.P().ids()    ? "kd_tree"
                       : order == cells.P().ids() ? "cell_list"
                       : order == input_order     ? "brute_force"
                                                  : "?";
  std::printf("%-16s %7zu %8.2e %7.1f %8.0f %10.3e %10.3e %10.3e %9.2f %10.3e %10.3e %10.3e  %s\n",
              d.name, n, h, mean_neighbours(points, h), cell_list_examined(points, h), te_cells,
              te_tree, te_auto, te_cells / te_tree, build_cells, build_tree, build_auto, choice);
}

}  // namespace

int main() {
  std::printf(
      "Density sum rho[i] = sum(j, |dx| < h, W(|dx|)), 2D periodic unit square, h for ~%g "
      "neighbours.\n"
      "Te: one evaluation, search built before (median of %d batches). build_c, _t, _a: building "
      "the\n"
      "cell list, the k-d tree, the automatic choice (a cell list first, to measure it).\n"
      "examined: points a cell-list query examines; auto takes the k-d tree above %g.\n"
      "Compiler: %s\n\n",
      target_neighbours, repetitions, partc::NeighbourSearch<2>::kd_tree_above_examined,
      __VERSION__);
  std::printf("%-16s %7s %8s %7s %8s %10s %10s %10s %9s %10s %10s %10s  %s\n", "distribution", "N",
              "h", "neighb.", "examined", "Te_cells/s", "Te_tree/s", "Te_auto/s", "cells/tree",
              "build_c/s", "build_t/s", "build_a/s", "auto chose");
  const Distribution distributions[] = {
      {"uniform", 0.0}, {"5 blobs s=0.002", 0.002}, {"5 blobs s=0.001", 0.001}};
  for (const std::size_t n : {std::size_t{10000}, std::size_t{100000}})
    for (const Distribution& d : distributions) measure(d, n);
}

// lj_melt_setup.hpp: the starting state of the LJ melt benchmark (LAMMPS's
// in.melt at 32000 atoms, examples/lj_melt.part), built here rather than by
// the model's init so that the benchmarks control it, and a hand-written
// cell-list evaluation of forces and energies that checks the model's
// physics independently of partc. Shared by bench_lj, bench_threads and
// bench_compose (which adds charges and Coulomb through for_each_pair_within).
//
//   MeltState state = melt_start();       // fcc lattice, T = 3, zero momentum, forces
//   load_melt(model, state);              // into LjMelt through load()
//   MeltState now = melt_state(model);    // back, by id, with forces recomputed here
//
// Units are LJ reduced units: epsilon = sigma = mass = 1.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "lj_melt.hpp"

namespace lj_melt_bench {

// in.melt's workload; examples/lj_melt.part spells the same numbers (its
// domain cannot take them from params).
constexpr int cells_per_side = 20;
constexpr double density = 0.8442;
constexpr double cutoff = 2.5;
constexpr double initial_temperature = 3.0;
constexpr int steps = 100;
constexpr std::size_t atom_count = 4 * cells_per_side * cells_per_side * cells_per_side;

inline double lattice_constant() { return std::cbrt(4.0 / density); }
inline double box_length() { return cells_per_side * lattice_constant(); }

using Vec3 = std::array<double, 3>;

// Per atom, in id order. Energies are totals over all atoms.
struct MeltState {
  std::vector<Vec3> position, velocity, force;
  double kinetic = 0.0, potential = 0.0;

  std::size_t size() const { return position.size(); }
  double total_energy() const { return kinetic + potential; }
  // Over the 3N - 3 degrees of freedom left by zero total momentum, as LAMMPS counts them.
  double temperature() const { return 2.0 * kinetic / (3.0 * static_cast<double>(size()) - 3.0); }
};

// Calls pair(i, j, d, r2) for every ordered pair i != j of the particles at
// `position` closer than reach, so each pair from both sides, i in index
// order: d = x_j - x_i by the minimum image in the periodic box of side
// box_length(), r2 = |d|^2. With a cell list of cubic cells at least reach
// wide (13 a side for 2.5, 11 for 3.0, so the 27-cell stencil never visits a
// cell twice: reach must be at most a third of the box). Written plainly: it
// checks partc's searches, and runs a few times per benchmark, not per step.
template <class Pair>
void for_each_pair_within(const std::vector<Vec3>& position, double reach, Pair&& pair) {
  const double L = box_length();
  const int n = static_cast<int>(L / reach);
  const double width = L / n;
  const auto cell_of = [&](double x) {
    const int c = static_cast<int>(std::floor(x / width));
    return ((c % n) + n) % n;  // positions may lie a hair outside [0, L)
  };
  std::vector<std::vector<std::size_t>> cells(static_cast<std::size_t>(n) * n * n);
  const auto index = [n](int x, int y, int z) {
    return (static_cast<std::size_t>(((x + n) % n) * n + (y + n) % n)) * n + (z + n) % n;
  };
  for (std::size_t i = 0; i < position.size(); ++i)
    cells[index(cell_of(position[i][0]), cell_of(position[i][1]), cell_of(position[i][2]))]
        .push_back(i);

  const double reach2 = reach * reach;
  for (std::size_t i = 0; i < position.size(); ++i) {
    const Vec3& pi = position[i];
    const int cx = cell_of(pi[0]), cy = cell_of(pi[1]), cz = cell_of(pi[2]);
    for (int ox = -1; ox <= 1; ++ox)
      for (int oy = -1; oy <= 1; ++oy)
        for (int oz = -1; oz <= 1; ++oz)
          for (const std::size_t j : cells[index(cx + ox, cy + oy, cz + oz)]) {
            if (j == i) continue;
            Vec3 d;
            for (int k = 0; k < 3; ++k) {
              d[k] = position[j][k] - pi[k];
              d[k] -= L * std::nearbyint(d[k] / L);  // the minimum image
            }
            const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            if (r2 < reach2) pair(i, j, d, r2);
          }
  }
}

// The LJ pair term at squared distance r2: 4 (r^-12 - r^-6), and the force on
// i from j as f_over_r * (x_i - x_j).
struct LjTerm {
  double energy, f_over_r;
};
inline LjTerm lj_term(double r2) {
  const double inv6 = 1.0 / (r2 * r2 * r2);
  return {4.0 * inv6 * (inv6 - 1.0), 24.0 * inv6 * (2.0 * inv6 - 1.0) / r2};
}

// Forces and the potential energy of the truncated (not shifted) LJ potential,
// U = sum over pairs r < rc of 4 (r^-12 - r^-6), as LAMMPS's pair_style lj/cut.
inline void compute_forces(MeltState& s) {
  s.force.assign(s.size(), Vec3{0, 0, 0});
  double potential = 0.0;  // counts every pair twice
  const auto add = [&](std::size_t i, std::size_t, const Vec3& d, double r2) {
    const LjTerm lj = lj_term(r2);
    potential += lj.energy;
    for (int k = 0; k < 3; ++k) s.force[i][k] -= lj.f_over_r * d[k];
  };
  for_each_pair_within(s.position, cutoff, add);
  s.potential = 0.5 * potential;
}

inline void compute_kinetic(MeltState& s) {
  double twice = 0.0;
  for (const Vec3& v : s.velocity) twice += v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  s.kinetic = 0.5 * twice;
}

// The fcc crystal of in.melt (LAMMPS's "lattice fcc 0.8442": basis atoms at
// (0,0,0), (1/2,1/2,0), (1/2,0,1/2), (0,1/2,1/2) of each cell), with Gaussian
// velocities (Box-Muller on mt19937_64, so the same on every platform), the
// mean removed and the rest scaled to exactly initial_temperature, as
// LAMMPS's "velocity all create 3.0 87287" does with its own generator (a
// uniform distribution there: the melt forgets the difference within tens of
// steps, not the temperature). Forces and energies computed.
inline MeltState melt_start(std::uint64_t seed = 87287) {
  const double a = lattice_constant();
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  MeltState s;
  for (int z = 0; z < cells_per_side; ++z)
    for (int y = 0; y < cells_per_side; ++y)
      for (int x = 0; x < cells_per_side; ++x)
        for (const auto& b : basis)
          s.position.push_back({a * (x + b[0]), a * (y + b[1]), a * (z + b[2])});

  std::mt19937_64 random(seed);
  const auto uniform = [&random] { return (static_cast<double>(random() >> 11) + 0.5) * 0x1p-53; };
  constexpr double two_pi = 6.283185307179586;
  s.velocity.resize(s.size());
  for (Vec3& v : s.velocity)
    for (double& c : v) c = std::sqrt(-2.0 * std::log(uniform())) * std::cos(two_pi * uniform());
  Vec3 mean{0, 0, 0};
  for (const Vec3& v : s.velocity)
    for (int k = 0; k < 3; ++k) mean[k] += v[k] / static_cast<double>(s.size());
  for (Vec3& v : s.velocity)
    for (int k = 0; k < 3; ++k) v[k] -= mean[k];
  compute_kinetic(s);
  const double scale = std::sqrt(initial_temperature / s.temperature());
  for (Vec3& v : s.velocity)
    for (double& c : v) c *= scale;
  compute_kinetic(s);
  compute_forces(s);
  return s;
}

// Replaces the model's particles by the state, ids 0..N-1 in state order. The
// forces go in too: step() starts with a half kick by the f of the previous
// step, which the model's init computes and a load must bring.
// Builds so far of the Verlet lists of the model's force statement ("force:"),
// as the model reports them.
inline std::size_t list_builds(const LjMelt& model) {
  for (const partc::SearchReport& search : model.search_report())
    if (search.serves.rfind("force at ", 0) == 0) return search.builds;
  return 0;
}

inline void load_melt(LjMelt& model, const MeltState& s) {
  partc::CsvTable table;
  table.header = {"id", "p_0", "p_1", "p_2", "v_0", "v_1", "v_2", "f_0", "f_1", "f_2"};
  table.rows.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3 &p = s.position[i], &v = s.velocity[i], &f = s.force[i];
    table.rows.push_back(
        {static_cast<double>(i), p[0], p[1], p[2], v[0], v[1], v[2], f[0], f[1], f[2]});
  }
  model.load({{"A", table}});
}

// The model's particles by id, with kinetic and potential energy and forces
// computed here; model_force gets the model's own f, to compare.
inline MeltState melt_state(const LjMelt& model, std::vector<Vec3>* model_force = nullptr) {
  const auto& set = model.A();
  const auto& v = set.get<LjMelt::A_v>();
  const auto& f = set.get<LjMelt::A_f>();
  MeltState s;
  s.position.resize(set.size());
  s.velocity.resize(set.size());
  if (model_force) model_force->resize(set.size());
  for (std::size_t k = 0; k < set.size(); ++k) {
    const auto i = static_cast<std::size_t>(set.ids()[k]);
    const auto& p = set.positions()[k];
    s.position[i] = {p[0], p[1], p[2]};
    s.velocity[i] = {v[k][0], v[k][1], v[k][2]};
    if (model_force) (*model_force)[i] = {f[k][0], f[k][1], f[k][2]};
  }
  compute_kinetic(s);
  compute_forces(s);
  return s;
}

}  // namespace lj_melt_bench

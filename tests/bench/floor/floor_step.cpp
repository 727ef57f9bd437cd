// A hand-written whole time step of examples/md.part (2D periodic unit
// square), the yardstick for partc's generated step, from the project's
// shared/floor/floor_step.cpp: each step rebuilds the cell grid (counting sort
// + halo ring), evaluates v_i += c*sum_{0<|dx|<rc} -exp(-|dx|) dx/|dx| with
// the AVX2 compaction kernel (a full sum per particle, no Newton-3 sharing),
// then p_i += v_i with wrapping. The particles stay in cell order between
// steps, as partc's ordered cell list keeps them. Positions start uniform in
// the square (its own generator: the step's cost does not depend on which
// uniform points). Only the steps are timed.
//
// Usage: floor_step N steps [seed]. Prints seconds per step and sum |v|.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "floor_kernels.hpp"

int main(int argc, char** argv) {
  const int N = argc > 1 ? std::atoi(argv[1]) : 100000;
  const int steps = argc > 2 ? std::atoi(argv[2]) : 20;
  const unsigned seed = argc > 3 ? std::atoi(argv[3]) : 1;
  const double rc = std::sqrt(3.0 / N);
  const double c = 1e-3;
  std::vector<double> x(N), y(N), vx(N, 0.0), vy(N, 0.0), tvx(N), tvy(N);
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < N; ++i) {
    x[i] = u(gen);
    y[i] = u(gen);
  }
  floor_ref::CellGrid g;
  floor_ref::CompactScratch cs;
  auto t0 = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) {
    if (!g.build(N, x.data(), y.data(), rc)) {
      std::fprintf(stderr, "nc < 3\n");
      return 1;
    }
    cs.fit(g);
    // v follows its particle into the new cell order.
    for (int k = 0; k < N; ++k) {
      tvx[k] = vx[g.perm[k]];
      tvy[k] = vy[g.perm[k]];
    }
    vx.swap(tvx);
    vy.swap(tvy);
    floor_ref::eval_compact_simd(g, cs, c, vx.data(), vy.data());
    for (int k = 0; k < N; ++k) {
      double a = g.sx[k] + vx[k], b = g.sy[k] + vy[k];
      a -= std::floor(a);
      b -= std::floor(b);
      x[k] = a >= 1 ? 0.0 : a;
      y[k] = b >= 1 ? 0.0 : b;
    }
  }
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double sv = 0;
  for (int i = 0; i < N; ++i) sv += std::abs(vx[i]) + std::abs(vy[i]);
  std::printf("N=%d steps=%d sec_per_step=%.6e sum|v|=%.15e\n", N, steps, dt / steps, sv);
}

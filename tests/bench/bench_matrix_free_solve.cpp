// bench_matrix_free_solve: the matrix-free solve (solve/matrix_free_solve.hpp:
// GMRES, fast-sum products, restricted Schwarz) run directly on the runtime,
// for the preconditioner's memory, iterations and time at N = 1e4 to 1e6.
//
// Problems, as the examples pose them on n x n nodes of the unit square:
//   franke  rbf_franke.part: multiquadrics, eps h = 0.5 (rcond near 1e-8),
//           Franke's function; error: the interpolant's RMS error on a
//           101 x 101 grid against Franke's function.
//   kansa   kansa_poisson.part: Gaussian, eps h = 0.6, boundary rows
//           interpolate, interior rows take -laplace; error: u's RMS error on
//           the grid against sin(pi x) sin(pi y).
// The fast sums run at tol / 100, as partc's code generator asks. Printed:
// the preconditioner's shape, iterations, solve time (the preconditioner's
// setup included), the residual GMRES saw and the one against the direct sums
// on 1000 sampled rows, the error on the grid, and the peak RSS (getrusage)
// before and after the solve: one configuration per process, so that the
// peak is the solve's.
//
// --save FILE writes x and the grid values; --compare FILE prints the
// difference to a saved run (an earlier preconditioner, or --dense: x by a
// dense LU of the assembled matrix, 0.8 GB at N = 1e4).
//
// Usage: bench_matrix_free_solve [--problem franke|kansa] [--n SIDE] [--tol T]
//          [--cluster C] [--overlap O] [--coarse-stride S] [--coarse-max M]
//          [--float-error E] [--eps-h EH] [--dense] [--setup-only] [--save FILE]
//          [--compare FILE]
// --setup-only builds the preconditioner alone (no fast sums, no GMRES): its
// time and memory at sizes where the whole solve takes too long.
#include <sys/resource.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "partc/fast_sum/fmm.hpp"
#include "partc/solve/direct_residual.hpp"
#include "partc/solve/matrix_free_solve.hpp"
#include "timing.hpp"

namespace {

using partc::Vec;

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

std::vector<Vec<2>> square_nodes(int n) {
  std::vector<Vec<2>> x;
  x.reserve(std::size_t(n) * std::size_t(n));
  for (int k = 0; k < n * n; ++k)
    x.push_back(Vec<2>{{double(k % n) / (n - 1), double(k / n) / (n - 1)}});
  return x;
}

double franke(double x, double y) {
  const double a = 9 * x, b = 9 * y;
  return 0.75 * std::exp(-((a - 2) * (a - 2) + (b - 2) * (b - 2)) / 4) +
         0.75 * std::exp(-(a + 1) * (a + 1) / 49 - (b + 1) / 10) +
         0.5 * std::exp(-((a - 7) * (a - 7) + (b - 3) * (b - 3)) / 4) -
         0.2 * std::exp(-(a - 4) * (a - 4) - (b - 7) * (b - 7));
}

struct Saved {
  Eigen::VectorXd x, grid;
};

void save(const std::string& file, const Saved& s) {
  std::ofstream out(file, std::ios::binary);
  const Eigen::Index sizes[2] = {s.x.size(), s.grid.size()};
  out.write(reinterpret_cast<const char*>(sizes), sizeof sizes);
  out.write(reinterpret_cast<const char*>(s.x.data()),
            std::streamsize(sizeof(double) * s.x.size()));
  out.write(reinterpret_cast<const char*>(s.grid.data()),
            std::streamsize(sizeof(double) * s.grid.size()));
}

Saved load(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  Eigen::Index sizes[2];
  if (!in.read(reinterpret_cast<char*>(sizes), sizeof sizes))
    throw std::runtime_error("cannot read " + file);
  Saved s{Eigen::VectorXd(sizes[0]), Eigen::VectorXd(sizes[1])};
  in.read(reinterpret_cast<char*>(s.x.data()), std::streamsize(sizeof(double) * sizes[0]));
  in.read(reinterpret_cast<char*>(s.grid.data()), std::streamsize(sizeof(double) * sizes[1]));
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string problem = "franke", save_to, compare_to;
  int side = 100;
  double tol = 1e-8;
  double eps_h = 0;  // 0: the problem's
  bool dense = false, setup_only = false;
  partc::MatrixFreeSolveOptions options;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    const auto next = [&] {
      if (k + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return std::string(argv[++k]);
    };
    if (a == "--problem")
      problem = next();
    else if (a == "--n")
      side = std::stoi(next());
    else if (a == "--tol")
      tol = std::stod(next());
    else if (a == "--cluster")
      options.schwarz.cluster_size = std::stoul(next());
    else if (a == "--overlap")
      options.schwarz.overlap = std::stod(next());
    else if (a == "--coarse-stride")
      options.schwarz.coarse_stride = std::stoul(next());
    else if (a == "--coarse-max")
      options.schwarz.coarse_max = std::stoul(next());
    else if (a == "--float-error")
      options.schwarz.float_error = std::stod(next());
    else if (a == "--eps-h")
      eps_h = std::stod(next());
    else if (a == "--dense")
      dense = true;
    else if (a == "--setup-only")
      setup_only = true;
    else if (a == "--save")
      save_to = next();
    else if (a == "--compare")
      compare_to = next();
    else {
      std::fprintf(stderr, "bench_matrix_free_solve: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (problem != "franke" && problem != "kansa") {
    std::fprintf(stderr, "bench_matrix_free_solve: --problem franke or kansa\n");
    return 2;
  }
  const bool kansa = problem == "kansa";
  const std::vector<Vec<2>> x = square_nodes(side);
  const std::vector<Vec<2>> grid = square_nodes(101);
  const std::size_t n = x.size();
  const double eps = (eps_h > 0 ? eps_h : kansa ? 0.6 : 0.5) * (side - 1), e2 = eps * eps;
  const auto phi = [=](double r) {
    return kansa ? std::exp(-e2 * r * r) : std::sqrt(1 + e2 * r * r);
  };
  const auto minus_laplace = [=](double r) {
    return -(4 * e2 * e2 * r * r - 4 * e2) * std::exp(-e2 * r * r);
  };
  std::vector<char> boundary(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i % std::size_t(side), b = i / std::size_t(side);
    boundary[i] =
        kansa && (a == 0 || b == 0 || a + 1 == std::size_t(side) || b + 1 == std::size_t(side));
  }
  const auto entry = [&](std::size_t i, std::size_t j) {
    const double r = partc::norm(x[j] - x[i]);
    return kansa && !boundary[i] ? minus_laplace(r) : phi(r);
  };
  Eigen::VectorXd f(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const double px = x[i][0], py = x[i][1];
    f[Eigen::Index(i)] = !kansa ? franke(px, py)
                         : boundary[i]
                             ? 0.0
                             : 2 * M_PI * M_PI * std::sin(M_PI * px) * std::sin(M_PI * py);
  }
  const auto exact = [&](const Vec<2>& p) {
    return kansa ? std::sin(M_PI * p[0]) * std::sin(M_PI * p[1]) : franke(p[0], p[1]);
  };

  if (setup_only) {
    std::optional<partc::RestrictedSchwarz<2>> schwarz;
    const double seconds = bench::seconds([&] { schwarz.emplace(x, entry, options.schwarz); });
    std::printf(
        "%s N = %zu (n = %d): restricted Schwarz alone, %zu blocks of up to %zu, %zu in "
        "double, %zu coarse points, %.2f s, peak RSS %.0f MB\n",
        problem.c_str(), n, side, schwarz->clusters(), schwarz->largest_block(),
        schwarz->double_blocks(), schwarz->coarse_points(), seconds, peak_rss_mb());
    return 0;
  }
  const partc::fast_sum::Accuracy accuracy{tol / 100};
  const partc::fast_sum::Fmm on_nodes(x, x, phi, accuracy);
  const partc::fast_sum::Fmm on_grid(x, grid, phi, accuracy);
  // Kansa's interior rows: a second sum, its kernel -laplace(phi), on the nodes.
  std::optional<partc::fast_sum::Fmm<2, decltype(minus_laplace)>> laplace_on_nodes;
  if (kansa) laplace_on_nodes.emplace(x, x, minus_laplace, accuracy);
  Eigen::VectorXd interior(static_cast<Eigen::Index>(n));
  const auto apply = [&](const Eigen::VectorXd& w, Eigen::VectorXd& y) {
    on_nodes.potential(w.data(), y.data());
    if (!kansa) return;
    laplace_on_nodes->potential(w.data(), interior.data());
    for (std::size_t i = 0; i < n; ++i)
      if (!boundary[i]) y[Eigen::Index(i)] = interior[Eigen::Index(i)];
  };
  const double rss_before = peak_rss_mb();

  partc::SolveResult result;
  if (dense) {
    const double seconds = bench::seconds([&] {
      Eigen::MatrixXd a(n, n);
      partc::parallel_for(n, partc::LoopWork::heavy, [&](std::size_t i) {
        for (std::size_t j = 0; j < n; ++j) a(Eigen::Index(i), Eigen::Index(j)) = entry(i, j);
      });
      result.x = a.partialPivLu().solve(f);
    });
    result.method = "dense LU (Eigen, assembled)";
    result.seconds = seconds;
    Eigen::VectorXd ax(f.size());
    apply(result.x, ax);
    result.residual = (ax - f).norm() / f.norm();
  } else {
    options.tolerance = tol;
    options.name = "w";
    result = partc::solve_matrix_free(x, apply, entry, f, options);
  }
  const double rss_after = peak_rss_mb();

  Saved run{result.x, Eigen::VectorXd(static_cast<Eigen::Index>(grid.size()))};
  on_grid.potential(run.x.data(), run.grid.data());
  double error2 = 0;
  for (std::size_t g = 0; g < grid.size(); ++g) {
    const double e = run.grid[Eigen::Index(g)] - exact(grid[g]);
    error2 += e * e;
  }
  // The residual against the direct sums: b as the "fast" product of x.
  const double direct_residual = partc::sampled_product_error(entry, result.x, f, f, 1000);

  std::printf("%s N = %zu (n = %d), tol %.0e: %s\n", problem.c_str(), n, side, tol,
              result.method.c_str());
  std::printf("  iterations %s, %s, residual %.2e (direct, 1000 rows: %.2e), %.2f s\n",
              result.iterations ? std::to_string(*result.iterations).c_str() : "-",
              result.converged ? "converged" : "NOT CONVERGED", result.residual, direct_residual,
              result.seconds);
  std::printf("  grid RMS error %.3e\n", std::sqrt(error2 / double(grid.size())));
  std::printf("  peak RSS %.0f MB before the solve, %.0f MB after\n", rss_before, rss_after);
  if (!compare_to.empty()) {
    const Saved ref = load(compare_to);
    std::printf(
        "  against %s: |x - x_ref| / |x_ref| %.2e, grid max |s - s_ref| / max |s_ref| %.2e\n",
        compare_to.c_str(), (run.x - ref.x).norm() / ref.x.norm(),
        (run.grid - ref.grid).cwiseAbs().maxCoeff() / ref.grid.cwiseAbs().maxCoeff());
  }
  if (!save_to.empty()) save(save_to, run);
  return 0;
}

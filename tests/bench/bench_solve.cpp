// bench_solve: partc's dense solve (runtime/partc/solve/dense_solve.hpp) on
// the system of an RBF interpolation, next to NumPy and SciPy on the same one.
//
// N = m^2 points on an m x m grid of the unit square, spacing h = 1 / (m - 1),
// point k at ((k % m) h, (k / m) h); the multiquadric A(i, j) =
// sqrt(1 + (eps r_ij)^2) with eps h = 0.5, which keeps rcond near 1e-8 for
// every N (a fixed eps would make the larger systems singular to working
// precision: rcond 1e-21 at N = 1600 for eps = 3); the right-hand side is
// Franke's function, the usual test function of RBF interpolation. Each solve
// (checks, LU, rcond, the substitutions and the residual) is timed alone on
// one thread, the median of `repetitions` runs kept. The target: under
// 0.5 s at N = 1600 on one core.
//
// NumPy/SciPy (optional): the argument is the output of solve_reference.py,
// which builds the same matrix and times numpy.linalg.solve (dgesv) and
// scipy.linalg.solve (dgetrf + dgecon + dgetrs: rcond too, as here) with the
// BLAS that Debian's alternatives give NumPy (its '#' lines say which). |w|
// of both solutions must agree within about eps / rcond, or the two did not
// solve the same system.
//
// Why SciPy is faster: Debian's OpenBLAS picks AVX2/FMA kernels for the CPU at
// run time, while this build, as the other benchmarks, is for baseline x86-64
// (SSE2, no -march=native). Measured at N = 1600 on a busy 2-core AMD EPYC,
// one thread: Eigen 0.27 s, Eigen with -march=native 0.18 s, Eigen through
// LAPACKE and OpenBLAS (EIGEN_USE_BLAS, EIGEN_USE_LAPACKE) 0.13 s. partc keeps
// plain Eigen: it meets the target, generated models need no library at run
// time, and x does not depend on the thread count (with OpenBLAS's dgetrf it
// differs between 1, 2 and 4 threads).
//
// Usage: bench_solve [SOLVE_REFERENCE_OUTPUT]   (see .ci/bench)
#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "partc/solve/dense_solve.hpp"
#include "timing.hpp"

namespace {

constexpr int sides[] = {20, 30, 40, 50};  // N = 400, 900, 1600, 2500
constexpr int repetitions = 3;
constexpr double eps_times_h = 0.5;
constexpr double target_n = 1600, target_seconds = 0.5;

double franke(double x, double y) {
  return 0.75 * std::exp(-((9 * x - 2) * (9 * x - 2) + (9 * y - 2) * (9 * y - 2)) / 4) +
         0.75 * std::exp(-((9 * x + 1) * (9 * x + 1)) / 49 - (9 * y + 1) / 10) +
         0.5 * std::exp(-((9 * x - 7) * (9 * x - 7) + (9 * y - 3) * (9 * y - 3)) / 4) -
         0.2 * std::exp(-((9 * x - 4) * (9 * x - 4)) - (9 * y - 7) * (9 * y - 7));
}

struct System {
  Eigen::MatrixXd A;
  Eigen::VectorXd f;
};

System rbf_system(int m) {
  const int n = m * m;
  const double h = 1.0 / (m - 1), eps = eps_times_h / h;
  System s{Eigen::MatrixXd(n, n), Eigen::VectorXd(n)};
  for (int j = 0; j < n; ++j) {
    const double xj = (j % m) * h, yj = (j / m) * h;
    s.f[j] = franke(xj, yj);
    for (int i = 0; i < n; ++i) {
      const double dx = (i % m) * h - xj, dy = (i / m) * h - yj;
      s.A(i, j) = std::sqrt(1 + eps * eps * (dx * dx + dy * dy));
    }
  }
  return s;
}

struct Reference {
  double numpy_seconds, scipy_seconds, w_norm;
};

// solve_reference.py's table by N; its '#' lines are printed as they are.
std::map<int, Reference> read_reference(const char* path) {
  std::ifstream in(path);
  if (!in) std::fprintf(stderr, "bench_solve: cannot read %s: no NumPy columns\n", path);
  std::map<int, Reference> table;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# ", 0) == 0) {
      std::printf("NumPy/SciPy: %s\n", line.c_str() + 2);
      continue;
    }
    std::istringstream fields(line);
    int n = 0;
    Reference r{};
    if (fields >> n >> r.numpy_seconds >> r.scipy_seconds >> r.w_norm) table[n] = r;
  }
  return table;
}

}  // namespace

int main(int argc, char** argv) {
  // One core, as the target says, whatever OMP_NUM_THREADS is.
  Eigen::setNbThreads(1);
  std::printf(
      "Dense solve of a multiquadric RBF system, sqrt(1 + (eps r)^2) with eps h = %g on an\n"
      "m x m grid of the unit square, Franke's function on the right: partc's solve_dense\n"
      "(Eigen %d.%d.%d PartialPivLU + rcond, %s, %d thread), median of %d runs.\n"
      "Compiler: %s\n",
      eps_times_h, EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION,
      Eigen::SimdInstructionSetsInUse(), Eigen::nbThreads(), repetitions, __VERSION__);
  const std::map<int, Reference> reference =
      argc > 1 ? read_reference(argv[1]) : std::map<int, Reference>{};
  if (argc == 1) std::printf("(no solve_reference.py output given: no NumPy/SciPy columns)\n");

  std::printf("\n%6s %10s %9s %9s %10s %10s %12s %12s\n", "N", "partc s", "rcond", "residual",
              "NumPy s", "SciPy s", "partc/SciPy", "|w| rel diff");
  double seconds_at_target = std::nan("");
  for (const int m : sides) {
    const System s = rbf_system(m);
    std::vector<double> times;
    partc::SolveResult result;
    for (int r = 0; r < repetitions; ++r)
      times.push_back(bench::seconds([&] { result = partc::solve_dense(s.A, s.f, {"w"}); }));
    const double seconds = bench::median(times);
    const int n = m * m;
    if (n == target_n) seconds_at_target = seconds;
    std::printf("%6d %10.4f %9.1e %9.1e", n, seconds, result.rcond.value_or(std::nan("")),
                result.residual);
    if (const auto found = reference.find(n); found != reference.end()) {
      const Reference& r = found->second;
      std::printf(" %10.4f %10.4f %12.2f %12.1e", r.numpy_seconds, r.scipy_seconds,
                  seconds / r.scipy_seconds, std::abs(result.x.norm() - r.w_norm) / r.w_norm);
    }
    std::printf("%s\n",
                result.warning.empty() ? "" : "  (fallback: singular to working precision)");
  }
  std::printf("\nTarget: N = %g under %g s on one core: %.3f s, %s\n", target_n, target_seconds,
              seconds_at_target, seconds_at_target < target_seconds ? "met" : "MISSED");
}

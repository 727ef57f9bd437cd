// bench_example_solves: the solve statements of the RBF examples, end to end,
// as partc generates them: examples/rbf_franke.part (interpolation with
// multiquadrics, `weights: solve w[i]: ...`) and examples/kansa_poisson.part
// (collocation of the Poisson problem with Gaussians, `collocation: solve
// lambda[i]: ...`), on n x n nodes, n = 10 to 40 (N = 100 to 1600).
//
// What is timed is the generated function of the solve statement: it
// allocates the dense N x N matrix, assembles it and the right side (a
// parallel_for over rows, here on one thread), calls partc::solve_dense (the
// input checks, LU, the rcond estimate, the substitutions, the residual) and
// copies x into the particles. Its SolveResult's own time splits that into
// solve and assembly (the rest: allocation and the copy too). Each figure is
// the median of `repetitions` calls on a model that init() has set up (Grid,
// the evaluation set, has m = 2 points: it is not timed and takes no time).
//
// The shape parameter is eps = 0.5 / h = 0.5 (n - 1), as in bench_solve: the
// examples' fixed defaults (eps = 3, eps = 6) make the larger systems singular
// to working precision, where solve_dense falls back to a complete orthogonal
// decomposition that takes 5-8 times as long as LU (rbf_franke at n = 40:
// rcond 3e-21, 2.4 s), and NumPy's LU on the same matrix would answer
// something else. kansa_poisson keeps its default basis (0, the Gaussian).
//
// The functions are private members of the generated classes: reached
// through explicit template instantiations, which are exempt from access
// checking ([temp.spec] in C++17). Their names are the generator's,
// init_<Set>_<variable> and <label>_solve_; if it renames them, this file
// stops compiling rather than timing something else.
//
// Output: a table on stdout; with an argument DIR, also each system as Matrix
// Market files DIR/<example>_n<n>_<unknown>.mtx and ..._rhs.mtx (the
// generated code's own --matrix-market writer, on a call that is not timed)
// and the figures, one line per system, in DIR/partc.txt, for
// example_solves.py, which solves the same matrices with NumPy and SciPy and
// prints them side by side.
//
// Usage: bench_example_solves [DIR]   (see .ci/bench)
#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

// Generated headers have no include guard: each is included exactly once.
#include "kansa_poisson.hpp"
#include "partc/parallel.hpp"
#include "rbf_franke.hpp"
#include "timing.hpp"

namespace {

// Expose<Tag, &Class::member>: get(Tag{}) returns the member pointer.
template <class Tag, typename Tag::type Member>
struct Expose {
  friend typename Tag::type get(Tag) { return Member; }
};

struct RbfSolveStatement {
  using type = void (RbfFranke::*)();
  friend type get(RbfSolveStatement);
};
struct RbfSolveResult {
  using type = partc::SolveResult RbfFranke::*;
  friend type get(RbfSolveResult);
};
struct KansaSolveStatement {
  using type = void (KansaPoisson::*)();
  friend type get(KansaSolveStatement);
};
struct KansaSolveResult {
  using type = partc::SolveResult KansaPoisson::*;
  friend type get(KansaSolveResult);
};
template struct Expose<RbfSolveStatement, &RbfFranke::init_Node_w>;
template struct Expose<RbfSolveResult, &RbfFranke::weights_solve_>;
template struct Expose<KansaSolveStatement, &KansaPoisson::init_Node_lambda>;
template struct Expose<KansaSolveResult, &KansaPoisson::collocation_solve_>;

constexpr int sides[] = {10, 20, 30, 40};  // N = 100, 400, 900, 1600
constexpr int repetitions = 5;
constexpr double eps_times_h = 0.5;

struct Figures {
  double total = 0, assembly = 0, solve = 0;  // medians, seconds
  std::string method;
  double rcond = std::nan(""), residual = 0, x_norm = 0;
};

// The 2-norm of variable `name` of the model's set Node (in id order = storage
// order: nothing has been removed or sorted).
template <class Model>
double node_norm(const Model& model, const std::string& name) {
  double sum = 0;
  model.for_each_set([&](const char* set, const auto& particles) {
    if (std::string(set) != "Node") return;
    particles.for_each_variable([&](const char* variable, const auto& values) {
      if (name != variable) return;
      if constexpr (std::is_same_v<typename std::decay_t<decltype(values)>::value_type, double>)
        for (const double v : values) sum += v * v;
    });
  });
  return std::sqrt(sum);
}

template <class Model, class StatementTag, class ResultTag>
Figures measure(Model& model, const std::string& unknown, const std::string& matrix_market) {
  const auto statement = get(StatementTag{});
  const auto result = get(ResultTag{});
  // init() runs the statement once already: with the Matrix Market files if asked.
  model.set_matrix_market(matrix_market);
  model.init();
  model.set_matrix_market("");
  std::vector<double> totals, assemblies, solves;
  for (int r = 0; r < repetitions; ++r) {
    totals.push_back(bench::seconds([&] { (model.*statement)(); }));
    solves.push_back((model.*result).seconds);
    assemblies.push_back(totals.back() - solves.back());
  }
  const partc::SolveResult& last = model.*result;
  Figures f;
  f.total = bench::median(totals);
  f.assembly = bench::median(assemblies);
  f.solve = bench::median(solves);
  f.method = last.method;
  f.rcond = last.rcond.value_or(std::nan(""));
  f.residual = last.residual;
  f.x_norm = node_norm(model, unknown);
  return f;
}

}  // namespace

template <class T>
struct Type {
  using type = T;
};

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "";
  if (argc > 2 || dir.rfind("-", 0) == 0) {
    std::printf("usage: bench_example_solves [DIR]  (DIR: also write the systems and figures)\n");
    return dir == "--help" || dir == "-h" ? 0 : 2;
  }
  std::FILE* figures_file = nullptr;
  if (!dir.empty() && !(figures_file = std::fopen((dir + "/partc.txt").c_str(), "w"))) {
    std::fprintf(stderr, "bench_example_solves: cannot write %s/partc.txt\n", dir.c_str());
    return 1;
  }
  Eigen::setNbThreads(1);
  std::printf(
      "The examples' solve statements as partc generates them, on n x n nodes, eps h = %g:\n"
      "the whole statement (allocation and assembly of the dense matrix, then solve_dense:\n"
      "checks, LU, rcond, substitutions, residual), and the solve alone; one thread,\n"
      "median of %d calls. Eigen %d.%d.%d (%s), %s.\n\n",
      eps_times_h, repetitions, EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION,
      Eigen::SimdInstructionSetsInUse(), __VERSION__);
  std::printf("%-14s %4s %6s %7s %10s %10s %10s %9s %9s  %s\n", "example", "n", "N", "eps",
              "whole s", "assembly s", "solve s", "rcond", "residual", "method");
  const auto row = [&](const char* example, const char* unknown, int n, double eps,
                       const Figures& f) {
    const int size = n * n;
    std::printf("%-14s %4d %6d %7.2f %10.3g %10.3g %10.3g %9.1e %9.1e  %s\n", example, n, size, eps,
                f.total, f.assembly, f.solve, f.rcond, f.residual, f.method.c_str());
    std::fflush(stdout);
    if (figures_file)
      std::fprintf(figures_file, "%s %s %d %.17g %.9g %.9g %.9g %.17g %.3g\n", example, unknown, n,
                   eps, f.total, f.assembly, f.solve, f.x_norm, f.rcond);
  };
  const std::string prefix = dir.empty() ? "" : dir + "/";
  const auto files = [&](const char* example, int n) {
    return dir.empty() ? "" : prefix + example + "_n" + std::to_string(n);
  };
  partc::with_threads(1, [&] {
    // Each example at each n, its shape parameter scaled with the node spacing.
    const auto example = [&](auto model_type, auto statement, auto result, const char* name,
                             const char* unknown) {
      using Model = typename decltype(model_type)::type;
      for (const int n : sides) {
        const double eps = eps_times_h * (n - 1);
        Model model;
        model.set_param("n", std::to_string(n));
        model.set_param("eps", std::to_string(eps));
        model.set_param("m", "2");
        row(name, unknown, n, eps,
            measure<Model, typename decltype(statement)::type, typename decltype(result)::type>(
                model, unknown, files(name, n)));
      }
    };
    example(Type<RbfFranke>{}, Type<RbfSolveStatement>{}, Type<RbfSolveResult>{}, "rbf_franke", "w");
    example(Type<KansaPoisson>{}, Type<KansaSolveStatement>{}, Type<KansaSolveResult>{},
            "kansa_poisson", "lambda");
  });
  if (figures_file) std::fclose(figures_file);
}

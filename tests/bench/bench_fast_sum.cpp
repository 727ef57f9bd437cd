// bench_fast_sum: the fast summation (partc/fast_sum/) against a vectorised
// direct sum, for the Coulomb kernel 1/r, multiquadrics sqrt(1 + (e r)^2)
// (e = 1, 3) and a Gaussian exp(-(e r)^2) (e = 3), uniform points in the unit
// cube and a Plummer sphere, in 3D, over a range of tol: the order chosen,
// the measured error (relative L2 and max, over 500 sampled targets, against
// the direct sum; charges uniform in [-1, 1]), the charges' cancellation the
// plan measured (cancellation.hpp), the plan and evaluation times
// (medians of --repeats), the direct sum's time, and the speed-up.
//
//   bench_fast_sum [--n 10000,100000] [--tols 1e-2,...] [--kernels coulomb,mq1,mq3,gauss3]
//                  [--dists uniform,plummer] [--field] [--threads 1] [--repeats 3] [--csv FILE]
//                  [--orders 2,4,6] [--blind] [--charge-seed 2]
//
// The plans are given the charges, as a model's fast sums are; --blind plans
// without them, as a matrix-free solve's products are (cancellation 1).
// --orders plans at the given orders instead of from tol (the tol column
// then shows 0): the comparison of the error model's prediction (column
// pred) with the measured error that error_model.hpp's calibration rests on.
// --charge-seed draws other charges (the points stay): for a smooth kernel
// the measured / predicted ratio moves from draw to draw (multiquadric e = 1,
// N = 1e4, order 2: 0.26 to 0.63 over seeds 2 to 7; 1/r: 0.52 to 0.70).
//
// N = 1e6 only when asked (--n 1000000): its plans and sums take minutes.
// The direct sum's time is measured on 1000 targets and scaled to all N
// (per pair it does not depend on which targets). Times are wall times on
// --threads threads (1 by default: core seconds).
//
// Built with -O3 -march=native -fno-math-errno (tests/bench/CMakeLists.txt),
// so the direct loops and the near field vectorise; exp does not without
// -ffast-math (glibc's vector exp), so the Gaussian's direct sum and near
// field are scalar, equally.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "../runtime/fast_sum_cases.hpp"
#include "partc/fast_sum/accuracy.hpp"
#include "partc/fast_sum/fmm.hpp"
#include "partc/parallel.hpp"
#include "timing.hpp"

using fast_sum_cases::Coulomb;
using fast_sum_cases::Gaussian;
using fast_sum_cases::Multiquadric;
using partc::Vec;
using partc::fast_sum::Accuracy;
using partc::fast_sum::Fmm;

namespace {

std::vector<Vec<3>> points(std::size_t n, const std::string& dist, unsigned seed) {
  return dist == "uniform" ? fast_sum_cases::uniform_points<3>(n, seed)
                           : fast_sum_cases::plummer_points<3>(n, seed);
}

// The vectorised direct sum at targets [0, count): coordinates as arrays.
template <class Kernel>
double direct_seconds(const std::vector<Vec<3>>& x, const std::vector<double>& q, Kernel kernel,
                      std::size_t count) {
  std::vector<double> xs(x.size()), ys(x.size()), zs(x.size()), out(count);
  for (std::size_t j = 0; j < x.size(); ++j) {
    xs[j] = x[j][0];
    ys[j] = x[j][1];
    zs[j] = x[j][2];
  }
  const double seconds = bench::seconds([&] {
    for (std::size_t i = 0; i < count; ++i) {
      const double xi = xs[i], yi = ys[i], zi = zs[i];
      double sum = 0;
#pragma omp simd reduction(+ : sum)
      for (std::size_t j = 0; j < x.size(); ++j) {
        const double dx = xs[j] - xi, dy = ys[j] - yi, dz = zs[j] - zi;
        sum += kernel(std::sqrt(dx * dx + dy * dy + dz * dz)) * q[j];
      }
      out[i] = sum;
    }
  });
  volatile double keep = out[0];
  (void)keep;
  return seconds;
}

struct Options {
  std::vector<double> ns{1e4, 1e5};
  std::vector<double> tols{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10};
  std::vector<std::string> kernels{"coulomb", "mq1", "mq3", "gauss3"};
  std::vector<std::string> dists{"uniform", "plummer"};
  std::vector<double> orders;  // fixed orders instead of tols, if any
  bool field = false, blind = false;
  int threads = 1, repeats = 3;
  unsigned charge_seed = 2;
  std::string csv;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}
std::vector<double> numbers(const std::string& s) {
  std::vector<double> out;
  for (const auto& item : split(s)) out.push_back(std::atof(item.c_str()));
  return out;
}

template <class Kernel>
void run(const Options& o, const std::string& name, Kernel kernel, const std::string& dist,
         std::size_t n, std::ofstream& csv) {
  const auto x = points(n, dist, 1);
  std::vector<double> q(n);
  std::mt19937_64 rng(o.charge_seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double& v : q) v = u(rng);
  const std::size_t sample = std::min<std::size_t>(n, 1000);
  std::vector<double> direct_runs;
  for (int r = 0; r < o.repeats; ++r) direct_runs.push_back(direct_seconds(x, q, kernel, sample));
  const double direct = bench::median(direct_runs) * double(n) / double(sample);
  std::vector<Accuracy> accuracies;
  for (double tol : o.tols) accuracies.push_back({tol, 0, o.field});
  if (!o.orders.empty()) accuracies.clear();
  for (double order : o.orders) accuracies.push_back({0, int(order), o.field});
  for (const Accuracy accuracy : accuracies) {
    const double tol = accuracy.tol;
    double predicted = 0, cancellation = 1;
    std::vector<double> plans, evals;
    partc::fast_sum::MeasuredError error;
    int order = 0;
    std::size_t leaf = 0;
    partc::with_threads(o.threads, [&] {
      for (int r = 0; r < o.repeats; ++r) {
        std::unique_ptr<Fmm<3, Kernel>> fmm;
        plans.push_back(bench::seconds([&] {
          fmm = std::make_unique<Fmm<3, Kernel>>(x, x, kernel, accuracy,
                                                 o.blind ? nullptr : q.data());
        }));
        order = fmm->order();
        predicted = fmm->predicted_error();
        leaf = fmm->stats().leaf_size;
        cancellation = fmm->stats().cancellation;
        if (o.field) {
          std::vector<Vec<3>> e(n);
          evals.push_back(bench::seconds([&] { fmm->field(q.data(), e.data()); }));
          if (r == 0) error = partc::fast_sum::measure_field(x, x, kernel, q.data(), e.data());
        } else {
          std::vector<double> phi(n);
          evals.push_back(bench::seconds([&] { fmm->potential(q.data(), phi.data()); }));
          if (r == 0)
            error = partc::fast_sum::measure_potential(x, x, kernel, q.data(), phi.data());
        }
      }
      return 0;
    });
    const double plan = bench::median(plans), eval = bench::median(evals);
    std::printf(
        "%-8s %-8s %8zu %7.0e %5d %6zu %9.2e %9.2e %9.2e %7.2f %9.3f %9.3f %10.2f %8.1f %8.1f "
        "%8.2f\n",
        name.c_str(), dist.c_str(), n, tol, order, leaf, predicted, error.rel_l2, error.max_rel,
        cancellation, plan, eval, direct, direct / eval, direct / (plan + eval),
        (plan + eval) * o.threads / double(n) * 1e6);
    std::fflush(stdout);
    if (csv)
      csv << name << ',' << dist << ',' << n << ',' << tol << ',' << order << ',' << leaf << ','
          << predicted << ',' << error.rel_l2 << ',' << error.max_rel << ',' << plan << ',' << eval
          << ',' << direct << ',' << (o.field ? "field" : "potential") << ',' << cancellation
          << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--field" || flag == "--blind") {
      (flag == "--field" ? o.field : o.blind) = true;
      continue;
    }
    if (i + 1 == argc) break;
    const std::string value = argv[++i];
    if (flag == "--n")
      o.ns = numbers(value);
    else if (flag == "--tols")
      o.tols = numbers(value);
    else if (flag == "--orders")
      o.orders = numbers(value);
    else if (flag == "--kernels")
      o.kernels = split(value);
    else if (flag == "--dists")
      o.dists = split(value);
    else if (flag == "--threads")
      o.threads = std::atoi(value.c_str());
    else if (flag == "--repeats")
      o.repeats = std::atoi(value.c_str());
    else if (flag == "--charge-seed")
      o.charge_seed = static_cast<unsigned>(std::atoi(value.c_str()));
    else if (flag == "--csv")
      o.csv = value;
    else {
      std::fprintf(stderr, "bench_fast_sum: unknown option %s\n", flag.c_str());
      return 2;
    }
  }
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    csv << "kernel,distribution,n,tol,order,leaf_size,predicted,rel_l2,max_rel,plan_s,eval_s,"
           "direct_s,sum,cancellation\n";
  }
  std::printf("%s on %d thread(s), medians of %d%s\n", o.field ? "field" : "potential", o.threads,
              o.repeats, o.blind ? ", planned without the charges" : "");
  std::printf("%-8s %-8s %8s %7s %5s %6s %9s %9s %9s %7s %9s %9s %10s %8s %8s %8s\n", "kernel",
              "dist", "N", "tol", "order", "leaf", "pred", "rel_L2", "max_rel", "cancel", "plan_s",
              "eval_s", "direct_s", "x_eval", "x_total", "us/pt");
  for (double n : o.ns)
    for (const auto& dist : o.dists)
      for (const auto& k : o.kernels) {
        if (k == "coulomb") run(o, k, Coulomb{}, dist, std::size_t(n), csv);
        if (k == "mq1") run(o, k, Multiquadric{1}, dist, std::size_t(n), csv);
        if (k == "mq3") run(o, k, Multiquadric{3}, dist, std::size_t(n), csv);
        if (k == "gauss3") run(o, k, Gaussian{3}, dist, std::size_t(n), csv);
      }
}

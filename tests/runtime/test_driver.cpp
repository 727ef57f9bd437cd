// driver.hpp end to end, through a small hand-written model that satisfies the
// Model concept the compiler generates: every bad argument gives exit 2 and
// its message, data files round-trip exactly, VTK series appear, and a NaN
// gives exit 3 with no --output file.
#include <catch2/catch.hpp>

#include "sample_set.hpp"
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "partc/driver.hpp"
#include "partc/errors.hpp"
#include "partc/finite.hpp"
#include "partc/io/csv.hpp"
#include "partc/model_support.hpp"
#include "partc/particle_set.hpp"
#include "partc/rng.hpp"
#include "partc/vec.hpp"

namespace fs = std::filesystem;
using partc::Vec;

fs::path scratch_directory();  // test_io.cpp: one fresh directory per test run

namespace {


// N particles drawn uniformly in the unit square, pulled towards its centre
// with strength c; e accumulates kinetic energy, so a NaN in it stays.
// nan_at = K (K >= 1) puts a NaN into e of the last particle at step K.
class Toy {
 public:
  static constexpr const char* model_name = "toy";

  static std::vector<partc::ParamInfo> param_info() {
    return {{"N", "int", "4"}, {"c", "real", "0.25"}, {"nan_at", "int", "0"}};
  }

  void set_seed(std::uint64_t seed) { rng_ = partc::CounterRng(seed); }

  void set_param(const std::string& name, const std::string& value) {
    if (name == "N")
      n_ = partc::parse_param<std::int64_t>(name, value);
    else if (name == "c")
      c_ = partc::parse_param<double>(name, value);
    else if (name == "nan_at")
      nan_at_ = partc::parse_param<std::int64_t>(name, value);
    else
      throw partc::UsageError("unknown parameter '" + name + "' (parameters: N, c, nan_at)");
  }

  void init() {
    for (std::int64_t i = 0; i < n_; ++i) {
      const auto id = static_cast<std::uint64_t>(p_.next_id());
      p_.push_back(Vec<2>{{rng_.uniform(id, 0, 0, 0), rng_.uniform(id, 0, 0, 1)}});
    }
  }

  void load(const std::map<std::string, partc::CsvTable>& tables) {
    if (const auto table = tables.find("P"); table != tables.end())
      partc::load_set(table->second, p_);
  }

  void step() {
    ++step_;
    auto& v = p_.get<sample::P_v>();
    auto& e = p_.get<sample::P_e>();
    for (std::size_t i = 0; i < p_.size(); ++i) {
      v[i] += c_ * (Vec<2>::filled(0.5) - p_.positions()[i]);
      p_.positions()[i] += v[i];
      e[i] += 0.5 * squared_norm(v[i]);
      p_.get<sample::P_hits>()[i] += 1;
      p_.get<sample::P_moving>()[i] = norm(v[i]) > 0.01;
    }
    if (step_ == nan_at_ && !p_.empty()) e.back() = std::nan("");
  }

  std::int64_t step_count() const { return step_; }

  template <class F>
  void for_each_set(F&& f) const {
    f("P", p_);
  }

  void check_finite() const { partc::check_finite(p_, "P", step_); }

  // As if one search over P were rebuilt and walked every step.
  std::vector<partc::SearchReport> search_report() const {
    return {{"sums over P", "cell list, 4 cells", static_cast<std::size_t>(step_),
             static_cast<std::size_t>(step_)}};
  }

 private:
  partc::CounterRng rng_;
  std::int64_t n_ = 4;
  double c_ = 0.25;
  std::int64_t nan_at_ = 0;
  std::int64_t step_ = 0;
  sample::Set p_;
};

// Toy plus a second set Q that only a file fills: the multi-set paths.
class TwoSets : public Toy {
 public:
  static constexpr const char* model_name = "two";

  void load(const std::map<std::string, partc::CsvTable>& tables) {
    Toy::load(tables);
    if (const auto table = tables.find("Q"); table != tables.end())
      partc::load_set(table->second, q_);
  }

  template <class F>
  void for_each_set(F&& f) const {
    Toy::for_each_set(f);
    f("Q", q_);
  }

  void check_finite() const {
    Toy::check_finite();
    partc::check_finite(q_, "Q", step_count());
  }

 private:
  sample::Set q_;
};

// Toy with a log of its step count every 4 steps, whose step(observed) notes
// the steps the driver says will be read.
class Observing : public Toy {
 public:
  static constexpr const char* model_name = "observing";
  static std::vector<std::string> log_columns() { return {"step"}; }
  std::int64_t log_every() const { return 4; }
  std::vector<double> log_row() const { return {static_cast<double>(step_count())}; }

  void step(bool observed = true) {
    if (observed) observed_steps.push_back(step_count() + 1);
    Toy::step();
  }
  inline static std::vector<std::int64_t> observed_steps;
};

struct Run {
  int status;
  std::string out, err;
};

template <class Model = Toy>
Run run(std::vector<std::string> args) {
  args.insert(args.begin(), "./toy");
  std::vector<char*> argv;
  for (auto& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::ostringstream out, err;
  const int status = partc::run_driver<Model>(static_cast<int>(args.size()), argv.data(), out, err);
  return {status, out.str(), err.str()};
}

std::string path_in(const std::string& directory, const std::string& file) {
  fs::create_directories(scratch_directory() / directory);
  return (scratch_directory() / directory / file).string();
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The first line of the error output; the second is the usage hint.
std::string usage_error(const std::vector<std::string>& args) {
  const Run result = run(args);
  CHECK(result.status == 2);
  CHECK(result.out.empty());
  const auto newline = result.err.find('\n');
  CHECK(result.err.substr(newline + 1).rfind("usage: toy [--steps K]", 0) == 0);
  return result.err.substr(0, newline);
}

}  // namespace

TEST_CASE("driver: every bad argument is exit 2 with a precise message", "[driver]") {
  CHECK(usage_error({"--frobnicate"}) == "toy: error: unknown option '--frobnicate'");
  CHECK(usage_error({"stray.csv"}) ==
        "toy: error: unexpected argument 'stray.csv' (options start with --)");
  CHECK(usage_error({"--steps"}) == "toy: error: option --steps needs a value");
  CHECK(usage_error({"--output", "--quiet"}) == "toy: error: option --output needs a value");
  CHECK(usage_error({"--steps="}) == "toy: error: option --steps needs a value");
  CHECK(usage_error({"--steps", "ten"}) ==
        "toy: error: --steps expects a non-negative integer, got 'ten'");
  CHECK(usage_error({"--steps=-3"}) ==
        "toy: error: --steps expects a non-negative integer, got '-3'");
  CHECK(usage_error({"--seed", "1.5"}) ==
        "toy: error: --seed expects a non-negative integer, got '1.5'");
  CHECK(usage_error({"--every", "0"}) ==
        "toy: error: --every must be at least 1 (step 0 is always written)");
  CHECK(usage_error({"--quiet=yes"}) == "toy: error: option --quiet takes no value");
  CHECK(usage_error({"--set", "M=3"}) ==
        "toy: error: unknown parameter 'M' (parameters: N, c, nan_at)");
  CHECK(usage_error({"--set", "N=abc"}) == "toy: error: parameter N expects an int, got 'abc'");
  CHECK(usage_error({"--set", "N"}) == "toy: error: --set expects NAME=VALUE, got 'N'");
  CHECK(usage_error({"--input", "Q=x.csv"}) ==
        "toy: error: --input Q=x.csv: the model has no set 'Q' (sets: P)");
  CHECK(usage_error({"--input", "a.csv", "--input", "P=b.csv"}) ==
        "toy: error: --input given twice for set 'P'");
  CHECK(usage_error({"--output", "no-such-dir/out.csv"}) ==
        "toy: error: --output no-such-dir/out.csv: directory 'no-such-dir' does not exist");
  // Arguments are all checked before any work: no output from a run that fails late.
  const std::string output = path_in("late", "out.csv");
  CHECK(usage_error({"--output", output, "--steps", "2", "--bogus"}) ==
        "toy: error: unknown option '--bogus'");
  CHECK_FALSE(fs::exists(output));

  const Run several = run<TwoSets>({"--input", "x.csv"});
  CHECK(several.status == 2);
  CHECK(several.err.rfind("two: error: --input x.csv: say which set the file is for, as --input "
                          "SET=x.csv (sets: P, Q)\nusage: two ",
                          0) == 0);
}

TEST_CASE("driver: --help lists the options and the model's parameters", "[driver]") {
  const Run result = run({"--steps", "oops", "--help"});
  CHECK(result.status == 0);
  CHECK(result.err.empty());
  CHECK(result.out.rfind("usage: toy ", 0) == 0);
  CHECK(result.out.find("(particle sets: P)") != std::string::npos);
  CHECK(result.out.find("  --check-every M ") != std::string::npos);
  CHECK(result.out.find("  c                  real   default 0.25\n") != std::string::npos);
}

TEST_CASE("driver: a run prints a summary per set unless --quiet", "[driver]") {
  const Run result = run({"--steps", "3", "--seed", "5", "--set", "N=6"});
  INFO(result.out);
  CHECK(result.status == 0);
  CHECK(result.err.empty());
  CHECK(result.out.rfind("toy: 3 steps, seed 5, ", 0) == 0);
  // p 16 (2 doubles) + id 8 + alive 1 + v 16 + e 8 + hits 8 (an int64) + moving 1 (a byte).
  CHECK(result.out.find("\nP: 6 particles, 58 bytes each\n") != std::string::npos);
  CHECK(result.out.find("\n  |v|  ") != std::string::npos);
  // hits counts the steps, so its min, mean and max are all 3.
  CHECK(result.out.find("\n  hits" + std::string(21, ' ') + "3" + std::string(13, ' ') + "3" +
                        std::string(13, ' ') + "3\n") != std::string::npos);
  CHECK(result.out.find("\nneighbour searches:\n  sums over P: cell list, 4 cells; built 3 times, "
                        "walked 3 times\n") != std::string::npos);

  const Run quiet = run({"--steps", "3", "--quiet"});
  CHECK(quiet.status == 0);
  CHECK(quiet.out.empty());
}

TEST_CASE("driver: --output then --input continues a run exactly", "[driver]") {
  const std::string three = path_in("round", "three.csv"), five = path_in("round", "five.csv"),
                    again = path_in("round", "again.csv"),
                    resumed = path_in("round", "resumed.csv");
  REQUIRE(run({"--steps", "3", "--seed", "9", "--output", three, "--quiet"}).status == 0);
  REQUIRE(run({"--steps", "5", "--seed", "9", "--output", five, "--quiet"}).status == 0);
  // Reading and writing with no step in between changes no byte.
  REQUIRE(run({"--input", three, "--steps", "0", "--output", again, "--quiet"}).status == 0);
  CHECK(read_file(again) == read_file(three));
  // 3 steps, saved, then 2 more: bit for bit the 5-step run (the toy has no
  // random numbers after init).
  const Run resume = run({"--input", "P=" + three, "--steps=2", "--output=" + resumed, "--quiet"});
  REQUIRE(resume.status == 0);
  CHECK(read_file(resumed) == read_file(five));
  CHECK(read_file(five).rfind("id,p_0,p_1,v_0,v_1,e,hits,moving\n0,", 0) == 0);
}

TEST_CASE("driver: a bad data file is exit 1 with the file's message", "[driver]") {
  const std::string bad = path_in("bad", "bad.csv");
  std::ofstream(bad) << "id,p_0,p_1\n0,0.5,0.5\n1,0.5,oops\n";
  const Run result = run({"--input", bad});
  CHECK(result.status == 1);
  CHECK(result.err == bad +
                          ":3:7: error: expected a number, got 'oops' in column 'p_1'\n"
                          "1,0.5,oops\n"
                          "      ^\n");
  const Run missing = run({"--input", path_in("bad", "missing.csv")});
  CHECK(missing.status == 1);
  CHECK(missing.err.find("cannot open: No such file or directory") != std::string::npos);
}

TEST_CASE("driver: --vtk writes a .pvd and a .vtu every --every steps", "[driver]") {
  const std::string prefix = path_in("vtk", "run");
  const Run result = run({"--steps", "5", "--every", "2", "--vtk", prefix, "--quiet"});
  REQUIRE(result.status == 0);
  CHECK(fs::exists(prefix + "_P.pvd"));
  for (const char* step : {"000000", "000002", "000004"})
    CHECK(fs::exists(prefix + "_P_" + step + ".vtu"));
  CHECK_FALSE(fs::exists(prefix + "_P_000001.vtu"));
  CHECK_FALSE(fs::exists(prefix + "_P_000005.vtu"));
  const std::string pvd = read_file(prefix + "_P.pvd");
  CHECK(pvd.find("timestep=\"4\" part=\"0\" file=\"run_P_000004.vtu\"") != std::string::npos);
  CHECK(read_file(prefix + "_P_000004.vtu")
            .find("<Piece NumberOfPoints=\"4\" NumberOfCells=\"4\">") != std::string::npos);
}

// A step is observed when the log shows or writes its row, a VTK frame is
// written, or it is the last; the log gets rows of observed steps only.
TEST_CASE("driver: observes the steps it logs, writes as frames, and the last", "[driver]") {
  const auto observed = [](std::vector<std::string> args) {
    Observing::observed_steps.clear();
    args.insert(args.end(), {"--steps", "10"});
    REQUIRE(run<Observing>(args).status == 0);
    return Observing::observed_steps;
  };
  using Steps = std::vector<std::int64_t>;
  CHECK(observed({"--quiet"}) == Steps{10});
  CHECK(observed({}) == Steps{4, 8, 10});
  CHECK(observed({"--log-every", "5"}) == Steps{5, 10});
  const std::string log = path_in("observed", "log.csv");
  CHECK(observed({"--quiet", "--log", log, "--log-file-every", "3"}) == Steps{3, 6, 9, 10});
  CHECK(read_file(log) == "step\n0\n3\n6\n9\n10\n");
  CHECK(observed({"--quiet", "--log", log}).size() == 10);
  CHECK(observed({"--quiet", "--vtk", path_in("observed", "run"), "--every", "5"}) == Steps{5, 10});
  const Run zero = run<Observing>({"--log-file-every", "0"});
  CHECK(zero.status == 2);
  CHECK(zero.err.rfind("observing: error: --log-file-every must be at least 1", 0) == 0);
}

TEST_CASE("driver: a NaN is exit 3 with variable, id and step, and no --output", "[driver]") {
  const std::string output = path_in("nan", "out.csv");
  const Run result = run({"--set", "nan_at=2", "--steps", "5", "--output", output});
  CHECK(result.status == 3);
  CHECK(result.out.empty());
  const std::string kept = path_in("nan", "out.last-finite.csv");
  CHECK(result.err ==
        "toy: error: numerical blow-up: variable 'e' of particle id 3 is nan at step 2 (set P)\n"
        "toy: note: the last state found finite, at step 1, is in " +
            kept + " (--input reads it back)\n");
  CHECK_FALSE(fs::exists(output));
  CHECK_FALSE(fs::exists(output + ".tmp"));
  CHECK(fs::exists(kept));

  // Checking every 4 steps of 3 still checks the final state before writing it.
  const Run sparse =
      run({"--set", "nan_at=2", "--steps", "3", "--check-every", "4", "--output", output});
  CHECK(sparse.status == 3);
  CHECK(sparse.err.find("is nan at step 3") != std::string::npos);
  CHECK_FALSE(fs::exists(output));

  // --check-every 0 is the user's choice to run on.
  CHECK(run({"--set", "nan_at=2", "--steps", "3", "--check-every", "0", "--quiet"}).status == 0);
}

TEST_CASE("driver: several sets take SET=FILE inputs and write FILE_SET outputs", "[driver]") {
  const std::string p = path_in("two", "p.csv"), q = path_in("two", "q.csv"),
                    output = path_in("two", "out.csv");
  std::ofstream(p) << "id,p_0,p_1\n7,0.25,0.75\n";
  std::ofstream(q) << "p_0,p_1\n0.5,0.5\n0.125,0.5\n";
  const Run result =
      run<TwoSets>({"--input", "Q=" + q, "--input", "P=" + p, "--steps", "1", "--output", output});
  REQUIRE(result.status == 0);
  CHECK(result.out.find("\nP: 1 particle, ") != std::string::npos);
  CHECK(result.out.find("\nQ: 2 particles, ") != std::string::npos);
  CHECK(read_file(path_in("two", "out_Q.csv")) ==
        "id,p_0,p_1,v_0,v_1,e,hits,moving\n0,0.5,0.5,0,0,0,0,0\n1,0.125,0.5,0,0,0,0,0\n");
  const std::string p_out = read_file(path_in("two", "out_P.csv"));
  CHECK(p_out.rfind("id,p_0,p_1,v_0,v_1,e,hits,moving\n7,", 0) == 0);
  CHECK_FALSE(fs::exists(output));
}

// partc/driver.cpp: the driver's command line, --help and exit statuses,
// the same for every model (driver.hpp says what the options do; the run
// itself is run_model.cpp).
#include "partc/driver.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <system_error>

namespace partc {

namespace detail {

std::string usage_line(const std::string& model) {
  return "usage: " + model +
         " [--steps K] [--seed S] [--set NAME=VALUE]... [--input [SET=]FILE.csv]..."
         " [--output FILE.csv] [--vtk PREFIX] [--every M] [--check-every M]"
         " [--last-finite FILE.csv] [--log FILE.csv] [--log-every M] [--log-file-every M]"
         " [--stage NAME[:K]]... [--matrix-market PREFIX] [--check-accuracy] [--quiet] [--help]";
}

std::string path_for_set(const std::string& path, const std::string& set) {
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "_" + set + p.extension().string())).string();
}

namespace {

template <class Int>
Int parse_count(const std::string& option, const std::string& text) {
  Int value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc() || stop != end || text[0] == '-')
    throw UsageError(option + " expects a non-negative integer, got '" + text + "'");
  return value;
}

void require_directory_of(const std::string& option, const std::string& path) {
  const std::filesystem::path directory = std::filesystem::path(path).parent_path();
  if (!directory.empty() && !std::filesystem::is_directory(directory))
    throw UsageError(option + " " + path + ": directory '" + directory.string() +
                     "' does not exist");
}

}  // namespace

DriverOptions parse_driver_options(const ModelFacts& facts, const std::vector<std::string>& args) {
  const std::vector<std::string>& sets = facts.sets;
  DriverOptions options;
  for (std::size_t a = 0; a < args.size(); ++a) {
    std::string option = args[a];
    std::optional<std::string> attached;  // the value of "--option=value"
    if (const auto equals = option.find('=');
        option.rfind("--", 0) == 0 && equals != std::string::npos) {
      attached = option.substr(equals + 1);
      option.resize(equals);
    }
    // A following "--x" is taken for a forgotten value, not as the value.
    const auto value = [&]() -> std::string {
      if (attached) {
        if (attached->empty()) throw UsageError("option " + option + " needs a value");
        return *attached;
      }
      if (a + 1 == args.size() || args[a + 1].empty() || args[a + 1].rfind("--", 0) == 0)
        throw UsageError("option " + option + " needs a value");
      return args[++a];
    };

    if (option == "--quiet") {
      if (attached) throw UsageError("option --quiet takes no value");
      options.quiet = true;
    } else if (option == "--steps") {
      options.steps = parse_count<std::int64_t>(option, value());
    } else if (option == "--seed") {
      options.seed = parse_count<std::uint64_t>(option, value());
    } else if (option == "--every") {
      options.every = parse_count<std::int64_t>(option, value());
      if (options.every == std::int64_t{0})
        throw UsageError("--every must be at least 1 (step 0 is always written)");
    } else if (option == "--check-every") {
      options.check_every = parse_count<std::int64_t>(option, value());
    } else if (option == "--last-finite") {
      options.last_finite = value();
      require_directory_of(option, options.last_finite);
    } else if (option == "--set") {
      const std::string assignment = value();
      const auto equals = assignment.find('=');
      if (equals == std::string::npos || equals == 0)
        throw UsageError("--set expects NAME=VALUE, got '" + assignment + "'");
      facts.set_param(assignment.substr(0, equals), assignment.substr(equals + 1));
    } else if (option == "--input") {
      const std::string spec = value();
      const auto equals = spec.find('=');
      std::string set = sets.size() == 1 ? sets[0] : "", file = spec;
      if (equals != std::string::npos) {
        set = spec.substr(0, equals);
        file = spec.substr(equals + 1);
        if (std::find(sets.begin(), sets.end(), set) == sets.end())
          throw UsageError("--input " + spec + ": the model has no set '" + set +
                           "' (sets: " + join(sets) + ")");
      } else if (sets.size() != 1) {
        throw UsageError("--input " + spec + ": say which set the file is for, as --input SET=" +
                         spec + " (sets: " + join(sets) + ")");
      }
      if (file.empty()) throw UsageError("--input " + spec + ": no file name");
      for (const auto& [other, ignored] : options.inputs)
        if (other == set) throw UsageError("--input given twice for set '" + set + "'");
      options.inputs.emplace_back(set, file);
    } else if (option == "--output") {
      options.output = value();
      require_directory_of(option, options.output);
    } else if (option == "--log" || option == "--log-every" || option == "--log-file-every") {
      if (!facts.logs)
        throw UsageError("option " + option + ": model " + facts.name +
                         " logs no observables (its .part file has no 'output' line)");
      if (option == "--log") {
        options.log = value();
        require_directory_of(option, options.log);
      } else if (option == "--log-every") {
        options.log_every = parse_count<std::int64_t>(option, value());
      } else {
        options.log_file_every = parse_count<std::int64_t>(option, value());
        if (options.log_file_every == 0)
          throw UsageError("--log-file-every must be at least 1 (step 0 is always written)");
      }
    } else if (option == "--stage") {
      const std::string spec = value();
      const auto colon = spec.find(':');
      const std::string name = spec.substr(0, colon);
      const std::vector<std::string>& known = facts.stages;
      if (std::find(known.begin(), known.end(), name) == known.end())
        throw UsageError("--stage " + spec + ": model " + facts.name +
                         (known.empty()
                              ? " has no named stage"
                              : " has no stage '" + name + "' (stages: " + join(known) + ")"));
      options.stages.emplace_back(name,
                                  colon == std::string::npos
                                      ? 1
                                      : parse_count<std::int64_t>(option, spec.substr(colon + 1)));
    } else if (option == "--matrix-market") {
      if (!facts.solves)
        throw UsageError("option --matrix-market: model " + facts.name + " has no solve statement");
      options.matrix_market = value();
      require_directory_of(option, options.matrix_market);
    } else if (option == "--check-accuracy") {
      if (!facts.fast_sums)
        throw UsageError("option --check-accuracy: model " + facts.name +
                         " has no fast sum (dense = fmm)");
      if (attached) throw UsageError("option --check-accuracy takes no value");
      options.check_accuracy = true;
    } else if (option == "--vtk") {
      options.vtk_prefix = value();
      require_directory_of(option, options.vtk_prefix);
    } else if (option.rfind("-", 0) == 0) {
      throw UsageError("unknown option '" + args[a] + "'");
    } else {
      throw UsageError("unexpected argument '" + args[a] + "' (options start with --)");
    }
  }
  return options;
}

void print_help(std::ostream& out, const ModelFacts& facts) {
  const std::string& name = facts.name;
  std::ostringstream text;
  text
      << usage_line(name) << "\n\n"
      << "Runs the partc model " << name << " (particle sets: " << join(facts.sets) << ").\n\n"
      << "  --steps K            number of steps (default 10)\n"
      << "  --seed S             random seed (default 0)\n"
      << "  --set NAME=VALUE     set a parameter; repeatable\n"
      << "  --input FILE.csv     start from a file instead of init; with several sets\n"
      << "                       --input SET=FILE.csv, once per set (the others start empty)\n"
      << "  --output FILE.csv    write the final state (FILE_SET.csv with several sets)\n"
      << "  --vtk PREFIX         write ParaView series PREFIX_SET.pvd + PREFIX_SET_NNNNNN.vtu\n"
      << "  --every M            VTK every M steps (default: the model's output interval, else 1;\n"
      << "                       step 0 is always written)\n"
      << "  --check-every M      NaN/Inf check every M steps (default 1; 0 turns it off)\n"
      << "  --last-finite F.csv  on a blow-up, write the last state found finite to F.csv\n"
      << "                       (default OUTPUT.last-finite.csv, else " << name
      << ".last-finite.csv)\n";
  if (!facts.stages.empty())
    text << "  --stage NAME[:K]     run a named stage K times (default 1) after init, before\n"
         << "                       the steps; repeatable, in order (stages: " << join(facts.stages)
         << ")\n";
  if (facts.solves)
    text << "  --matrix-market P    write each solve's matrix and right side to P_NAME.mtx,\n"
         << "                       P_NAME_rhs.mtx (Matrix Market)\n";
  if (facts.fast_sums)
    text << "  --check-accuracy     check every fast sum against the direct sum on a sample of\n"
         << "                       targets; an error above its tolerance stops the run (exit 3)\n";
  if (facts.logs)
    text << "  --log FILE.csv       write the logged observables every step (columns: "
         << join(facts.log_columns) << ")\n"
         << "  --log-every M        a progress row every M steps (default " << facts.log_every
         << "; 0: none)\n"
         << "  --log-file-every M   a row in --log's file every M steps (default 1; the first and\n"
         << "                       the last always)\n";
  text << "  --quiet              no summary at the end\n"
       << "  --help               this text\n\n"
       << "Parameters:\n";
  const std::vector<ParamInfo>& params = facts.params;
  if (params.empty()) text << "  (none)\n";
  for (const ParamInfo& param : params)
    text << "  " << std::left << std::setw(18) << param.name << " " << std::setw(6) << param.type
         << " default " << param.default_value << "\n";
  text << "\nExit status: 0 success, 1 bad input file or I/O failure, 2 bad arguments,\n"
       << "3 numerical blow-up (NaN or Inf in a variable).\n";
  out << text.str();
}

int exit_status_of(const std::string& model, std::ostream& err, const std::function<void()>& run) {
  try {
    run();
    return 0;
  } catch (const UsageError& e) {
    err << model << ": error: " << e.what() << "\n" << usage_line(model) << "\n";
    return 2;
  } catch (const InputError& e) {
    err << e.what() << "\n";  // already "file:line:col: error: ..."
    return 1;
  } catch (const NumericalError& e) {
    err << model << ": error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    err << model << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace detail

}  // namespace partc

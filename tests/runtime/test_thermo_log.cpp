// ThermoLog: which rows reach the terminal, and that the CSV file holds
// every row, exactly, read back with the runtime's own CSV reader.
#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "partc/io/csv.hpp"
#include "partc/io/thermo_log.hpp"

namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

}  // namespace

TEST_CASE("thermo log: a header, every k-th row and the last on the terminal", "[io][log]") {
  std::ostringstream terminal;
  partc::ThermoLog log({"step", "e"}, &terminal, 4, "");
  for (int step = 0; step <= 10; ++step) log.row(step, {double(step), 0.5 * step});
  log.close();
  const std::vector<std::string> lines = lines_of(terminal.str());
  REQUIRE(lines.size() == 5);  // header, steps 0, 4, 8 and the last, 10
  CHECK(lines[0] == "        step           e");
  CHECK(lines[1] == "           0           0");
  CHECK(lines[2] == "           4           2");
  CHECK(lines[3] == "           8           4");
  CHECK(lines[4] == "          10           5");
}

TEST_CASE("thermo log: the last row is not shown twice, and every = 0 shows none", "[io][log]") {
  std::ostringstream shown, silent;
  partc::ThermoLog every_two({"step"}, &shown, 2, "");
  partc::ThermoLog none({"step"}, &silent, 0, "");
  for (int step = 0; step <= 4; ++step) {
    every_two.row(step, {double(step)});
    none.row(step, {double(step)});
  }
  every_two.close();
  none.close();
  CHECK(lines_of(shown.str()).size() == 4);  // header, 0, 2, 4
  CHECK(silent.str().empty());
}

TEST_CASE("thermo log: the CSV file holds every row and reads back exactly", "[io][log]") {
  const std::string path =
      (std::filesystem::temp_directory_path() / "partc_test_thermo_log.csv").string();
  const double third = 1.0 / 3.0;
  {
    partc::ThermoLog log({"step", "t", "e_0", "e_1"}, nullptr, 10, path);
    for (int step = 0; step < 7; ++step)
      log.row(step, {double(step), step * 0.1, third * step, -1e-300});
    log.close();
  }
  const partc::CsvTable table = partc::read_csv(path);
  REQUIRE(table.header == std::vector<std::string>{"step", "t", "e_0", "e_1"});
  REQUIRE(table.rows.size() == 7);
  for (int step = 0; step < 7; ++step) {
    CHECK(table.rows[step][0] == step);
    CHECK(table.rows[step][1] == step * 0.1);
    CHECK(table.rows[step][2] == third * step);
    CHECK(table.rows[step][3] == -1e-300);
  }
  std::filesystem::remove(path);
}

// The driver computes a row only for the steps the log uses and the last:
// what it gets then is what it writes and shows.
TEST_CASE("thermo log: the rows it uses, and a CSV file of every k-th row and the last",
          "[io][log]") {
  const std::string path =
      (std::filesystem::temp_directory_path() / "partc_test_thermo_log_every.csv").string();
  std::ostringstream terminal;
  {
    partc::ThermoLog log({"step", "e"}, &terminal, 4, path, 3);
    std::vector<int> used;
    for (int step = 0; step <= 10; ++step)
      if (log.uses(step) || step == 10) {
        used.push_back(step);
        log.row(step, {double(step), 0.5 * step});
      }
    log.close();
    CHECK(used == std::vector<int>{0, 3, 4, 6, 8, 9, 10});
  }
  const partc::CsvTable table = partc::read_csv(path);
  const std::vector<double> steps = {0, 3, 6, 9, 10};  // every third and the last
  REQUIRE(table.rows.size() == steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) CHECK(table.rows[k][0] == steps[k]);
  CHECK(lines_of(terminal.str()).size() == 5);  // header, 0, 4, 8, 10
  partc::ThermoLog quiet({"step"}, nullptr, 4, "");
  CHECK_FALSE(quiet.uses(0));
  std::filesystem::remove(path);
}

TEST_CASE("thermo log: an unwritable path is an error naming it", "[io][log]") {
  CHECK_THROWS_WITH(partc::ThermoLog({"step"}, nullptr, 1, "/nonexistent/dir/log.csv"),
                    Catch::Contains("cannot open '/nonexistent/dir/log.csv'"));
}

// csv.hpp, vtk.hpp and finite.hpp: every complaint about a bad file is checked
// word for word (location, line, caret), written files are read back, and the
// VTK output is parsed as XML.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include "sample_set.hpp"
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "partc/errors.hpp"
#include "partc/finite.hpp"
#include "partc/io/csv.hpp"
#include "partc/io/vtk.hpp"
#include "partc/particle_set.hpp"
#include "partc/vec.hpp"

namespace fs = std::filesystem;
using partc::Vec;

// One fresh directory per test run, removed at exit; test_driver.cpp uses it too.
fs::path scratch_directory() {
  struct Directory {
    fs::path path;
    Directory() {
      std::string pattern = (fs::temp_directory_path() / "partc-runtime-io-XXXXXX").string();
      if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
      path = pattern;
    }
    ~Directory() { fs::remove_all(path); }
  };
  static const Directory directory;
  return directory.path;
}

namespace {

using namespace sample;  // P_v, P_e, P_hits, P_moving, Set

std::string file_path(const std::string& name) { return (scratch_directory() / name).string(); }

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = file_path(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The message read_csv gives for a file holding `text`, with the path as "F".
std::string csv_error(const std::string& text) {
  const std::string path = write_file("bad.csv", text);
  try {
    partc::read_csv(path);
  } catch (const partc::InputError& e) {
    std::string message = e.what();
    REQUIRE(message.compare(0, path.size(), path) == 0);
    return "F" + message.substr(path.size());
  }
  FAIL("read_csv accepted: " << text);
  return "";
}

// Three particles stored in the order of ids 5, 1, 3, with values that are
// hard to round-trip.
Set sample_set() {
  Set set;
  set.push_back_with_id(Vec<2>{{0.1, -0.0}}, 5);
  set.push_back_with_id(Vec<2>{{1.0, 2.0}}, 1);
  set.push_back_with_id(Vec<2>{{-3e-7, 1e300}}, 3);
  set.get<P_v>() = {Vec<2>{{1.0 / 3, 1e-300}}, Vec<2>{{0, 0}}, Vec<2>{{-2.5, 4.9e-324}}};
  set.get<P_e>() = {2.5, 0, 123456789.125};
  set.get<P_hits>() = {-7, 0, (std::int64_t{1} << 53)};
  set.get<P_moving>() = {1, 0, 1};
  return set;
}

}  // namespace

TEST_CASE("read_csv reads numbers, tolerating spaces, CRLF, a BOM and trailing blank lines",
          "[csv]") {
  const std::string path = write_file(
      "good.csv", "\xEF\xBB\xBFid , p_0,\tp_1\r\n0, 1.5 ,-2e-3\r\n1,+4,  .25\r\n\r\n  \n");
  const partc::CsvTable table = partc::read_csv(path);
  CHECK(table.path == path);
  CHECK(table.header == std::vector<std::string>{"id", "p_0", "p_1"});
  CHECK(table.rows == std::vector<std::vector<double>>{{0, 1.5, -2e-3}, {1, 4, 0.25}});
  CHECK(table.lines == std::vector<std::size_t>{2, 3});
  CHECK(table.column("p_1") == 2);
  CHECK(table.column("q") == -1);
}

TEST_CASE("read_csv accepts a header without rows", "[csv]") {
  const partc::CsvTable table = partc::read_csv(write_file("header_only.csv", "id,p_0\n"));
  CHECK(table.header.size() == 2);
  CHECK(table.rows.empty());
}

TEST_CASE("read_csv points at the offending field with a caret", "[csv]") {
  CHECK(csv_error("id,p_0,p_1\n0,1.5x,2\n") ==
        "F:2:3: error: expected a number, got '1.5x' in column 'p_0'\n"
        "0,1.5x,2\n"
        "  ^");
  // Tabs are copied into the caret line so that the caret lines up.
  CHECK(csv_error("a,b\n\t1,\t\tabc \n") ==
        "F:2:6: error: expected a number, got 'abc' in column 'b'\n"
        "\t1,\t\tabc \n"
        "\t  \t\t^");
  CHECK(csv_error("a,b\n1,\n") ==
        "F:2:3: error: expected a number, got an empty field in column 'b'\n"
        "1,\n"
        "  ^");
  CHECK(csv_error("a,b\n1,nan\n") ==
        "F:2:3: error: expected a finite number, got 'nan' in column 'b'\n1,nan\n  ^");
  CHECK(csv_error("a,b\n-inf,1\n") ==
        "F:2:1: error: expected a finite number, got '-inf' in column 'a'\n-inf,1\n^");
  CHECK(csv_error("a\n1e999\n") ==
        "F:2:1: error: '1e999' is out of the range of a double in column 'a'\n1e999\n^");
  CHECK(csv_error("a\n+-1\n") ==
        "F:2:1: error: expected a number, got '+-1' in column 'a'\n+-1\n^");
}

TEST_CASE("read_csv rejects rows of the wrong width", "[csv]") {
  CHECK(csv_error("a,b\n1,2\n1,2, 3\n") ==
        "F:3:6: error: expected 2 fields as in the header, got 3\n"
        "1,2, 3\n"
        "     ^");
  CHECK(csv_error("a,b\r\n1\r\n") ==
        "F:2:2: error: expected 2 fields as in the header, got 1\n"
        "1\n"
        " ^");
}

TEST_CASE("read_csv rejects bad headers and bad files", "[csv]") {
  CHECK(csv_error("") ==
        "F:1:1: error: expected a header line naming the columns, such as 'id,p_0,p_1'\n\n^");
  CHECK(csv_error(" \n1,2\n") ==
        "F:1:1: error: expected a header line naming the columns, such as 'id,p_0,p_1'\n \n^");
  CHECK(csv_error("a,,b\n") == "F:1:3: error: empty column name\na,,b\n  ^");
  CHECK(csv_error("a, b, a\n") ==
        "F:1:7: error: duplicate column name 'a' (also column 1)\na, b, a\n      ^");
  CHECK(csv_error("0.5,1\n1,2\n") ==
        "F:1:1: error: the first line must name the columns, but it holds numbers; is the header "
        "line missing?\n0.5,1\n^");
  // Data without its header, with a repeated number: still the missing header.
  CHECK(csv_error("0,1,1\n1,2,2\n") ==
        "F:1:1: error: the first line must name the columns, but it holds numbers; is the header "
        "line missing?\n0,1,1\n^");
  CHECK(csv_error("a\n1\n\n2\n") ==
        "F:3:1: error: blank line inside the data (only trailing blank lines are allowed)\n\n^");

  const std::string missing = file_path("no-such-file.csv");
  CHECK_THROWS_WITH(partc::read_csv(missing),
                    missing + ": error: cannot open: No such file or directory");
  const std::string directory = scratch_directory().string();
  CHECK_THROWS_WITH(partc::read_csv(directory),
                    directory + ": error: this is a directory, not a CSV file");
}

TEST_CASE("a header of 100000 columns is checked for duplicates in linear time", "[csv]") {
  std::string header, row;
  for (int c = 0; c < 100000; ++c) {
    header += (c ? ",c" : "c") + std::to_string(c);
    row += c ? ",1" : "1";
  }
  const std::string path = write_file("wide.csv", header + "\n" + row + "\n");
  const auto table = partc::read_csv(path);  // was 6 s with a quadratic check
  CHECK(table.header.size() == 100000);
  CHECK(table.column("c99999") == 99999);
  CHECK(table.column("c100000") == -1);
}

TEST_CASE("an error in CSV read through a pipe still quotes its line", "[csv]") {
  const std::string fifo = file_path("piped.csv");
  std::remove(fifo.c_str());
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  const pid_t writer = fork();
  REQUIRE(writer >= 0);
  if (writer == 0) {
    std::ofstream out(fifo);
    out << "id,p_0,p_1,vx\n0,1,2,3\n4,5,6,7\n2.5,0,0,0\n";
    out.close();
    _exit(0);
  }
  Set set = sample_set();
  std::string message = "accepted";
  try {
    partc::load_set(partc::read_csv(fifo), set);
  } catch (const partc::InputError& e) {
    message = e.what();
  }
  int status = 0;
  waitpid(writer, &status, 0);
  std::remove(fifo.c_str());
  CHECK(message == fifo + ":1:12: error: unknown column 'vx'; the columns are id, p_0, p_1, v_0, "
                          "v_1, e, hits, moving\nid,p_0,p_1,vx\n           ^");
}

TEST_CASE("ids must be below 2^53, where a double still tells neighbours apart", "[csv]") {
  Set set;
  // 2^53 + 1 reads as 2^53: refused, rather than loaded as another particle's id.
  const std::string path = write_file("big_ids.csv", "id,p_0,p_1\n9007199254740993,0,0\n");
  CHECK_THROWS_WITH(partc::load_set(partc::read_csv(path), set),
                    Catch::Contains("holds non-negative integer ids below 2^53, got 9007199254740992"));
  const std::string fine = write_file("fine_ids.csv", "id,p_0,p_1\n9007199254740991,0,0\n");
  partc::load_set(partc::read_csv(fine), set);
  CHECK(set.ids() == std::vector<std::int64_t>{9007199254740991});
}

TEST_CASE("write_csv writes rows in id order, each number in its shortest exact form", "[csv]") {
  const std::string path = file_path("sample.csv");
  partc::write_csv(path, sample_set());
  CHECK(read_file(path) ==
        "id,p_0,p_1,v_0,v_1,e,hits,moving\n"
        "1,1,2,0,0,0,0,0\n"
        "3,-3e-07,1e+300,-2.5,5e-324,123456789.125,9007199254740992,1\n"
        "5,0.1,-0,0.3333333333333333,1e-300,2.5,-7,1\n");
  CHECK_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("write_csv then read_csv and load_set give back the same set", "[csv]") {
  const std::string path = file_path("round_trip.csv");
  const Set original = sample_set();
  partc::write_csv(path, original);
  Set loaded;
  partc::load_set(partc::read_csv(path), loaded);
  // Rows come back in id order: 1, 3, 5 are original indices 1, 2, 0.
  const std::vector<std::size_t> from = {1, 2, 0};
  REQUIRE(loaded.size() == 3);
  CHECK(loaded.next_id() == 6);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t o = from[i];
    CHECK(loaded.ids()[i] == original.ids()[o]);
    for (int k = 0; k < 2; ++k) {
      CHECK(loaded.positions()[i][k] == original.positions()[o][k]);
      CHECK(std::signbit(loaded.positions()[i][k]) == std::signbit(original.positions()[o][k]));
      CHECK(loaded.get<P_v>()[i][k] == original.get<P_v>()[o][k]);
    }
    CHECK(loaded.get<P_e>()[i] == original.get<P_e>()[o]);
    CHECK(loaded.get<P_hits>()[i] == original.get<P_hits>()[o]);
    CHECK(loaded.get<P_moving>()[i] == original.get<P_moving>()[o]);
  }
}

TEST_CASE("load_set: ids and variables may be left out, positions may not", "[csv]") {
  Set set;
  set.push_back(Vec<2>::zero());  // replaced by the load, but its id stays taken
  partc::load_set(partc::read_csv(write_file("minimal.csv", "p_1,p_0,e\n2,1,0.5\n4,3,0.25\n")),
                  set);
  REQUIRE(set.size() == 2);
  CHECK(set.ids() == std::vector<std::int64_t>{0, 1});
  CHECK(set.next_id() == 2);
  CHECK(set.positions()[1] == Vec<2>{{3, 4}});
  CHECK(set.get<P_e>() == std::vector<double>{0.5, 0.25});
  CHECK(set.get<P_v>()[1] == Vec<2>::zero());
  CHECK(set.get<P_moving>() == std::vector<std::uint8_t>{0, 0});
}

TEST_CASE("load_set: initialise gives the declared initial values, the table overrides", "[csv]") {
  Set set;
  std::vector<std::size_t> initialised;
  const auto initialise = [&](std::size_t i) {
    initialised.push_back(i);
    set.get<P_e>()[i] = 7;
    set.get<P_hits>()[i] = set.ids()[i] * 10;  // ids are already set
  };
  const std::string path = write_file("initialise.csv", "id,p_0,p_1,hits\n4,0,0,1\n9,0,0,2\n");
  partc::load_set(partc::read_csv(path), set, initialise);
  CHECK(initialised == std::vector<std::size_t>{0, 1});
  CHECK(set.get<P_e>() == std::vector<double>{7, 7});
  CHECK(set.get<P_hits>() == std::vector<std::int64_t>{1, 2});
  CHECK(set.next_id() == 10);
}

TEST_CASE("load_set points at the field or column it cannot use", "[csv]") {
  const auto load_error = [](const std::string& text) {
    const std::string path = write_file("bad_load.csv", text);
    Set set = sample_set();
    try {
      partc::load_set(partc::read_csv(path), set);
    } catch (const partc::InputError& e) {
      CHECK(set.ids() == sample_set().ids());  // checked before touched
      const std::string message = e.what();
      return "F" + message.substr(path.size());
    }
    return std::string("accepted");
  };
  CHECK(load_error("id,p_0,p_1,vx\n0,1,2,3\n") ==
        "F:1:12: error: unknown column 'vx'; the columns are id, p_0, p_1, v_0, v_1, e, hits, "
        "moving\nid,p_0,p_1,vx\n           ^");
  CHECK(load_error("id,p_0\n0,1\n") ==
        "F:1:7: error: missing column 'p_1' (positions are required)\nid,p_0\n      ^");
  CHECK(load_error("p_0,p_1,v_1\n0,1,2\n") ==
        "F:1:12: error: missing column 'v_0' (a vec needs all its components)\np_0,p_1,v_1\n"
        "           ^");
  CHECK(load_error("id,p_0,p_1\n0,0,0\n1.5,0,0\n") ==
        "F:3:1: error: column 'id' holds non-negative integer ids below 2^53, got 1.5\n1.5,0,0\n^");
  CHECK(load_error("id,p_0,p_1\n-1,0,0\n") ==
        "F:2:1: error: column 'id' holds non-negative integer ids below 2^53, got -1\n-1,0,0\n^");
  CHECK(load_error("p_0,p_1, id\n0,0,4\n\n") == "accepted");
  CHECK(load_error("p_0,p_1, id\n0,0,4\n0,0,  4\n") ==
        "F:3:7: error: duplicate id 4 (also on line 2)\n0,0,  4\n      ^");
  CHECK(load_error("p_0,p_1,moving\n0,0,2\n") ==
        "F:2:5: error: column 'moving' holds 0 or 1 (a bool), got 2\n0,0,2\n    ^");
  CHECK(load_error("p_0,p_1,hits\n0,0,0.5\n") ==
        "F:2:5: error: column 'hits' holds integers, got 0.5\n0,0,0.5\n    ^");
}

TEST_CASE("write_csv leaves nothing behind when it cannot write", "[csv]") {
  const std::string path = file_path("no-such-directory/out.csv");
  CHECK_THROWS_WITH(partc::write_csv(path, sample_set()),
                    "cannot create '" + path + ".tmp': No such file or directory");
  CHECK_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("a writer that fails half way leaves the previous file as it was", "[csv]") {
  const std::string path = write_file("kept.csv", "id,p_0\n0,1\n");
  const auto fail_half_way = [](std::ostream& out) {
    out << "id,p_0\n";
    throw std::runtime_error("disk on fire");
  };
  CHECK_THROWS_WITH(partc::detail::write_file_atomically(path, fail_half_way), "disk on fire");
  CHECK(read_file(path) == "id,p_0\n0,1\n");
  CHECK_FALSE(fs::exists(path + ".tmp"));
}

TEST_CASE("a signal while a temporary is written removes it and ends the program", "[csv]") {
  const std::string path = write_file("signalled.csv", "id,p_0\n0,1\n");
  for (int signal : {SIGINT, SIGTERM}) {
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {  // the child is stopped by the signal half way through writing
      std::signal(signal, SIG_DFL);  // Catch's own handler, inherited, would report instead
      partc::detail::write_file_atomically(path, [&](std::ostream& out) {
        out << "id,p_0\n" << std::flush;
        std::raise(signal);
      });
      _exit(0);  // not reached
    }
    int status = 0;
    REQUIRE(waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal);
    CHECK_FALSE(fs::exists(path + ".tmp"));
    CHECK(read_file(path) == "id,p_0\n0,1\n");
  }
}

TEST_CASE("check_finite reports the first NaN or Inf with variable, id and step", "[finite]") {
  Set set = sample_set();
  CHECK_NOTHROW(partc::check_finite(set, "P", 3));

  set.get<P_e>()[2] = std::numeric_limits<double>::infinity();
  set.get<P_v>()[1][1] = std::nan("");
  set.get<P_v>()[2][0] = -std::numeric_limits<double>::infinity();
  // v comes before e; within v, storage index 1 (id 1) before index 2 (id 3).
  try {
    partc::check_finite(set, "P", 42);
    FAIL("no NumericalError");
  } catch (const partc::NumericalError& e) {
    CHECK(std::string(e.what()) ==
          "numerical blow-up: variable 'v' of particle id 1 is nan at step 42 (set P)");
    CHECK(e.set == "P");
    CHECK(e.variable == "v");
    CHECK(e.id == 1);
    CHECK(e.step == 42);
    CHECK(std::isnan(e.value));
  }
  set.get<P_v>()[1][1] = 0;
  CHECK_THROWS_WITH(partc::check_finite(set, "P", 7),
                    "numerical blow-up: variable 'v' of particle id 3 is -inf at step 7 (set P)");
  set.positions()[0][1] = std::nan("");
  CHECK_THROWS_WITH(partc::check_finite(set, "Q", 0),
                    "numerical blow-up: variable 'p' of particle id 5 is nan at step 0 (set Q)");
}

// The vectorised test on the bits against std::isfinite: every special value
// of double and float, alone at every offset of arrays longer than a vector.
template <class T>
void check_all_finite_agrees() {
  using limits = std::numeric_limits<T>;
  const T specials[] = {T(0),          -T(0),           T(1),
                        limits::max(), -limits::max(),  limits::min(),
                        limits::denorm_min(),           limits::infinity(),
                        -limits::infinity(),            limits::quiet_NaN(),
                        -limits::quiet_NaN(),           limits::signaling_NaN()};
  for (std::size_t n : {1, 7, 33}) {
    for (std::size_t at = 0; at < n; ++at)
      for (const T value : specials) {
        std::vector<T> x(n, T(0.5));
        x[at] = value;
        INFO("n " << n << ", value " << value << " at " << at);
        CHECK(partc::detail::all_finite(x.data(), n) == static_cast<bool>(std::isfinite(value)));
      }
  }
  CHECK(partc::detail::all_finite(static_cast<const T*>(nullptr), 0));
}

TEST_CASE("check_finite's test on the bits agrees with std::isfinite", "[finite]") {
  check_all_finite_agrees<double>();
  check_all_finite_agrees<float>();
}

// ---- VTK: a minimal XML reader, enough to check well-formedness and content.

namespace {

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;
  std::vector<XmlElement> children;

  const XmlElement& child(const std::string& wanted) const {
    for (const auto& c : children)
      if (c.name == wanted) return c;
    throw std::runtime_error("no <" + wanted + "> in <" + name + ">");
  }
  // The DataArray children of this element, by Name.
  std::map<std::string, const XmlElement*> arrays() const {
    std::map<std::string, const XmlElement*> found;
    for (const auto& c : children)
      if (c.name == "DataArray") found[c.attributes.at("Name")] = &c;
    return found;
  }
  // strtod, not istream >> double, which fails on subnormals such as 5e-324.
  std::vector<double> numbers() const {
    std::istringstream in(text);
    std::vector<double> values;
    for (std::string word; in >> word;) {
      char* end = nullptr;
      values.push_back(std::strtod(word.c_str(), &end));
      if (*end != '\0') throw std::runtime_error("not a number in <" + name + ">: " + word);
    }
    return values;
  }
};

// Throws on anything that is not well-formed (for what our writers emit).
class XmlReader {
 public:
  explicit XmlReader(std::string text) : s_(std::move(text)) {}

  XmlElement document() {
    skip_space();
    if (s_.compare(i_, 5, "<?xml") == 0) i_ = s_.find("?>", i_) + 2;
    skip_space();
    XmlElement root = element();
    skip_space();
    if (i_ != s_.size()) throw std::runtime_error("text after the root element");
    return root;
  }

 private:
  XmlElement element() {
    expect("<");
    XmlElement e;
    e.name = name();
    while (true) {
      skip_space();
      if (s_.compare(i_, 2, "/>") == 0) {
        i_ += 2;
        return e;
      }
      if (s_.compare(i_, 1, ">") == 0) break;
      const std::string key = name();
      expect("=\"");
      const std::size_t end = s_.find('"', i_);
      if (end == std::string::npos || !e.attributes.emplace(key, s_.substr(i_, end - i_)).second)
        throw std::runtime_error("bad attribute " + key);
      i_ = end + 1;
    }
    ++i_;
    while (s_.compare(i_, 2, "</") != 0) {
      if (i_ >= s_.size()) throw std::runtime_error("unclosed <" + e.name + ">");
      if (s_[i_] == '<')
        e.children.push_back(element());
      else if (s_[i_] == '&')
        throw std::runtime_error("entity in text");
      else
        e.text += s_[i_++];
    }
    i_ += 2;
    if (name() != e.name) throw std::runtime_error("mismatched </...> for <" + e.name + ">");
    expect(">");
    return e;
  }

  std::string name() {
    const std::size_t start = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_'))
      ++i_;
    if (i_ == start) throw std::runtime_error("expected a name at offset " + std::to_string(i_));
    return s_.substr(start, i_ - start);
  }
  void expect(const std::string& token) {
    if (s_.compare(i_, token.size(), token) != 0)
      throw std::runtime_error("expected '" + token + "' at offset " + std::to_string(i_));
    i_ += token.size();
  }
  void skip_space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }

  std::string s_;
  std::size_t i_ = 0;
};

XmlElement read_xml(const std::string& path) { return XmlReader(read_file(path)).document(); }

}  // namespace

TEST_CASE("write_vtu writes a VTK UnstructuredGrid of vertices in id order", "[vtk]") {
  const std::string path = file_path("sample.vtu");
  partc::write_vtu(path, sample_set());
  const XmlElement root = read_xml(path);
  CHECK(root.name == "VTKFile");
  CHECK(root.attributes.at("type") == "UnstructuredGrid");
  const XmlElement& piece = root.child("UnstructuredGrid").child("Piece");
  CHECK(piece.attributes.at("NumberOfPoints") == "3");
  CHECK(piece.attributes.at("NumberOfCells") == "3");

  const auto data = piece.child("PointData").arrays();
  CHECK(data.size() == 5);  // id, v, e, hits, moving: positions are the points
  CHECK(data.at("id")->attributes.at("type") == "Int64");
  CHECK(data.at("id")->numbers() == std::vector<double>{1, 3, 5});
  CHECK(data.at("v")->attributes.at("type") == "Float64");
  CHECK(data.at("v")->attributes.at("NumberOfComponents") == "3");
  CHECK(data.at("v")->numbers() ==
        std::vector<double>{0, 0, 0, -2.5, 4.9e-324, 0, 1.0 / 3, 1e-300, 0});
  CHECK(data.at("e")->numbers() == std::vector<double>{0, 123456789.125, 2.5});
  CHECK(data.at("hits")->attributes.at("type") == "Int64");
  CHECK(data.at("hits")->numbers() == std::vector<double>{0, 9007199254740992.0, -7});
  CHECK(data.at("moving")->attributes.at("type") == "UInt8");
  CHECK(data.at("moving")->numbers() == std::vector<double>{0, 1, 1});

  const auto points = piece.child("Points").arrays();
  CHECK(points.at("Points")->attributes.at("NumberOfComponents") == "3");
  CHECK(points.at("Points")->numbers() ==
        std::vector<double>{1, 2, 0, -3e-7, 1e300, 0, 0.1, -0.0, 0});

  const auto cells = piece.child("Cells").arrays();
  CHECK(cells.at("connectivity")->numbers() == std::vector<double>{0, 1, 2});
  CHECK(cells.at("offsets")->numbers() == std::vector<double>{1, 2, 3});
  CHECK(cells.at("types")->numbers() == std::vector<double>{1, 1, 1});  // VTK_VERTEX
}

namespace {
struct Q_w {
  using type = Vec<4>;
  static constexpr const char* name = "w";
};
}  // namespace

TEST_CASE("write_vtu: a 4D set shows 3 coordinates as points and all 4 as data", "[vtk]") {
  partc::ParticleSet<4, Q_w> set;
  set.push_back(Vec<4>{{1, 2, 3, 4}});
  set.get<Q_w>()[0] = Vec<4>{{5, 6, 7, 8}};
  const std::string path = file_path("four.vtu");
  partc::write_vtu(path, set);
  const XmlElement root = read_xml(path);
  const XmlElement& piece = root.child("UnstructuredGrid").child("Piece");
  CHECK(piece.child("Points").arrays().at("Points")->numbers() == std::vector<double>{1, 2, 3});
  const auto data = piece.child("PointData").arrays();
  CHECK(data.at("p")->attributes.at("NumberOfComponents") == "4");
  CHECK(data.at("p")->numbers() == std::vector<double>{1, 2, 3, 4});
  CHECK(data.at("w")->numbers() == std::vector<double>{5, 6, 7, 8});
}

TEST_CASE("write_vtu of an empty set is still a valid file", "[vtk]") {
  const std::string path = file_path("empty.vtu");
  partc::write_vtu(path, Set{});
  const XmlElement root = read_xml(path);
  const XmlElement& piece = root.child("UnstructuredGrid").child("Piece");
  CHECK(piece.attributes.at("NumberOfPoints") == "0");
  CHECK(piece.child("Points").arrays().at("Points")->numbers().empty());
}

TEST_CASE("VtkSeries keeps a .pvd that lists every frame so far", "[vtk]") {
  const fs::path directory = scratch_directory() / "series";
  fs::create_directories(directory);
  const std::string prefix = (directory / "run_P").string();
  partc::VtkSeries series(prefix);
  Set set = sample_set();
  series.write(partc::view_of("P", set), 0, 0.0);
  CHECK(read_xml(prefix + ".pvd").child("Collection").children.size() == 1);
  set.positions()[0][0] = 7;
  series.write(partc::view_of("P", set), 10, 0.25);

  const XmlElement pvd = read_xml(prefix + ".pvd");
  CHECK(pvd.attributes.at("type") == "Collection");
  const auto& frames = pvd.child("Collection").children;
  REQUIRE(frames.size() == 2);
  CHECK(frames[0].attributes.at("file") == "run_P_000000.vtu");  // relative to the .pvd
  CHECK(frames[0].attributes.at("timestep") == "0");
  CHECK(frames[1].attributes.at("file") == "run_P_000010.vtu");
  CHECK(frames[1].attributes.at("timestep") == "0.25");
  const auto points = [&](const std::string& file) {
    return read_xml((directory / file).string())
        .child("UnstructuredGrid")
        .child("Piece")
        .child("Points")
        .arrays()
        .at("Points")
        ->numbers();
  };
  CHECK(points("run_P_000000.vtu")[6] == 0.1);  // id 5 is the last point
  CHECK(points("run_P_000010.vtu")[6] == 7);
  for (const auto& entry : fs::directory_iterator(directory))
    CHECK(entry.path().extension() != ".tmp");
}

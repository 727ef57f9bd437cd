// Storage precision (a schedule's precision = float): values stored as float
// and Vec<D, float>, computed in double. Loads widen exactly, stores round
// once to nearest; float positions stay inside the periodic box after
// rounding; searches over float positions match searches over the same
// points as doubles; files round-trip float data exactly, as Float32 in VTK.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "partc/domain.hpp"
#include "partc/errors.hpp"
#include "partc/faces.hpp"
#include "partc/finite.hpp"
#include "partc/io/csv.hpp"
#include "partc/io/vtk.hpp"
#include "partc/particle_set.hpp"
#include "partc/search/neighbour_search.hpp"
#include "partc/search/verlet_list.hpp"
#include "partc/vec.hpp"

namespace fs = std::filesystem;
using partc::Vec;

fs::path scratch_directory();  // test_io.cpp

namespace {

using Vecf = Vec<2, float>;

struct F_m {
  using type = float;
  static constexpr const char* name = "m";
};
struct F_v {
  using type = Vec<2, float>;
  static constexpr const char* name = "v";
};
struct F_n {
  using type = std::int64_t;
  static constexpr const char* name = "n";
};
using FloatSet = partc::BasicParticleSet<Vecf, F_m, F_v, F_n>;

const partc::Domain<2> unit_box{{{0.0, 0.0}}, {{1.0, 1.0}}, {{true, true}}};

// Points of [0, 1)^2 that are floats, so that double and float sets hold the same ones.
std::vector<Vec<2>> float_points(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec<2>> points(n);
  for (auto& p : points)
    for (int k = 0; k < 2; ++k) p[k] = partc::round_inside<float>(u(rng), 0.0, 1.0);
  return points;
}

}  // namespace

TEST_CASE("Vec<D, float> widens exactly and rounds once on a store", "[float]") {
  const Vec<2> wide{{0.1, 1.0 + 0x1p-30}};
  const Vecf narrow = wide;  // to nearest
  CHECK(narrow[0] == 0.1f);
  CHECK(narrow[1] == 1.0f);
  const Vec<2> back = partc::widen(narrow);
  CHECK(back[0] == static_cast<double>(0.1f));
  CHECK(partc::widen(0.1f) == static_cast<double>(0.1f));

  // float += double computes in double: 1 + 2^-25 + 2^-26 is above the
  // midpoint 1 + 2^-24, so it rounds up to 1 + 2^-23. In float arithmetic the
  // addend alone would first round to 2^-25 + 2^-26 (exact) and then
  // 1 + 0.75 * 2^-24 rounds down to 1: only double arithmetic gives 1 + 2^-23.
  Vecf v{{1.0f, 1.0f}};
  v += Vec<2>{{0x1p-24 + 0x1p-25, 0.0}};
  CHECK(v[0] == 1.0f + 0x1p-23f);
  v *= 3.0;  // 3 + 3 * 2^-23, exact in double, rounds once to the float nearest
  CHECK(v[0] == static_cast<float>(3.0 * (1.0 + 0x1p-23)));
}

TEST_CASE("round_inside keeps a float inside [lo, hi) even where hi is the nearest float",
          "[float]") {
  // Just below hi = 1: the nearest float is 1 itself; the float below is taken.
  const float below_one = partc::round_inside<float>(1.0 - 1e-10, 0.0, 1.0);
  CHECK(below_one < 1.0f);
  CHECK(below_one == std::nextafter(1.0f, 0.0f));
  // hi = 0.1 is no float: float(0.1) = 0.100000001 > 0.1 is outside.
  const float below_tenth = partc::round_inside<float>(0.1 - 1e-12, 0.0, 0.1);
  CHECK(static_cast<double>(below_tenth) < 0.1);
  CHECK(static_cast<double>(std::nextafter(below_tenth, 1.0f)) >= 0.1);
  // lo = 0.7 is no float either: float(0.7) = 0.699999988 < 0.7.
  const float at_lo = partc::round_inside<float>(0.7, 0.7, 1.0);
  CHECK(static_cast<double>(at_lo) >= 0.7);
  // A closed interval (reflecting faces) keeps hi itself when it is a float.
  CHECK(partc::round_inside<float>(1.0 - 1e-10, 0.0, 1.0, true) == 1.0f);
  CHECK(std::isnan(partc::round_inside<float>(std::nan(""), 0.0, 1.0)));
  // Doubles pass unchanged.
  CHECK(partc::round_inside<double>(0.25, 0.0, 1.0) == 0.25);
}

TEST_CASE("Domain::wrap_into keeps float positions in [lo, hi) after rounding", "[float]") {
  const partc::Domain<2> box{{{-0.3, 0.7}}, {{0.1, 1.9}}, {{true, true}}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> offset(-1e-9, 1e-9);
  for (int trial = 0; trial < 20000; ++trial) {
    // Near the faces, where rounding can cross them; and far outside.
    const double x = (trial % 2 ? box.hi[0] : box.lo[0]) + offset(rng) + (trial % 5 == 0 ? 3 : 0);
    const double y = (trial % 3 ? box.hi[1] : box.lo[1]) + offset(rng);
    Vecf stored{};
    box.wrap_into(stored, Vec<2>{{x, y}});
    for (int k = 0; k < 2; ++k) {
      INFO("trial " << trial << " component " << k << " stored " << stored[k]);
      CHECK(static_cast<double>(stored[k]) >= box.lo[k]);
      CHECK(static_cast<double>(stored[k]) < box.hi[k]);
    }
  }
}

TEST_CASE("reflecting faces keep float positions in [lo, hi]", "[float]") {
  FloatSet set;
  const partc::Faces<2> faces{{{0.0, 0.0}}, {{0.1, 0.3}}, {{true, true}}, {{false, false}}};
  set.push_back(Vec<2>{{0.1 + 1e-12, -1e-12}});  // just past hi (no float) and lo
  set.get<F_v>()[0] = Vec<2>{{1.0, 2.0}};
  partc::reflect_through_faces(set, faces, set.get<F_v>());
  const Vecf p = set.positions()[0];
  CHECK(static_cast<double>(p[0]) <= 0.1);
  CHECK(p[1] >= 0.0f);
  CHECK(set.get<F_v>()[0][0] == -1.0f);  // turned with it
}

TEST_CASE("searches over float positions find what they find over the same doubles", "[float]") {
  const auto points = float_points(3000, 11);
  partc::ParticleSet<2> doubles;
  partc::BasicParticleSet<Vecf> floats;
  for (const auto& p : points) {
    doubles.push_back(p);
    floats.push_back(p);
  }
  for (const auto kind :
       {partc::NeighbourSearch<2>::Kind::brute_force, partc::NeighbourSearch<2>::Kind::cell_list,
        partc::NeighbourSearch<2>::Kind::kd_tree}) {
    partc::NeighbourSearch<2> over_doubles(kind), over_floats(kind);
    over_doubles.build(unit_box, 0.03, doubles);
    over_floats.build(unit_box, 0.03, floats);
    REQUIRE(doubles.ids() == floats.ids());  // the same reorder
    std::size_t pairs = 0, same = 0;
    for (std::size_t i = 0; i < doubles.size(); ++i) {
      std::vector<std::pair<std::size_t, Vec<2>>> a, b;
      over_doubles.for_each_near(i, [&](std::size_t j, const Vec<2>& dx) { a.push_back({j, dx}); });
      over_floats.for_each_near(i, [&](std::size_t j, const Vec<2>& dx) { b.push_back({j, dx}); });
      pairs += a.size();
      same += a == b;
    }
    INFO("search kind " << static_cast<int>(kind));
    CHECK(same == doubles.size());  // neighbours, order and dx bit for bit
    CHECK(pairs > doubles.size());
  }

  // Verlet lists measure moves from the widened positions too.
  partc::VerletList<2> lists_d(0.01), lists_f(0.01);
  lists_d.update(unit_box, 0.03, doubles);
  lists_f.update(unit_box, 0.03, floats);
  CHECK(lists_d.entry_count() == lists_f.entry_count());
  for (auto& p : floats.positions()) p[0] = partc::round_inside<float>(p[0] + 0.004, 0.0, 1.0);
  CHECK_FALSE(lists_f.update(unit_box, 0.03, floats));  // 0.004 < skin / 2
  for (auto& p : floats.positions()) p[0] = partc::round_inside<float>(p[0] + 0.002, 0.0, 1.0);
  CHECK(lists_f.update(unit_box, 0.03, floats));  // 0.006 > skin / 2
}

TEST_CASE("float data round-trips exactly through CSV, and is Float32 in VTK", "[float]") {
  FloatSet set;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (const auto& p : float_points(500, 5)) {
    const std::size_t i = set.push_back(p);
    set.get<F_m>()[i] = static_cast<float>(u(rng) * 1e-30);  // tiny, subnormal at the end
    set.get<F_v>()[i] = Vec<2>{{u(rng), u(rng) * 1e20}};
    set.get<F_n>()[i] = static_cast<std::int64_t>(i) * 3;
  }
  set.get<F_m>()[0] = std::numeric_limits<float>::denorm_min();
  set.get<F_m>()[1] = std::numeric_limits<float>::max();
  set.get<F_m>()[2] = -0.0f;
  const std::string path = (scratch_directory() / "float_set.csv").string();
  partc::write_csv(path, set);
  FloatSet back;
  partc::load_set(partc::read_csv(path), back);
  REQUIRE(back.size() == set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    CHECK(back.positions()[i] == set.positions()[i]);
    CHECK(std::signbit(back.get<F_m>()[i]) == std::signbit(set.get<F_m>()[i]));
    CHECK(back.get<F_m>()[i] == set.get<F_m>()[i]);
    CHECK(back.get<F_v>()[i] == set.get<F_v>()[i]);
    CHECK(back.get<F_n>()[i] == set.get<F_n>()[i]);
  }

  // A double in the file is rounded to the nearest float on loading.
  {
    std::ofstream out(path);
    out << "id,p_0,p_1,m,v_0,v_1,n\n0,0.1,0.2,0.3,1e-50,-2.5,7\n";
  }
  partc::load_set(partc::read_csv(path), back);
  CHECK(back.positions()[0][0] == 0.1f);
  CHECK(back.get<F_m>()[0] == 0.3f);
  CHECK(back.get<F_v>()[0][0] == 0.0f);

  const std::string vtu = (scratch_directory() / "float_set.vtu").string();
  partc::write_vtu(vtu, set);
  std::ifstream in(vtu);
  std::stringstream text;
  text << in.rdbuf();
  CHECK(text.str().find("<DataArray type=\"Float32\" Name=\"m\"") != std::string::npos);
  CHECK(text.str().find("<DataArray type=\"Float32\" Name=\"v\"") != std::string::npos);
  CHECK(text.str().find("<DataArray type=\"Int64\" Name=\"n\"") != std::string::npos);
  CHECK(text.str().find("<DataArray type=\"Float32\" Name=\"Points\"") != std::string::npos);
}

TEST_CASE("check_finite finds a NaN or Inf stored as float", "[float]") {
  FloatSet set;
  set.push_back(Vec<2>{{0.5, 0.5}});
  CHECK_NOTHROW(partc::check_finite(set, "F", 0));
  set.get<F_v>()[0][1] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_AS(partc::check_finite(set, "F", 4), partc::NumericalError);
  set.get<F_v>()[0][1] = 0.0f;
  set.get<F_m>()[0] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(partc::check_finite(set, "F", 4), Catch::Contains("'m'"));
}

TEST_CASE("a value beyond a float's range is an error where the column is stored as float",
          "[float]") {
  const std::string path = (scratch_directory() / "float_range.csv").string();
  {
    std::ofstream out(path);
    out << "id,p_0,p_1,m\n0,0.5,0.5,1e39\n";
  }
  FloatSet set;
  CHECK_THROWS_WITH(partc::load_set(partc::read_csv(path), set),
                    path + ":2:11: error: column 'm' is stored as float, which cannot hold 1e+39\n"
                           "0,0.5,0.5,1e39\n"
                           "          ^");
  CHECK(set.empty());  // untouched
}

// Faces<D> (partc/faces.hpp): reflecting and open faces, against positions
// and turn counts worked out by hand.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "partc/faces.hpp"
#include "partc/particle_set.hpp"

namespace {

// [0, 2] along x reflects; y is open on [0, 1); z is left alone.
const partc::Faces<3> kFaces{{{0.0, 0.0, 0.0}}, {{2.0, 1.0, 1.0}}, {{true, false, false}},
                             {{false, true, false}}};

double reflected_x(double x, bool& turned) {
  std::array<bool, 3> t{};
  const double out = kFaces.reflect_position({{x, 0.5, 7.0}}, t)[0];
  turned = t[0];
  CHECK_FALSE(t[1]);
  CHECK_FALSE(t[2]);
  return out;
}

struct Mirrored {
  using type = partc::Vec<3>;
  static constexpr const char* name = "v";
};

}  // namespace

TEST_CASE("a reflecting face mirrors a position back in and says it turned", "[faces]") {
  bool turned = true;
  CHECK(reflected_x(1.25, turned) == 1.25);
  CHECK_FALSE(turned);
  CHECK(reflected_x(0.0, turned) == 0.0);  // on a face: in the box
  CHECK(reflected_x(2.0, turned) == 2.0);
  CHECK_FALSE(turned);
  CHECK(reflected_x(-0.25, turned) == 0.25);  // one bounce off lo
  CHECK(turned);
  CHECK(reflected_x(2.5, turned) == 1.5);  // one bounce off hi
  CHECK(turned);
  CHECK(reflected_x(-3.0, turned) == Approx(1.0).margin(1e-15));  // lo, then hi: two bounces
  CHECK_FALSE(turned);
  CHECK(reflected_x(5.0, turned) == Approx(1.0).margin(1e-15));  // hi, then lo, then goes on
  CHECK(turned == false);
  CHECK(reflected_x(7.5, turned) == Approx(0.5).margin(1e-15));  // three bounces: hi, lo, hi
  CHECK(turned);
  CHECK(reflected_x(1e6 + 0.5, turned) == Approx(0.5).margin(1e-9));  // 250000 round trips
  CHECK_FALSE(turned);
  CHECK(std::isnan(reflected_x(std::numeric_limits<double>::quiet_NaN(), turned)));
}

TEST_CASE("an open face removes the particles past it, keeps the others in order, counts",
          "[faces]") {
  CHECK(kFaces.outside_open({{0.5, -1e-300, 0.5}}));
  CHECK(kFaces.outside_open({{0.5, 1.0, 0.5}}));  // hi is outside: the box is [lo, hi)
  CHECK_FALSE(kFaces.outside_open({{0.5, 0.0, 0.5}}));
  CHECK_FALSE(kFaces.outside_open({{9.0, 0.5, -9.0}}));  // other axes are not open
  CHECK_FALSE(kFaces.outside_open({{0.5, std::numeric_limits<double>::quiet_NaN(), 0.5}}));

  partc::ParticleSet<3, Mirrored> set;
  for (double y : {0.5, 1.5, 0.25, -0.5, 0.75}) {
    set.push_back({{0.0, y, 0.0}});
    set.get<Mirrored>().back() = {{y, 0.0, 0.0}};
  }
  CHECK(partc::leave_through_open_faces(set, kFaces) == 2);
  REQUIRE(set.size() == 3);
  CHECK(set.ids() == std::vector<std::int64_t>{0, 2, 4});
  CHECK(set.get<Mirrored>()[1][0] == 0.25);
  CHECK(partc::leave_through_open_faces(set, kFaces) == 0);
}

TEST_CASE("reflect_through_faces turns the mirrored variables with the positions", "[faces]") {
  partc::ParticleSet<3, Mirrored> set;
  for (double x : {1.0, -0.5, 3.0}) {
    set.push_back({{x, 0.5, 0.5}});
    set.get<Mirrored>().back() = {{-1.0, 2.0, 3.0}};
  }
  partc::reflect_through_faces(set, kFaces, set.get<Mirrored>());
  CHECK(set.positions()[1][0] == 0.5);
  CHECK(set.positions()[2][0] == 1.0);
  CHECK(set.get<Mirrored>()[0][0] == -1.0);
  CHECK(set.get<Mirrored>()[1][0] == 1.0);
  CHECK(set.get<Mirrored>()[2][0] == 1.0);
  CHECK(set.get<Mirrored>()[1][1] == 2.0);  // only the normal component turns
}

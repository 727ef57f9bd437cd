// Pair-dependent neighbourhoods (tests/e2e/contacts.part): grains of
// different radii in contact when |dx| < r[i] + r[j], against a brute-force
// loop over all pairs written here.
#include <catch2/catch.hpp>

#include "contacts.hpp"
#include "reference.hpp"

TEST_CASE("contacts sized by r[i] + r[j] match brute force over all pairs", "[e2e][dem]") {
  Contacts model;
  model.set_seed(21);
  model.init();
  const auto radius = reference::values_by_id<Contacts::G_r>(model.G());
  for (int step = 0; step < 3; ++step) {
    const auto p = reference::positions_by_id(model.G());
    model.step();
    const auto f = reference::values_by_id<Contacts::G_f>(model.G());
    const auto touching = reference::values_by_id<Contacts::G_touching>(model.G());
    double worst = 0, scale = 0;
    std::size_t contacts = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      reference::Vec2 want{0, 0};
      std::int64_t count = 0;
      for (std::size_t j = 0; j < p.size(); ++j) {
        reference::Vec2 d{p[j][0] - p[i][0], p[j][1] - p[i][1]};
        d[1] -= std::round(d[1]);  // periodic in y only, box length 1
        const double s = reference::norm(d), reach = radius[i] + radius[j];
        if (s < reach && s > 0)
          for (int k = 0; k < 2; ++k) want[k] += -model.params().stiffness * (reach - s) * d[k] / s;
        if (s < reach && i != j) ++count;
      }
      contacts += static_cast<std::size_t>(count);
      CHECK(touching[i] == count);
      worst = std::max(worst, reference::norm({f[i][0] - want[0], f[i][1] - want[1]}));
      scale = std::max(scale, reference::norm(want));
    }
    REQUIRE(contacts > 100);  // the test is about real contacts
    CHECK(worst <= 1e-12 * scale);
  }
}

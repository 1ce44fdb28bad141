/// @file EventOverlayTests.cpp
/// overlayEvents: hit counts and order, renumbered ids, the rotation of
/// the copies (positions and local axes; radius and z kept), validation.

#include "conftrack/core/Error.hpp"
#include "conftrack/simulation/EventOverlay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace conftrack {
namespace {

Event eventWith(std::uint64_t number, int nHits, double phi0) {
  Event e;
  e.number = number;
  for (int i = 0; i < nHits; ++i) {
    Hit h;
    h.id = 1000 * number + static_cast<std::uint64_t>(i);
    const double r = 30.0 + 10.0 * i;
    const double phi = phi0 + 0.1 * i;
    h.position = Vector3(r * std::cos(phi), r * std::sin(phi), -50.0 + i);
    h.uAxis = Vector3(-std::sin(phi), std::cos(phi), 0.0);
    h.vAxis = Vector3::UnitZ();
    h.detId.layer = static_cast<std::uint16_t>(i);
    h.detId.module = 7;
    h.sigmaU = 0.01;
    h.sigmaV = 0.02;
    e.hits.push_back(h);
    HitTruth t;
    t.particleId = 5;
    e.truth.push_back(t);
  }
  return e;
}

TEST(EventOverlay, CopiesRotatedAndRenumbered) {
  const std::vector<Event> events{eventWith(1, 3, 0.2), eventWith(2, 2, -1.0)};
  EventOverlayConfig cfg;
  cfg.copies = 3;
  cfg.rotation = 0.5;
  cfg.number = 42;
  const Event out = overlayEvents(events, cfg);
  EXPECT_EQ(out.number, 42u);
  ASSERT_EQ(out.hits.size(), 15u);  // (3 + 2) hits x 3 copies
  EXPECT_FALSE(out.hasTruth());
  EXPECT_TRUE(out.particles.empty());
  for (std::size_t i = 0; i < out.hits.size(); ++i) {
    EXPECT_EQ(out.hits[i].id, i + 1);
  }
  // Event 1 first, copy 0 unchanged, then copies 1 and 2 rotated by 0.5
  // and 1.0 rad; then event 2.
  for (int copy = 0; copy < 3; ++copy) {
    for (int i = 0; i < 3; ++i) {
      const Hit& in = events[0].hits[i];
      const Hit& h = out.hits[3 * copy + i];
      const double dphi = std::atan2(h.position.y(), h.position.x()) -
                          std::atan2(in.position.y(), in.position.x());
      EXPECT_NEAR(std::remainder(dphi - 0.5 * copy, 2.0 * std::numbers::pi),
                  0.0, 1e-12);
      EXPECT_NEAR(h.position.head<2>().norm(), in.position.head<2>().norm(),
                  1e-12);
      EXPECT_DOUBLE_EQ(h.position.z(), in.position.z());
      // The local axes turn with the hit.
      EXPECT_NEAR(h.uAxis.dot(h.position.normalized()),
                  in.uAxis.dot(in.position.normalized()), 1e-12);
      EXPECT_EQ(h.detId, in.detId);
      EXPECT_EQ(h.sigmaU, in.sigmaU);
      EXPECT_EQ(h.sigmaV, in.sigmaV);
    }
  }
  EXPECT_EQ(out.hits[9].detId, events[1].hits[0].detId);
  EXPECT_EQ(out.hits[9].position, events[1].hits[0].position);
}

TEST(EventOverlay, OneCopyIsAConcatenation) {
  const std::vector<Event> events{eventWith(1, 4, 0.0), eventWith(3, 1, 2.0)};
  const Event out = overlayEvents(events, EventOverlayConfig{});
  ASSERT_EQ(out.hits.size(), 5u);
  EXPECT_EQ(out.hits[4].position, events[1].hits[0].position);
}

TEST(EventOverlay, BadSettingsAreRejected) {
  const std::vector<Event> events{eventWith(1, 2, 0.0)};
  EventOverlayConfig cfg;
  cfg.copies = 0;
  EXPECT_THROW(overlayEvents(events, cfg), InputError);
  cfg.copies = 2;
  cfg.rotation = std::nan("");
  EXPECT_THROW(overlayEvents(events, cfg), InputError);
}

}  // namespace
}  // namespace conftrack

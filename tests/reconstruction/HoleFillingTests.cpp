/// @file HoleFillingTests.cpp
/// Hole filling (detail/HoleFilling.hpp) on a synthetic helix: a layer the
/// track skipped between its first and last hit is filled with the hit of
/// the helix there, in track order, and not with a hit 1 mm off it nor
/// beyond the track's ends; bad configurations are rejected naming the key.

#include "conftrack/reconstruction/finding/detail/HoleFilling.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "ExtensionFixture.hpp"

namespace conftrack {
namespace {

using detail::HoleFilling;
using Ids = std::vector<std::uint64_t>;
using Residuals = HoleFilling::Residuals;

constexpr double kRho = 3000.0;  // [mm]: 3.6 GeV in the 4 T of the detector
constexpr double kPhi0 = 0.4;
constexpr double kTanL = 0.3;

std::vector<Hit> helix(const Detector& det) {
  return test::helixHits(det, kRho, kPhi0, 1, kTanL, 1);
}

HoleFilling holeFilling(const FinderConfig& cfg, Residuals residuals) {
  return HoleFilling(
      HoleFilling::Config::fromStep(cfg.steps[0], cfg, residuals));
}

class HoleFillingModes : public ::testing::TestWithParam<Residuals> {};

TEST_P(HoleFillingModes, FillsASkippedLayer) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, helix(det), test::oneBuildStep());
  // The hits of layers 2 and 5 (ids 3 and 6) are missing from the track.
  const std::uint32_t t = ev.addTrack({1, 2, 4, 5, 7, 8});
  const double chi2Before = ev.state.tracks[t].uv.chi2;
  holeFilling(ev.cfg, GetParam()).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(ev.stats.extendedHits, 2u);
  EXPECT_EQ(ev.state.used[ev.index(3)], 1);
  EXPECT_EQ(ev.state.used[ev.index(6)], 1);
  // Exact hits: the refit stays as good as before.
  EXPECT_NEAR(ev.state.tracks[t].uv.chi2, chi2Before, 1e-3);
  EXPECT_LT(ev.state.tracks[t].sz.chi2PerNdf(), 1e-3);
}

TEST_P(HoleFillingModes, LeavesAHitOneMillimetreOffTheHelixOut) {
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits = helix(det);
  hits[3] = test::shiftedHit(det, 3, hits[3].position, 1.0, 100);
  test::Event ev(det, hits, test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3, 5, 6, 7, 8});
  holeFilling(ev.cfg, GetParam()).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 5, 6, 7, 8}));
  EXPECT_EQ(ev.stats.extendedHits, 0u);
  EXPECT_EQ(ev.state.used[ev.index(100)], 0);
}

TEST_P(HoleFillingModes, FillsOnlyBetweenTheFirstAndLastHit) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, helix(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({2, 3, 4, 5, 6, 7});
  holeFilling(ev.cfg, GetParam()).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(ev.state.used[ev.index(1)], 0);
  EXPECT_EQ(ev.state.used[ev.index(8)], 0);
}

INSTANTIATE_TEST_SUITE_P(Residuals, HoleFillingModes,
                         ::testing::Values(Residuals::eToFits,
                                           Residuals::eToNeighbours));

TEST(HoleFilling, NeighbourResidualsForgiveALocalDeviation) {
  // The hole's hit and its neighbours on the track (layers 2 to 4) lie
  // 70 um (14 sigma) off the helix on the same side, as a particle
  // deflected smoothly by multiple scattering would leave them: the fit
  // through the track's hits (chi2/ndf 42) passes between the deviating
  // and the other hits and misses the hole hit by 6.5 sigma (chi2 42, above
  // the hole cut of 30), but the hole hit lies where its neighbours'
  // residuals put it. Only the neighbour residuals accept it.
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits = helix(det);
  for (std::uint16_t l = 2; l <= 4; ++l) {
    hits[l] = test::shiftedHit(det, l, hits[l].position, 0.07, hits[l].id);
  }
  for (Residuals mode : {Residuals::eToFits, Residuals::eToNeighbours}) {
    test::Event ev(det, hits, test::oneBuildStep());
    const std::uint32_t t = ev.addTrack({1, 2, 3, 5, 6, 7, 8});
    holeFilling(ev.cfg, mode).run(ev.state, ev.pool, ev.stats, t);
    const bool local = mode == Residuals::eToNeighbours;
    EXPECT_EQ(ev.holds(t, 4), local) << static_cast<int>(mode);
    EXPECT_EQ(ev.stats.extendedHits, local ? 1u : 0u);
  }
}

/// Expects the construction of a hole filling with `change` applied to a
/// good configuration to throw std::invalid_argument naming `key`.
template <typename Change>
void expectRejected(Change change, const std::string& key) {
  HoleFilling::Config c;
  change(c);
  try {
    HoleFilling unit(c);
    ADD_FAILURE() << "accepted a bad " << key;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'" + key + "'"), std::string::npos)
        << e.what();
  }
}

TEST(HoleFillingConfig, FromStepTakesTheStepAndFinderSettings) {
  FinderConfig cfg = test::oneBuildStep();
  cfg.extensionPhiWindow = 0.07;
  cfg.maxWindowHits = 17;
  cfg.scatteringAllowance = false;
  cfg.steps[0].chi2PtScale = 2.5;
  const HoleFilling::Config c = HoleFilling::Config::fromStep(
      cfg.steps[0], cfg, Residuals::eToNeighbours);
  EXPECT_DOUBLE_EQ(c.chi2Cut, 50.0);
  EXPECT_DOUBLE_EQ(c.chi2PtScale, 2.5);
  EXPECT_DOUBLE_EQ(c.phiWindow, 0.07);
  EXPECT_EQ(c.maxWindowHits, 17u);
  EXPECT_FALSE(c.scatteringAllowance);
  EXPECT_EQ(c.residuals, Residuals::eToNeighbours);
  EXPECT_DOUBLE_EQ(c.chi2CutAt(1.25), 200.0);
}

TEST(HoleFillingConfig, RejectsBadValuesNamingTheKey) {
  EXPECT_NO_THROW(HoleFilling(HoleFilling::Config{}));
  expectRejected([](auto& c) { c.chi2Cut = 0.0; }, "chi2_cut");
  expectRejected(
      [](auto& c) { c.chi2Cut = std::numeric_limits<double>::infinity(); },
      "chi2_cut");
  expectRejected([](auto& c) { c.chi2PtScale = -1.0; },
                 "chi2_cut_pt_scale_GeV");
  expectRejected(
      [](auto& c) { c.phiWindow = std::numeric_limits<double>::quiet_NaN(); },
      "extension_phi_window");
  expectRejected([](auto& c) { c.maxWindowHits = 0; }, "max_window_hits");
}

}  // namespace
}  // namespace conftrack

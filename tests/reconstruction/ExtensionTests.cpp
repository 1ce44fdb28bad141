/// @file ExtensionTests.cpp
/// The extension units (detail/TrackExtension.hpp, CatchAllExtension.hpp,
/// InwardExtension.hpp, EndExtension.hpp) on synthetic helices: each takes the
/// hits of the helix it is meant to follow, in track order, and no hit off the
/// helix; each rejects bad configurations naming the key.

#include "conftrack/reconstruction/finding/detail/CatchAllExtension.hpp"
#include "conftrack/reconstruction/finding/detail/EndExtension.hpp"
#include "conftrack/reconstruction/finding/detail/InwardExtension.hpp"
#include "conftrack/reconstruction/finding/detail/TrackExtension.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "ExtensionFixture.hpp"

namespace conftrack {
namespace {

using detail::CatchAllExtension;
using detail::EndExtension;
using detail::ExtensionCuts;
using detail::InwardExtension;
using detail::TrackExtension;
using Ids = std::vector<std::uint64_t>;

constexpr double kRho = 3000.0;  // [mm]: 3.6 GeV in the 4 T of the detector
constexpr double kPhi0 = 0.4;
constexpr double kTanL = 0.3;
/// pT of a radius of kRho in 4 T [GeV].
const double kPt = 0.299792458 * 4.0 * kRho / 1000.0;

/// The eight hits of the kRho helix (ids 1 to 8, layers 0 to 7).
std::vector<Hit> helix(const Detector& det) {
  return test::helixHits(det, kRho, kPhi0, 1, kTanL, 1);
}

/// `hits` with hit `id` (of layer id - 1) replaced by one 1 mm off the
/// helix across it (id 100).
std::vector<Hit> withHitOff(const Detector& det, std::vector<Hit> hits,
                            std::uint64_t id) {
  const std::size_t k = id - 1;
  hits[k] = test::shiftedHit(det, static_cast<std::uint16_t>(k),
                             hits[k].position, 1.0, 100);
  return hits;
}

TrackExtension::Config extensionConfig(const FinderConfig& cfg) {
  return TrackExtension::Config::fromStep(cfg.steps[0], cfg);
}

TEST(TrackExtension, TakesTheHelixBeyondAThreeHitSeed) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, helix(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3});
  const TrackExtension ext(extensionConfig(ev.cfg));
  ext.run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(ev.stats.extendedHits, 5u);
  for (std::uint64_t id = 4; id <= 8; ++id) {
    EXPECT_EQ(ev.state.used[ev.index(id)], 1) << id;
  }
  // The refitted track: the helix's pT, fits through exact hits.
  const TrackCandidate& track = ev.state.tracks[t];
  EXPECT_NEAR(track.pt, kPt, 0.01 * kPt);
  EXPECT_NEAR(track.sz.tanLambda, kTanL, 1e-3);
  EXPECT_LT(track.uv.chi2PerNdf(), 1e-3);
  EXPECT_LT(track.sz.chi2PerNdf(), 1e-3);
}

TEST(TrackExtension, SkipsAHitOneMillimetreOffTheHelix) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, withHitOff(det, helix(det), 4), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3});
  TrackExtension(extensionConfig(ev.cfg)).run(ev.state, ev.pool, ev.stats, t);
  // The layer of the off hit is skipped, the ones beyond it are taken.
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 5, 6, 7, 8}));
  EXPECT_EQ(ev.state.used[ev.index(100)], 0);
}

TEST(TrackExtension, PrefersTheHitOnTheHelixToOneBesideIt) {
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits = helix(det);
  hits.push_back(test::shiftedHit(det, 3, hits[3].position, 1.0, 100));
  test::Event ev(det, hits, test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3});
  TrackExtension(extensionConfig(ev.cfg)).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_FALSE(ev.holds(t, 100));
}

/// The helix without its hit on layer 4 (id 5: the particle crossed no
/// module there) and with a hit `offset` [mm] beside it (id 100, a
/// neighbour's).
std::vector<Hit> gapWithNeighbour(const Detector& det, double offset) {
  std::vector<Hit> hits = helix(det);
  hits[4] = test::shiftedHit(det, 4, hits[4].position, offset, 100);
  return hits;
}

TEST(TrackExtension, RefusesAHitFarBeyondTheTrackFitQuality) {
  // With a chi2_cut so loose that the neighbour's hit passes it (the rise
  // of chi2/ndf that one hit causes on a long track), only the hit chi2
  // cut relative to the track's fit quality refuses it, and the extension
  // goes on to the helix's hits beyond the gap.
  const Detector det = test::barrelDetector();
  FinderConfig cfg = test::oneBuildStep();
  cfg.steps[0].chi2Cut = 1e5;
  {
    test::Event ev(det, gapWithNeighbour(det, 0.2), cfg);
    const std::uint32_t t = ev.addTrack({1, 2, 3, 4});
    TrackExtension(extensionConfig(ev.cfg)).run(ev.state, ev.pool, ev.stats, t);
    EXPECT_TRUE(ev.holds(t, 100)) << "the cut is off by default";
  }
  cfg.extensionHitChi2Ratio = 30.0;
  cfg.extensionHitChi2Floor = 100.0;
  test::Event ev(det, gapWithNeighbour(det, 0.2), cfg);
  const std::uint32_t t = ev.addTrack({1, 2, 3, 4});
  TrackExtension(extensionConfig(ev.cfg)).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 6, 7, 8}));
  EXPECT_EQ(ev.state.used[ev.index(100)], 0);
}

TEST(TrackExtension, PassesAPoorHitByForABetterOneBeyond) {
  // The neighbour's hit beside the gap passes the loose chi2_cut; with
  // extension_skip_chi2 below its chi2 the extension compares it with the
  // helix's hit on the next layer, which is better by far more than a
  // missing hit's charge, and passes the gap by.
  const Detector det = test::barrelDetector();
  FinderConfig cfg = test::oneBuildStep();
  cfg.steps[0].chi2Cut = 1e5;
  auto extended = [&](double skipChi2, bool& neighbourFree) {
    cfg.extensionSkipChi2 = skipChi2;
    test::Event ev(det, gapWithNeighbour(det, 0.2), cfg);
    const std::uint32_t t = ev.addTrack({1, 2, 3, 4});
    TrackExtension(extensionConfig(ev.cfg)).run(ev.state, ev.pool, ev.stats, t);
    neighbourFree = ev.state.used[ev.index(100)] == 0;
    return ev.ids(t);
  };
  bool free = false;
  EXPECT_EQ(extended(0.0, free), (Ids{1, 2, 3, 4, 100, 6, 7, 8}))
      << "off by default";
  EXPECT_FALSE(free);
  EXPECT_EQ(extended(1e6, free), (Ids{1, 2, 3, 4, 100, 6, 7, 8}))
      << "a hit below the threshold is taken as before";
  EXPECT_EQ(extended(50.0, free), (Ids{1, 2, 3, 4, 6, 7, 8}));
  EXPECT_TRUE(free);
}

TEST(ExtensionCuts, HitChi2CutFollowsTheTrackFitQuality) {
  ExtensionCuts cuts;
  ConformalFitResult uv;
  SzFitResult sz;
  uv.chi2 = 40.0;
  uv.ndf = 4;
  sz.chi2 = 60.0;
  sz.ndf = 6;
  EXPECT_EQ(cuts.maxHitChi2(uv, sz), std::numeric_limits<double>::infinity());
  cuts.hitChi2Ratio = 30.0;
  cuts.hitChi2Floor = 100.0;
  EXPECT_DOUBLE_EQ(cuts.maxHitChi2(uv, sz), 300.0);  // 30 x 100 / 10
  uv.chi2 = 1.0;
  sz.chi2 = 1.0;
  EXPECT_DOUBLE_EQ(cuts.maxHitChi2(uv, sz), 100.0);  // the floor
}

TEST(TrackExtension, GoesOutwardsOnly) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, helix(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({4, 5, 6, 7, 8});
  TrackExtension(extensionConfig(ev.cfg)).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{4, 5, 6, 7, 8}));
  EXPECT_EQ(ev.stats.extendedHits, 0u);
}

TEST(EndExtension, TakesTheHelixBeyondItsLastHit) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, helix(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3, 4, 5});
  EndExtension(EndExtension::Config::fromStep(ev.cfg.steps[0], ev.cfg))
      .run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(ev.stats.extendedHits, 3u);
}

TEST(EndExtension, LeavesTracksOfFewerThanFiveHitsAlone) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, helix(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3, 4});
  EndExtension::Config c =
      EndExtension::Config::fromStep(ev.cfg.steps[0], ev.cfg);
  EXPECT_EQ(c.minHits, 5u);
  EndExtension(c).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4}));
  c.minHits = 4;
  EndExtension(c).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(EndExtension, TakesAHitBeyondTheStepsAngleCut) {
  // The hit of layer 5 (r = 100 mm) 2 mm off the helix, after a track of
  // the five hits before it, with a chi2 cut that passes anything: the
  // cell to it is beyond the step's (u, v) angle cut (0.05 rad; 1.5 mm is
  // too, 1 mm is not), within three times it.
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits = helix(det);
  hits[5] = test::shiftedHit(det, 5, hits[5].position, 2.0, 100);
  hits.resize(6);
  FinderConfig cfg = test::oneBuildStep();
  cfg.steps[0].chi2Cut = 1e5;
  auto takes = [&](auto unit) {
    test::Event ev(det, hits, cfg);
    const std::uint32_t t = ev.addTrack({1, 2, 3, 4, 5});
    unit.run(ev.state, ev.pool, ev.stats, t);
    return ev.holds(t, 100);
  };
  EXPECT_FALSE(takes(
      TrackExtension(TrackExtension::Config::fromStep(cfg.steps[0], cfg))));
  EndExtension::Config end = EndExtension::Config::fromStep(cfg.steps[0], cfg);
  EXPECT_DOUBLE_EQ(end.angleFactor, 3.0);
  EXPECT_TRUE(takes(EndExtension(end)));
  end.angleFactor = 1.0;
  EXPECT_FALSE(takes(EndExtension(end)));
}

TEST(InwardExtension, CompletesATrackTowardsTheIp) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, helix(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({4, 5, 6, 7, 8});
  const InwardExtension inward(
      InwardExtension::Config::fromStep(ev.cfg.steps[0], ev.cfg));
  inward.run(ev.state, ev.pool, ev.stats, t);
  // Prepended: the track stays in path order, innermost first.
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(ev.stats.extendedHits, 3u);
  EXPECT_NEAR(ev.state.tracks[t].pt, kPt, 0.01 * kPt);
}

TEST(InwardExtension, SkipsAHitOneMillimetreOffTheHelix) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, withHitOff(det, helix(det), 2), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({4, 5, 6, 7, 8});
  InwardExtension(InwardExtension::Config::fromStep(ev.cfg.steps[0], ev.cfg))
      .run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(ev.state.used[ev.index(100)], 0);
}

/// A looper: radius kLoopRho reaches 110 mm, so it crosses the six layers
/// up to 100 mm on its way out (ids 1 to 6) and again on its way back in
/// (ids 11 to 16, layers 5 down to 0).
constexpr double kLoopRho = 55.0;
std::vector<Hit> looper(const Detector& det) {
  std::vector<Hit> hits = test::helixHits(det, kLoopRho, kPhi0, 1, kTanL, 1);
  EXPECT_EQ(hits.size(), 6u);
  for (std::uint16_t l = 0; l < 6; ++l) {
    const auto layer = static_cast<std::uint16_t>(5 - l);
    const Vector3 p = test::helixAtRadius(kLoopRho, kPhi0, 1, kTanL,
                                          det.layers()[layer].r, true);
    hits.push_back(test::barrelHit(det, layer, p.x(), p.y(), p.z(), 11 + l));
  }
  return hits;
}

TEST(CatchAllExtension, FollowsALooperBackIn) {
  const Detector det = test::barrelDetector();
  test::Event ev(det, looper(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3});
  const CatchAllExtension catchAll(
      CatchAllExtension::Config::fromStep(ev.cfg.steps[0], ev.cfg));
  catchAll.run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6, 11, 12, 13, 14, 15, 16}));
  EXPECT_EQ(ev.stats.extendedHits, 9u);
  const double pt = 0.299792458 * 4.0 * kLoopRho / 1000.0;
  EXPECT_NEAR(ev.state.tracks[t].pt, pt, 0.01 * pt);
}

TEST(CatchAllExtension, PerLayerExtensionStopsAtTheTurn) {
  // The per-layer extension takes only hits further out than the last.
  const Detector det = test::barrelDetector();
  test::Event ev(det, looper(det), test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3});
  TrackExtension(extensionConfig(ev.cfg)).run(ev.state, ev.pool, ev.stats, t);
  EXPECT_EQ(ev.ids(t), (Ids{1, 2, 3, 4, 5, 6}));
}

TEST(CatchAllExtension, RejectsAHitOneMillimetreOffTheLooper) {
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits = looper(det);
  // The returning hit on layer 3 (id 13) moved off the helix.
  hits[8] = test::shiftedHit(det, 3, hits[8].position, 1.0, 100);
  test::Event ev(det, hits, test::oneBuildStep());
  const std::uint32_t t = ev.addTrack({1, 2, 3});
  CatchAllExtension(
      CatchAllExtension::Config::fromStep(ev.cfg.steps[0], ev.cfg))
      .run(ev.state, ev.pool, ev.stats, t);
  EXPECT_FALSE(ev.holds(t, 100));
  EXPECT_TRUE(ev.holds(t, 14));
  EXPECT_EQ(ev.state.used[ev.index(100)], 0);
}

/// Expects `make` to throw std::invalid_argument naming `key`.
template <typename Make>
void expectRejected(Make make, const std::string& key) {
  try {
    make();
    ADD_FAILURE() << "accepted a bad " << key;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'" + key + "'"), std::string::npos)
        << e.what();
  }
}

TEST(ExtensionConfig, FromStepTakesTheStepAndFinderSettings) {
  FinderConfig cfg = test::oneBuildStep();
  cfg.extensionPhiWindow = 0.07;
  cfg.maxWindowHits = 17;
  cfg.extensionLookahead = 1;
  cfg.scatteringAllowance = false;
  cfg.extensionHitChi2Ratio = 25.0;
  cfg.extensionHitChi2Floor = 60.0;
  cfg.extensionSkipChi2 = 250.0;
  cfg.steps[0].chi2PtScale = 2.5;
  const TrackExtension::Config c = extensionConfig(cfg);
  EXPECT_DOUBLE_EQ(c.cuts.maxCellAngle, 0.05);
  EXPECT_DOUBLE_EQ(c.cuts.maxCellAngleRZ, 0.05);
  EXPECT_DOUBLE_EQ(c.cuts.chi2Cut, 50.0);
  EXPECT_DOUBLE_EQ(c.cuts.chi2PtScale, 2.5);
  EXPECT_DOUBLE_EQ(c.cuts.phiWindow, 0.07);
  EXPECT_EQ(c.cuts.maxWindowHits, 17u);
  EXPECT_EQ(c.cuts.lookahead, 1);
  EXPECT_DOUBLE_EQ(c.cuts.hitChi2Ratio, 25.0);
  EXPECT_DOUBLE_EQ(c.cuts.hitChi2Floor, 60.0);
  EXPECT_DOUBLE_EQ(c.cuts.skipChi2, 250.0);
  EXPECT_FALSE(c.scatteringAllowance);
  // The pT scaling of the step's cut (one formula, scaledChi2Cut).
  for (double pt : {0.0, 1e-4, 0.5, 1.25, 2.4999, 2.5, 10.0}) {
    EXPECT_EQ(c.cuts.chi2CutAt(pt), cfg.steps[0].chi2CutAt(pt)) << pt;
  }
  EXPECT_DOUBLE_EQ(c.cuts.chi2CutAt(1.25), 200.0);
  // The inward completion has its own key (inward_scattering_allowance).
  EXPECT_TRUE(
      InwardExtension::Config::fromStep(cfg.steps[0], cfg).scatteringAllowance);
  cfg.inwardScatteringAllowance = false;
  EXPECT_FALSE(
      InwardExtension::Config::fromStep(cfg.steps[0], cfg).scatteringAllowance);
}

TEST(ExtensionConfig, RejectsBadValuesNamingTheKey) {
  const ExtensionCuts good;
  EXPECT_NO_THROW(TrackExtension({good, true}));
  EXPECT_NO_THROW(CatchAllExtension({good}));
  EXPECT_NO_THROW(InwardExtension({good, true}));
  auto bad = [&](auto change) {
    ExtensionCuts c = good;
    change(c);
    return c;
  };
  expectRejected(
      [&] {
        TrackExtension({bad([](auto& c) { c.maxCellAngle = 0.0; }), true});
      },
      "max_cell_angle");
  expectRejected(
      [&] {
        TrackExtension({bad([](auto& c) { c.maxCellAngleRZ = -0.1; }), true});
      },
      "max_cell_angle_rz");
  expectRejected(
      [&] {
        InwardExtension({bad([](auto& c) {
                           c.chi2Cut = std::numeric_limits<double>::quiet_NaN();
                         }),
                         true});
      },
      "chi2_cut");
  expectRejected(
      [&] {
        InwardExtension({bad([](auto& c) { c.chi2PtScale = -1.0; }), true});
      },
      "chi2_cut_pt_scale_GeV");
  expectRejected(
      [&] { CatchAllExtension({bad([](auto& c) { c.phiWindow = 4.0; })}); },
      "extension_phi_window");
  expectRejected(
      [&] { CatchAllExtension({bad([](auto& c) { c.maxWindowHits = 0; })}); },
      "max_window_hits");
  expectRejected(
      [&] { CatchAllExtension({bad([](auto& c) { c.hitChi2Ratio = -1.0; })}); },
      "extension_hit_chi2_ratio");
  expectRejected(
      [&] { CatchAllExtension({bad([](auto& c) { c.skipChi2 = -1.0; })}); },
      "extension_skip_chi2");
  expectRejected(
      [&] {
        TrackExtension({bad([](auto& c) { c.hitChi2Floor = 0.0; }), true});
      },
      "extension_hit_chi2_floor");
  expectRejected(
      [&] { CatchAllExtension({bad([](auto& c) { c.lookahead = 6; })}); },
      "extension_lookahead");
  expectRejected(
      [&] {
        TrackExtension({bad([](auto& c) { c.lookahead = -1; }), true});
      },
      "extension_lookahead");
}

TEST(EndExtension, ConfigFromTheFinderKeys) {
  FinderConfig cfg = test::oneBuildStep();
  cfg.extensionPhiWindow = 0.02;
  cfg.finalExtensionPhiWindow = 0.09;
  cfg.finalExtensionAngleFactor = 4.0;
  const EndExtension::Config c =
      EndExtension::Config::fromStep(cfg.steps[0], cfg);
  EXPECT_DOUBLE_EQ(c.cuts.phiWindow, 0.09);
  EXPECT_DOUBLE_EQ(c.angleFactor, 4.0);
  EXPECT_DOUBLE_EQ(c.cuts.maxCellAngle, cfg.steps[0].maxCellAngle);
  EXPECT_DOUBLE_EQ(c.cuts.chi2Cut, cfg.steps[0].chi2Cut);
  EndExtension::Config bad = c;
  bad.angleFactor = 0.5;
  expectRejected([&] { EndExtension{bad}; }, "final_extension_angle_factor");
  bad = c;
  bad.cuts.phiWindow = 0.0;
  expectRejected([&] { EndExtension{bad}; }, "final_extension_phi_window");
  bad = c;
  bad.minHits = 2;
  expectRejected([&] { EndExtension{bad}; }, "minHits");
}

}  // namespace
}  // namespace conftrack

/// @file BeamSpotPrepassTests.cpp
/// The beam-line pre-pass (BeamSpotPrepass, algorithm.md 3.24): its
/// estimate on simulated CLICdet events whose beams collide off the
/// detector axis, its fallback, its chain table, and the finder with it.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/finding/BeamSpotPrepass.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "ChainText.hpp"
#include "InputErrorOf.hpp"

namespace conftrack {
namespace {

/// CLICdet tt-bar events (with `bx` crossings of overlay) whose
/// interactions are centred on (x, y).
EventSimulation::Config offAxisTtbar(double x, double y, std::size_t bx) {
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = bx;
  cfg.seed = 51;
  LuminousRegion::Config region =
      LuminousRegion::findPreset("clic3tev")->config;
  region.position = Vector3(x, y, 0.0);
  cfg.luminousRegion = region;
  return cfg;
}

BeamSpotPrepass::Config vertexBarrel(const Detector& det) {
  BeamSpotPrepass::Config c;
  c.collections = {det.findSubdetector("VertexBarrel").value()};
  return c;
}

TEST(BeamSpotPrepass, MeasuresTheBeamLineOfEachEvent) {
  // Five CLICdet tt-bar events per beam line, with and without 30 BX of
  // overlay, the configured line (0.2, -0.1) mm. Measured (2026-11-30):
  // every estimate within 43 um of the true line in each coordinate (the
  // fit's own uncertainty, 8-29 um, knows only the circles' spread, not
  // the random triplets it keeps); with overlay 9 of 10 events measured,
  // without it 7 of 10 (the third event has 35 circles, too few
  // directions for the fit); the others keep the configured line. The finder
  // does not notice 0.06 mm: a straight track that far from the map's
  // origin bends by under one hit resolution across the vertex barrel
  // (algorithm.md 3.24).
  const Detector det = loadDetector("clicdet");
  const BeamSpotPrepass prepass(det, vertexBarrel(det));
  ASSERT_EQ(prepass.layers().size(), 3u);
  for (const auto& [x, y, bx] :
       {std::tuple{0.0, 0.0, 0}, std::tuple{1.0, -1.0, 0},
        std::tuple{-0.3, 0.6, 30}, std::tuple{1.0, 1.0, 30}}) {
    EventSimulation sim(det, offAxisTtbar(x, y, bx));
    int measured = 0;
    for (std::uint64_t e = 1; e <= 5; ++e) {
      const Event ev = sim.simulate(e);
      const Vector2 configured(0.2, -0.1);
      const BeamSpotPrepass::Result r = prepass.run(ev.hits, configured);
      std::printf(
          "[ beam (%.2f, %.2f), %d BX, event %lu ] (%.4f, %.4f) +- "
          "%.4f mm, %lu of %lu circles, %.2f ms\n",
          x, y, static_cast<int>(bx), static_cast<unsigned long>(e),
          r.position.x(), r.position.y(), r.uncertainty,
          static_cast<unsigned long>(r.inliers),
          static_cast<unsigned long>(r.triplets), r.milliseconds);
      if (r.valid) {
        ++measured;
        EXPECT_NEAR(r.position.x(), x, 0.06);
        EXPECT_NEAR(r.position.y(), y, 0.06);
      } else {
        // Not measured: the configured line stays.
        EXPECT_EQ(r.position, configured);
      }
    }
    EXPECT_GE(measured, bx == 0 ? 3 : 4);
  }
}

TEST(BeamSpotPrepass, TooFewTracksKeepTheConfiguredLine) {
  // One 10 GeV muon: one circle, no direction across it.
  const Detector det = loadDetector("clicdet");
  const BeamSpotPrepass prepass(det, vertexBarrel(det));
  EventSimulation::Config cfg;
  cfg.sample = "muons";
  cfg.seed = 3;
  cfg.generatorToml =
      "[generator]\nsample = \"gun\"\nparticle = \"mu-\"\n"
      "multiplicity = 1\npt_GeV = 10.0\ntheta_deg = 80.0\n";
  EventSimulation sim(det, cfg);
  const BeamSpotPrepass::Result r =
      prepass.run(sim.simulate(1).hits, Vector2(0.5, 0.25));
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.position, Vector2(0.5, 0.25));
  EXPECT_LE(r.triplets, 2u);
}

TEST(BeamSpotPrepass, ChainTable) {
  const Detector det = loadDetector("clicdet");
  const std::string step = minimalStep("VertexBarrel");
  const FinderConfig c = parseChain(
      "[beam_spot_prepass]\ncollections = [\"VertexBarrel\"]\n"
      "min_pt_GeV = 0.8\nmax_d0_mm = 5\n" +
          step,
      "c.toml", det);
  ASSERT_TRUE(c.beamSpotPrepass.has_value());
  EXPECT_DOUBLE_EQ(c.beamSpotPrepass->minPt, 0.8 * units::GeV);
  EXPECT_DOUBLE_EQ(c.beamSpotPrepass->maxD0, 5.0 * units::mm);
  EXPECT_FALSE(parseChain(step, "c.toml", det).beamSpotPrepass.has_value());
  for (const auto& [table, where] :
       std::vector<std::pair<std::string, std::string>>{
           {"collections = [\"VertexBarrel\"]\nmax_d0_mm = 20\n",
            "c.toml:3: key 'beam_spot_prepass.max_d0_mm'"},
           {"collections = [\"VertexEndcap\"]\n",
            "c.toml:2: key 'beam_spot_prepass.collections': need three "
            "barrel layers"},
           {"collections = [\"VertexBarrel\"]\nspeed = 1\n",
            "c.toml:3: key 'beam_spot_prepass.speed': unknown key"}}) {
    const std::string what = test::inputErrorOf([&] {
      parseChain("[beam_spot_prepass]\n" + table + step, "c.toml", det);
    });
    EXPECT_NE(what.find(where), std::string::npos) << what;
  }
}

TEST(BeamSpotPrepass, FinderMapsAboutTheMeasuredLine) {
  // The CLICdet chain with the pre-pass on tt-bar + 30 BX whose beams
  // collide 1 mm off the axis in x and y: the finder reports the line it
  // used (the measured one) and builds as many tracks as about the true
  // line, within 1 % (measured on three events: 1,821 either way; about
  // the axis 1,910, the pieces of split particles).
  const Detector det = loadDetector("clicdet");
  FinderConfig chain = readChain(resolveChainPath("clicdet"), det);
  const ConformalTrackFinder axis(det, {chain});
  chain.beamSpotX = 1.0 * units::mm;
  chain.beamSpotY = -1.0 * units::mm;
  const ConformalTrackFinder given(det, {chain});
  chain.beamSpotX = 0.0;
  chain.beamSpotY = 0.0;
  chain.beamSpotPrepass = vertexBarrel(det);
  const ConformalTrackFinder measured(det, {chain});
  EventSimulation sim(det, offAxisTtbar(1.0, -1.0, 30));
  std::size_t nGiven = 0;
  std::size_t nMeasured = 0;
  std::size_t nAxis = 0;
  for (std::uint64_t e = 1; e <= 3; ++e) {
    const Event ev = sim.simulate(e);
    const FindingResult g = given.run(ev.hits);
    const FindingResult m = measured.run(ev.hits);
    const FindingResult a = axis.run(ev.hits);
    EXPECT_EQ(g.beamSpot, Vector2(1.0, -1.0));
    EXPECT_EQ(a.beamSpot, Vector2::Zero());
    EXPECT_NEAR(m.beamSpot.x(), 1.0, 0.06);
    EXPECT_NEAR(m.beamSpot.y(), -1.0, 0.06);
    ASSERT_FALSE(m.steps.empty());
    EXPECT_EQ(m.steps.front().name, "BeamSpot");
    nGiven += g.tracks.size();
    nMeasured += m.tracks.size();
    nAxis += a.tracks.size();
  }
  std::printf("[ tracks ] given %zu, measured %zu, about the axis %zu\n",
              nGiven, nMeasured, nAxis);
  EXPECT_NEAR(double(nMeasured), double(nGiven), 0.01 * double(nGiven));
  EXPECT_GT(double(nAxis), 1.02 * double(nGiven));  // premise: pieces
}

TEST(BeamSpotPrepass, LaterPassKeepsTheFirstPassLine) {
  // A later pass (Reconstruction's second pass) maps about the line it is
  // given, without measuring again; given none, about the chain's.
  const Detector det = loadDetector("clicdet");
  FinderConfig chain = readChain(resolveChainPath("clicdet"), det);
  chain.beamSpotX = 0.5 * units::mm;
  chain.beamSpotPrepass = vertexBarrel(det);
  const ConformalTrackFinder finder(det, {chain});
  EventSimulation sim(det, offAxisTtbar(0.3, 0.2, 0));
  const Event ev = sim.simulate(1);
  const std::vector<std::uint8_t> taken(ev.hits.size(), 0);
  const std::vector<std::uint16_t> steps{0};
  ConformalTrackFinder::Pass pass{steps, taken, {}, Vector2(0.3, 0.2)};
  const FindingResult given = finder.run(ev.hits, pass);
  EXPECT_EQ(given.beamSpot, Vector2(0.3, 0.2));
  pass.beamSpot.reset();
  const FindingResult chains = finder.run(ev.hits, pass);
  EXPECT_EQ(chains.beamSpot, Vector2(0.5, 0.0));
  for (const FindingResult* r : {&given, &chains}) {
    for (const StepStats& s : r->steps) {
      EXPECT_NE(s.name, "BeamSpot");
    }
  }
  // The first pass measures it.
  const FindingResult first = finder.run(ev.hits);
  EXPECT_NEAR(first.beamSpot.x(), 0.3, 0.06);
  EXPECT_NEAR(first.beamSpot.y(), 0.2, 0.06);
}

}  // namespace
}  // namespace conftrack

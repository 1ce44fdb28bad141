/// @file SplitTrackMergerTests.cpp
/// Merging the pieces of one particle after the fit (SplitTrackMerger):
/// a displaced particle's vertex-detector piece and tracker piece, fitted
/// apart, become one track; pieces of two particles stay apart; the chain
/// file's [split_merging] table is read and checked.

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/reconstruction/selection/SplitTrackMerger.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "ClicdetParticles.hpp"

namespace conftrack {
namespace {

using test::clicdetDetector;
using test::pion;
using Simulated = test::SimulatedParticles;
const KalmanFitter& fitter() { return test::clicdetFitter(); }
Simulated simulate(const std::vector<Particle>& particles) {
  return test::simulateInClicdet(particles, 3);
}

/// The fitted track of some of a particle's hits, [first, last), its
/// perigee about `beamLine`.
Track piece(const Simulated& s, std::size_t particle, std::size_t first,
            std::size_t last, const Vector2& beamLine = Vector2::Zero()) {
  const std::vector<HitIndex> hits(s.byParticle[particle].begin() + first,
                                   s.byParticle[particle].begin() + last);
  Track t = fitter().fit(s.event.hits, FitInput{hits, false, beamLine});
  EXPECT_TRUE(t.fitted);
  return t;
}

SplitTrackMerger::Config enabled() {
  SplitTrackMerger::Config c;
  c.enabled = true;
  return c;
}

TEST(SplitTrackMerger, PiecesOfADisplacedParticleBecomeOneTrack) {
  // A 3 GeV pion produced 15 mm off the beam line: its vertex-detector
  // hits and its tracker hits fitted as two tracks, as two finding steps
  // leave such a particle (CLICdet tt-bar: docs/algorithm.md 10.1). Of
  // either charge: the arc length that orders the hits turns with it.
  for (const double charge : {1.0, -1.0}) {
    const Simulated s = simulate(
        {pion(1, 3.0, 0.3, 70.0 * units::degree, {15.0, 0.0, 1.0}, charge)});
    const std::size_t n = s.byParticle[0].size();
    ASSERT_GE(n, 10u);
    std::vector<Track> tracks = {piece(s, 0, 0, 4), piece(s, 0, 4, n)};
    const SplitTrackMerger merger(fitter(), enabled());
    const SplitTrackMerger::Result merged = merger.run(s.event.hits, tracks);
    ASSERT_EQ(merged.tracks.size(), 1u);
    EXPECT_EQ(merged.merges, 1u);
    const Track& t = merged.tracks[0];
    EXPECT_TRUE(t.fitted);
    EXPECT_EQ(t.hits.size(), n);
    EXPECT_EQ(t.numOutliers(), 0u);
    EXPECT_LT(t.chi2 / t.ndf, 3.0);
    // In path order: the merged list is the particle's, time-ordered.
    EXPECT_EQ(t.hits, s.byParticle[0]);
    // Three pieces become one over two rounds.
    tracks = {piece(s, 0, 0, 4), piece(s, 0, 4, 7), piece(s, 0, 7, n)};
    const SplitTrackMerger::Result three = merger.run(s.event.hits, tracks);
    ASSERT_EQ(three.tracks.size(), 1u);
    EXPECT_EQ(three.merges, 2u);
    EXPECT_EQ(three.tracks[0].hits.size(), n);
    // Off, nothing changes.
    const SplitTrackMerger off(fitter(), SplitTrackMerger::Config{});
    EXPECT_EQ(off.run(s.event.hits, tracks).tracks.size(), 3u);
    // Perigees about a beam line off the axis: the pieces merge as about
    // the axis, and the merged fit keeps their line (its refit took the
    // axis before). Pieces about two lines are not compared, even 1 um
    // apart, where their parameters would agree: no perigee of one line
    // is taken as one of another.
    const Vector2 line(9.0, -4.0);
    const SplitTrackMerger::Result aboutLine = merger.run(
        s.event.hits, {piece(s, 0, 0, 4, line), piece(s, 0, 4, n, line)});
    ASSERT_EQ(aboutLine.tracks.size(), 1u);
    EXPECT_EQ(aboutLine.tracks[0].hits, s.byParticle[0]);
    EXPECT_EQ(aboutLine.tracks[0].atIp.reference, Vector3(9.0, -4.0, 0.0));
    EXPECT_EQ(
        merger
            .run(s.event.hits, {piece(s, 0, 0, 4, line),
                                piece(s, 0, 4, n, line + Vector2(1e-3, 0.0))})
            .tracks.size(),
        2u);
  }
}

TEST(SplitTrackMerger, PiecesOfTwoParticlesStayApart) {
  // Two pions from one displaced vertex, 3 and 3.3 GeV, 5 mrad apart: the
  // first one's vertex-detector piece and the second one's tracker piece
  // point the same way, but the tracker piece measures the curvature to
  // far better than the 10 % between them.
  const Vector3 vertex(15.0, 0.0, 1.0);
  const Simulated s =
      simulate({pion(1, 3.0, 0.3, 70.0 * units::degree, vertex),
                pion(2, 3.3, 0.305, 70.0 * units::degree, vertex)});
  const std::size_t n2 = s.byParticle[1].size();
  ASSERT_GE(n2, 10u);
  const std::vector<Track> tracks = {piece(s, 0, 0, 4), piece(s, 1, 4, n2)};
  const SplitTrackMerger merger(fitter(), enabled());
  const SplitTrackMerger::Result result = merger.run(s.event.hits, tracks);
  EXPECT_EQ(result.tracks.size(), 2u);
  EXPECT_EQ(result.merges, 0u);
  // A loose parameter bound lets the pair through to the merged fit,
  // which then fails (its chi2/ndf, its outliers): still apart.
  SplitTrackMerger::Config loose = enabled();
  loose.maxParameterChi2 = 1e6;
  EXPECT_EQ(SplitTrackMerger(fitter(), loose).run(s.event.hits, tracks).merges,
            0u);
  // The second particle's own pieces, in the same company, do merge.
  const std::vector<Track> own = {piece(s, 0, 0, 4), piece(s, 1, 0, 4),
                                  piece(s, 1, 4, n2)};
  const SplitTrackMerger::Result ownResult = merger.run(s.event.hits, own);
  ASSERT_EQ(ownResult.tracks.size(), 2u);
  EXPECT_EQ(ownResult.tracks[1].hits, s.byParticle[1]);
}

TEST(SplitTrackMerger, ChainFileTableIsReadAndChecked) {
  // Off by default; the shipped CLICdet chain switches it on.
  EXPECT_FALSE(SplitTrackMerger::Config{}.enabled);
  EXPECT_TRUE(
      readReconstructionConfig(resolveChainPath("clicdet"), clicdetDetector())
          .merger.enabled);
  // A chain of the shipped one's finder and first step, and the table.
  const std::string shipped =
      readTextFile(resolveChainPath("clicdet").string());
  const std::string base =
      shipped.substr(0, shipped.find("[[step]]", shipped.find("[[step]]") + 1));
  EXPECT_FALSE(parseReconstructionConfig(base, "chain.toml", clicdetDetector())
                   .merger.enabled);
  const Reconstruction::Config on = parseReconstructionConfig(
      base +
          "[split_merging]\nenabled = true\nmax_parameter_chi2 = 20.0\n"
          "max_same_layer_distance_mm = 4.0\n",
      "chain.toml", clicdetDetector());
  EXPECT_TRUE(on.merger.enabled);
  EXPECT_DOUBLE_EQ(on.merger.maxParameterChi2, 20.0);
  EXPECT_DOUBLE_EQ(on.merger.maxSameLayerDistance, 4.0 * units::mm);
  try {
    parseReconstructionConfig(base + "[split_merging]\nmax_chi2_ratio = 0.5\n",
                              "chain.toml", clicdetDetector());
    FAIL() << "a chi2 ratio below 1 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_chi2_ratio"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(
      parseReconstructionConfig(base + "[split_merging]\nmax_chi2 = 3.0\n",
                                "chain.toml", clicdetDetector()),
      InputError);
  SplitTrackMerger::Config bad = enabled();
  bad.maxPhi0Difference = 4.0;
  EXPECT_THROW(SplitTrackMerger(fitter(), bad), std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

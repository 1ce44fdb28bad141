/// @file SeedZ0Tests.cpp
/// The z0 of a prompt build's seed cells (SeedAutomaton::seedCellZ0,
/// algorithm.md 3.16): taken along the arc of the circle through the
/// origin and the cell's hits, on which the helix is straight in z, so
/// that a low-momentum track from z = 0 passes a z0 cut far tighter than
/// the curvature of its (R, z) chords (also through the seeds' (z, R)
/// search cone, which is widened for the arc: without that it refused
/// them); a track from elsewhere does not.
///
/// Tolerances: the hits lie exactly on their helices (5 um errors), so the
/// arc's z0 is exact to rounding; the cut (0.3 mm) is below half the
/// chords' miss, which the test checks as its premise.

#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

constexpr double kRho = 100.0;  // mm: 0.12 GeV in 4 T
constexpr double kTanL = 2.0;
constexpr double kPhi0 = 0.7;
constexpr double kCut = 0.3;  // mm

FinderConfig buildWithZ0Cut() {
  FinderConfig cfg = test::oneBuildStep();
  cfg.steps.front().maxSeedZ0 = kCut;
  return cfg;
}

/// The hits of the helix from (0, 0, z0) on the barrel layers.
std::vector<Hit> trackFrom(const Detector& det, double z0) {
  std::vector<Hit> hits = test::helixHits(det, kRho, kPhi0, +1, kTanL, 1);
  for (Hit& h : hits) {
    h.position.z() += z0;
  }
  return hits;
}

TEST(SeedZ0, LowMomentumTrackFromTheVertexPassesATightZ0Cut) {
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = trackFrom(det, 0.0);
  ASSERT_EQ(hits.size(), 8u);
  // Premise: the (R, z) chord of each pair of neighbouring layers meets
  // R = 0 more than twice the cut from the vertex (0.7 mm for the first
  // pair, growing outwards), as upstream's z0 took it.
  for (std::size_t i = 0; i + 1 < hits.size(); ++i) {
    const Vector3& a = hits[i].position;
    const Vector3& b = hits[i + 1].position;
    const double ra = a.head<2>().norm();
    const double rb = b.head<2>().norm();
    const double chordZ0 = a.z() - (b.z() - a.z()) / (rb - ra) * ra;
    EXPECT_GT(std::abs(chordZ0), 2.0 * kCut) << "layers " << i;
  }
  const FindingResult r =
      ConformalTrackFinder(det, {buildWithZ0Cut()}).run(hits);
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].hits.size(), 8u);
}

TEST(SeedZ0, TrackFromOutsideTheCutIsNotSeeded) {
  // The same track from z0 = 1 mm: no seed cell passes.
  const Detector det = test::barrelDetector();
  const FindingResult r =
      ConformalTrackFinder(det, {buildWithZ0Cut()}).run(trackFrom(det, 1.0));
  EXPECT_TRUE(r.tracks.empty());
  // Without the cut it is found: the cut, not the track, refused it.
  const FindingResult open = ConformalTrackFinder(det, {test::oneBuildStep()})
                                 .run(trackFrom(det, 1.0));
  ASSERT_EQ(open.tracks.size(), 1u);
}

}  // namespace
}  // namespace conftrack

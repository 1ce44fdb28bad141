/// @file OverlapHitTests.cpp
/// Overlap hits (detail/OverlapHits.hpp): a particle crossing two
/// overlapping sensors of one layer leaves two hits there, and the finder's
/// track must hold both; hits on the track's own sensor, off the track, or
/// further along the layer's normal than two sensors of one layer can be,
/// stay off it.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/MaterialInteractions.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/detail/OverlapHits.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

constexpr double kRho = 3000.0;  // [mm]: 3.6 GeV in the 4 T of the detector
constexpr double kPhi0 = 0.4;
constexpr double kTanL = 0.3;
constexpr std::uint16_t kLayer = 3;  // r = 65 mm
constexpr std::uint64_t kOverlapId = 100;

/// Point of the test helix (through the origin, positive charge) at
/// transverse radius r.
Vector3 helixAtRadius(double r) {
  const double omega = 1.0 / kRho;
  auto pos = [&](double s) {
    return Vector3((std::sin(kPhi0) - std::sin(kPhi0 - omega * s)) / omega,
                   -(std::cos(kPhi0) - std::cos(kPhi0 - omega * s)) / omega,
                   s * kTanL);
  };
  double lo = 0.0;
  double hi = 1000.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (pos(mid).head<2>().norm() < r ? lo : hi) = mid;
  }
  return pos(0.5 * (lo + hi));
}

/// The eight hits of the helix plus a hit of it `dr` outside layer kLayer
/// (a second sensor of that layer), on sensor `module` of that layer or on
/// the next one, shifted by `offset` mm along its u axis.
std::vector<Hit> trackWithOverlap(const Detector& det, double dr,
                                  bool sameSensor, double offset = 0.0) {
  std::vector<Hit> hits = test::helixHits(det, kRho, kPhi0, 1, kTanL, 1);
  const double r = det.layers()[kLayer].r + dr;
  const Vector3 p = helixAtRadius(r);
  Hit second = test::barrelHit(det, kLayer, p.x(), p.y(), p.z(), kOverlapId);
  second.position += offset * second.uAxis;
  second.detId.module =
      sameSensor ? hits[kLayer].detId.module : hits[kLayer].detId.module + 1;
  hits.push_back(second);
  return hits;
}

FinderConfig oneStep(bool overlaps) {
  FinderConfig cfg = test::oneBuildStep();
  cfg.overlapHits = overlaps;
  return cfg;
}

bool holds(const FoundTrack& track, const std::vector<Hit>& hits,
           std::uint64_t id) {
  return std::any_of(track.hits.begin(), track.hits.end(),
                     [&](HitIndex h) { return hits[h].id == id; });
}

TEST(OverlapHits, TrackHoldsBothHitsOfAnOverlap) {
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = trackWithOverlap(det, 3.0, false);
  const FindingResult r = ConformalTrackFinder(det, {oneStep(true)}).run(hits);
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].hits.size(), 9u);
  EXPECT_TRUE(holds(r.tracks[0], hits, kOverlapId));
  EXPECT_EQ(r.steps[0].overlapHits, 1u);
  // In path order: the overlap hit right after the layer's first hit.
  const auto at =
      std::find_if(r.tracks[0].hits.begin(), r.tracks[0].hits.end(),
                   [&](HitIndex h) { return hits[h].id == kOverlapId; });
  ASSERT_NE(at, r.tracks[0].hits.begin());
  EXPECT_EQ(hits[*(at - 1)].id, 1u + kLayer);

  // Without the stage the track takes one hit of the layer.
  const FindingResult off =
      ConformalTrackFinder(det, {oneStep(false)}).run(hits);
  ASSERT_EQ(off.tracks.size(), 1u);
  EXPECT_EQ(off.tracks[0].hits.size(), 8u);
  EXPECT_EQ(off.steps[0].overlapHits, 0u);
}

TEST(OverlapHits, TwoHitsOnEveryLayerGiveOneTrack) {
  // A second sensor 2 mm outside every layer: the automaton can build two
  // disjoint candidates of the particle (one through each sensor), which
  // share no hit and so are no clones; the overlap search gives each the
  // other's hits, and the two are merged into one track.
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits = test::helixHits(det, kRho, kPhi0, 1, kTanL, 1);
  const std::size_t n = hits.size();
  for (std::size_t l = 0; l < n; ++l) {
    const Vector3 p = helixAtRadius(det.layers()[l].r + 2.0);
    Hit second = test::barrelHit(det, static_cast<std::uint16_t>(l), p.x(),
                                 p.y(), p.z(), 200 + l);
    second.detId.module = hits[l].detId.module + 1;
    hits.push_back(second);
  }
  const FindingResult r = ConformalTrackFinder(det, {oneStep(true)}).run(hits);
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].hits.size(), 2 * n);
  // The two candidates through the two sensors of every layer, merged.
  EXPECT_EQ(r.steps[0].mergedTracks, 1u);
  // In path order: radii grow along the track.
  for (std::size_t k = 1; k < r.tracks[0].hits.size(); ++k) {
    EXPECT_LT(hits[r.tracks[0].hits[k - 1]].position.head<2>().norm(),
              hits[r.tracks[0].hits[k]].position.head<2>().norm());
  }
}

TEST(OverlapHits, OrderOfTheInputHitsDoesNotMatter) {
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits = trackWithOverlap(det, 3.0, false);
  const FindingResult a = ConformalTrackFinder(det, {oneStep(true)}).run(hits);
  std::reverse(hits.begin(), hits.end());
  const FindingResult b = ConformalTrackFinder(det, {oneStep(true)}).run(hits);
  ASSERT_EQ(a.tracks.size(), 1u);
  ASSERT_EQ(b.tracks.size(), 1u);
  std::vector<std::uint64_t> idsA;
  std::vector<std::uint64_t> idsB;
  std::reverse(hits.begin(), hits.end());  // back to the order of run a
  for (HitIndex h : a.tracks[0].hits) {
    idsA.push_back(hits[h].id);
  }
  const std::size_t n = hits.size();
  for (HitIndex h : b.tracks[0].hits) {
    idsB.push_back(hits[n - 1 - h].id);
  }
  EXPECT_EQ(idsA, idsB);
}

TEST(OverlapHits, IncompatibleHitsStayOff) {
  const Detector det = test::barrelDetector();
  const ConformalTrackFinder finder(det, {oneStep(true)});
  // On the sensor of the track's own hit on that layer: one sensor gives
  // one hit per particle.
  {
    const std::vector<Hit> hits = trackWithOverlap(det, 3.0, true);
    const FindingResult r = finder.run(hits);
    ASSERT_EQ(r.tracks.size(), 1u);
    EXPECT_EQ(r.tracks[0].hits.size(), 8u);
  }
  // 50 um off the helix in r-phi: 10 sigma of the 5 um hits.
  {
    const std::vector<Hit> hits = trackWithOverlap(det, 3.0, false, 0.05);
    const FindingResult r = finder.run(hits);
    ASSERT_EQ(r.tracks.size(), 1u);
    EXPECT_FALSE(holds(r.tracks[0], hits, kOverlapId));
    EXPECT_EQ(r.tracks[0].hits.size(), 8u);
  }
  // On the helix, but 14 mm outside the layer's first hit: further than
  // two sensors of one layer lie apart (FinderConfig::overlapMaxGap 12 mm).
  {
    const std::vector<Hit> hits = trackWithOverlap(det, 14.0, false);
    const FindingResult r = finder.run(hits);
    ASSERT_FALSE(r.tracks.empty());
    EXPECT_FALSE(holds(r.tracks[0], hits, kOverlapId));
  }
  // A looser gap admits it.
  {
    FinderConfig cfg = oneStep(true);
    cfg.overlapMaxGap = 20.0 * units::mm;
    const std::vector<Hit> hits = trackWithOverlap(det, 14.0, false);
    const FindingResult r = ConformalTrackFinder(det, {cfg}).run(hits);
    ASSERT_FALSE(r.tracks.empty());
    EXPECT_TRUE(holds(r.tracks[0], hits, kOverlapId));
  }
}

TEST(OverlapHits, ScatteringBetweenTheTwoSensorsFollowsHighland) {
  // A track of 0.3 GeV and tanLambda 2 crossing two sensors of 1 % X0
  // 9 mm apart: its path through the first is sqrt(5) times the
  // thickness (layerTheta0), and the deflection there moves it by
  // theta0 * 9 mm at the second.
  const Detector det = test::barrelDetector(0.01);
  const SensitiveLayer& layer = det.layers()[kLayer];
  const double p = 0.3 * std::sqrt(5.0);
  const double theta0 = highlandTheta0(p, 1.0, 1.0, 0.01 * std::sqrt(5.0));
  EXPECT_NEAR(theta0, 0.0026, 0.0001);  // 13.6 MeV / p sqrt(x) (1 + ...)
  EXPECT_DOUBLE_EQ(detail::layerTheta0(layer, p, 2.0), theta0);
  EXPECT_EQ(
      detail::layerTheta0(test::barrelDetector(0.0).layers()[kLayer], p, 2.0),
      0.0);
  const std::vector<Hit> pair = {
      test::barrelHit(det, kLayer, 65.0, 0.0, 10.0, 1),
      test::barrelHit(det, kLayer, 65.0, 0.0, 19.0, 2)};
  const ConformalHits conformal = makeConformalHits(pair, det);
  EXPECT_NEAR(detail::overlapScatteringVariance(conformal, 0, 1, theta0),
              (theta0 * 9.0) * (theta0 * 9.0), 1e-12);
}

TEST(OverlapHits, SecondHitMovedByScatteringIsTaken) {
  // A steep track of 0.24 GeV (radius 200 mm in 4 T, tanLambda 2) through
  // sensors of 1 % X0 with 5 um resolution; its second sensor on layer
  // kLayer lies 4 mm further out, 9-10 mm along the track, and its hit
  // there is moved across the track by twice the scattering in the first
  // sensor (0.03 mm of a 0.015 mm sigma). Against the two hits' errors
  // alone its pair chi2 would be 35, beyond the cut of 20; with the
  // scattering it is about 4.
  constexpr double kRadius = 200.0;
  constexpr double kSteep = 2.0;
  const Detector det = test::barrelDetector(0.01);
  std::vector<Hit> hits = test::helixHits(det, kRadius, kPhi0, 1, kSteep, 1);
  const Hit& first = hits[kLayer];
  const double r = det.layers()[kLayer].r + 4.0;
  // The helix at radius r, as test::helixHits draws it (positive charge
  // turns clockwise, through the origin).
  const double omega = 1.0 / kRadius;
  const double s = 2.0 * std::asin(r * omega / 2.0) / omega;
  const Vector3 at((std::sin(kPhi0) - std::sin(kPhi0 - omega * s)) / omega,
                   -(std::cos(kPhi0) - std::cos(kPhi0 - omega * s)) / omega,
                   s * kSteep);
  const double distance = (at - first.position).norm();
  ASSERT_GT(distance, 8.0);
  ASSERT_LT(distance, 11.0);
  const double pt = constants::kPtPerTeslaMm * 4.0 * kRadius;
  const double sigmaScatter =
      detail::layerTheta0(det.layers()[kLayer], pt * std::hypot(1.0, kSteep),
                          kSteep) *
      distance;
  const double shift = 2.0 * sigmaScatter;
  const double sigmaHits = std::sqrt(2.0) * 0.005;
  ASSERT_GT((shift / sigmaHits) * (shift / sigmaHits), 20.0);
  Hit second = test::barrelHit(det, kLayer, at.x(), at.y(), at.z(), kOverlapId);
  second.position += shift * second.uAxis;
  second.detId.module = first.detId.module + 1;
  hits.push_back(second);
  const FindingResult found =
      ConformalTrackFinder(det, {oneStep(true)}).run(hits);
  ASSERT_EQ(found.tracks.size(), 1u);
  EXPECT_TRUE(holds(found.tracks[0], hits, kOverlapId));
  EXPECT_EQ(found.tracks[0].hits.size(), 9u);
  // Moved by ten times the scattering instead, it stays off.
  hits.back().position += 8.0 * sigmaScatter * second.uAxis;
  const FindingResult far =
      ConformalTrackFinder(det, {oneStep(true)}).run(hits);
  ASSERT_EQ(far.tracks.size(), 1u);
  EXPECT_FALSE(holds(far.tracks[0], hits, kOverlapId));
}

TEST(OverlapHits, CutsAreValidated) {
  const Detector det = test::barrelDetector();
  FinderConfig cfg = oneStep(true);
  cfg.overlapMaxGap = 0.0;
  auto p = findChainProblem(cfg, det);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->key, "finder.overlap_max_gap_mm");
  cfg = oneStep(true);
  cfg.overlapMaxChi2 = std::nan("");
  p = findChainProblem(cfg, det);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->key, "finder.overlap_max_chi2");
  cfg = oneStep(true);
  cfg.overlapMaxArc = -1.0;
  EXPECT_THROW(ConformalTrackFinder(det, {cfg}), std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

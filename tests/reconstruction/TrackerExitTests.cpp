/// @file TrackerExitTests.cpp
/// Extensions end where a track leaves the tracker: a disk crossing that
/// the helix reaches only after passing the tracker's outer radius is not
/// predicted (on TrackML events such crossings, a turn later, gave tracks
/// endcap hits of other particles and derailed their fits). Where the
/// chain says particles end after half a turn (max_track_turns), they end
/// there too.

#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

/// A build over the barrel of test::barrelDetector(), then an extension
/// over its disk (z = 600 mm, R 10-300 mm).
FinderConfig buildThenDisk() {
  FinderConfig cfg = test::oneBuildStep();
  FindingStep e = cfg.steps.front();
  e.name = "Disk";
  e.collections = {1};
  e.build = false;
  e.extend = true;
  e.highPtCut = 0.0;
  e.chi2Cut = 1000.0;
  cfg.steps.push_back(e);
  cfg.extensionPhiWindow = 0.05;
  return cfg;
}

/// Point at transverse arc length s of the helix of test::helixHits
/// (through the origin, phi0, charge +1).
Vector3 helixPoint(double rho, double phi0, double tanL, double s) {
  const double omega = 1.0 / rho;
  return {(std::sin(phi0) - std::sin(phi0 - omega * s)) / omega,
          -(std::cos(phi0) - std::cos(phi0 - omega * s)) / omega, s * tanL};
}

/// Hits of the helix on the 8 barrel layers plus one on the disk at its
/// crossing at arc length sDisk; the number of hits on the found track.
std::size_t hitsOnTrack(double rho, double tanL, double sDisk,
                        double maxTrackTurns = 0.0) {
  const Detector det = test::barrelDetector();
  constexpr double kPhi0 = 0.3;
  std::vector<Hit> hits = test::helixHits(det, rho, kPhi0, +1, tanL, 1);
  EXPECT_EQ(hits.size(), 8u);
  const Vector3 p = helixPoint(rho, kPhi0, tanL, sDisk);
  EXPECT_NEAR(p.z(), 600.0, 1e-6);
  // The endcap has a disk on either side: the one at z = +600 mm.
  std::uint16_t disk = 0;
  for (std::uint16_t l = 0; l < det.layers().size(); ++l) {
    if (det.layers()[l].isDisk() && det.layers()[l].z() > 0.0) {
      disk = l;
    }
  }
  EXPECT_NE(disk, 0u);
  hits.push_back(test::barrelHit(det, disk, p.x(), p.y(), p.z(), 100));
  FinderConfig cfg = buildThenDisk();
  cfg.maxTrackTurns = maxTrackTurns;
  const FindingResult r = ConformalTrackFinder(det, {cfg}).run(hits);
  EXPECT_EQ(r.tracks.size(), 1u);
  return r.tracks.empty() ? 0 : r.tracks.front().hits.size();
}

TEST(TrackerExit, DiskCrossingBeforeTheExitIsTaken) {
  // Radius 2 m: the disk is crossed at R = 200 mm, inside the tracker's
  // outer radius (the disk's 300 mm).
  const double tanL = 3.0;
  EXPECT_EQ(hitsOnTrack(2000.0, tanL, 600.0 / tanL), 9u);
}

TEST(TrackerExit, DiskCrossingAfterTheExitIsNot) {
  // Radius 200 mm: the circle goes out to R = 400 mm, beyond the tracker
  // (300 mm), and comes back through the disk's R range on its way in
  // (R = 272 mm at s = 957 mm). That crossing lies after the track has
  // left the tracker.
  const double rho = 200.0;
  const double sDisk = 2.0 * rho * (std::numbers::pi - 0.75);
  const double r = helixPoint(rho, 0.3, 1.0, sDisk).head<2>().norm();
  ASSERT_LT(r, 300.0);
  EXPECT_EQ(hitsOnTrack(rho, 600.0 / sDisk, sDisk), 8u);
}

TEST(TrackerExit, CrossingPastTheTurnLimitIsNot) {
  // Radius 90 mm: the circle stays inside the tracker (out to R = 180 mm)
  // and comes back through the disk's R range after half a turn (R = 123
  // mm at s = 430 mm, half a turn being 283 mm). A detector simulation
  // that ends particles after half a turn (TrackML) can have no hit of
  // this particle there: taken without a limit, not with one of 0.5.
  const double rho = 90.0;
  const double sDisk = 2.0 * rho * (std::numbers::pi - 0.75);
  ASSERT_GT(sDisk, std::numbers::pi * rho);
  const double tanL = 600.0 / sDisk;
  EXPECT_EQ(hitsOnTrack(rho, tanL, sDisk), 9u);
  EXPECT_EQ(hitsOnTrack(rho, tanL, sDisk, 0.5), 8u);
}

TEST(TrackerExit, TurnLimitIsValidated) {
  FinderConfig cfg = buildThenDisk();
  cfg.maxTrackTurns = -0.5;
  EXPECT_THROW(ConformalTrackFinder(test::barrelDetector(), {cfg}),
               std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

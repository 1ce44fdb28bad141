/// @file TrackMergingFollowerTests.cpp
/// The turn follower of the track merging (TrackMerger::followTurns,
/// TrackMergingTurnFollower.cpp): the hits of a looper's further turns
/// that no track holds, on a turn shrunk by energy loss, join its first
/// half-turn's track unfitted, hit by hit and, across the apex where no
/// layer lies, as a segment of the next turn found on its own; also for a
/// segment that lies outside the predicted circle (that circle's own
/// error) and for loopers of a few hundred MeV whose apex lies in a wide
/// gap between layers. The index of unused hits skips hits taken after it
/// was built.
///
/// Tolerances: the synthetic hits lie exactly on their paths (5 um
/// errors); each test states where it puts the hits against the
/// follower's bounds.

#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"
#include "conftrack/reconstruction/finding/detail/UnusedHits.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "SyntheticHits.hpp"
#include "TrackMergingFixture.hpp"

namespace conftrack {
namespace {

using test::Fixture;
using test::kPhi0;
using test::looperCentre;
using test::moveOntoCircle;

/// A looper from the origin on looperHits' circle of radius rho0 (centre
/// looperCentre(rho0), clockwise seen from +z) that loses `loss` of its
/// transverse momentum at each layer it crosses: its radius shrinks there and
/// its circle stays tangent to the path, as energy loss leaves it. Hits 1 + l
/// on the way out, 51 + l on the way in (l: layer), up to the first crossing of
/// the innermost layer on the way in.
std::vector<Hit> energyLossLooperHits(const Detector& det, double rho0,
                                      double tanL, double loss) {
  constexpr double kStep = 0.002;  // mm of transverse path
  std::vector<Hit> hits;
  Vector2 p(0.0, 0.0);
  Vector2 d(std::cos(kPhi0), std::sin(kPhi0));
  double rho = rho0;
  double s = 0.0;
  bool incoming = false;
  for (int i = 0; i < 2000000; ++i) {
    const double r0 = p.norm();
    d = Eigen::Rotation2Dd(-kStep / rho) * d;
    p += kStep * d;
    s += kStep;
    const double r1 = p.norm();
    incoming = incoming || r1 < r0;
    for (std::uint16_t l = 0; l < 8; ++l) {
      const double rl = det.layers()[l].r;
      if ((r0 < rl) != (r1 < rl)) {
        hits.push_back(test::barrelHit(det, l, p.x(), p.y(), s * tanL,
                                       (incoming ? 51 : 1) + l));
        rho *= 1.0 - loss;
        if (incoming && l == 0) {
          return hits;
        }
      }
    }
  }
  return hits;
}

/// The hits (ids, sorted) that join the first half-turn (hits 1-7, or
/// `track`, the only track) of `hits` on `det` when the merger runs with
/// `cfg`.
std::vector<std::uint64_t> joinedToFirstHalfTurn(
    const std::vector<Hit>& hits, const detail::TrackMerger::Config& cfg,
    const std::vector<std::uint64_t>& track = {1, 2, 3, 4, 5, 6, 7},
    const Detector& det = test::barrelDetector()) {
  Fixture f;
  f.det = det;
  f.hits = hits;
  f.cfg.steps[0].chi2Cut = 1e9;  // the energy loss bends its own hits
  f.prepare({track});
  detail::TrackMerger(*f.state, cfg).run();
  return f.turnIds(0);
}

/// Moves the hits with ids in [firstId, lastId] by dr away from the
/// centre of energyLossLooperHits' circle of initial radius rho0
/// (outwards for dr > 0).
void moveFromCentre(std::vector<Hit>& hits, double rho0, std::uint64_t firstId,
                    std::uint64_t lastId, double dr) {
  const Vector2 centre = looperCentre(rho0);
  for (Hit& hit : hits) {
    if (hit.id >= firstId && hit.id <= lastId) {
      const double radius = (hit.position.head<2>() - centre).norm();
      moveOntoCircle(hit, centre, centre, radius + dr);
    }
  }
}

TEST(TrackMerging, FollowerTakesTheHitsOfAShrinkingTurn) {
  // Only the first half-turn is a track. A 0.076 GeV looper (rho 63 mm
  // at the start, whose apex lies just beyond the layer at 120 mm: 25 mm
  // of path between its two crossings of that layer) loses
  // 1 % of its momentum at each layer, as a pion of 60 MeV in the CLICdet
  // vertex detector: the incoming half-turn's hits, on no track, lie
  // 0.4 mm (the first) and 1.9 to 4.6 mm inside the first half-turn's
  // free circle, the latter beyond the single-hit search's 0.95 mm. The
  // follower, refitting its circle to the latest hits, takes them all.
  Fixture f;
  f.hits = energyLossLooperHits(f.det, 63.0, 0.05, 0.01);
  ASSERT_EQ(f.hits.size(), 14u);
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 6, 7}});
  const TrackCandidate before = f.state->tracks[0];
  EXPECT_EQ(f.merge(), 0u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.turnIds(0),
            (std::vector<std::uint64_t>{51, 52, 53, 54, 55, 56, 57}));
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
  EXPECT_DOUBLE_EQ(f.state->tracks[0].uv.chi2, before.uv.chi2);

  // Without the follower the single-hit search takes only the first.
  detail::TrackMerger::Config cfg;
  cfg.maxFollowScore = 0.0;
  EXPECT_EQ(joinedToFirstHalfTurn(f.hits, cfg),
            (std::vector<std::uint64_t>{57}));

  // A hit 2 mm off the path (another particle's; the band is 1.5 mm at
  // the default score of 0.25) is not taken, and the follow goes on past
  // it.
  std::vector<Hit> withForeign = f.hits;
  for (Hit& hit : withForeign) {
    if (hit.id == 54) {
      const Vector2 xy = hit.position.head<2>();
      const Vector2 c = looperCentre(63.0);
      moveOntoCircle(hit, c, c, (xy - c).norm() + 2.0);
    }
  }
  EXPECT_EQ(joinedToFirstHalfTurn(withForeign, {}),
            (std::vector<std::uint64_t>{51, 52, 53, 55, 56, 57}));

  cfg.followMaxGapTurns = 1.0;
  EXPECT_THROW(detail::TrackMerger(*f.state, cfg), std::invalid_argument);
}

TEST(TrackMerging, FollowerJumpsTheApexToTheNextTurnsSegment) {
  // rho 72 mm at the start: 135 mm of path lie between the two crossings
  // of the layer at 120 mm, round the apex, beyond the follower's reach
  // from one hit to the next (0.25 turn, 107 mm), and energy loss (1 %
  // per layer) has moved the incoming half-turn's hits 2.9-4.5 mm inside
  // the first half-turn's circle. The incoming half-turn is found as a
  // segment of its own (four hits on four layers, close to the track's
  // circle and tanLambda) and followed on: all seven hits join.
  const std::vector<Hit> hits =
      energyLossLooperHits(test::barrelDetector(), 72.0, 0.05, 0.01);
  ASSERT_EQ(hits.size(), 14u);
  EXPECT_EQ(joinedToFirstHalfTurn(hits, {}),
            (std::vector<std::uint64_t>{51, 52, 53, 54, 55, 56, 57}));

  // Without the jump none of them joins.
  detail::TrackMerger::Config cfg;
  cfg.followJumps = false;
  EXPECT_TRUE(joinedToFirstHalfTurn(hits, cfg).empty());

  // Three hits beyond the gap are no segment: three points always lie on
  // a circle.
  std::vector<Hit> three;
  for (const Hit& hit : hits) {
    if (hit.id < 51 || hit.id > 54) {
      three.push_back(hit);
    }
  }
  EXPECT_TRUE(joinedToFirstHalfTurn(three, {}).empty());
}

TEST(TrackMerging, JumpIsPredictedByTheWholeTurnsCircle) {
  // The looper of the test above, with only its first four hits a track
  // and hits 5 and 6 moved 1 mm outwards and inwards (scattering of a
  // 60 MeV pion in a layer moves its next hits by as much). The follower
  // takes hit 5, not hit 6, and its latest four hits (2-5) give a circle
  // whose prediction across the apex misses the incoming half-turn; the
  // jump is predicted by the circle of all the hits of the turn followed
  // so far (up to kJumpFitHits, six), and the incoming half-turn joins,
  // all seven of its hits (with the 20 mm inside bound of the segment
  // search before stop 40, its last hit, 57, stayed off).
  std::vector<Hit> hits =
      energyLossLooperHits(test::barrelDetector(), 72.0, 0.05, 0.01);
  ASSERT_EQ(hits.size(), 14u);
  moveFromCentre(hits, 72.0, 5, 5, 1.0);
  moveFromCentre(hits, 72.0, 6, 6, -1.0);
  EXPECT_EQ(joinedToFirstHalfTurn(hits, {}, {1, 2, 3, 4}),
            (std::vector<std::uint64_t>{5, 51, 52, 53, 54, 55, 56, 57}));
}

TEST(TrackMerging, UnusedHitsSkipsHitsTakenAfterTheIndexWasBuilt) {
  // One index serves the single-hit search and the follower, each taking
  // hits: a hit marked used after the index was built is not returned.
  Fixture f;
  f.hits = energyLossLooperHits(f.det, 63.0, 0.05, 0.01);
  f.cfg.steps[0].chi2Cut = 1e9;  // the energy loss bends its own hits
  f.prepare({{1, 2, 3, 4, 5, 6, 7}});
  std::vector<std::uint8_t>& used = f.state->used;
  const detail::UnusedHits unused(f.conformal, used);
  const detail::TransverseCircle everywhere{0.0, 0.0, 1000.0, 1};
  const auto found = [&] {
    std::vector<ConfIndex> out;
    unused.forEachNear(everywhere, 1000.0, 0.0, 2.0 * std::numbers::pi,
                       [&](ConfIndex h) { out.push_back(h); });
    std::sort(out.begin(), out.end());
    return out;
  };
  const std::vector<ConfIndex> before = found();
  ASSERT_EQ(before.size(), 7u);  // the incoming half-turn
  for (const ConfIndex h : before) {
    EXPECT_EQ(used[h], 0);
  }
  used[before[2]] = 1;
  std::vector<ConfIndex> expected = before;
  expected.erase(expected.begin() + 2);
  EXPECT_EQ(found(), expected);
}

TEST(TrackMerging, JumpTakesATurnOutsideThePredictedCircle) {
  // The looper of FollowerJumpsTheApexToTheNextTurnsSegment with its
  // incoming half-turn moved 8 mm outwards: its first hits now lie 4.3-4.9
  // mm outside the circle predicted from the first half-turn instead of
  // 3.1-3.7 mm inside. The predicted circle, fitted to a few hits of the
  // turn behind, errs by that much either way in CLICdet (true next turns
  // 2-13 mm outside it, stop 40); the segment search takes a first hit up
  // to kJumpOutside (6 mm) outside (2 mm before stop 40: nothing joined).
  std::vector<Hit> hits =
      energyLossLooperHits(test::barrelDetector(), 72.0, 0.05, 0.01);
  ASSERT_EQ(hits.size(), 14u);
  moveFromCentre(hits, 72.0, 51, 57, 8.0);
  EXPECT_EQ(joinedToFirstHalfTurn(hits, {}),
            (std::vector<std::uint64_t>{51, 52, 53, 54, 55, 56, 57}));

  // 16 mm out, the first hit lies about 13 mm outside: no jump.
  moveFromCentre(hits, 72.0, 51, 57, 8.0);
  EXPECT_TRUE(joinedToFirstHalfTurn(hits, {}).empty());
}

/// Three double layers of a vertex barrel (30-63 mm) and two layers at 127
/// and 340 mm, as in CLICdet's vertex detector and inner tracker: a
/// looper of a few hundred MeV turns beyond them.
Detector gapDetector() {
  return test::barrelDetector(
      0.001, {30.0, 33.0, 45.0, 48.0, 60.0, 63.0, 127.0, 340.0});
}

TEST(TrackMerging, LooperOfAFewHundredMeVJumpsTheGapBeyondTheLayers) {
  // A 0.3 GeV looper (rho 250 mm in 4 T, apex at 500 mm) crosses the eight
  // layers, turns beyond the outermost (340 mm) and crosses it again on
  // its way in 760 mm of path after its last hit on the way out: beyond
  // the follower's step (0.25 turn, 390 mm) and, before stop 40, beyond
  // the jumps' bounds (pT 0.18 GeV, 400 mm of arc), so that its track held
  // half of its hits, as CLICdet's loopers of 0.2-0.6 GeV were found.
  // Energy loss of 0.5 % per layer moves the incoming half-turn 2.7-3 mm
  // inside the predicted circle, out of the single-hit search's band
  // (0.95 mm).
  const Detector det = gapDetector();
  const std::vector<Hit> hits = energyLossLooperHits(det, 250.0, 0.05, 0.005);
  ASSERT_EQ(hits.size(), 16u);
  EXPECT_EQ(joinedToFirstHalfTurn(hits, {}, {1, 2, 3, 4, 5, 6, 7, 8}, det),
            (std::vector<std::uint64_t>{51, 52, 53, 54, 55, 56, 57, 58}));

  // Only by the jump.
  detail::TrackMerger::Config cfg;
  cfg.followJumps = false;
  EXPECT_TRUE(
      joinedToFirstHalfTurn(hits, cfg, {1, 2, 3, 4, 5, 6, 7, 8}, det).empty());
}

}  // namespace
}  // namespace conftrack

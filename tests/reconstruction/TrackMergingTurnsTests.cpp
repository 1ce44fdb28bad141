/// @file TrackMergingTurnsTests.cpp
/// The looper rule of the track merging (TrackMerger::dropTurns,
/// TrackMergingTurns.cpp): a looper's second half-turn is neither merged
/// into its first half-turn nor kept as a second track, also when it has
/// been scattered, shrunk by energy loss, produced off the beam line or
/// found across its apex, and also when either half-turn ends on another
/// particle's hit; it never joins another particle's track, and other
/// particles on nearby circles, beside the first half-turn or on the
/// mirror image of a prompt looper are kept. Well-matched further turns
/// and unused hits on the helix a whole number of turns on join the first
/// half-turn's track unfitted (the turn follower, which reaches the hits
/// of a shrinking turn, also across the apex, is tested in
/// TrackMergingFollowerTests.cpp). Incoming half-turns are
/// listed inner hit first, as the finder finds them (outwards), and are
/// recognised also when a short piece's conformal circle flips.
///
/// Tolerances: the synthetic hits lie exactly on their helices (5 um
/// errors); each test states the distances it puts a turn or a neighbour
/// at against the rule's gates (10 mm, 20 mm in z, 30 mm for centres).

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
using test::kRho;
using test::looperCentre;
using test::looperHits;
using test::moveOntoCircle;

/// A 0.094 GeV looper (rho 70 mm, tanLambda 0.5) whose incoming
/// half-turn is moved by dz in z (as scattering leaves it), both
/// half-turns prepared as tracks.
void prepareLooperWithTurnShiftedInZ(Fixture& f, double dz) {
  f.hits = looperHits(f.det, 70.0, 0.5);
  for (Hit& h : f.hits) {
    if (h.id > 50) {
      h.position.z() += dz;
    }
  }
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
}

TEST(TrackMerging, LooperFurtherHalfTurnIsLeftAlone) {
  Fixture f;
  // rho = 70 mm (0.084 GeV): reaches R = 140 mm, seven layers.
  f.hits = looperHits(f.det, 70.0, 0.05);
  ASSERT_EQ(f.hits.size(), 14u);
  // The incoming half-turn, found outwards: a track of opposite charge on
  // the same circle. Its hits are neither merged into the first half-turn
  // (they cross its layers far from its hits) nor kept as a second track.
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));

  // Without the looper rule the two half-turns stay two tracks (no merge).
  Fixture g;
  g.hits = f.hits;
  g.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  detail::TrackMerger::Config cfg;
  cfg.dropTurns = false;
  EXPECT_EQ(detail::TrackMerger(*g.state, cfg).run(), 0u);

  // The same through the chain (FinderConfig::mergeDropTurns, chain key
  // merge_drop_turns, off in chains/trackml.toml): the finder's merging
  // keeps both half-turns.
  Fixture h;
  h.hits = f.hits;
  h.cfg.mergeDropTurns = false;
  h.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  EXPECT_EQ(h.merge(), 0u);
  EXPECT_EQ(h.state->tracks.size(), 2u);
}

TEST(TrackMerging, WellMatchedFurtherTurnJoinsTheFirstHalfTurnsTrack) {
  // The incoming half-turn on the first one's helix (turn score near 0):
  // its hits join the first half-turn's track, outside its fits, so that
  // the track holds all of the particle's hits.
  Fixture f;
  f.hits = looperHits(f.det, 70.0, 0.05);
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  const TrackCandidate before = f.state->tracks[0];
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
  // Then the incoming half-turn's first hit, on no track, joins too
  // (collectTurnHits).
  EXPECT_EQ(f.ids(0, true),
            (std::vector<std::uint64_t>{52, 53, 54, 55, 56, 57, 51}));
  EXPECT_DOUBLE_EQ(f.state->tracks[0].uv.chi2, before.uv.chi2);
  EXPECT_DOUBLE_EQ(f.state->tracks[0].sz.tanLambda, before.sz.tanLambda);

  // With maxJoinScore 0 the turn is dropped and its hits left alone.
  Fixture g;
  g.hits = f.hits;
  g.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  detail::TrackMerger::Config cfg;
  cfg.maxJoinScore = 0.0;
  cfg.maxTurnHitScore = 0.0;
  EXPECT_EQ(detail::TrackMerger(*g.state, cfg).run(), 1u);
  g.state->compact();
  ASSERT_EQ(g.state->tracks.size(), 1u);
  EXPECT_TRUE(g.ids(0, true).empty());

  cfg.maxJoinScore = cfg.maxTurnScore + 1.0;
  EXPECT_THROW(detail::TrackMerger(*g.state, cfg), std::invalid_argument);
}

TEST(TrackMerging, UnusedHitsOnAFurtherTurnJoinTheTrack) {
  // Only the first half-turn is a track; the incoming half-turn's hits
  // are on none (no step built them). They lie on its helix half a turn
  // on and join it, not fitted: the track then holds every hit of its
  // particle. A hit moved 2 mm off the circle (another particle's; the
  // band is 0.95 mm at the default score of 0.1) stays unused.
  Fixture f;
  f.hits = looperHits(f.det, 70.0, 0.05);
  const Vector2 centre = looperCentre(70.0);
  for (Hit& h : f.hits) {
    if (h.id == 55) {
      moveOntoCircle(h, centre, centre, 72.0);
    }
  }
  f.prepare({{1, 2, 3, 4, 5, 6, 7}});
  const TrackCandidate before = f.state->tracks[0];
  EXPECT_EQ(f.merge(), 0u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.turnIds(0), (std::vector<std::uint64_t>{51, 52, 53, 54, 56, 57}));
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
  EXPECT_DOUBLE_EQ(f.state->tracks[0].sz.tanLambda, before.sz.tanLambda);

  // None where the chain's tracks end within half a turn (TrackML): the
  // search stops max_track_turns from the first hit, at the apex here.
  Fixture g;
  g.hits = f.hits;
  g.cfg.maxTrackTurns = 0.5;
  g.prepare({{1, 2, 3, 4, 5, 6, 7}});
  g.merge();
  EXPECT_TRUE(g.ids(0, true).empty());
}

TEST(TrackMerging, LooselyMatchedFurtherTurnIsDroppedNotJoined) {
  // The incoming half-turn 40 mm off in z: a further turn within the
  // gates (divided by 1 + path / 94 mm at 0.094 GeV, its hits' z distance
  // is at most 15.5 mm, inside the 20 mm gate), but that gives a turn
  // score near 10, above maxJoinScore (4): as likely another particle on a
  // nearby circle as this one's turn (CLICdet: 61-83 % the same particle
  // at such scores), so its hits stay off the first half-turn's track.
  Fixture f;
  prepareLooperWithTurnShiftedInZ(f, 40.0);
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_TRUE(f.ids(0, true).empty());
}

TEST(TrackMerging, ScatteredFurtherTurnIsStillRecognised) {
  // The incoming half-turn 21 mm off in z (as scattering leaves it a few
  // hundred millimetres of path on; tanLambda 0.5, 220 mm per turn):
  // beyond the 20 mm z gate at the first half-turn's end, inside it once
  // the distance is divided by 1 + path / 1 m (path 150-270 mm).
  Fixture f;
  prepareLooperWithTurnShiftedInZ(f, 21.0);
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
}

TEST(TrackMerging, ShrunkFurtherTurnIsRecognisedByItsFreeCircle) {
  // Energy lost at the apex: the incoming half-turn continues on a circle
  // 4 mm smaller, touching the first one there (its centre moved 4 mm
  // towards the apex), so it passes 8 mm from the origin. Its conformal
  // fit, a circle through the origin, puts its centre 10 mm off, its free
  // circle 4 mm: with the centre gate at 8 mm, only the free circle lets
  // it be recognised as the further turn it is.
  Fixture f;
  constexpr double kLoopRho = 70.0;
  constexpr double kLoss = 4.0;
  f.hits = looperHits(f.det, kLoopRho, 0.05);
  const Vector2 centre = looperCentre(kLoopRho);
  const Vector2 shrunkCentre = centre + kLoss * centre.normalized();
  for (Hit& h : f.hits) {
    if (h.id > 50) {
      moveOntoCircle(h, centre, shrunkCentre, kLoopRho - kLoss);
    }
  }
  // The piece fails a circle-through-the-origin cut (an extension, not a
  // build, would have made it).
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {54, 55, 56, 57}});
  const double conformalOffset =
      std::hypot(f.state->tracks[1].uv.centreX - centre.x(),
                 f.state->tracks[1].uv.centreY - centre.y());
  EXPECT_GT(conformalOffset, 8.0);
  detail::TrackMerger::Config cfg;
  cfg.maxTurnCentreDistance = 8.0;
  EXPECT_EQ(detail::TrackMerger(*f.state, cfg).run(), 1u);
  f.state->compact();
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
}

TEST(TrackMerging, FurtherTurnOfADisplacedLooperIsRecognised) {
  // A looper produced 15 mm off the beam line (a conversion or decay in the
  // beam pipe): the first half-turn's conformal fit, a circle through the
  // origin, lies up to 30 mm off its own hits beyond the apex, and the
  // incoming half-turn's hits with it, beyond the 10 mm turn distance. The
  // first half-turn's free circle goes through them.
  constexpr double kLoopRho = 70.0;
  const Vector2 production(15.0 * std::cos(kPhi0 + 1.0),
                           15.0 * std::sin(kPhi0 + 1.0));
  const Vector2 centre =
      production + kLoopRho * Vector2(std::sin(kPhi0), -std::cos(kPhi0));
  Fixture f;
  // Outgoing (ids 1..) and incoming (ids 51..) crossings of each layer: the
  // circle's points at the layer radius, ordered by angle round the centre.
  const double startAngle =
      std::atan2(production.y() - centre.y(), production.x() - centre.x());
  for (std::uint16_t l = 0; l < 8; ++l) {
    const double r = f.det.layers()[l].r;
    const double d = centre.norm();
    // Circle-circle intersection: |p| = r and |p - centre| = rho.
    const double a = (r * r - kLoopRho * kLoopRho + d * d) / (2.0 * d);
    const double h2 = r * r - a * a;
    if (h2 <= 0.0) {
      break;
    }
    const Vector2 base = a * centre / d;
    const Vector2 normal(-centre.y() / d, centre.x() / d);
    std::vector<std::pair<double, Vector2>> crossings;
    for (const double sign : {1.0, -1.0}) {
      const Vector2 p = base + sign * std::sqrt(h2) * normal;
      // Clockwise (positive charge, as helixHits): angle decreasing.
      double turned =
          startAngle - std::atan2(p.y() - centre.y(), p.x() - centre.x());
      turned =
          std::fmod(turned + 4.0 * std::numbers::pi, 2.0 * std::numbers::pi);
      crossings.emplace_back(turned, p);
    }
    std::sort(crossings.begin(), crossings.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t k = 0; k < 2; ++k) {
      const double s = crossings[k].first * kLoopRho;
      const Vector2& p = crossings[k].second;
      f.hits.push_back(test::barrelHit(f.det, l, p.x(), p.y(), 0.05 * s,
                                       (k == 0 ? 1u : 51u) + l));
    }
  }
  ASSERT_EQ(f.hits.size(), 14u);
  // The displaced pieces fail a circle-through-the-origin cut (an
  // extension, not a build, would have made them).
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  double offCircle = 0.0;
  const auto& first = f.state->tracks[0].uv;
  for (const Hit& h : f.hits) {
    if (h.id > 50) {
      offCircle = std::max(offCircle,
                           std::abs(std::hypot(h.position.x() - first.centreX,
                                               h.position.y() - first.centreY) -
                                    first.radius));
    }
  }
  EXPECT_GT(offCircle, 10.0);
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
}

TEST(TrackMerging, PieceAcrossTheApexIsRecognised) {
  // A piece of the looper round its apex (R = 140 mm: out through layer
  // 120, back through 120-80) beside a first track through layers 30-100
  // (they cross layer 100 on opposite sides, so they are not merged). The
  // piece's hits lie on both sides of the point of the circle opposite
  // the first hit, where arc lengths measured from the first hit wrap
  // round by a period; counted continuously along the piece they match
  // the first track's helix, and the piece is dropped as its further turn.
  Fixture f;
  f.hits = looperHits(f.det, 70.0, 0.5);
  f.prepare({{1, 2, 3, 4, 5, 6}, {7, 57, 56, 55}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6}));
}

TEST(TrackMerging, LooperSecondHalfTurnDoesNotJoinAnotherTrack) {
  Fixture f;
  f.hits = looperHits(f.det, 70.0, 0.05);
  // A second particle along the looper's initial direction.
  std::vector<Hit> other = test::helixHits(f.det, kRho, kPhi0, 1, 0.05, 101);
  f.hits.insert(f.hits.end(), other.begin(), other.end());
  f.prepare(
      {{101, 102, 103, 104, 105, 106, 107, 108}, {51, 52, 53, 54, 55, 56, 57}});
  EXPECT_EQ(f.merge(), 0u);
  ASSERT_EQ(f.state->tracks.size(), 2u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{101, 102, 103, 104, 105, 106,
                                                  107, 108}));
}

TEST(TrackMerging, AnotherLooperOnANearbyCircleIsKept) {
  Fixture f;
  // Two central loopers from the origin 0.05 rad apart in azimuth (circle
  // centres 3.5 mm apart) and 0.15 apart in tanLambda, the second found on
  // six layers (arc lengths 30-111 mm): its hits lie within 3 mm of the
  // first one's circle and within 17 mm in z of the first one's helix.
  // Only its tanLambda tells it from a further turn of the first (score 25
  // from tanLambda alone, above 16).
  f.hits = looperHits(f.det, 70.0, 0.05);
  std::vector<Hit> other = looperHits(f.det, 70.0, 0.2, kPhi0 + 0.05, 101);
  f.hits.insert(f.hits.end(), other.begin(), other.end());
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {101, 102, 103, 104, 105, 106}});
  EXPECT_EQ(f.merge(), 0u);
  EXPECT_EQ(f.state->tracks.size(), 2u);
}

TEST(TrackMerging, FurtherTurnShrunkByEnergyLossIsRecognised) {
  // Energy lost over the first half-turn: the incoming half-turn lies on a
  // circle 13 mm smaller round the same centre, all its hits 13 mm inside
  // the first half-turn's circle (beyond the 10 mm turn distance). Their
  // distance is nearly constant (spread < 0.1 mm), and its mean is
  // divided by 1 + path / (1 m * p / 1 GeV): p = 0.084 GeV, 40-260 mm of
  // path, a factor of about 2.7.
  constexpr double kLoopRho = 70.0;
  constexpr double kLoss = 13.0;
  std::vector<Hit> hits = looperHits(test::barrelDetector(), kLoopRho, 0.05);
  const Vector2 centre = looperCentre(kLoopRho);
  for (Hit& h : hits) {
    if (h.id > 50) {
      moveOntoCircle(h, centre, centre, kLoopRho - kLoss);
    }
  }
  Fixture f;
  f.hits = hits;
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));

  // Without the path's allowance the 13 mm are refused.
  Fixture g;
  g.hits = hits;
  g.cfg.steps[0].chi2Cut = 1e9;
  g.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  detail::TrackMerger::Config cfg;
  cfg.turnDzPathScale = 1e12;
  EXPECT_EQ(detail::TrackMerger(*g.state, cfg).run(), 0u);
}

TEST(TrackMerging, NeighbourBesideTheFirstHalfTurnIsKept) {
  // A second low-momentum particle 0.02 rad beside the looper's first
  // half-turn (1.4 mm away, the same tanLambda), found on four of the same
  // layers: its hits lie on the first one's circle and helix, but beside
  // its hits on their own layers, which no piece of the same half-turn
  // does. It is not a further turn: a whole turn on, its z is 220 mm off.
  Fixture f;
  f.hits = looperHits(f.det, 70.0, 0.5);
  std::vector<Hit> other = looperHits(f.det, 70.0, 0.5, kPhi0 + 0.02, 101);
  f.hits.insert(f.hits.end(), other.begin(), other.end());
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {102, 103, 104, 105}});
  EXPECT_EQ(f.merge(), 0u);
  EXPECT_EQ(f.state->tracks.size(), 2u);
}

TEST(TrackMerging, NextOutgoingTurnBesideTheFirstIsDropped) {
  // The same looper a whole turn later (z 22 mm on: tanLambda 0.05, 440
  // mm per turn), 1 mm inside its first half-turn: beside its hits on the
  // same layers, so not a piece of the first half-turn, and on its helix
  // one turn on.
  Fixture f;
  constexpr double kLoopRho = 70.0;
  constexpr double kTanLambda = 0.05;
  f.hits = looperHits(f.det, kLoopRho, kTanLambda);
  const Vector2 centre = looperCentre(kLoopRho);
  std::vector<Hit> next;
  for (const Hit& h : f.hits) {
    if (h.id >= 2 && h.id <= 6) {
      Hit n = h;
      moveOntoCircle(n, centre, centre, kLoopRho - 1.0);
      n.position.z() += 2.0 * std::numbers::pi * kLoopRho * kTanLambda;
      n.id = h.id + 200;
      next.push_back(n);
    }
  }
  f.hits.insert(f.hits.end(), next.begin(), next.end());
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {202, 203, 204, 205, 206}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
}

TEST(TrackMerging, FirstHalfTurnEndingOnAForeignHitStillDropsItsTurn) {
  // The first half-turn was extended past its own hits (R 30-80 mm) to a
  // hit of another particle on the 150 mm layer, 71 mm off the looper's
  // circle (beyond its apex at R = 140 mm). That hit's lever arm moves the
  // centre of the free circle of all six hits by 46 mm, beyond the 30 mm
  // centre gate (its residual there is no larger than the others'), so
  // the incoming half-turn was not recognised and stayed a second track
  // of the particle. The circle without that end hit is the looper's: the
  // turn is dropped, and the foreign hit leaves the first half-turn.
  constexpr double kLoopRho = 70.0;
  Fixture f;
  f.hits = looperHits(f.det, kLoopRho, 0.05);
  const Vector2 centre = looperCentre(kLoopRho);
  const double apexPhi = std::atan2(centre.y(), centre.x());
  const double foreignPhi = apexPhi - 1.2;
  const double outer = f.det.layers()[7].r;
  Hit foreign = test::barrelHit(f.det, 7, outer * std::cos(foreignPhi),
                                outer * std::sin(foreignPhi),
                                f.hits[12].position.z(), 999);
  ASSERT_GT(std::abs(std::hypot(foreign.position.x() - centre.x(),
                                foreign.position.y() - centre.y()) -
                     kLoopRho),
            60.0);
  f.hits.push_back(foreign);
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 999}, {53, 54, 55, 56}});
  // Premise: the free circle of all six hits is far from the looper's.
  detail::TransverseCircle all;
  ASSERT_TRUE(detail::fitCircle(f.conformal, f.state->tracks[0].hits, all));
  EXPECT_GT(std::hypot(all.cx - centre.x(), all.cy - centre.y()), 30.0);
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
}

TEST(TrackMerging, FurtherTurnStartingOnAForeignHitIsStillDropped) {
  // The incoming half-turn (R 40-120 mm, found outwards) starts on another
  // particle's hit on the 30 mm layer, 1 rad in azimuth from its own: the
  // turn is recognised by its other hits (the foreign one, tens of
  // millimetres off the looper's circle, would fail the distance-spread
  // test).
  constexpr double kLoopRho = 70.0;
  Fixture f;
  f.hits = looperHits(f.det, kLoopRho, 0.05);
  const Hit& own = f.hits[1];  // the incoming half-turn's hit at R = 30 mm
  ASSERT_EQ(own.id, 51u);
  const double phi = std::atan2(own.position.y(), own.position.x()) + 1.0;
  const double inner = f.det.layers()[0].r;
  f.hits.push_back(test::barrelHit(f.det, 0, inner * std::cos(phi),
                                   inner * std::sin(phi), own.position.z(),
                                   999));
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {999, 52, 53, 54, 55, 56, 57}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
  // The turn's hits join the track, but not the foreign one that its
  // circle left out; the turn's own hit on that layer, unused, joins
  // instead.
  EXPECT_EQ(f.turnIds(0),
            (std::vector<std::uint64_t>{51, 52, 53, 54, 55, 56, 57}));
}

TEST(TrackMerging, TurnSharingAHitWithTheFirstHalfTurnJoinsItOnce) {
  // Near the apex both half-turns cross the outermost layer they reach
  // close together, and the incoming half-turn's track ended on the first
  // half-turn's hit there (7, on the looper's circle) instead of its own
  // (57). Joining the turn put hit 7 on the track twice, fitted and as a
  // turn hit (CLICdet tt-bar + 30 BX with sensors, event 55: the track
  // file was refused on reading).
  Fixture f;
  f.hits = looperHits(f.det, 70.0, 0.05);
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 7}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));
  // Every hit once: the turn's own hits, and its unused ones (51, 57).
  EXPECT_EQ(f.turnIds(0),
            (std::vector<std::uint64_t>{51, 52, 53, 54, 55, 56, 57}));
}

TEST(TrackMerging, TurnWhoseConformalCircleFlipsIsRecognised) {
  // A 0.48 GeV looper (rho = 400 mm, tanLambda 0.3) whose incoming
  // half-turn, moved 5 mm outwards by energy loss and scattering, passes
  // 5 mm from the beam line. Its four vertex-barrel hits (R 30-65 mm,
  // found outwards) bend by about a millimetre; a circle forced through
  // the origin and them bends the other way, so that its conformal
  // orientation equals the first half-turn's. Their order round the free
  // circle, along which the s-z line measures tanLambda, is the opposite
  // one: the turn is recognised (by the conformal orientation its
  // tanLambda would differ by 0.6 from the first's).
  constexpr double kLoopRho = 400.0;
  constexpr double kShift = 5.0;
  Fixture f;
  f.hits = looperHits(f.det, kLoopRho, 0.3);
  const Vector2 centre = looperCentre(kLoopRho);
  const Vector2 moved = centre + kShift * centre.normalized();
  for (Hit& h : f.hits) {
    if (h.id > 50) {
      moveOntoCircle(h, centre, moved, kLoopRho);
    }
  }
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4, 5, 6, 7, 8}, {51, 52, 53, 54}});
  ASSERT_EQ(f.state->tracks[0].uv.orientation,
            f.state->tracks[1].uv.orientation);
  // The default loop diameter (1.5 m): the 800 mm circle can loop.
  detail::TrackMerger::Config cfg;
  EXPECT_EQ(detail::TrackMerger(*f.state, cfg).run(), 1u);
  f.state->compact();
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(TrackMerging, MirrorImageOfAPromptLooperIsKept) {
  // Two particles from the origin on one circle (radius 70 mm), one each
  // way round it and to either side in z (tanLambda +-0.5: a two-body
  // decay's back-to-back opposite charges). Found outwards, the second is
  // a track of opposite sense on the first one's circle whose hits lie on
  // its helix continued back through the beam line, a whole turn before
  // the incoming half-turn: it is another particle, not a further turn.
  constexpr double kLoopRho = 70.0;
  constexpr double kTanLambda = 0.5;
  Fixture f;
  f.hits = looperHits(f.det, kLoopRho, kTanLambda);
  for (Hit& h : f.hits) {
    if (h.id > 50) {
      h.position.z() -= 2.0 * std::numbers::pi * kLoopRho * kTanLambda;
    }
  }
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {52, 53, 54, 55, 56, 57}});
  EXPECT_EQ(f.merge(), 0u);
  EXPECT_EQ(f.state->tracks.size(), 2u);
}

}  // namespace
}  // namespace conftrack

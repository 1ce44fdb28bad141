/// @file TrackMergingTests.cpp
/// Track merging (detail/TrackMerging.hpp): two pieces of one helix become
/// one track, without a hit of another particle that ended one of them,
/// also when the particle was produced off the beam line; pieces of two
/// different nearby helices stay apart; a looper's second half-turn is
/// neither merged into its first half-turn nor kept as a second track, and
/// never joins another particle's track, and the mirror image of a prompt
/// looper (another particle) is not taken for its turn. The pieces are
/// made directly (fitted hit lists in a FinderState), as the finder would
/// leave them after a gap.
///
/// Tolerances: the synthetic hits lie exactly on their helices (5 um
/// errors); "nearby" helices differ by 10 mrad in azimuth (1 mm at the
/// outer layers: inside the 10 mm geometric gate, 200 sigma for the merged
/// fit) or by 0.02 in tanLambda (2 mm in z); the merged pT is checked to
/// 0.05 GeV of 3.6 GeV and tanLambda to 1e-3.

#include "conftrack/core/Error.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "ChainText.hpp"
#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

constexpr double kRho = 3000.0;  // [mm]: 3.6 GeV in 4 T
constexpr double kPhi0 = 0.4;
constexpr double kTanL = 0.3;

FinderConfig chain() {
  FinderConfig cfg;
  FindingStep s;
  s.name = "build";
  s.collections = {0};
  s.build = true;
  s.chi2Cut = 100.0;
  s.minHits = 3;
  cfg.steps.push_back(s);
  return cfg;
}

/// The event's hits in conformal form, the finder state, and pieces
/// (hit ids along the path) fitted as tracks of step 0.
struct Fixture {
  Detector det = test::barrelDetector();
  FinderConfig cfg = chain();
  std::vector<Hit> hits;
  ConformalHits conformal;
  std::unique_ptr<detail::FinderState> state;

  void prepare(const std::vector<std::vector<std::uint64_t>>& pieces) {
    conformal = makeConformalHits(hits, det);
    state = std::make_unique<detail::FinderState>(conformal, det, cfg, 4.0);
    for (const auto& ids : pieces) {
      std::vector<ConfIndex> list;
      for (std::uint64_t id : ids) {
        for (ConfIndex c = 0; c < conformal.size(); ++c) {
          if (conformal.id[c] == id) {
            list.push_back(c);
          }
        }
      }
      ASSERT_EQ(list.size(), ids.size());
      TrackCandidate t;
      ASSERT_TRUE(detail::fitCandidate(*state, cfg.steps[0], list, t));
      state->tracks.push_back(t);
    }
  }
  std::uint32_t merge() {
    StepStats stats;
    detail::mergeTracks(*state, stats);
    return static_cast<std::uint32_t>(stats.mergedTracks);
  }
  std::vector<std::uint64_t> ids(std::size_t t) const {
    std::vector<std::uint64_t> out;
    for (ConfIndex c : state->tracks[t].hits) {
      out.push_back(conformal.id[c]);
    }
    return out;
  }
};

TEST(TrackMerging, TwoPiecesOfOneHelixAreMerged) {
  Fixture f;
  f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
  ASSERT_EQ(f.hits.size(), 8u);
  f.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  // All eight hits, along the path.
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_NEAR(f.state->tracks[0].pt, 0.3 * 4.0 * kRho / 1000.0, 0.05);
  EXPECT_NEAR(f.state->tracks[0].sz.tanLambda, kTanL, 1e-3);
}

TEST(TrackMerging, PiecesBeyondTheirStepsCutAreMergedByTheRatio) {
  // Hits 30 um off the helix, alternately on either side (6 sigma): each
  // piece's circle fit has a chi2/ndf of order 100, above a step cut of
  // 10 that the pieces passed when they were built (the extension, not
  // the step, took them past it). The merged fit is as good as the
  // pieces', so they merge; the step's cut is not applied again.
  Fixture f;
  f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
  for (std::size_t i = 0; i < f.hits.size(); ++i) {
    Hit& h = f.hits[i];
    const Vector3 across =
        Vector3(-h.position.y(), h.position.x(), 0.0).normalized();
    h.position += (i % 2 == 0 ? 0.03 : -0.03) * across;
  }
  f.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
  const double pieceChi2 = f.state->tracks[0].uv.chi2PerNdf();
  EXPECT_GT(pieceChi2, 10.0);
  f.cfg.steps[0].chi2Cut = 10.0;
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(TrackMerging, OrderOfHitsAndPiecesDoesNotMatter) {
  Fixture f;
  f.hits = test::helixHits(f.det, kRho, kPhi0, -1, kTanL, 1);
  f.prepare({{1, 2, 3}, {4, 5, 6, 7, 8}});
  ASSERT_EQ(f.merge(), 1u);
  Fixture g;
  g.hits = test::helixHits(g.det, kRho, kPhi0, -1, kTanL, 1);
  std::reverse(g.hits.begin(), g.hits.end());
  g.prepare({{4, 5, 6, 7, 8}, {1, 2, 3}});
  ASSERT_EQ(g.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  ASSERT_EQ(g.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), g.ids(0));
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(TrackMerging, DifferentNearbyHelicesStayApart) {
  for (int which = 0; which < 2; ++which) {
    Fixture f;
    f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
    const double phi = which == 0 ? kPhi0 + 0.01 : kPhi0;
    const double tanL = which == 0 ? kTanL : kTanL + 0.02;
    std::vector<Hit> second = test::helixHits(f.det, kRho, phi, 1, tanL, 101);
    f.hits.insert(f.hits.end(), second.begin(), second.end());
    f.prepare({{1, 2, 3, 4}, {105, 106, 107, 108}});
    EXPECT_EQ(f.merge(), 0u) << "case " << which;
    EXPECT_EQ(f.state->tracks.size(), 2u);
  }
}

TEST(TrackMerging, PieceEndingOnAnotherParticlesHitIsMergedWithoutIt) {
  // The inner piece's extension ended on a hit of a particle 0.1 rad away
  // (12 mm off at 120 mm, 15 mm at 150 mm: beyond the 10 mm gate). That
  // hit is left out and the pieces merge; with no outlier allowed they
  // stay apart.
  for (std::uint64_t foreign : {107u, 108u}) {
    Fixture f;
    f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
    std::vector<Hit> second =
        test::helixHits(f.det, kRho, kPhi0 - 0.1, 1, kTanL, 101);
    f.hits.insert(f.hits.end(), second.begin(), second.end());
    f.cfg.steps[0].chi2Cut = 1e9;
    // With 108 (150 mm) the inner piece reaches further out than the outer
    // one (layers 80-120): its circle, bent by that hit, is tried first.
    if (foreign == 107) {
      f.prepare({{1, 2, 3, 4, 107}, {5, 6, 7, 8}});
    } else {
      f.prepare({{1, 2, 3, 4, 108}, {5, 6, 7}});
    }
    EXPECT_EQ(f.merge(), 1u) << foreign;
    ASSERT_EQ(f.state->tracks.size(), 1u) << foreign;
    std::vector<std::uint64_t> expected{1, 2, 3, 4, 5, 6, 7, 8};
    if (foreign == 108) {
      expected.pop_back();
    }
    EXPECT_EQ(f.ids(0), expected) << foreign;

    Fixture g;
    g.hits = f.hits;
    g.cfg.steps[0].chi2Cut = 1e9;
    if (foreign == 107) {
      g.prepare({{1, 2, 3, 4, 107}, {5, 6, 7, 8}});
    } else {
      g.prepare({{1, 2, 3, 4, 108}, {5, 6, 7}});
    }
    detail::TrackMerger::Config cfg;
    cfg.maxOutliers = 0;
    EXPECT_EQ(detail::TrackMerger(*g.state, cfg).run(), 0u) << foreign;
  }
}

TEST(TrackMerging, DisplacedPiecesArePairedByTheirFreeCircles) {
  // A particle that passes 10 mm from the beam line (d0, 1.2 GeV): the
  // conformal fits, circles through the origin, put the centres of its
  // inner (30-65 mm) and outer (80-150 mm) pieces 0.26 rad apart in
  // azimuth, beyond the 0.1 rad sweep; their free circles lie within it.
  constexpr double kDisplacedRho = 1000.0;
  Fixture f;
  f.hits = test::helixHits(f.det, kDisplacedRho, kPhi0, 1, kTanL, 1, 10.0);
  ASSERT_EQ(f.hits.size(), 8u);
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
  const auto azimuth = [&](std::size_t t) {
    const auto& uv = f.state->tracks[t].uv;
    return std::atan2(uv.centreY, uv.centreX);
  };
  EXPECT_GT(std::abs(azimuth(0) - azimuth(1)), 0.1);
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

/// Hits of a looper (circle of radius rho through the origin) on every
/// barrel layer it crosses, outgoing half-turn (ids from 1) and incoming
/// half-turn (ids from 51); firstId and firstId + 50 for another one.
std::vector<Hit> looperHits(const Detector& det, double rho, double tanL,
                            double phi0 = kPhi0, std::uint64_t firstId = 1) {
  const double omega = 1.0 / rho;
  auto pos = [&](double s) {
    return Vector3((std::sin(phi0) - std::sin(phi0 - omega * s)) / omega,
                   -(std::cos(phi0) - std::cos(phi0 - omega * s)) / omega,
                   s * tanL);
  };
  std::vector<Hit> hits;
  const double half = std::numbers::pi * rho;
  for (std::uint16_t l = 0; l < 8; ++l) {
    const double r = det.layers()[l].r;
    if (pos(half).head<2>().norm() < r) {
      break;
    }
    for (int turn = 0; turn < 2; ++turn) {
      // Outgoing: R grows on [0, half]; incoming: R falls on [half, 2 half].
      double lo = turn == 0 ? 0.0 : half;
      double hi = turn == 0 ? half : 2.0 * half;
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        const bool inside = pos(mid).head<2>().norm() < r;
        ((turn == 0) == inside ? lo : hi) = mid;
      }
      const Vector3 p = pos(0.5 * (lo + hi));
      hits.push_back(test::barrelHit(det, l, p.x(), p.y(), p.z(),
                                     (turn == 0 ? firstId : firstId + 50) + l));
    }
  }
  return hits;
}

/// Centre of the circle of looperHits(det, rho, ..., kPhi0).
Vector2 looperCentre(double rho) {
  return {rho * std::sin(kPhi0), -rho * std::cos(kPhi0)};
}

/// Moves a hit in (x, y) to `radius` from `centre`, in its direction seen
/// from `from` (a circle shrunk round, or moved from, the looper's).
void moveOntoCircle(Hit& h, const Vector2& from, const Vector2& centre,
                    double radius) {
  const Vector2 p =
      centre + radius * (h.position.head<2>() - from).normalized();
  h.position.x() = p.x();
  h.position.y() = p.y();
}

TEST(TrackMerging, LooperFurtherHalfTurnIsLeftAlone) {
  Fixture f;
  // rho = 70 mm (0.084 GeV): reaches R = 140 mm, seven layers.
  f.hits = looperHits(f.det, 70.0, 0.05);
  ASSERT_EQ(f.hits.size(), 14u);
  // The incoming half-turn, found outwards: a track of opposite charge on
  // the same circle. Its hits are neither merged into the first half-turn
  // (they cross its layers far from its hits) nor kept as a second track.
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54, 53, 52}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));

  // Without the looper rule the two half-turns stay two tracks (no merge).
  Fixture g;
  g.hits = f.hits;
  g.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54, 53, 52}});
  detail::TrackMerger::Config cfg;
  cfg.dropTurns = false;
  EXPECT_EQ(detail::TrackMerger(*g.state, cfg).run(), 0u);
}

TEST(TrackMerging, ScatteredFurtherTurnIsStillRecognised) {
  // The incoming half-turn 21 mm off in z (as scattering leaves it a few
  // hundred millimetres of path on; tanLambda 0.5, 220 mm per turn):
  // beyond the 20 mm z gate at the first half-turn's end, inside it once
  // the distance is divided by 1 + path / 1 m (path 150-270 mm).
  Fixture f;
  f.hits = looperHits(f.det, 70.0, 0.5);
  for (Hit& h : f.hits) {
    if (h.id > 50) {
      h.position.z() += 21.0;
    }
  }
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54, 53, 52}});
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
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54}});
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
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54, 53, 52}});
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
      {{101, 102, 103, 104, 105, 106, 107, 108}, {57, 56, 55, 54, 53, 52, 51}});
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
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54, 53, 52}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7}));

  // Without the path's allowance the 13 mm are refused.
  Fixture g;
  g.hits = hits;
  g.cfg.steps[0].chi2Cut = 1e9;
  g.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54, 53, 52}});
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
  f.prepare({{1, 2, 3, 4, 5, 6, 7}, {57, 56, 55, 54, 53, 52}});
  EXPECT_EQ(f.merge(), 0u);
  EXPECT_EQ(f.state->tracks.size(), 2u);
}

TEST(TrackMerging, ChainKeysAreRead) {
  const Detector det = test::barrelDetector();
  const FinderConfig c = parseChain(
      "[finder]\ntrack_merging = false\nmerge_max_dphi = 0.2\n"
      "merge_max_distance_mm = 4.0\nmerge_max_dz_mm = 8.0\n"
      "merge_max_chi2_ratio = 5.0\n" +
          minimalStep("Barrel"),
      "chain.toml", det);
  EXPECT_FALSE(c.trackMerging);
  EXPECT_DOUBLE_EQ(c.mergeMaxDeltaPhi, 0.2);
  EXPECT_DOUBLE_EQ(c.mergeMaxDistance, 4.0 * units::mm);
  EXPECT_DOUBLE_EQ(c.mergeMaxDz, 8.0 * units::mm);
  EXPECT_DOUBLE_EQ(c.mergeMaxChi2Ratio, 5.0);
  EXPECT_THROW(
      parseChain("[finder]\nmerge_max_dz_mm = -1.0\n" + minimalStep("Barrel"),
                 "chain.toml", det),
      InputError);
}

TEST(TrackMerging, CutsAreValidated) {
  const Detector det = test::barrelDetector();
  FinderConfig cfg = chain();
  cfg.mergeMaxDistance = 0.0;
  auto p = findChainProblem(cfg, det);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->key, "finder.merge_max_distance_mm");
  cfg = chain();
  cfg.mergeMaxChi2Ratio = 0.5;
  p = findChainProblem(cfg, det);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->key, "finder.merge_max_chi2_ratio");

  const ConformalHits none = makeConformalHits({}, det);
  cfg = chain();
  detail::FinderState state(none, det, cfg, 4.0);
  detail::TrackMerger::Config bad;
  bad.maxDz = std::nan("");
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
  bad = {};
  bad.maxDeltaPhi = 4.0;
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
  bad = {};
  bad.turnScaleTanLambda = 0.0;
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
  bad = {};
  bad.maxTurnScore = std::nan("");
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

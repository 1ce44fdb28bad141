#pragma once

/// @file TrackMergingFixture.hpp
/// Shared set-up of the track-merging tests (TrackMergingTests.cpp: pieces
/// of one helix; TrackMergingTurnsTests.cpp: loopers' further half-turns):
/// a one-step chain, a fixture that fits hit-id lists as the finder's
/// tracks, and the hits of a looper on the barrel layers.

#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "SyntheticHits.hpp"

namespace conftrack::test {

/// The helix of the piece-merging tests: radius [mm] (3.6 GeV in 4 T),
/// initial azimuth, dip.
inline constexpr double kRho = 3000.0;
inline constexpr double kPhi0 = 0.4;
inline constexpr double kTanL = 0.3;

/// One build step over the barrel whose fit the pieces are made with
/// (chi2 cut 100, three hits: a piece of any length passes).
inline FinderConfig chain() {
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
      for (ConfIndex c : list) {
        state->used[c] = 1;  // on a track, as the finder marks them
      }
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
  /// Hit ids of track t (its fitted hits, or with turns = true the hits
  /// of further half-turns joined to it).
  std::vector<std::uint64_t> ids(std::size_t t, bool turns = false) const {
    std::vector<std::uint64_t> out;
    const TrackCandidate& c = state->tracks[t];
    for (ConfIndex h : turns ? c.turnHits : c.hits) {
      out.push_back(conformal.id[h]);
    }
    return out;
  }
  /// The ids of track t's turn hits (TrackCandidate::turnHits), sorted: the
  /// searches add them in the order they find them.
  std::vector<std::uint64_t> turnIds(std::size_t t) const {
    std::vector<std::uint64_t> out = ids(t, true);
    std::sort(out.begin(), out.end());
    return out;
  }
};

/// Hits of a looper (circle of radius rho through the origin) on every
/// barrel layer it crosses, outgoing half-turn (ids from 1) and incoming
/// half-turn (ids from 51); firstId and firstId + 50 for another one.
inline std::vector<Hit> looperHits(const Detector& det, double rho, double tanL,
                                   double phi0 = kPhi0,
                                   std::uint64_t firstId = 1) {
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
inline Vector2 looperCentre(double rho) {
  return {rho * std::sin(kPhi0), -rho * std::cos(kPhi0)};
}

/// Moves a hit in (x, y) to `radius` from `centre`, in its direction seen
/// from `from` (a circle shrunk round, or moved from, the looper's).
inline void moveOntoCircle(Hit& h, const Vector2& from, const Vector2& centre,
                           double radius) {
  const Vector2 p =
      centre + radius * (h.position.head<2>() - from).normalized();
  h.position.x() = p.x();
  h.position.y() = p.y();
}

}  // namespace conftrack::test

// Track merging, the last part of the looper rule (TrackMerger::
// collectTurnHits; the rule itself is in TrackMergingTurns.cpp).
//
// A looper curls through the same layers turn after turn. The finder
// builds tracks of some of its half-turns, and the looper rule joins those
// to the first half-turn's track (Config::maxJoinScore); the hits of the
// other turns, of which no track was built (too few hits in a row, hits
// shared with neighbours when the steps ran), stay unused. Then the track
// holds less than half of its particle's hits: a fake in the ACTS double
// matching (CLICdet tt-bar + 30 BX: most such tracks are of overlay
// particles below 0.3 GeV, many below 0.1 GeV, curling inside the vertex
// detector).
//
// Here each unused hit close to a looping track's helix some whole number
// of turns on joins that track: within Config::maxTurnHitScore of it, the
// transverse distance from the track's free circle over turnScaleDistance
// and the z distance from its helix (the s-z line continued from its last
// hit, k = 0..kTurnSearchTurns turns on) over turnScaleDz, squared and summed.
// Unlike a further turn of several hits, a single hit carries no
// direction, radius or tanLambda of its own, so the test is much tighter
// than the turn rule's and takes no allowance for the path: it keeps the
// hits that energy loss and scattering have not yet moved off the first
// half-turn's helix. A hit that several tracks claim goes to the one it
// scores best with (ties by track, then hit index: the same for any
// thread count).
// The helix is searched from the track's last hit on, up to the chain's
// max_track_turns from its first hit (on TrackML, whose particles end
// after half a turn, the rest of that half-turn). The unused hits are
// kept in strips of x, each sorted by y, and each track tests those
// within the box of its arc.

#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"
#include "conftrack/reconstruction/finding/detail/UnusedHits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

namespace conftrack::detail {

namespace {

/// A hit that a track could take, with its score.
struct Claim {
  double score;
  std::uint32_t track;
  ConfIndex hit;
};

}  // namespace

std::optional<double> TrackMerger::turnSearchReach(
    const TrackCandidate& track, const TransverseCircle& circle) const {
  if (!track.alive || track.hits.size() < 4 ||
      !(2.0 * circle.rho <= m_config.maxLoopDiameter)) {
    return std::nullopt;
  }
  const double period = 2.0 * std::numbers::pi * circle.rho;
  // No further along the helix than the extensions predict
  // (FinderConfig::maxTrackTurns, from the track's first hit): where the
  // data's particles end after half a turn (TrackML), only the rest of the
  // track's half-turn is searched.
  double reach = (kTurnSearchTurns + 1) * period;
  if (m_state.config.maxTrackTurns > 0.0) {
    reach =
        std::min(reach, m_state.config.maxTrackTurns * period - track.sz.lastS);
  }
  if (!(reach > 0.0)) {
    return std::nullopt;
  }
  return reach;
}

std::uint32_t TrackMerger::collectTurnHits(std::span<const std::uint32_t> order,
                                           std::span<const TurnCircle> circles,
                                           const UnusedHits& unused) {
  std::vector<TrackCandidate>& tracks = m_state.tracks;
  const double maxScore = m_config.maxTurnHitScore;
  // Within the score, a hit lies within these distances.
  const double band = m_config.turnScaleDistance * std::sqrt(maxScore);
  const double maxDz = m_config.turnScaleDz * std::sqrt(maxScore);
  std::vector<Claim> claims;
  for (const std::uint32_t t : order) {
    const TrackCandidate& track = tracks[t];
    const TransverseCircle& circle = circles[t].circle;
    const std::optional<double> reach = turnSearchReach(track, circle);
    if (!reach) {
      continue;
    }
    const double arcTo = *reach;
    const ConfIndex last = track.hits.back();
    const double zLast = track.sz.z0 + track.sz.tanLambda * track.sz.lastS;
    const double period = 2.0 * std::numbers::pi * circle.rho;
    // The band as squared radii: most hits tested lie far off it.
    const double inner = std::max(0.0, circle.rho - band);
    const double inner2 = inner * inner;
    const double outer2 = (circle.rho + band) * (circle.rho + band);
    unused.forEachNear(
        circle, band,
        std::atan2(m_hits.y[last] - circle.cy, m_hits.x[last] - circle.cx),
        arcTo / circle.rho, [&](ConfIndex h) {
          const double dx = m_hits.x[h] - circle.cx;
          const double dy = m_hits.y[h] - circle.cy;
          const double r2 = dx * dx + dy * dy;
          if (r2 < inner2 || r2 > outer2) {
            return;
          }
          const double off = std::abs(std::sqrt(r2) - circle.rho);
          // Along the motion from the last hit: the rest of this turn, then
          // whole turns on.
          const double arc = circle.arc(m_hits.x[last], m_hits.y[last],
                                        m_hits.x[h], m_hits.y[h]);
          double dz = std::numeric_limits<double>::infinity();
          for (int k = 0; k <= kTurnSearchTurns; ++k) {
            const double path = arc + k * period;
            if (path > arcTo) {
              break;
            }
            dz = std::min(dz, std::abs(m_hits.z[h] -
                                       (zLast + track.sz.tanLambda * path)));
          }
          if (!(dz <= maxDz)) {
            return;
          }
          const double score = square(off / m_config.turnScaleDistance) +
                               square(dz / m_config.turnScaleDz);
          if (score <= maxScore) {
            claims.push_back({score, t, h});
          }
        });
  }
  std::sort(claims.begin(), claims.end(), [](const Claim& a, const Claim& b) {
    return std::tie(a.score, a.track, a.hit) <
           std::tie(b.score, b.track, b.hit);
  });
  std::uint32_t collected = 0;
  for (const Claim& c : claims) {
    if (m_state.used[c.hit] != 0) {
      continue;  // taken by a better claim
    }
    m_state.used[c.hit] = 1;
    tracks[c.track].turnHits.push_back(c.hit);
    ++collected;
  }
  return collected;
}

}  // namespace conftrack::detail

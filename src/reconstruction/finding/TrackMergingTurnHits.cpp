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
// hit, k = 0..kMaxTurns turns on) over turnScaleDz, squared and summed.
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

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <tuple>
#include <vector>

namespace conftrack::detail {

namespace {

/// Turns searched beyond a track's last hit (as the turn rule's).
constexpr int kMaxTurns = 3;

/// Width of the strips of x of UnusedHits [mm].
constexpr double kStripWidth = 20.0;

/// Most strips (a wider spread of hits gets wider strips).
constexpr std::size_t kMaxStrips = 1024;

/// The unused hits in strips of x, each sorted by y: the hits in a box
/// are those of a few strips, each a binary search.
class UnusedHits {
 public:
  UnusedHits(const ConformalHits& hits, const std::vector<std::uint8_t>& used)
      : m_hits(&hits) {
    double xMax = -std::numeric_limits<double>::infinity();
    for (ConfIndex h = 0; h < hits.size(); ++h) {
      if (used[h] == 0) {
        m_x0 = std::min(m_x0, hits.x[h]);
        xMax = std::max(xMax, hits.x[h]);
      }
    }
    if (!(m_x0 <= xMax)) {
      return;  // no unused hit
    }
    m_width = std::max(kStripWidth, (xMax - m_x0) / (kMaxStrips - 1));
    const std::size_t strips = stripOf(xMax) + 1;
    m_start.assign(strips + 1, 0);
    for (ConfIndex h = 0; h < hits.size(); ++h) {
      if (used[h] == 0) {
        ++m_start[stripOf(hits.x[h]) + 1];
      }
    }
    for (std::size_t k = 1; k <= strips; ++k) {
      m_start[k] += m_start[k - 1];
    }
    m_byY.resize(m_start.back());
    std::vector<std::uint32_t> fill(m_start.begin(), m_start.end() - 1);
    for (ConfIndex h = 0; h < hits.size(); ++h) {
      if (used[h] == 0) {
        m_byY[fill[stripOf(hits.x[h])]++] = h;
      }
    }
    for (std::size_t k = 0; k < strips; ++k) {
      std::sort(m_byY.begin() + m_start[k], m_byY.begin() + m_start[k + 1],
                [&](ConfIndex a, ConfIndex b) {
                  return std::tie(hits.y[a], a) < std::tie(hits.y[b], b);
                });
    }
    m_y.reserve(m_byY.size());
    for (ConfIndex h : m_byY) {
      m_y.push_back(hits.y[h]);
    }
  }

  /// Calls f(h) for each hit in the box of the arc of circle `c` that
  /// starts at angle `start` round its centre and runs `sweep` radians
  /// along the motion (the whole circle from 2 pi on), widened by `band`:
  /// a superset of the hits within `band` of the arc.
  template <class F>
  void forEachNear(const TransverseCircle& c, double band, double start,
                   double sweep, F&& f) const {
    if (m_y.empty()) {
      return;
    }
    double xLo = c.cx - c.rho;
    double xHi = c.cx + c.rho;
    double yLo = c.cy - c.rho;
    double yHi = c.cy + c.rho;
    if (sweep < 2.0 * std::numbers::pi) {
      // The arc's ends, and each axis extreme that the arc passes.
      const auto include = [&](double angle) {
        const double x = c.cx + c.rho * std::cos(angle);
        const double y = c.cy + c.rho * std::sin(angle);
        xLo = std::min(xLo, x);
        xHi = std::max(xHi, x);
        yLo = std::min(yLo, y);
        yHi = std::max(yHi, y);
      };
      xLo = yLo = std::numeric_limits<double>::infinity();
      xHi = yHi = -xLo;
      include(start);
      include(start + c.orientation * sweep);
      for (int q = 0; q < 4; ++q) {
        const double axis = 0.5 * std::numbers::pi * q;
        double ahead = std::remainder(c.orientation * (axis - start),
                                      2.0 * std::numbers::pi);
        if (ahead < 0.0) {
          ahead += 2.0 * std::numbers::pi;
        }
        if (ahead <= sweep) {
          include(axis);
        }
      }
    }
    if (xHi + band < m_x0) {
      return;
    }
    const std::size_t strips = m_start.size() - 1;
    const std::size_t first = xLo - band <= m_x0 ? 0 : stripOf(xLo - band);
    const std::size_t last = std::min(stripOf(xHi + band), strips - 1);
    for (std::size_t k = first; k <= last; ++k) {
      const auto begin = m_y.begin() + m_start[k];
      const auto end = m_y.begin() + m_start[k + 1];
      for (auto it = std::lower_bound(begin, end, yLo - band);
           it != end && *it <= yHi + band; ++it) {
        f(m_byY[static_cast<std::size_t>(it - m_y.begin())]);
      }
    }
  }

 private:
  std::size_t stripOf(double x) const {
    return static_cast<std::size_t>((x - m_x0) / m_width);
  }

  const ConformalHits* m_hits;
  double m_x0 = std::numeric_limits<double>::infinity();
  double m_width = kStripWidth;
  std::vector<std::uint32_t> m_start;  ///< first hit of each strip
  std::vector<ConfIndex> m_byY;        ///< unused hits by strip, then y
  std::vector<double> m_y;             ///< their y
};

double square(double x) { return x * x; }

/// A hit that a track could take, with its score.
struct Claim {
  double score;
  std::uint32_t track;
  ConfIndex hit;
};

}  // namespace

std::uint32_t TrackMerger::collectTurnHits(
    std::span<const std::uint32_t> order, std::span<const TurnCircle> circles) {
  std::vector<TrackCandidate>& tracks = m_state.tracks;
  const double maxScore = m_config.maxTurnHitScore;
  // Within the score, a hit lies within these distances.
  const double band = m_config.turnScaleDistance * std::sqrt(maxScore);
  const double maxDz = m_config.turnScaleDz * std::sqrt(maxScore);
  const UnusedHits unused(m_hits, m_state.used);
  std::vector<Claim> claims;
  for (const std::uint32_t t : order) {
    const TrackCandidate& track = tracks[t];
    const TransverseCircle& circle = circles[t].circle;
    // Four hits at least: the free circle of fewer is the conformal one.
    if (!track.alive || track.hits.size() < 4 ||
        !(2.0 * circle.rho <= m_config.maxLoopDiameter)) {
      continue;
    }
    const ConfIndex last = track.hits.back();
    const double zLast = track.sz.z0 + track.sz.tanLambda * track.sz.lastS;
    const double period = 2.0 * std::numbers::pi * circle.rho;
    // No further along the helix than the extensions predict
    // (FinderConfig::maxTrackTurns, from the track's first hit): where the
    // data's particles end after half a turn (TrackML), only the rest of
    // the track's half-turn is searched.
    double arcTo = (kMaxTurns + 1) * period;
    if (m_state.config.maxTrackTurns > 0.0) {
      arcTo = std::min(arcTo,
                       m_state.config.maxTrackTurns * period - track.sz.lastS);
    }
    if (!(arcTo > 0.0)) {
      continue;
    }
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
          for (int k = 0; k <= kMaxTurns; ++k) {
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

// Track merging, the turn follower: the last part of the looper rule
// (TrackMerger::followTurns; the rule is in TrackMergingTurns.cpp, the
// single-hit search before this one in TrackMergingTurnHits.cpp).
//
// A looper below about 0.1 GeV loses a per cent of its momentum at each
// layer it crosses (CLICdet vertex barrel, a 60 MeV pion: pT 60.2 ->
// 56.8 MeV over the six layers of its first half-turn, 50.8 MeV after
// the second), so its circle shrinks and moves turn by turn: the hits of
// its second half-turn lie a median 10 mm inside the first half-turn's
// circle, and neither the turn rule's single-hit search (within 0.95 mm
// of that circle) nor any step of the chain takes them. Such a track
// holds less than half of its particle's hits: a fake in the ACTS double
// matching.
//
// Here each looping track is followed hit by hit from its last hit: the
// next hit is the unused hit (or one of the track's own joined turn hits,
// which are already on it) nearest along the motion, within
// Config::followMaxGapTurns of a turn, whose score against the circle
// and s-z line of the track's latest kFollowFitHits hits, continued to it,
// is at most Config::maxFollowScore (the squared transverse distance over
// turnScaleDistance squared plus the squared z distance over turnScaleDz
// squared). Then circle and line are fitted again to the latest hits, so
// that the prediction follows the shrinking circle. A track is followed no
// further than the single-hit search looks (kMaxTurns turns, the chain's
// max_track_turns from its first hit). The tracks are followed in the
// looper rule's order, each taking the hits it reaches first; the hits
// join the track unfitted, as the joined turns' do.
//
// Where no hit is within reach, the follow has come to a gap that its
// prediction cannot cross: mostly the apex of a looper beyond the last
// layer of the vertex detector (CLICdet: none from 60 to 127 mm), half a
// turn or more without material in which the next hits move 5-20 mm off
// the predicted circle. Then (Config::followJumps) the next turn is looked
// for as a segment of its own: four unused hits on four layers, the first
// three on a circle (their own) that is close to the track's (centre
// within kJumpCentre, radius within kJumpRadius), whose tanLambda is the
// track's within kJumpTanLambda and whose first hit lies at most
// kJumpInside inside the predicted circle and kJumpOutside outside it
// (energy loss moves the next turn inwards), at the z the track's line
// predicts within kJumpDz; the fourth within kJumpFourthDistance of their
// circle. The predicted circle is that of the latest kJumpFitHits hits of
// the turn followed so far, not the follow's latest kFollowFitHits. The
// first three hits of the nearest such segment along the motion join, and
// the follow goes on from them with their circle (and takes the fourth
// next). Only tracks below kJumpMaxPt jump, over at most kJumpMaxArc
// (the loopers whose further turns CLICdet's ACTS fakes lacked: see the
// bounds below).

#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"
#include "conftrack/reconstruction/finding/detail/UnusedHits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

namespace conftrack::detail {

namespace {

/// Latest hits of a followed track that predict its next hit: a few
/// layers' worth, so that the circle is that of the particle's current
/// momentum (TrackMerging.FollowerTakesTheHitsOfAShrinkingTurn: with 8,
/// half of them from the first half-turn's larger circle, the prediction
/// lags 1.4 mm behind the shrinking turn, with 4 at most 0.8 mm;
/// CLICdet tt-bar + 30 BX: the same rates with 4, 5 and 8).
constexpr std::size_t kFollowFitHits = 4;

/// Hits of the turn being followed (since its start or the last jump)
/// whose free circle predicts a jump across the apex. Over the apex the
/// prediction runs 50-150 mm on, and the latest kFollowFitHits alone,
/// mostly the two hits of each of two double layers a few millimetres
/// apart, carry the scattering of a 50 MeV track: their circle was 30 %
/// too small where the particle's was (CLICdet tt-bar + 30 BX, sensors:
/// a 0.049 GeV looper, radius 41 mm, predicted on 29 mm, 35 mm with six).
constexpr std::size_t kJumpFitHits = 6;

/// Shortest arc spanned by those hits for a new tanLambda [mm]: over a
/// shorter arc (an overlap pair, a double layer) the slope is the
/// previous one.
constexpr double kFollowMinLever = 10.0;

/// The segment search (see the file comment). First set on CLICdet tt-bar
/// + 30 BX, 20 events, the jumps matched to the truth: 110 of 126 segments
/// were the followed particle's, with a first hit 1.9 mm (median) inside
/// the predicted circle and a centre 5.3 mm off. Widened at stop 40, where
/// the ACTS-fake tracks whose particle's next hits were free and whose
/// segment search failed (30 events: 179 of the 353 ACTS fakes) were traced:
/// the predicted circle, fitted to a few hits of the turn behind, is
/// itself off by several millimetres either way (true next turns 2-13 mm
/// outside it, not only inside as energy loss alone would put them), a
/// three-hit segment's radius is measured to 20-30 % and its tanLambda
/// to 0.1-0.2 (the jumps that the truth confirms); and loopers of 0.2-0.6 GeV
/// (radius 170-500 mm in 4 T) never jumped, though their next hits lay on the
/// predicted circle within millimetres beyond the inner tracker's layers
/// (200-1100 mm of arc). The fourth hit and the z of the second are held
/// tighter instead (0.5 mm, 1 mm): they tell another particle's segment
/// from the turn's at little cost (CLICdet ideal layers / sensors, 100
/// events: ACTS fake rate 2.16 / 2.39 % -> 1.98 / 2.24 %, CLICdp fake rate
/// 0.225 / 0.281 % -> 0.232 / 0.286 %; algorithm.md 3.17).
constexpr double kJumpInside = 30.0;         ///< [mm]
constexpr double kJumpOutside = 6.0;         ///< [mm]
constexpr double kJumpCentre = 10.0;         ///< [mm]
constexpr double kJumpRadius = 0.3;          ///< fraction of the radius
constexpr double kJumpTanLambda = 0.2;       ///< scattering of 60 MeV
constexpr double kJumpDz = 10.0;             ///< [mm], plus:
constexpr double kJumpDzPerArc = 0.05;       ///< the tanLambda error's share
constexpr double kJumpMidDz = 1.0;           ///< z of the 2nd, 4th hit [mm]
constexpr double kJumpFourthDistance = 0.5;  ///< [mm]
constexpr double kJumpMaxPt = 0.6;           ///< [GeV]
constexpr double kJumpMaxArc = 1200.0;       ///< [mm]
constexpr double kJumpMaxTurns = 0.75;       ///< of the circle
constexpr int kMaxJumps = 6;                 ///< per track

/// A segment found across a gap: its hits in order and their circle and
/// line.
struct Segment {
  std::array<ConfIndex, 3> hits{};
  double arc = 0.0;  ///< from the last hit to the segment's third
  TransverseCircle circle;
  double tanLambda = 0.0;
};

/// A followed track's s-z line at its last hit.
struct SzLine {
  double tanLambda = 0.0;
  double zLast = 0.0;  ///< the line's z at the last hit
};

/// The nearest segment along the motion beyond a gap after hit `last`
/// (see the file comment): unused hits, consecutive ones at most `maxGap`
/// apart along the arc, the first at most `maxArc` on.
std::optional<Segment> findSegment(const ConformalHits& hits,
                                   const UnusedHits& unused, ConfIndex last,
                                   const TransverseCircle& local,
                                   const SzLine& line, double maxGap,
                                   double maxArc) {
  const double xLast = hits.x[last];
  const double yLast = hits.y[last];
  maxArc = std::min(maxArc, kJumpMaxTurns * 2.0 * std::numbers::pi * local.rho);
  // The candidates, by arc from the last hit.
  std::vector<std::pair<double, ConfIndex>> near;
  unused.forEachNear(
      local, kJumpInside, std::atan2(yLast - local.cy, xLast - local.cx),
      maxArc / local.rho, [&](ConfIndex h) {
        // The distance from the circle first: most hits in the box of a
        // long arc lie far off it, and it needs no arctangent.
        const double off =
            norm2(hits.x[h] - local.cx, hits.y[h] - local.cy) - local.rho;
        if (!(off >= -kJumpInside && off <= kJumpOutside)) {
          return;
        }
        const double arc = local.arc(xLast, yLast, hits.x[h], hits.y[h]);
        if (!(arc > 0.0 && arc <= maxArc)) {
          return;
        }
        const double dz = hits.z[h] - (line.zLast + line.tanLambda * arc);
        if (std::abs(dz) <= kJumpDz + kJumpDzPerArc * arc) {
          near.emplace_back(arc, h);
        }
      });
  std::sort(near.begin(), near.end());
  const auto on = [&](const TransverseCircle& c, double tanLambda,
                      ConfIndex from, ConfIndex h, double maxDistance) {
    const double off =
        std::abs(norm2(hits.x[h] - c.cx, hits.y[h] - c.cy) - c.rho);
    const double z =
        hits.z[from] +
        tanLambda * c.arc(hits.x[from], hits.y[from], hits.x[h], hits.y[h]);
    return off <= maxDistance && std::abs(hits.z[h] - z) <= kJumpMidDz;
  };
  for (std::size_t i = 0; i < near.size(); ++i) {
    const ConfIndex a = near[i].second;
    for (std::size_t j = i + 1;
         j < near.size() && near[j].first - near[i].first <= maxGap; ++j) {
      const ConfIndex b = near[j].second;
      if (hits.layer[b] == hits.layer[a]) {
        continue;
      }
      for (std::size_t k = j + 1;
           k < near.size() && near[k].first - near[j].first <= maxGap; ++k) {
        const ConfIndex c = near[k].second;
        if (hits.layer[c] == hits.layer[a] || hits.layer[c] == hits.layer[b]) {
          continue;
        }
        TransverseCircle circle;
        if (!circleThrough(hits.x[a], hits.y[a], hits.x[b], hits.y[b],
                           hits.x[c], hits.y[c], circle) ||
            circle.orientation != local.orientation ||
            std::abs(circle.rho - local.rho) > kJumpRadius * local.rho ||
            norm2(circle.cx - local.cx, circle.cy - local.cy) > kJumpCentre) {
          continue;
        }
        const double arcAC =
            circle.arc(hits.x[a], hits.y[a], hits.x[c], hits.y[c]);
        if (!(arcAC > 0.0)) {
          continue;
        }
        const double tanLambda = (hits.z[c] - hits.z[a]) / arcAC;
        if (std::abs(tanLambda - line.tanLambda) > kJumpTanLambda ||
            !on(circle, tanLambda, a, b, std::numeric_limits<double>::max())) {
          continue;
        }
        // A fourth hit on the segment's helix: three points always lie on
        // a circle.
        bool fourth = false;
        for (std::size_t l = k + 1; !fourth && l < near.size() &&
                                    near[l].first - near[k].first <= maxGap;
             ++l) {
          const ConfIndex e = near[l].second;
          fourth = hits.layer[e] != hits.layer[a] &&
                   hits.layer[e] != hits.layer[b] &&
                   hits.layer[e] != hits.layer[c] &&
                   on(circle, tanLambda, a, e, kJumpFourthDistance);
        }
        if (fourth) {
          return Segment{{a, b, c}, near[k].first, circle, tanLambda};
        }
      }
    }
  }
  return std::nullopt;
}

/// Puts the latest `n` hits of `path` (at most all) into `latest` and
/// replaces `circle` by their free circle unless the fit fails or is wider
/// than `maxLoopDiameter` (a track that cannot loop).
void fitLatest(const ConformalHits& hits, std::span<const ConfIndex> path,
               std::size_t n, double maxLoopDiameter,
               std::vector<ConfIndex>& latest, TransverseCircle& circle) {
  n = std::min(n, path.size());
  latest.assign(path.end() - static_cast<std::ptrdiff_t>(n), path.end());
  TransverseCircle refit;
  if (fitCircle(hits, latest, refit) && 2.0 * refit.rho <= maxLoopDiameter) {
    circle = refit;
  }
}

/// Fits `local` and `line` to the latest kFollowFitHits hits of `path`
/// (a circle wider than `maxLoopDiameter` is not taken; `latest` is
/// scratch).
void refitToLatest(const ConformalHits& hits, std::span<const ConfIndex> path,
                   double maxLoopDiameter, HelixPath& latest,
                   TransverseCircle& local, SzLine& line) {
  fitLatest(hits, path, kFollowFitHits, maxLoopDiameter, latest.hits, local);
  const std::size_t n = latest.hits.size();
  // Arc lengths along the new circle; an overlap partner may lie a
  // little behind the hit before it.
  latest.s.assign(1, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    const ConfIndex a = latest.hits[i - 1];
    const ConfIndex b = latest.hits[i];
    double step = local.arc(hits.x[a], hits.y[a], hits.x[b], hits.y[b]);
    if (step > std::numbers::pi * local.rho) {
      step -= 2.0 * std::numbers::pi * local.rho;
    }
    latest.s.push_back(latest.s.back() + step);
  }
  // Over a shorter arc than kFollowMinLever the slope is the previous
  // one.
  latest.t = line.tanLambda;
  if (latest.s.back() - latest.s.front() >= kFollowMinLever) {
    fitPathSz(hits, latest);
    line = SzLine{latest.t, latest.z0 + latest.t * latest.s.back()};
  } else {
    // The previous slope through all n hits: their mean z, carried to
    // the last hit.
    double zAtLast = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      zAtLast += hits.z[latest.hits[i]] +
                 line.tanLambda * (latest.s.back() - latest.s[i]);
    }
    line.zLast = zAtLast / static_cast<double>(n);
  }
}

}  // namespace

std::uint32_t TrackMerger::followTurns(std::span<const std::uint32_t> order,
                                       std::span<const TurnCircle> circles,
                                       const UnusedHits& unused) {
  std::vector<TrackCandidate>& tracks = m_state.tracks;
  const double maxScore = m_config.maxFollowScore;
  // Within the score, a hit lies within this distance of the circle.
  const double band = m_config.turnScaleDistance * std::sqrt(maxScore);
  std::vector<ConfIndex> path;
  std::vector<ConfIndex> taken;
  HelixPath latest;  // the latest hits, for the s-z line
  std::uint32_t collected = 0;
  // The circle that predicts a jump: that of the turn's latest
  // kJumpFitHits hits where there are more of them than the follow's
  // kFollowFitHits, else the follow's own.
  std::vector<ConfIndex> jumpHits;
  const auto jumpCircle = [&](std::span<const ConfIndex> turn,
                              TransverseCircle circle) {
    if (turn.size() > kFollowFitHits) {
      fitLatest(m_hits, turn, kJumpFitHits, m_config.maxLoopDiameter, jumpHits,
                circle);
    }
    return circle;
  };
  for (const std::uint32_t t : order) {
    TrackCandidate& track = tracks[t];
    const TransverseCircle& circle = circles[t].circle;
    const std::optional<double> trackReach = turnSearchReach(track, circle);
    if (!trackReach) {
      continue;
    }
    const double reach = *trackReach;
    const double maxGap =
        m_config.followMaxGapTurns * 2.0 * std::numbers::pi * circle.rho;
    const std::span<const ConfIndex> own = circles[t].hitsOf(track);
    path.assign(own.begin(), own.end());
    taken.clear();
    TransverseCircle local = circle;
    SzLine line{track.sz.tanLambda,
                track.sz.z0 + track.sz.tanLambda * track.sz.lastS};
    double travelled = 0.0;
    int jumps = 0;
    std::size_t turnStart = 0;  // in path: where the turn followed began
    while (travelled < reach) {
      const ConfIndex last = path.back();
      const double xLast = m_hits.x[last];
      const double yLast = m_hits.y[last];
      // The next hit along the motion; ties by score, then hit index.
      double bestArc = std::numeric_limits<double>::infinity();
      double bestScore = 0.0;
      ConfIndex best = 0;
      bool bestIsNew = false;
      const auto consider = [&](ConfIndex h, bool isNew) {
        // The distance from the circle first, as in findSegment: it needs
        // no arctangent, and most hits of the search box fail it.
        const double off = std::abs(
            norm2(m_hits.x[h] - local.cx, m_hits.y[h] - local.cy) - local.rho);
        if (!(off <= band)) {
          return;
        }
        const double arc = local.arc(xLast, yLast, m_hits.x[h], m_hits.y[h]);
        if (!(arc > 0.0 && arc <= maxGap && travelled + arc <= reach)) {
          return;
        }
        const double dz = m_hits.z[h] - (line.zLast + line.tanLambda * arc);
        const double score = square(off / m_config.turnScaleDistance) +
                             square(dz / m_config.turnScaleDz);
        if (score <= maxScore &&
            std::tie(arc, score, h) < std::tie(bestArc, bestScore, best)) {
          bestArc = arc;
          bestScore = score;
          best = h;
          bestIsNew = isNew;
        }
      };
      unused.forEachNear(
          local, band, std::atan2(yLast - local.cy, xLast - local.cx),
          maxGap / local.rho, [&](ConfIndex h) { consider(h, true); });
      // The track's joined turns are on its path already.
      for (const ConfIndex h : track.turnHits) {
        if (std::find(path.begin(), path.end(), h) == path.end()) {
          consider(h, false);
        }
      }
      if (!std::isfinite(bestArc)) {
        if (!m_config.followJumps || jumps == kMaxJumps ||
            circlePt(local, m_state.bzForPt) > kJumpMaxPt) {
          break;
        }
        ++jumps;
        const std::optional<Segment> segment = findSegment(
            m_hits, unused, last,
            jumpCircle(std::span<const ConfIndex>(path).subspan(turnStart),
                       local),
            line, maxGap, std::min(kJumpMaxArc, reach - travelled));
        if (!segment) {
          break;
        }
        turnStart = path.size();
        for (const ConfIndex h : segment->hits) {
          path.push_back(h);
          taken.push_back(h);
          m_state.used[h] = 1;
        }
        travelled += segment->arc;
        local = segment->circle;
        line = SzLine{segment->tanLambda, m_hits.z[segment->hits.back()]};
        continue;
      }
      path.push_back(best);
      if (bestIsNew) {
        taken.push_back(best);
        m_state.used[best] = 1;
      }
      travelled += bestArc;
      refitToLatest(m_hits, path, m_config.maxLoopDiameter, latest, local,
                    line);
    }
    // (Marked as used when taken.)
    track.turnHits.insert(track.turnHits.end(), taken.begin(), taken.end());
    collected += static_cast<std::uint32_t>(taken.size());
  }
  return collected;
}

}  // namespace conftrack::detail

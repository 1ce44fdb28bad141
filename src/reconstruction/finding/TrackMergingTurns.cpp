// Track merging, loopers' further half-turns (TrackMerger::dropTurns; the
// merging itself is in TrackMerging.cpp).
//
// Loopers: a particle below about 1 GeV (CLICdet) curls inside the tracker
// and the finder builds one track per half-turn: the incoming half-turn is
// found as an outgoing track of opposite charge on the same circle, the
// next outgoing one as a copy of the first. They cross the same layers as
// the first half-turn far from its hits, so they are never merged; instead
// (Config::dropTurns) a track is dropped as a further turn of a better
// track (betterCandidate: more hits first) whose diameter is below the
// outermost layer radius (Config::maxLoopDiameter: only such a particle
// turns back inside the tracker; CLICdet pT < 0.9 GeV) if
//   * its circle (a free fit to its hits: the conformal one assumes a
//     circle through the origin, which a further turn no longer is) lies
//     within Config::maxTurnCentreDistance of the better track's free
//     circle. Either circle leaves out an end hit lying further than
//     Config::maxTurnDistance from the circle of the track's other hits
//     (TurnCircle: another particle's hit that an extension took), the
//     tests below skip it, and a better track that drops a turn loses it;
//   * its hits lie within Config::maxDz of the z of that track's helix
//     some whole number of turns k on (|k| <= kMaxTurns; k = 0 for the
//     sense-reversed incoming half-turn, never for a track beside the
//     better one's hits on their layers), the distance divided by
//     1 + path / scale (scale: Config::turnDzPathScale times p / 1 GeV
//     below 1 GeV);
//   * their distance from that track's circle varies along them by at
//     most Config::maxTurnDistance and its mean, divided as the z one, is
//     at most that (energy loss shrinks a looper's circle turn by turn);
//   * its turn score (the squared differences in tanLambda, centre, z
//     and distance, each over its scale) is at most
//     Config::maxTurnScore;
//   * and, crossed in the opposite sense, it does not lie on the other
//     side in z of where a better track that starts at the beam line
//     begins (the mirror test: two particles of one vertex on the same
//     circle continued through the beam line).
// Its hits are left alone rather than becoming a second track of the
// particle. The score keeps the tracks of other particles on nearby
// circles (they differ in tanLambda), which the position gates alone
// dropped for central loopers. Helix-step tracks take part in this rule
// (their circle is the free real-space one, their z line a straight s-z
// fit) but not in the merging, whose refit is the conformal one.

#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"
#include "conftrack/reconstruction/finding/detail/UnusedHits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace conftrack::detail {

namespace {

/// Turns searched on either side of a track for its looper's further
/// half-turns.
constexpr int kMaxTurns = 3;

/// Largest distance from the beam line of the circle of a first
/// half-turn that starts there [mm] (isFurtherTurn, the mirror test).
constexpr double kPromptDistance = 5.0;

/// Smallest |tanLambda| of a first half-turn for the mirror test: a
/// central looper's z moves by less than a millimetre or two per
/// centimetre of path, and the better track of two of its turns can be
/// the later one, whose start at the beam line is not where the particle
/// began (CLICdet tt-bar + 30 BX, 10 events: without this bound the test
/// refused 8 true turns of central loopers, with 0.1 none of them).
constexpr double kMirrorMinTanLambda = 0.1;

/// Fewest hits of a track whose circle may leave one out (TurnCircle):
/// four remain for a free fit.
constexpr std::size_t kMinHitsForOutlier = 5;

}  // namespace

TrackMerger::TurnCircle TrackMerger::turnCircle(const TrackCandidate& c) const {
  TurnCircle out;
  if (c.helix || c.hits.size() < 4 || !fitCircle(m_hits, c.hits, out.circle)) {
    out.circle.cx = c.uv.centreX;
    out.circle.cy = c.uv.centreY;
    out.circle.rho = c.uv.radius;
    out.circle.orientation = c.uv.orientation;
    return out;
  }
  if (c.hits.size() < kMinHitsForOutlier) {
    return out;
  }
  // One hit of another particle, taken by an extension past where the
  // track's own hits end (a vertex-barrel pass of a central looper
  // extended to a hit in the outer tracker), bends a free circle of a few
  // hits by hundreds of millimetres: then the track's further turns are
  // not recognised. Such a hit is at an end of the track, where its lever
  // arm pulls the circle through it (its residual is no larger than the
  // others'). Each end hit is tried: it is an outlier if it lies further
  // than maxTurnDistance (what a turn's hits may stray) from the circle of
  // the others; the one further off is left out.
  const auto distance = [&](const TransverseCircle& circle, ConfIndex h) {
    return std::abs(norm2(m_hits.x[h] - circle.cx, m_hits.y[h] - circle.cy) -
                    circle.rho);
  };
  const std::span<const ConfIndex> hits(c.hits);
  double worstDistance = m_config.maxTurnDistance;
  for (const bool front : {true, false}) {
    const ConfIndex end = front ? hits.front() : hits.back();
    TransverseCircle withoutEnd;
    if (fitCircle(m_hits, hits.subspan(front ? 1 : 0, hits.size() - 1),
                  withoutEnd) &&
        distance(withoutEnd, end) > worstDistance) {
      worstDistance = distance(withoutEnd, end);
      out.circle = withoutEnd;
      out.skipsFront = front;
      out.skipsBack = !front;
    }
  }
  return out;
}

std::optional<double> TrackMerger::furtherTurnScore(
    const TrackCandidate& first, const TurnCircle& firstFit,
    const TrackCandidate& turn, const TurnCircle& turnFit) const {
  const TransverseCircle& firstCircle = firstFit.circle;
  const TransverseCircle& turnCircle = turnFit.circle;
  const std::span<const ConfIndex> turnHits = turnFit.hitsOf(turn);
  // (dropTurns passes only firsts whose circle can loop: maxLoopDiameter.)
  // Both half-turns are compared by their free circles: the first one's
  // conformal fit is a circle through the origin, which the half-turn of
  // a particle produced off the beam line (a conversion, a decay) is not,
  // and then its further turn lies off it by tens of millimetres. The z
  // test below keeps the first one's conformal arc frame, in which its s-z
  // line was fitted.
  const double radius = firstCircle.rho;
  const double centreDistance =
      norm2(firstCircle.cx - turnCircle.cx, firstCircle.cy - turnCircle.cy);
  if (centreDistance > m_config.maxTurnCentreDistance ||
      std::abs(radius - turnCircle.rho) > m_config.maxTurnCentreDistance) {
    return std::nullopt;
  }
  // A turn crossed in the opposite sense (the incoming half-turn, found
  // as an outgoing track of opposite charge) runs backwards in z. The
  // sense is that in which each track's hits run round its free circle,
  // in the order they were found, along which its s-z line measures
  // tanLambda: a short piece of a turn whose circle passes a few
  // millimetres from the beam line can have its conformal circle, forced
  // through the origin, on the other side of its hits, with the opposite
  // orientation (CLICdet tt-bar + 30 BX: 78 of 16,319 pairs examined in
  // 20 events, four-hit vertex-barrel pieces of central loopers).
  const double sense =
      firstCircle.orientation == turnCircle.orientation ? 1.0 : -1.0;
  const double dTanLambda = turn.sz.tanLambda - sense * first.sz.tanLambda;
  // Energy loss shrinks the circle from turn to turn: a further turn's
  // few hits lie at a nearly constant distance from the first half-turn's
  // circle, which grows with the path. The spread of that distance is
  // tested as it is (first: it needs no arc lengths), its mean below with
  // the path's allowance (a track of another particle crosses the circle:
  // its distance varies along it).
  double sumOff = 0.0;
  double minOff = std::numeric_limits<double>::infinity();
  double maxOff = -minOff;
  for (ConfIndex h : turnHits) {
    const double d =
        norm2(m_hits.x[h] - firstCircle.cx, m_hits.y[h] - firstCircle.cy) -
        radius;
    sumOff += d;
    minOff = std::min(minOff, d);
    maxOff = std::max(maxOff, d);
  }
  const double meanOff = sumOff / static_cast<double>(turnHits.size());
  const double spread = std::max(maxOff - meanOff, meanOff - minOff);
  if (!(spread <= m_config.maxTurnDistance)) {
    return std::nullopt;
  }
  const ArcFrame arc = makeArcFrame(first.uv, m_hits, first.hits.front());
  const double period = 2.0 * std::numbers::pi * arc.radius;
  std::vector<double> s;
  s.reserve(turnHits.size());
  for (ConfIndex h : turnHits) {
    // Continued from the previous hit: a turn that crosses the far side
    // of the circle (the first hit's azimuth + pi) would otherwise jump
    // by a period between its hits and match no single turn number.
    s.push_back(arc.hitArcLength(m_hits, h, s.empty() ? 0.0 : s.back()));
  }
  // Distances from the first half-turn's helix are divided by
  // 1 + path / pathScale, path being the arc length from its last hit:
  // scattering and energy loss move a further turn off that helix in
  // proportion to 1 / p, so the scale (Config::turnDzPathScale) shrinks in
  // proportion to p below 1 GeV. (CLICdet tt-bar + 30 BX, 100 events: the
  // duplicate rate 3.29 -> 3.04 % for the z test alone, no particle lost.)
  const double momentum =
      circlePt(firstCircle, m_state.bzForPt) * norm2(1.0, first.sz.tanLambda);
  const double pathScale =
      m_config.turnDzPathScale * std::min(1.0, momentum / units::GeV);
  // Crossed in the same sense with k = 0, the track would be a piece of
  // the first half-turn itself, and such a piece lies before or after the
  // first one's hits along the arc, never beside them on the same layers.
  // A track with at least half its hits beside them is another particle
  // running alongside (the same circle and z within the gates over a few
  // layers: a 1.7 GeV piece beside a 0.3 GeV looper in the vertex detector)
  // or the next outgoing turn: k = 0 is not tried for it. (At least half:
  // one hit of another particle in either track puts a hit beside.)
  std::size_t nBeside = 0;
  if (sense > 0.0) {
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!(s[i] > 0.0 && s[i] < first.sz.lastS)) {
        continue;
      }
      for (ConfIndex f : first.hits) {
        if (f != turnHits[i] && m_hits.layer[f] == m_hits.layer[turnHits[i]]) {
          ++nBeside;
          break;
        }
      }
    }
  }
  const bool besideFirst = 2 * nBeside >= s.size();
  // A first half-turn that starts at the beam line (its free circle
  // passes within kPromptDistance of it) has every later hit of its
  // particle on its own side in z of that start: z advances one way along
  // a helix. A track on the other side is another particle from the same
  // vertex on the mirror image of its helix (a two-body decay's opposite
  // charges, back to back: the same circle continued through the beam
  // line), which the sense-reversed test would otherwise take for the
  // incoming half-turn.
  if (sense < 0.0 && std::abs(first.sz.tanLambda) >= kMirrorMinTanLambda &&
      std::abs(norm2(firstCircle.cx, firstCircle.cy) - firstCircle.rho) <
          kPromptDistance) {
    const double zStart =
        first.sz.z0 + first.sz.tanLambda * arc.arcLength(0.0, 0.0, 0.0);
    const double side = first.sz.tanLambda >= 0.0 ? 1.0 : -1.0;
    double meanSide = 0.0;
    for (ConfIndex h : turnHits) {
      meanSide += side * (m_hits.z[h] - zStart);
    }
    meanSide /= static_cast<double>(turnHits.size());
    if (meanSide < -m_config.maxDz) {
      return std::nullopt;
    }
  }
  // The z test takes the best whole number of turns k; the transverse
  // one below the shortest path among those that pass it (a central
  // looper's z fits every k alike).
  double bestDz = std::numeric_limits<double>::infinity();
  double meanPath = std::numeric_limits<double>::infinity();
  for (int k = -kMaxTurns; k <= kMaxTurns; ++k) {
    if (k == 0 && besideFirst) {
      continue;
    }
    double worst = 0.0;
    double pathSum = 0.0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double z = first.sz.z0 + first.sz.tanLambda * (s[i] + k * period);
      const double path = std::abs(s[i] + k * period - first.sz.lastS);
      worst = std::max(worst, std::abs(m_hits.z[turnHits[i]] - z) /
                                  (1.0 + path / pathScale));
      pathSum += path;
    }
    bestDz = std::min(bestDz, worst);
    if (worst <= m_config.maxDz) {
      meanPath = std::min(meanPath, pathSum / static_cast<double>(s.size()));
    }
  }
  if (!(bestDz <= m_config.maxDz)) {
    return std::nullopt;
  }
  const double meanDistance = std::abs(meanOff) / (1.0 + meanPath / pathScale);
  if (!(meanDistance <= m_config.maxTurnDistance)) {
    return std::nullopt;
  }
  const double distance = std::max(spread, meanDistance);
  const double score = square(dTanLambda / m_config.turnScaleTanLambda) +
                       square(centreDistance / m_config.turnScaleCentre) +
                       square(bestDz / m_config.turnScaleDz) +
                       square(distance / m_config.turnScaleDistance);
  if (!(score <= m_config.maxTurnScore)) {
    return std::nullopt;
  }
  return score;
}

void TrackMerger::refitTo(TrackCandidate& c,
                          std::span<const ConfIndex> hits) const {
  const ConformalFitResult uv = fitConformal(m_hits, hits, c.uv.quadratic);
  if (!uv.valid) {
    return;
  }
  const SzFitResult sz =
      fitSz(m_hits, hits, makeArcFrame(uv, m_hits, hits.front()));
  if (!sz.valid) {
    return;
  }
  // `hits` may view c.hits itself: copied before it is replaced.
  c.hits = std::vector<ConfIndex>(hits.begin(), hits.end());
  c.uv = uv;
  c.sz = sz;
  c.pt = uv.pt(m_state.bzForPt);
}

std::uint32_t TrackMerger::dropTurns() {
  std::vector<TrackCandidate>& tracks = m_state.tracks;
  std::vector<std::uint32_t> order;
  for (std::uint32_t t = 0; t < tracks.size(); ++t) {
    const TrackCandidate& c = tracks[t];
    if (c.alive && c.hits.size() >= 3 && c.uv.valid && c.sz.valid &&
        c.uv.radius > 0.0) {
      order.push_back(t);
    }
  }
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return betterCandidate(tracks[a], tracks[b]);
  });
  // Rank in that order, and the tracks sorted by circle-centre x: a turn's
  // centre lies within maxTurnCentreDistance of the first half-turn's.
  std::vector<std::uint32_t> rank(tracks.size(), 0);
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    rank[order[i]] = i;
  }
  // Each track's circle, as a first half-turn and as a further turn: a
  // free least-squares circle through its hits. The conformal fit assumes
  // a circle through the origin, which a turn that energy loss and
  // scattering have moved is not, nor the half-turn of a particle produced
  // off the beam line: its conformal centre lies tens of millimetres off
  // (helix-step tracks have a free circle already; three-hit ones keep
  // theirs).
  std::vector<TurnCircle> circles(tracks.size());
  for (std::uint32_t t : order) {
    circles[t] = turnCircle(tracks[t]);
  }
  std::vector<std::pair<double, std::uint32_t>> byX;
  byX.reserve(order.size());
  for (std::uint32_t t : order) {
    byX.emplace_back(circles[t].circle.cx, t);
  }
  std::sort(byX.begin(), byX.end());
  std::vector<std::pair<std::uint32_t, double>> turns;  // (track, score)
  std::uint32_t dropped = 0;
  for (std::uint32_t t : order) {
    const TrackCandidate& first = tracks[t];
    if (!first.alive ||
        !(2.0 * circles[t].circle.rho <= m_config.maxLoopDiameter)) {
      continue;
    }
    turns.clear();
    const double centreX = circles[t].circle.cx;
    auto it = std::lower_bound(
        byX.begin(), byX.end(),
        std::make_pair(centreX - m_config.maxTurnCentreDistance, 0u));
    for (; it != byX.end() &&
           it->first <= centreX + m_config.maxTurnCentreDistance;
         ++it) {
      const std::uint32_t u = it->second;
      if (rank[u] <= rank[t] || !tracks[u].alive) {
        continue;
      }
      if (const std::optional<double> score =
              furtherTurnScore(first, circles[t], tracks[u], circles[u])) {
        turns.emplace_back(u, *score);
      }
    }
    // The first half-turn's end hit that its circle left out lies off the
    // circle that its further turns were found on: it is another
    // particle's (CLICdet tt-bar + 30 BX: kept, that hit made the Kalman
    // fit of the first half-turn fail, and then neither track was left).
    if (!turns.empty() && (circles[t].skipsFront || circles[t].skipsBack)) {
      refitTo(tracks[t], circles[t].hitsOf(first));
    }
    // A well-matched turn is the same particle nearly always, and its
    // hits join the first half-turn's track; a looser one may be another
    // particle on a nearby circle, whose hits would make the track impure.
    for (const auto& [u, score] : turns) {
      tracks[u].alive = false;
      if (score <= m_config.maxJoinScore) {
        // Not the end hit that the turn's circle left out: another
        // particle's, which an extension took.
        // Nor a hit the two half-turns share (near the apex the turn's
        // track may end on the first half-turn's hit): it is on the
        // track already.
        const std::span<const ConfIndex> hits = circles[u].hitsOf(tracks[u]);
        std::vector<ConfIndex>& joined = tracks[t].turnHits;
        for (const ConfIndex h : hits) {
          if (std::find(first.hits.begin(), first.hits.end(), h) ==
                  first.hits.end() &&
              std::find(joined.begin(), joined.end(), h) == joined.end()) {
            joined.push_back(h);
          }
        }
      }
      ++dropped;
    }
  }
  // One index of the unused hits for both searches: each checks
  // FinderState::used for the hits the one before took.
  if (m_config.maxTurnHitScore > 0.0 || m_config.maxFollowScore > 0.0) {
    const UnusedHits unused(m_hits, m_state.used);
    if (m_config.maxTurnHitScore > 0.0) {
      collectTurnHits(order, circles, unused);
    }
    if (m_config.maxFollowScore > 0.0) {
      followTurns(order, circles, unused);
    }
  }
  return dropped;
}

}  // namespace conftrack::detail

// Track merging (issue 15, item 4: no split tracks).
//
// The finder can leave one particle in several tracks: an extension that
// stopped at a gap (a missed layer, a barrel-endcap transition), after
// which a later build step seeds a second piece from the particle's
// leftover hits. Each piece holds less than half of the particle's hits, so
// it counts both as a duplicate and, for the ACTS-style double matching, as
// a fake.
//
// After the final hole filling, pairs of live tracks are tested:
//   * same orientation (charge), circle centres within Config::maxDeltaPhi
//     in azimuth (seen from the origin: for a track through the beam line
//     the centre lies at its initial direction -+ pi/2, measured well even
//     by a short piece), so that the pair search is a sweep over tracks
//     sorted by that azimuth;
//   * every hit of the piece that reaches less far out within
//     Config::maxDistance (transverse) and Config::maxDz (along z) of the
//     other piece's circle and s-z line;
//   * no conflicting hits: two hits on one sensor, or two hits on one layer
//     further apart than an overlap of neighbouring sensors
//     (Config::maxSameLayerDistance). A looper's further half-turn crosses
//     the layers of its first one far away from it, so it is never merged
//     (it is also not a helix through its first half-turn's hits);
//   * the merged fits' (uv and s-z) chi2/ndf are at most
//     Config::maxChi2Ratio times the pieces' own (at least 1): two nearby
//     particles' pieces fit each other far worse than each fits itself
//     (on CLICdet tt-bar + 30 BX the ratio is about 1 for the pieces of
//     one particle and about 1000 for two particles). The chi2 cut of the
//     pieces' steps is not applied: it holds when a step builds a track,
//     not after the extension, and the pieces of a low-momentum particle,
//     extended through its multiple scattering, exceed it themselves
//     (required, it rejected 98 % of the pairs of one particle that
//     reached it; without it the duplicate rate went from 5.42 to
//     5.36 %).
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
//     circle;
//   * its hits lie within Config::maxDz of the z of that track's helix
//     some whole number of turns k on (|k| <= kMaxTurns; k = 0 for the
//     sense-reversed incoming half-turn, never for a track beside the
//     better one's hits on their layers), the distance divided by
//     1 + path / scale (scale: Config::turnDzPathScale times p / 1 GeV
//     below 1 GeV);
//   * their distance from that track's circle varies along them by at
//     most Config::maxTurnDistance and its mean, divided as the z one, is
//     at most that (energy loss shrinks a looper's circle turn by turn);
//   * and its turn score (the squared differences in tanLambda, centre, z
//     and distance, each over its scale) is at most
//     Config::maxTurnScore.
// Its hits are left alone rather than becoming a
// second track of the particle. The score keeps the tracks of other
// particles on nearby circles (they differ in tanLambda), which the
// position gates alone dropped for central loopers. Helix-step tracks take part
// in this rule (their circle is the free real-space one, their z line a
// straight s-z fit) but not in the merging, whose refit is the conformal one.
//
// Compatible pairs are merged best merged fit first (total order: quality,
// then track indices), each track at most once per round; rounds repeat
// until nothing merges, so that three pieces become one. The result does
// not depend on the thread count or the input hit order (tracks and hits
// are in the finder's deterministic order).

#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace conftrack::detail {

namespace {

/// Turns searched on either side of a track for its looper's further
/// half-turns.
constexpr int kMaxTurns = 3;

bool positiveFinite(double x) { return x > 0.0 && std::isfinite(x); }

/// Largest transverse radius of a track's hits.
double reach(const ConformalHits& hits, const TrackCandidate& t) {
  double r = 0.0;
  for (ConfIndex h : t.hits) {
    r = std::max(r, hits.radius[h]);
  }
  return r;
}

}  // namespace

TrackMerger::TrackMerger(FinderState& state, Config config)
    : m_state(state), m_hits(state.hits), m_config(config) {
  if (!positiveFinite(m_config.maxDeltaPhi) ||
      m_config.maxDeltaPhi >= std::numbers::pi) {
    throw std::invalid_argument("TrackMerger: maxDeltaPhi must be in (0, pi)");
  }
  if (!positiveFinite(m_config.maxDistance)) {
    throw std::invalid_argument(
        "TrackMerger: maxDistance must be positive and finite");
  }
  if (!positiveFinite(m_config.maxDz)) {
    throw std::invalid_argument(
        "TrackMerger: maxDz must be positive and finite");
  }
  if (!positiveFinite(m_config.maxSameLayerDistance)) {
    throw std::invalid_argument(
        "TrackMerger: maxSameLayerDistance must be positive and finite");
  }
  if (!positiveFinite(m_config.maxChi2Ratio) || m_config.maxChi2Ratio < 1.0) {
    throw std::invalid_argument(
        "TrackMerger: maxChi2Ratio must be finite and at least 1");
  }
  if (!positiveFinite(m_config.maxTurnDistance)) {
    throw std::invalid_argument(
        "TrackMerger: maxTurnDistance must be positive and finite");
  }
  if (!positiveFinite(m_config.maxTurnCentreDistance) ||
      !positiveFinite(m_config.turnScaleTanLambda) ||
      !positiveFinite(m_config.turnScaleCentre) ||
      !positiveFinite(m_config.turnScaleDz) ||
      !positiveFinite(m_config.turnScaleDistance) ||
      !positiveFinite(m_config.turnDzPathScale) ||
      !positiveFinite(m_config.maxTurnScore)) {
    throw std::invalid_argument(
        "TrackMerger: the turn gates, scales and maxTurnScore must be "
        "positive and finite");
  }
  if (!positiveFinite(m_config.maxLoopDiameter)) {
    throw std::invalid_argument(
        "TrackMerger: maxLoopDiameter must be positive and finite");
  }
  if (m_config.maxRounds < 1) {
    throw std::invalid_argument("TrackMerger: maxRounds must be at least 1");
  }
}

bool TrackMerger::conflict(const TrackCandidate& a,
                           const TrackCandidate& b) const {
  const double maxD2 =
      m_config.maxSameLayerDistance * m_config.maxSameLayerDistance;
  for (ConfIndex ha : a.hits) {
    for (ConfIndex hb : b.hits) {
      if (ha == hb || m_hits.layer[ha] != m_hits.layer[hb]) {
        continue;
      }
      if (m_hits.module[ha] == m_hits.module[hb]) {
        return true;
      }
      const double dx = m_hits.x[ha] - m_hits.x[hb];
      const double dy = m_hits.y[ha] - m_hits.y[hb];
      if (dx * dx + dy * dy > maxD2) {
        return true;
      }
    }
  }
  return false;
}

bool TrackMerger::isFurtherTurn(const TrackCandidate& first,
                                const TransverseCircle& firstCircle,
                                const TrackCandidate& turn,
                                const TransverseCircle& turnCircle) const {
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
    return false;
  }
  // A turn crossed in the opposite sense (the incoming half-turn, found
  // as an outgoing track of opposite charge) runs backwards in z.
  const double sense = first.uv.orientation == turn.uv.orientation ? 1.0 : -1.0;
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
  for (ConfIndex h : turn.hits) {
    const double d =
        norm2(m_hits.x[h] - firstCircle.cx, m_hits.y[h] - firstCircle.cy) -
        radius;
    sumOff += d;
    minOff = std::min(minOff, d);
    maxOff = std::max(maxOff, d);
  }
  const double meanOff = sumOff / static_cast<double>(turn.hits.size());
  const double spread = std::max(maxOff - meanOff, meanOff - minOff);
  if (!(spread <= m_config.maxTurnDistance)) {
    return false;
  }
  const ArcFrame arc = makeArcFrame(first.uv, m_hits, first.hits.front());
  const double period = 2.0 * std::numbers::pi * arc.radius;
  std::vector<double> s;
  s.reserve(turn.hits.size());
  for (ConfIndex h : turn.hits) {
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
        if (f != turn.hits[i] &&
            m_hits.layer[f] == m_hits.layer[turn.hits[i]]) {
          ++nBeside;
          break;
        }
      }
    }
  }
  const bool besideFirst = 2 * nBeside >= s.size();
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
      worst = std::max(worst, std::abs(m_hits.z[turn.hits[i]] - z) /
                                  (1.0 + path / pathScale));
      pathSum += path;
    }
    bestDz = std::min(bestDz, worst);
    if (worst <= m_config.maxDz) {
      meanPath = std::min(meanPath, pathSum / static_cast<double>(s.size()));
    }
  }
  if (!(bestDz <= m_config.maxDz)) {
    return false;
  }
  const double meanDistance = std::abs(meanOff) / (1.0 + meanPath / pathScale);
  if (!(meanDistance <= m_config.maxTurnDistance)) {
    return false;
  }
  const double distance = std::max(spread, meanDistance);
  const auto square = [](double x) { return x * x; };
  const double score = square(dTanLambda / m_config.turnScaleTanLambda) +
                       square(centreDistance / m_config.turnScaleCentre) +
                       square(bestDz / m_config.turnScaleDz) +
                       square(distance / m_config.turnScaleDistance);
  return score <= m_config.maxTurnScore;
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
  std::vector<TransverseCircle> circles(tracks.size());
  for (std::uint32_t t : order) {
    const TrackCandidate& c = tracks[t];
    if (c.helix || c.hits.size() < 4 ||
        !fitCircle(m_hits, c.hits, circles[t])) {
      circles[t].cx = c.uv.centreX;
      circles[t].cy = c.uv.centreY;
      circles[t].rho = c.uv.radius;
    }
  }
  std::vector<std::pair<double, std::uint32_t>> byX;
  byX.reserve(order.size());
  for (std::uint32_t t : order) {
    byX.emplace_back(circles[t].cx, t);
  }
  std::sort(byX.begin(), byX.end());
  std::vector<std::uint32_t> turns;
  std::uint32_t dropped = 0;
  for (std::uint32_t t : order) {
    const TrackCandidate& first = tracks[t];
    if (!first.alive || !(2.0 * circles[t].rho <= m_config.maxLoopDiameter)) {
      continue;
    }
    turns.clear();
    const double centreX = circles[t].cx;
    auto it = std::lower_bound(
        byX.begin(), byX.end(),
        std::make_pair(centreX - m_config.maxTurnCentreDistance, 0u));
    for (; it != byX.end() &&
           it->first <= centreX + m_config.maxTurnCentreDistance;
         ++it) {
      const std::uint32_t u = it->second;
      if (rank[u] > rank[t] && tracks[u].alive &&
          isFurtherTurn(first, circles[t], tracks[u], circles[u])) {
        turns.push_back(u);
      }
    }
    for (std::uint32_t u : turns) {
      tracks[u].alive = false;
      ++dropped;
    }
  }
  return dropped;
}

bool TrackMerger::tryMerge(std::uint32_t ia, std::uint32_t ib,
                           TrackCandidate& out) const {
  const TrackCandidate& a = m_state.tracks[ia];
  const TrackCandidate& b = m_state.tracks[ib];
  if (a.uv.orientation != b.uv.orientation) {
    return false;
  }
  // The piece reaching further out has the better-measured circle.
  const bool aRef = m_reach[ia] >= m_reach[ib];
  const TrackCandidate& ref = aRef ? a : b;
  const TrackCandidate& other = aRef ? b : a;
  const ArcFrame arc = makeArcFrame(ref.uv, m_hits, ref.hits.front());
  // The transverse test first: it rejects most pairs and needs no atan2.
  for (ConfIndex h : other.hits) {
    const double d =
        norm2(m_hits.x[h] - arc.centreX, m_hits.y[h] - arc.centreY) -
        arc.radius;
    if (!(std::abs(d) <= m_config.maxDistance)) {
      return false;
    }
  }
  for (ConfIndex h : other.hits) {
    const double s = arc.hitArcLength(m_hits, h, 0.0);
    const double dz = m_hits.z[h] - (ref.sz.z0 + ref.sz.tanLambda * s);
    if (!(std::abs(dz) <= m_config.maxDz)) {
      return false;
    }
  }
  if (conflict(a, b)) {
    return false;
  }

  // The union along the reference circle (within half a turn of its first
  // hit: a looper's further turn was rejected above).
  std::vector<std::pair<double, ConfIndex>> ordered;
  ordered.reserve(a.hits.size() + b.hits.size());
  for (const TrackCandidate* t : {&a, &b}) {
    for (ConfIndex h : t->hits) {
      ordered.emplace_back(arc.hitArcLength(m_hits, h, 0.0), h);
    }
  }
  std::sort(ordered.begin(), ordered.end());
  ordered.erase(std::unique(ordered.begin(), ordered.end(),
                            [](const auto& x, const auto& y) {
                              return x.second == y.second;
                            }),
                ordered.end());
  std::vector<ConfIndex> hits;
  hits.reserve(ordered.size());
  for (const auto& [s, h] : ordered) {
    hits.push_back(h);
  }

  const bool quadratic = a.uv.quadratic || b.uv.quadratic;
  ConformalFitResult uv = fitConformal(m_hits, hits, quadratic);
  if (!uv.valid) {
    return false;
  }
  const double pt = uv.pt(m_state.bzForPt);
  const double uvBound = m_config.maxChi2Ratio *
                         std::max({1.0, a.uv.chi2PerNdf(), b.uv.chi2PerNdf()});
  if (!(uv.chi2PerNdf() <= uvBound) && !(uv.chi2PerNdf() <= 1.0)) {
    return false;
  }
  SzFitResult sz = fitSz(m_hits, hits, makeArcFrame(uv, m_hits, hits.front()));
  const double szBound = m_config.maxChi2Ratio *
                         std::max({1.0, a.sz.chi2PerNdf(), b.sz.chi2PerNdf()});
  if (!sz.valid ||
      (!(sz.chi2PerNdf() <= szBound) && !(sz.chi2PerNdf() <= 1.0))) {
    return false;
  }
  const TrackCandidate& longer = a.hits.size() >= b.hits.size() ? a : b;
  out = TrackCandidate{};
  out.hits = std::move(hits);
  out.uv = uv;
  out.sz = sz;
  out.pt = pt;
  out.step = std::min(a.step, b.step);
  out.fitBackward = longer.fitBackward;
  out.helix = false;
  out.alive = true;
  return true;
}

std::uint32_t TrackMerger::run() {
  std::vector<TrackCandidate>& tracks = m_state.tracks;
  std::uint32_t merges = 0;
  std::vector<std::pair<double, std::uint32_t>> byPhi;
  std::vector<Merge> found;
  std::vector<std::uint8_t> taken;
  for (std::uint32_t round = 0; round < m_config.maxRounds; ++round) {
    m_reach.assign(tracks.size(), 0.0);
    for (std::uint32_t t = 0; t < tracks.size(); ++t) {
      m_reach[t] = reach(m_hits, tracks[t]);
    }
    byPhi.clear();
    for (std::uint32_t t = 0; t < tracks.size(); ++t) {
      const TrackCandidate& c = tracks[t];
      if (c.alive && !c.helix && c.hits.size() >= 3 && c.uv.valid &&
          c.sz.valid && c.uv.radius > 0.0) {
        byPhi.emplace_back(std::atan2(c.uv.centreY, c.uv.centreX), t);
      }
    }
    std::sort(byPhi.begin(), byPhi.end());
    found.clear();
    const std::size_t n = byPhi.size();
    for (std::size_t i = 0; i < n; ++i) {
      // Forward sweep with wrap-around: each pair once.
      for (std::size_t k = 1; k < n; ++k) {
        const std::size_t j = (i + k) % n;
        double dphi = byPhi[j].first - byPhi[i].first;
        if (j < i) {
          dphi += 2.0 * std::numbers::pi;
        }
        if (!(dphi <= m_config.maxDeltaPhi)) {
          break;
        }
        const std::uint32_t a = std::min(byPhi[i].second, byPhi[j].second);
        const std::uint32_t b = std::max(byPhi[i].second, byPhi[j].second);
        // After the first round only pairs with a track that changed can
        // have become compatible (the others were tested already).
        if (tracks[a].uv.orientation != tracks[b].uv.orientation ||
            (round > 0 && taken[a] == 0 && taken[b] == 0)) {
          continue;
        }
        TrackCandidate merged;
        if (tryMerge(a, b, merged)) {
          const double score = merged.quality();
          found.push_back({score, a, b, std::move(merged)});
        }
      }
    }
    if (found.empty()) {
      break;
    }
    std::sort(found.begin(), found.end(), [](const Merge& x, const Merge& y) {
      return std::tie(x.score, x.a, x.b) < std::tie(y.score, y.a, y.b);
    });
    taken.assign(tracks.size(), 0);
    std::uint32_t merged = 0;
    for (Merge& m : found) {
      if (taken[m.a] != 0 || taken[m.b] != 0) {
        continue;
      }
      taken[m.a] = 1;
      taken[m.b] = 1;
      tracks[m.a] = std::move(m.merged);
      tracks[m.b].alive = false;
      ++merged;
    }
    merges += merged;
  }
  if (m_config.dropTurns) {
    merges += dropTurns();
  }
  return merges;
}

void mergeTracks(FinderState& state, StepStats& stats) {
  TrackMerger::Config config;
  config.maxDeltaPhi = state.config.mergeMaxDeltaPhi;
  config.maxDistance = state.config.mergeMaxDistance;
  config.maxTurnDistance = state.config.mergeMaxDistance;
  config.maxDz = state.config.mergeMaxDz;
  config.maxChi2Ratio = state.config.mergeMaxChi2Ratio;
  config.maxSameLayerDistance = state.config.overlapMaxArc;
  double outer = 0.0;
  for (const SensitiveLayer& layer : state.detector.layers()) {
    outer = std::max(outer, layer.rMax);
  }
  config.maxLoopDiameter = outer;
  TrackMerger merger(state, config);
  stats.mergedTracks += merger.run();
  state.compact();
}

}  // namespace conftrack::detail

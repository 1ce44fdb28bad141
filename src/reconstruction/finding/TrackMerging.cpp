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
//     sorted by that azimuth. The sweep is made twice, once with each
//     track's conformal circle and once with its free circle: a piece of
//     a particle produced tens of millimetres off the beam line fits no
//     circle through the origin, and its vertex-detector piece's conformal
//     centre lies 0.1-0.3 rad from its outer piece's;
//   * every hit of one piece (the one reaching less far out first, then
//     the other) within Config::maxDistance (transverse) and Config::maxDz
//     (along z) of the other piece's circle and s-z line, but for at most
//     Config::maxOutliers hits, which the merged track leaves out: an
//     extension often ends a piece on one hit of another particle, and
//     such a hit can also make a vertex-detector piece the one reaching
//     further out. The arc length of a hit on the other piece's helix is
//     that of the turn its z fits (ArcFrame::helixArcLength): a forward
//     low-momentum piece can run more than half a turn;
//   * no conflicting hits: two hits on one sensor, or two hits on one layer
//     further apart than an overlap of neighbouring sensors
//     (Config::maxSameLayerDistance). A looper's further half-turn crosses
//     the layers of its first one far away from it, so it is never merged
//     (it is also not a helix through its first half-turn's hits);
//   * the merged fits' (uv and s-z) chi2/ndf are at most
//     Config::maxChi2Ratio times the pieces' own (at least 1; the other
//     piece's without its outliers): two nearby particles' pieces fit
//     each other far worse than each fits itself (on CLICdet tt-bar + 30
//     BX the ratio is about 1 for the pieces of one particle and about
//     1000 for two particles); the s-z bound is multiplied by
//     (Config::scatteringMomentum / p)^2 below that momentum, for the
//     scattering between the pieces. If the uv fit fails it and an outlier is
//     left, the other piece's hit with the largest pull is left out and
//     the fit repeated (a neighbouring particle's vertex-detector hit
//     within maxDistance but far outside its errors). The chi2 cut of the
//     pieces' steps is not applied: it holds when a step builds a track,
//     not after the extension, and the pieces of a low-momentum particle,
//     extended through its multiple scattering, exceed it themselves
//     (required, it rejected 98 % of the pairs of one particle that
//     reached it; without it the duplicate rate went from 5.42 to
//     5.36 %).
// Loopers' further half-turns are dropped after the merging rounds
// (Config::dropTurns; TrackMergingTurns.cpp).
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

/// Fewest hits of a piece that a merge keeps after its outliers.
constexpr std::size_t kMinKeptHits = 3;

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
  if (!positiveFinite(m_config.scatteringMomentum)) {
    throw std::invalid_argument(
        "TrackMerger: scatteringMomentum must be positive and finite");
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
  if (!(m_config.maxTurnHitScore >= 0.0 &&
        std::isfinite(m_config.maxTurnHitScore))) {
    throw std::invalid_argument(
        "TrackMerger: maxTurnHitScore must be finite and >= 0");
  }
  if (!(m_config.maxFollowScore >= 0.0 &&
        std::isfinite(m_config.maxFollowScore))) {
    throw std::invalid_argument(
        "TrackMerger: maxFollowScore must be finite and >= 0");
  }
  if (!(m_config.followMaxGapTurns > 0.0 && m_config.followMaxGapTurns < 1.0)) {
    throw std::invalid_argument(
        "TrackMerger: followMaxGapTurns must lie in (0, 1)");
  }
  if (!(m_config.maxJoinScore >= 0.0 &&
        m_config.maxJoinScore <= m_config.maxTurnScore)) {
    throw std::invalid_argument(
        "TrackMerger: maxJoinScore must lie in [0, maxTurnScore]");
  }
  if (!positiveFinite(m_config.maxLoopDiameter)) {
    throw std::invalid_argument(
        "TrackMerger: maxLoopDiameter must be positive and finite");
  }
  if (m_config.maxRounds < 1) {
    throw std::invalid_argument("TrackMerger: maxRounds must be at least 1");
  }
}

bool TrackMerger::conflict(std::span<const ConfIndex> a,
                           std::span<const ConfIndex> b) const {
  const double maxD2 =
      m_config.maxSameLayerDistance * m_config.maxSameLayerDistance;
  for (ConfIndex ha : a) {
    for (ConfIndex hb : b) {
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

bool TrackMerger::tryMerge(std::uint32_t ia, std::uint32_t ib,
                           TrackCandidate& out) const {
  const TrackCandidate& a = m_state.tracks[ia];
  const TrackCandidate& b = m_state.tracks[ib];
  if (a.uv.orientation != b.uv.orientation) {
    return false;
  }
  // The piece reaching further out has the better-measured circle, unless
  // it reaches out only by one hit of another particle (a vertex-detector
  // piece that an extension ended on a far disk): then the other piece's
  // circle is the one to test against.
  const bool aRef = m_reach[ia] >= m_reach[ib];
  const TrackCandidate& further = aRef ? a : b;
  const TrackCandidate& nearer = aRef ? b : a;
  return mergeOnto(further, nearer, out) || mergeOnto(nearer, further, out);
}

bool TrackMerger::mergeOnto(const TrackCandidate& ref,
                            const TrackCandidate& other,
                            TrackCandidate& out) const {
  const ArcFrame arc = makeArcFrame(ref.uv, m_hits, ref.hits.front());
  // Arc lengths on the reference helix: a piece can run more than half a
  // turn from the reference's first hit (a forward low-momentum track from
  // the vertex barrel to a disk), and then its turn is the one its z fits.
  const auto arcLength = [&](ConfIndex h) {
    return arc.helixArcLength(m_hits, h, 0.0, 0.0, ref.sz.z0, ref.sz.tanLambda);
  };
  // Every hit of the other piece within maxDistance of the reference
  // circle and maxDz of its s-z line, but for at most maxOutliers of them,
  // which stay out of the merged track: an extension often ends a piece
  // with one hit of another particle (a far disk's hit that its circle
  // passed), and that hit alone kept the pieces apart.
  // The transverse test first: it rejects most pairs and needs no atan2.
  thread_local std::vector<ConfIndex> outlierHits;
  outlierHits.clear();
  const auto outlier = [&](ConfIndex h) {
    return std::find(outlierHits.begin(), outlierHits.end(), h) !=
           outlierHits.end();
  };
  for (ConfIndex h : other.hits) {
    const double d =
        norm2(m_hits.x[h] - arc.centreX, m_hits.y[h] - arc.centreY) -
        arc.radius;
    if (!(std::abs(d) <= m_config.maxDistance)) {
      if (outlierHits.size() == m_config.maxOutliers) {
        return false;
      }
      outlierHits.push_back(h);
    }
  }
  for (ConfIndex h : other.hits) {
    if (outlier(h)) {
      continue;
    }
    const double s = arcLength(h);
    const double dz = m_hits.z[h] - (ref.sz.z0 + ref.sz.tanLambda * s);
    if (!(std::abs(dz) <= m_config.maxDz)) {
      if (outlierHits.size() == m_config.maxOutliers) {
        return false;
      }
      outlierHits.push_back(h);
    }
  }
  if (other.hits.size() < kMinKeptHits + outlierHits.size()) {
    return false;
  }
  thread_local std::vector<ConfIndex> kept;
  kept.clear();
  for (ConfIndex h : other.hits) {
    if (!outlier(h)) {
      kept.push_back(h);
    }
  }
  if (conflict(ref.hits, kept)) {
    return false;
  }

  // The union along the reference helix (a looper's further turn, on the
  // layers of the first one, was rejected above).
  std::vector<std::pair<double, ConfIndex>> ordered;
  ordered.reserve(ref.hits.size() + kept.size());
  for (const std::vector<ConfIndex>* piece :
       {&ref.hits, static_cast<const std::vector<ConfIndex>*>(&kept)}) {
    for (ConfIndex h : *piece) {
      ordered.emplace_back(arcLength(h), h);
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

  const bool quadratic = ref.uv.quadratic || other.uv.quadratic;
  // The merged fit is held to the pieces' own fits, the other piece's
  // without its outliers (which would otherwise loosen the bound that they
  // were left out for).
  const auto uvBound = [&]() {
    double otherChi2 = other.uv.chi2PerNdf();
    if (!outlierHits.empty()) {
      const ConformalFitResult fit =
          fitConformal(m_hits, kept, other.uv.quadratic);
      otherChi2 = fit.valid ? fit.chi2PerNdf() : 0.0;
    }
    return m_config.maxChi2Ratio *
           std::max({1.0, ref.uv.chi2PerNdf(), otherChi2});
  };
  const auto passes = [](double chi2PerNdf, double bound) {
    return chi2PerNdf <= bound || chi2PerNdf <= 1.0;
  };
  double bound = uvBound();
  ConformalFitResult uv = fitConformal(m_hits, hits, quadratic);
  if (uv.valid && !passes(uv.chi2PerNdf(), bound) &&
      outlierHits.size() < m_config.maxOutliers && kept.size() > kMinKeptHits) {
    // One hit of the other piece off the merged circle by less than
    // maxDistance but far beyond its errors (a neighbouring particle's
    // hit in the vertex detector): its worst-fitting hit is the outlier.
    const ConfIndex kNone = std::numeric_limits<ConfIndex>::max();
    ConfIndex worst = kNone;
    double worstPull = 0.0;
    for (ConfIndex h : kept) {
      if (std::find(ref.hits.begin(), ref.hits.end(), h) != ref.hits.end()) {
        continue;  // a hit of both pieces stays
      }
      double variance = 0.0;
      const double r = uv.residual(m_hits, h, variance);
      if (r * r / variance > worstPull) {
        worstPull = r * r / variance;
        worst = h;
      }
    }
    if (worst != kNone) {
      hits.erase(std::find(hits.begin(), hits.end(), worst));
      kept.erase(std::find(kept.begin(), kept.end(), worst));
      outlierHits.push_back(worst);
      bound = uvBound();
      uv = fitConformal(m_hits, hits, quadratic);
    }
  }
  if (!uv.valid || !passes(uv.chi2PerNdf(), bound)) {
    return false;
  }
  const double pt = uv.pt(m_state.bzForPt);
  SzFitResult sz = fitSz(m_hits, hits, makeArcFrame(uv, m_hits, hits.front()));
  // Scattering between the pieces adds to the merged s-z chi2 (whose
  // errors hold none) in proportion to 1 / p^2.
  const double momentum = pt * norm2(1.0, sz.tanLambda);
  const double scattering =
      momentum > 0.0
          ? std::max(1.0, std::pow(m_config.scatteringMomentum / momentum, 2))
          : 1.0;
  const double szBound =
      scattering * m_config.maxChi2Ratio *
      std::max({1.0, ref.sz.chi2PerNdf(), other.sz.chi2PerNdf()});
  if (!sz.valid || !passes(sz.chi2PerNdf(), szBound)) {
    return false;
  }
  const TrackCandidate& longer =
      ref.hits.size() >= other.hits.size() ? ref : other;
  out = TrackCandidate{};
  out.hits = std::move(hits);
  out.uv = uv;
  out.sz = sz;
  out.pt = pt;
  out.step = std::min(ref.step, other.step);
  out.fitBackward = longer.fitBackward;
  out.helix = false;
  out.alive = true;
  return true;
}

std::uint32_t TrackMerger::run() {
  std::vector<TrackCandidate>& tracks = m_state.tracks;
  std::uint32_t merges = 0;
  std::vector<std::pair<double, std::uint32_t>> byPhi;
  std::vector<double> conformalPhi;
  std::vector<Merge> found;
  std::vector<std::uint8_t> taken;
  for (std::uint32_t round = 0; round < m_config.maxRounds; ++round) {
    m_reach.assign(tracks.size(), 0.0);
    for (std::uint32_t t = 0; t < tracks.size(); ++t) {
      m_reach[t] = reach(m_hits, tracks[t]);
    }
    // Candidate pairs: circle centres within maxDeltaPhi in azimuth, by
    // each track's conformal circle and by its free circle. The conformal
    // one is a circle through the origin; a piece of a particle produced
    // off the beam line (tens of millimetres out) fits it poorly, and its
    // short vertex-detector piece's centre then lies 0.1-0.3 rad from the
    // outer piece's. The free circle of a short piece measures its radius
    // poorly but the azimuth of its centre well.
    const auto eligible = [&](const TrackCandidate& c) {
      return c.alive && !c.helix && c.hits.size() >= 3 && c.uv.valid &&
             c.sz.valid && c.uv.radius > 0.0;
    };
    conformalPhi.assign(tracks.size(), 0.0);
    for (std::uint32_t t = 0; t < tracks.size(); ++t) {
      if (eligible(tracks[t])) {
        conformalPhi[t] =
            std::atan2(tracks[t].uv.centreY, tracks[t].uv.centreX);
      }
    }
    const auto withinDeltaPhi = [&](double x, double y) {
      double d = std::abs(x - y);
      d = std::min(d, 2.0 * std::numbers::pi - d);
      return d <= m_config.maxDeltaPhi;
    };
    found.clear();
    for (int key = 0; key < 2; ++key) {
      byPhi.clear();
      for (std::uint32_t t = 0; t < tracks.size(); ++t) {
        const TrackCandidate& c = tracks[t];
        if (!eligible(c)) {
          continue;
        }
        TransverseCircle freeCircle;
        if (key == 0) {
          byPhi.emplace_back(conformalPhi[t], t);
        } else if (c.hits.size() >= 4 &&
                   fitCircle(m_hits, c.hits, freeCircle)) {
          byPhi.emplace_back(std::atan2(freeCircle.cy, freeCircle.cx), t);
        }
      }
      std::sort(byPhi.begin(), byPhi.end());
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
          // After the first round only pairs with a track that changed
          // can have become compatible (the others were tested already);
          // the free-circle sweep skips the pairs that the conformal one
          // tried.
          if (tracks[a].uv.orientation != tracks[b].uv.orientation ||
              (round > 0 && taken[a] == 0 && taken[b] == 0) ||
              (key == 1 && withinDeltaPhi(conformalPhi[a], conformalPhi[b]))) {
            continue;
          }
          TrackCandidate merged;
          if (tryMerge(a, b, merged)) {
            const double score = merged.quality();
            found.push_back({score, a, b, std::move(merged)});
          }
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
  config.dropTurns = state.config.mergeDropTurns;
  TrackMerger merger(state, config);
  stats.mergedTracks += merger.run();
  state.compact();
}

}  // namespace conftrack::detail

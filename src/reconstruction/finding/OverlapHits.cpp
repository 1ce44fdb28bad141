// Overlap hits (issue 15, item 1).
//
// Real layers are made of flat sensors that overlap in azimuth (and along
// z or R), so a particle crossing an overlap leaves two hits on one layer,
// a few mm apart along its path. The finder's cells and extensions take one
// hit per layer: on the module-level TrackML simulation the hits left off
// found tracks on layers the track already had were 8.5 % of the score
// weight, and the leftover second hits seeded split pieces in later steps.
//
// After each step's building and extension, every live track looks for
// unused hits of the step's pool on each layer where it has a hit, on
// another sensor than its own, within a transverse arc length
// Config::maxArc of its hit there. A candidate is judged by the difference
// between its residuals to the track's fits (uv and sz) and those of the
// track's own hit on that layer: the two crossings are so close that
// scattering between them is negligible, while the deviation of the track
// from its fits (multiple scattering, far larger than the hit errors below a
// few GeV) is common to both and cancels. The best candidate per sensor is
// added when that chi2 (2 degrees of freedom) is below Config::maxChi2, and
// the track is refitted.

#include "conftrack/reconstruction/finding/detail/OverlapHits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

namespace conftrack::detail {

namespace {

/// Margin of the search box around the predicted second crossing [mm]
/// (hit errors of pixels and along the strips' precise coordinate).
constexpr double kSidewaysMargin = 2.0;
/// The box extends this many of the track hit's own errors along the layer
/// (z on barrels, R on disks: TrackML long strips measure them to 3 mm).
constexpr double kAlongSigmas = 5.0;
/// Largest half-width of the azimuth window [rad].
constexpr double kMaxHalfPhi = 0.5;

}  // namespace

OverlapHitCollector::OverlapHitCollector(FinderState& state,
                                         const HitPool& pool, StepStats& stats,
                                         Config config)
    : m_state(state),
      m_hits(state.hits),
      m_pool(pool),
      m_stats(stats),
      m_config(config) {
  if (!(m_config.maxChi2 > 0.0) || !std::isfinite(m_config.maxChi2)) {
    throw std::invalid_argument(
        "OverlapHitCollector: maxChi2 must be positive and finite");
  }
  if (!(m_config.maxGap > 0.0) || !std::isfinite(m_config.maxGap)) {
    throw std::invalid_argument(
        "OverlapHitCollector: maxGap must be positive and finite");
  }
  if (!(m_config.maxArc > 0.0) || !std::isfinite(m_config.maxArc)) {
    throw std::invalid_argument(
        "OverlapHitCollector: maxArc must be positive and finite");
  }
  if (m_config.maxHitsPerLayer < 2) {
    throw std::invalid_argument(
        "OverlapHitCollector: maxHitsPerLayer must be at least 2");
  }
  m_inPool.assign(state.detector.layers().size(), 0);
  for (std::uint32_t layer : pool.layers()) {
    m_inPool[layer] = 1;
  }
}

double overlapScatteringVariance(const ConformalHits& hits, ConfIndex a,
                                 ConfIndex h, double theta0) {
  const double d = std::hypot(hits.x[h] - hits.x[a], hits.y[h] - hits.y[a],
                              hits.z[h] - hits.z[a]);
  return theta0 * theta0 * d * d;
}

void keepBestPerSensor(std::vector<OverlapCandidate>& candidates) {
  std::sort(candidates.begin(), candidates.end(),
            [](const OverlapCandidate& x, const OverlapCandidate& y) {
              return std::tie(x.module, x.chi2, x.hit) <
                     std::tie(y.module, y.chi2, y.hit);
            });
  candidates.erase(
      std::unique(candidates.begin(), candidates.end(),
                  [](const OverlapCandidate& x, const OverlapCandidate& y) {
                    return x.module == y.module;
                  }),
      candidates.end());
  std::sort(candidates.begin(), candidates.end(),
            [](const OverlapCandidate& x, const OverlapCandidate& y) {
              return std::tie(x.chi2, x.hit) < std::tie(y.chi2, y.hit);
            });
}

double OverlapHitCollector::pairChi2(const TrackCandidate& track, ConfIndex a,
                                     double sa, ConfIndex h, double sh,
                                     double theta0) const {
  double va = 0.0;
  double vh = 0.0;
  const double eUv =
      track.uv.residual(m_hits, h, vh) - track.uv.residual(m_hits, a, va);
  double varUv = va + vh;
  double wa = 0.0;
  double wh = 0.0;
  const double eSz =
      track.sz.residual(sh, m_hits.z[h], m_hits.varZ[h], m_hits.varRxy[h], wh) -
      track.sz.residual(sa, m_hits.z[a], m_hits.varZ[a], m_hits.varRxy[a], wa);
  double varSz = wa + wh;
  // Scattering in a's sensor moves h across the track.
  const double tanLambda = track.sz.tanLambda;
  const double scatter = overlapScatteringVariance(m_hits, a, h, theta0);
  const double r2 = std::max(m_hits.radius[a] * m_hits.radius[a], 1.0);
  varUv += scatter / (r2 * r2);  // conformal: a shift d at radius r is d / r^2
  varSz += scatter * (1.0 + tanLambda * tanLambda);
  if (!(varUv > 0.0) || !(varSz > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  return eUv * eUv / varUv + eSz * eSz / varSz;
}

std::uint32_t OverlapHitCollector::collect(std::uint32_t t) {
  TrackCandidate& track = m_state.tracks[t];
  if (!track.alive || track.helix || track.hits.size() < 3) {
    return 0;
  }
  const std::vector<ConfIndex>& hits = track.hits;
  const ArcFrame arc = makeArcFrame(track.uv, m_hits, hits.front());
  // Arc lengths, unwrapped hit by hit from the first, are taken only as
  // far as a candidate needs them: most tracks have none (CLICdet's ideal
  // layers: 5,250 candidates for 58,136 searched layers in two tt̄ + 30 BX
  // events), and each costs an atan2.
  std::vector<double> hitS(hits.size(), 0.0);
  std::size_t arcsKnown = 1;
  auto arcLengthOf = [&](std::size_t k) {
    for (; arcsKnown <= k; ++arcsKnown) {
      hitS[arcsKnown] =
          arc.hitArcLength(m_hits, hits[arcsKnown], hitS[arcsKnown - 1]);
    }
    return hitS[k];
  };
  const double slope = std::abs(track.sz.tanLambda);

  std::vector<std::pair<ConfIndex, double>> added;
  std::vector<OverlapCandidate> candidates;
  auto onTrackSensor = [&](ConfIndex h) {
    for (ConfIndex k : hits) {
      if (m_hits.sameSensor(k, h)) {
        return true;
      }
    }
    for (const auto& [k, s] : added) {
      if (m_hits.sameSensor(k, h)) {
        return true;
      }
    }
    return false;
  };
  auto hitsOnLayer = [&](std::uint32_t layer) {
    std::uint32_t n = 0;
    for (ConfIndex k : hits) {
      n += m_hits.layer[k] == layer ? 1u : 0u;
    }
    for (const auto& [k, s] : added) {
      n += m_hits.layer[k] == layer ? 1u : 0u;
    }
    return n;
  };

  for (std::size_t k = 0; k < hits.size(); ++k) {
    const ConfIndex a = hits[k];
    const std::uint32_t layer = m_hits.layer[a];
    if (m_inPool[layer] == 0 ||
        hitsOnLayer(layer) >= m_config.maxHitsPerLayer) {
      continue;
    }
    // The second crossing lies at most maxGap further along the layer's
    // normal (radial on barrels, z on disks): a transverse arc of maxGap /
    // cos(psi) on a barrel crossed at psi to the radial direction, maxGap /
    // |tanLambda| on a disk.
    const double r = std::max(m_hits.radius[a], 1.0);
    const double dx = m_hits.x[a] - arc.centreX;
    const double dy = m_hits.y[a] - arc.centreY;
    const double dr = std::max(norm2(dx, dy), 1e-9);
    // Tangent of the circle at a, and its cosine to the radial direction.
    const double cosPsi =
        std::abs((m_hits.x[a] * -dy + m_hits.y[a] * dx) / (r * dr));
    const bool disk = m_hits.isEndcap(a);
    const double arcReach =
        disk
            ? std::min(m_config.maxArc, m_config.maxGap / std::max(slope, 1e-3))
            : std::min(m_config.maxArc,
                       m_config.maxGap / std::max(cosPsi, 1e-3));
    const double tanPsi = std::sqrt(std::max(0.0, 1.0 - cosPsi * cosPsi)) /
                          std::max(cosPsi, 1e-3);
    const double sideways =
        disk ? arcReach : std::min(arcReach, m_config.maxGap * tanPsi);
    const double halfPhi =
        std::min(kMaxHalfPhi, (sideways + kSidewaysMargin) / r);
    const double alongZ = slope * arcReach +
                          kAlongSigmas * std::sqrt(m_hits.varZ[a]) +
                          kSidewaysMargin;
    const double alongR =
        arcReach + kAlongSigmas * std::sqrt(m_hits.varRxy[a]) + kSidewaysMargin;
    m_window.clear();
    // The scattering in a's sensor, the same for every candidate (taken at
    // the first one).
    std::optional<double> theta0;
    m_pool.layerBox(layer, m_hits.phi[a], halfPhi, m_hits.z[a] - alongZ,
                    m_hits.z[a] + alongZ, r - alongR, r + alongR, m_window);
    candidates.clear();
    for (ConfIndex h : m_window) {
      if (m_state.used[h] != 0 || m_hits.layer[h] != layer ||
          onTrackSensor(h)) {
        continue;
      }
      const double sa = arcLengthOf(k);
      const double s = arc.hitArcLength(m_hits, h, sa);
      if (!(std::abs(s - sa) <= arcReach + kSidewaysMargin)) {
        continue;
      }
      if (!theta0) {
        theta0 = layerTheta0(m_state.detector.layers()[layer],
                             track.pt * std::hypot(1.0, slope), slope);
      }
      const double chi2 = pairChi2(track, a, sa, h, s, *theta0);
      if (!(chi2 <= m_config.maxChi2)) {
        continue;
      }
      candidates.push_back({m_hits.module[h], chi2, h, s});
    }
    if (candidates.empty()) {
      continue;
    }
    keepBestPerSensor(candidates);
    std::uint32_t room = m_config.maxHitsPerLayer - hitsOnLayer(layer);
    for (const OverlapCandidate& c : candidates) {
      if (room == 0) {
        break;
      }
      added.emplace_back(c.hit, c.s);
      --room;
    }
  }
  if (added.empty()) {
    return 0;
  }

  // Insert along the track and refit with the track's model; a track whose
  // fit fails with them keeps its hits.
  arcLengthOf(hits.size() - 1);
  std::vector<std::pair<double, ConfIndex>> ordered;
  ordered.reserve(hits.size() + added.size());
  for (std::size_t k = 0; k < hits.size(); ++k) {
    ordered.emplace_back(hitS[k], hits[k]);
  }
  for (const auto& [h, s] : added) {
    ordered.emplace_back(s, h);
  }
  std::stable_sort(
      ordered.begin(), ordered.end(),
      [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<ConfIndex> grown;
  grown.reserve(ordered.size());
  for (const auto& [s, h] : ordered) {
    grown.push_back(h);
  }
  ConformalFitResult uv =
      fitConformal(m_hits, grown, track.uv.quadratic, &track.uv);
  if (!uv.valid) {
    return 0;
  }
  const ArcFrame grownArc = makeArcFrame(uv, m_hits, grown.front());
  SzFitResult sz = fitSz(m_hits, grown, grownArc);
  if (!sz.valid) {
    return 0;
  }
  for (const auto& [h, s] : added) {
    m_state.used[h] = 1;
    m_state.clones.addHit(h, t);
  }
  track.hits = std::move(grown);
  track.uv = uv;
  track.sz = sz;
  track.pt = uv.pt(m_state.bzForPt);
  m_stats.overlapHits += added.size();
  return static_cast<std::uint32_t>(added.size());
}

namespace {

/// Arc lengths of `hits` on the circle of `arc`, each unwrapped against
/// the nearest (in 3-D) hit of the reference list (refHits, refS).
void arcLengths(const ConformalHits& ch, const ArcFrame& arc,
                const std::vector<ConfIndex>& refHits,
                const std::vector<double>& refS,
                const std::vector<ConfIndex>& hits, std::vector<double>& out) {
  out.resize(hits.size());
  for (std::size_t k = 0; k < hits.size(); ++k) {
    const ConfIndex h = hits[k];
    double best = std::numeric_limits<double>::infinity();
    double near = 0.0;
    for (std::size_t j = 0; j < refHits.size(); ++j) {
      const ConfIndex r = refHits[j];
      const double dx = ch.x[h] - ch.x[r];
      const double dy = ch.y[h] - ch.y[r];
      const double dz = ch.z[h] - ch.z[r];
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < best) {
        best = d2;
        near = refS[j];
      }
    }
    out[k] = arc.hitArcLength(ch, h, near);
  }
}

}  // namespace

std::uint32_t mergeTracksSharingHits(FinderState& state, StepStats& stats) {
  const ConformalHits& ch = state.hits;
  // Hits held twice pair tracks: each hit's holders in ascending track
  // order, every one with the holder before it (the neighbours of the
  // hit's run in the sorted list of (hit, track) that this replaces; that
  // sort of every hit on a track took 1.3 % of CLICdet's reconstruction,
  // once per step).
  constexpr std::uint32_t kNoHolder = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> lastHolder(ch.size(), kNoHolder);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (state.tracks[t].alive) {
      for (ConfIndex h : state.tracks[t].hits) {
        if (lastHolder[h] != kNoHolder && lastHolder[h] != t) {
          pairs.emplace_back(lastHolder[h], t);
        }
        lastHolder[h] = t;
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());

  std::uint32_t merged = 0;
  std::vector<double> sA;
  std::vector<double> sB;
  for (const auto& [a, b] : pairs) {
    TrackCandidate& ta = state.tracks[a];
    TrackCandidate& tb = state.tracks[b];
    if (!ta.alive || !tb.alive || ta.helix || tb.helix) {
      continue;
    }
    // Both halves along the first track's circle.
    const ArcFrame arc = makeArcFrame(ta.uv, ch, ta.hits.front());
    sA.assign(ta.hits.size(), 0.0);
    for (std::size_t k = 1; k < ta.hits.size(); ++k) {
      sA[k] = arc.hitArcLength(ch, ta.hits[k], sA[k - 1]);
    }
    arcLengths(ch, arc, ta.hits, sA, tb.hits, sB);
    std::vector<std::pair<double, ConfIndex>> ordered;
    ordered.reserve(ta.hits.size() + tb.hits.size());
    for (std::size_t k = 0; k < ta.hits.size(); ++k) {
      ordered.emplace_back(sA[k], ta.hits[k]);
    }
    for (std::size_t k = 0; k < tb.hits.size(); ++k) {
      if (std::find(ta.hits.begin(), ta.hits.end(), tb.hits[k]) ==
          ta.hits.end()) {
        ordered.emplace_back(sB[k], tb.hits[k]);
      }
    }
    std::sort(ordered.begin(), ordered.end());
    std::vector<ConfIndex> hits;
    hits.reserve(ordered.size());
    bool conflict = false;
    for (const auto& [s, h] : ordered) {
      for (ConfIndex k : hits) {
        conflict = conflict || ch.sameSensor(k, h);
      }
      hits.push_back(h);
    }
    if (conflict) {
      continue;
    }
    // The merged track must pass the cuts of the step that built the first.
    TrackCandidate out;
    if (!fitCandidate(state, state.config.steps[ta.step], hits, out)) {
      continue;
    }
    out.step = ta.step;
    out.fitBackward = ta.fitBackward;
    for (ConfIndex h : out.hits) {
      state.used[h] = 1;
    }
    ta = std::move(out);
    tb.alive = false;
    ++merged;
  }
  if (merged > 0) {
    state.compact();
  }
  stats.mergedTracks += merged;
  return merged;
}

std::uint32_t dropUnpairedShortTracks(FinderState& state, std::uint16_t step,
                                      std::uint32_t belowHits) {
  const ConformalHits& hits = state.hits;
  auto paired = [&](const TrackCandidate& t) {
    for (std::size_t i = 1; i < t.hits.size(); ++i) {
      for (std::size_t j = 0; j < i; ++j) {
        if (hits.sameLayer(t.hits[i], t.hits[j])) {
          return true;
        }
      }
    }
    return false;
  };
  std::vector<std::uint32_t> dropped;
  for (std::uint32_t k = 0; k < state.tracks.size(); ++k) {
    TrackCandidate& t = state.tracks[k];
    if (t.alive && t.step == step && t.hits.size() < belowHits && !paired(t)) {
      t.alive = false;
      dropped.push_back(k);
    }
  }
  // Free the hits that no live track holds (candidates of one step may
  // share hits), as for replaced clones.
  for (std::uint32_t k : dropped) {
    for (ConfIndex h : state.tracks[k].hits) {
      if (!state.clones.held(h, state.tracks)) {
        state.used[h] = 0;
      }
    }
  }
  if (!dropped.empty()) {
    state.compact();
  }
  return static_cast<std::uint32_t>(dropped.size());
}

void addOverlapHits(FinderState& state, const HitPool& pool, StepStats& stats) {
  OverlapHitCollector::Config config;
  config.maxChi2 = state.config.overlapMaxChi2;
  config.maxArc = state.config.overlapMaxArc;
  config.maxGap = state.config.overlapMaxGap;
  OverlapHitCollector collector(state, pool, stats, config);
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    collector.collect(t);
  }
  mergeTracksSharingHits(state, stats);
}

}  // namespace conftrack::detail

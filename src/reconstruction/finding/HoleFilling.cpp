// Hole filling (detail/HoleFilling.hpp): unused hits on layers that a
// track crosses between its first and last hit without a hit on the track,
// best chi2 first.

#include "conftrack/reconstruction/finding/detail/HoleFilling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace conftrack::detail {

namespace {

/// Largest chi2_uv + chi2_sz increase of a hit filled into a hole.
constexpr double kMaxHoleChi2 = 30.0;
/// Half-length along the layer (z on barrels, R on disks) of the search box
/// around a hole's predicted crossing [mm]: 16 sigma of the coarsest strip
/// coordinate (TrackML long strips, 3 mm); a hole hit passing kMaxHoleChi2
/// lies within 5.5 sigma.
constexpr double kHoleWindow = 50.0;

}  // namespace

HoleFilling::Config HoleFilling::Config::fromStep(const FindingStep& step,
                                                  const FinderConfig& finder,
                                                  Residuals residuals) {
  Config c;
  c.chi2Cut = step.chi2Cut;
  c.chi2PtScale = step.chi2PtScale;
  c.phiWindow = finder.extensionPhiWindow;
  c.maxWindowHits = finder.maxWindowHits;
  c.scatteringAllowance = finder.scatteringAllowance;
  c.residuals = residuals;
  return c;
}

HoleFilling::HoleFilling(const Config& config) : m_config(config) {
  // NaN fails every comparison, so each check passes only good values.
  if (!(m_config.chi2Cut > 0.0 && std::isfinite(m_config.chi2Cut))) {
    throwBadKey("HoleFilling", "chi2_cut", "must be positive and finite",
                m_config.chi2Cut);
  }
  if (!(m_config.chi2PtScale >= 0.0 && std::isfinite(m_config.chi2PtScale))) {
    throwBadKey("HoleFilling", "chi2_cut_pt_scale_GeV",
                "must be >= 0 and finite", m_config.chi2PtScale);
  }
  if (!(m_config.phiWindow > 0.0 && m_config.phiWindow <= kMaxSearchAngle)) {
    throwBadKey("HoleFilling", "extension_phi_window",
                "must be in (0, 3.14159] rad", m_config.phiWindow);
  }
  if (m_config.maxWindowHits < 1) {
    throwBadKey("HoleFilling", "max_window_hits", "must be at least 1",
                static_cast<double>(m_config.maxWindowHits));
  }
}

void HoleFilling::run(FinderState& state, const HitPool& pool, StepStats& stats,
                      std::uint32_t t) const {
  LayerCrossingSearch search(state, pool, stats, m_config.maxWindowHits,
                             m_work.crossing);
  TrackCandidate& track = state.tracks[t];
  Chain& chain = m_work.chain;
  if (!search.begin(track, chain)) {
    return;
  }
  const ConformalHits& hits = state.hits;
  std::vector<double>& hitS = m_work.hitS;
  bool added = false;
  while (true) {
    // Arc lengths of the hits, unwrapped along the track.
    hitS.assign(chain.hits.size(), 0.0);
    for (std::size_t k = 1; k < chain.hits.size(); ++k) {
      ConfIndex h = chain.hits[k];
      hitS[k] = chain.arc.hitArcLength(hits, h, hitS[k - 1]);
    }
    ConfIndex best = kInvalidIndex;
    double bestS = 0.0;
    findHole(search, chain, false, best, bestS);
    if (best == kInvalidIndex && m_config.scatteringAllowance) {
      findHole(search, chain, true, best, bestS);
    }
    if (best == kInvalidIndex) {
      break;
    }
    auto pos = std::upper_bound(hitS.begin(), hitS.end(), bestS);
    chain.hits.insert(chain.hits.begin() + (pos - hitS.begin()), best);
    claimHit(state, stats, best, t);
    added = true;
    if (!search.refit(chain, &chain.uv)) {
      break;
    }
  }
  if (added) {
    storeChain(state, chain, track);
  }
}

void HoleFilling::findHole(LayerCrossingSearch& search, const Chain& chain,
                           bool allowance, ConfIndex& best,
                           double& bestS) const {
  const FinderState& state = search.state();
  const ConformalHits& hits = search.hits();
  const std::vector<double>& hitS = m_work.hitS;
  const bool local = m_config.residuals == Residuals::eToNeighbours;
  double bestChi2 = std::numeric_limits<double>::infinity();
  // From the first hit (s = 0) outwards, on the branch the track is on.
  const SearchStart from =
      search.start(chain.arc, chain.sz, 0.0, Direction::eOutward);
  for (std::uint32_t layer : search.pool().layers()) {
    bool present = false;
    for (ConfIndex h : chain.hits) {
      present = present || hits.layer[h] == layer;
    }
    if (present) {
      continue;
    }
    const std::vector<Prediction>& predictions =
        search.predict(layer, from, Branches::eOutgoing);
    for (const Prediction& p : predictions) {
      if (!(p.s < hitS.back())) {
        continue;
      }
      // Only hits near the predicted crossing along the layer (z on
      // barrels, R on disks) can pass the hole cut, kMaxHoleChi2: without
      // the box every hit of the layer's azimuth window is examined.
      const double zAt = chain.sz.z0 + chain.sz.tanLambda * p.s;
      const double rAt = chain.arc.pointAt(p.s).norm();
      const std::vector<ConfIndex>& window = search.boxWindow(
          layer, p.phi, m_config.phiWindow, zAt - kHoleWindow,
          zAt + kHoleWindow, rAt - kHoleWindow, rAt + kHoleWindow,
          Vector3(rAt * std::cos(p.phi), rAt * std::sin(p.phi), zAt));
      for (ConfIndex h : window) {
        if (state.used[h] != 0 || search.onSensorOf(chain.hits, h)) {
          continue;
        }
        double s = chain.arc.hitArcLength(hits, h, p.s);
        if (!(s > 0.0 && s < hitS.back())) {
          continue;
        }
        // The hit before the hole along the track.
        const std::size_t before = static_cast<std::size_t>(
            std::upper_bound(hitS.begin(), hitS.end(), s) - hitS.begin() - 1);
        const Scatter ms =
            allowance ? search.scatter(chain.uv, chain.sz, chain.hits[before],
                                       h, s - hitS[before])
                      : Scatter{};
        double dUv = chain.uv.deltaChi2(hits, h, ms.uv);
        double dSz = chain.sz.deltaChi2(s, hits.z[h], hits.varZ[h] + ms.z,
                                        hits.varRxy[h]);
        const double cut = m_config.chi2CutAt(chain.uv.pt(state.bzForPt));
        if (LayerCrossingSearch::increase(chain.uv.chi2, chain.uv.ndf, dUv) >
                cut ||
            LayerCrossingSearch::increase(chain.sz.chi2, chain.sz.ndf, dSz) >
                cut) {
          continue;
        }
        // A hit in a hole between measured hits is well predicted: an
        // absolute bound keeps neighbours in dense jets out.
        double chi2 =
            local ? localHoleChi2(hits, chain, before, h, s, ms) : dUv + dSz;
        if (chi2 > kMaxHoleChi2) {
          continue;
        }
        if (chi2 < bestChi2 || (chi2 == bestChi2 && h < best)) {
          bestChi2 = chi2;
          best = h;
          bestS = s;
        }
      }
    }
  }
}

double HoleFilling::localHoleChi2(const ConformalHits& hits, const Chain& chain,
                                  std::size_t before, ConfIndex h, double s,
                                  const Scatter& ms) const {
  const std::vector<double>& hitS = m_work.hitS;
  const std::size_t after = before + 1;
  const ConfIndex a = chain.hits[before];
  const ConfIndex b = chain.hits[after];
  const double span = hitS[after] - hitS[before];
  const double wa = span > 0.0 ? (hitS[after] - s) / span : 0.5;
  const double wb = 1.0 - wa;
  double vh = 0.0;
  double va = 0.0;
  double vb = 0.0;
  const ConformalFitResult& uv = chain.uv;
  double eUv = uv.residual(hits, h, vh) - wa * uv.residual(hits, a, va) -
               wb * uv.residual(hits, b, vb);
  double varUv = vh + wa * wa * va + wb * wb * vb + ms.uv;
  const SzFitResult& sz = chain.sz;
  double eSz = sz.residual(s, hits.z[h], hits.varZ[h], hits.varRxy[h], vh) -
               wa * sz.residual(hitS[before], hits.z[a], hits.varZ[a],
                                hits.varRxy[a], va) -
               wb * sz.residual(hitS[after], hits.z[b], hits.varZ[b],
                                hits.varRxy[b], vb);
  double varSz = vh + wa * wa * va + wb * wb * vb + ms.z;
  return eUv * eUv / varUv + eSz * eSz / varSz;
}

void fillHoles(FinderState& state, const HitPool& pool, StepStats& stats) {
  // One unit per step: each track is filled with the cuts of the step that
  // built it.
  std::vector<HoleFilling> units;
  units.reserve(state.config.steps.size());
  for (const FindingStep& step : state.config.steps) {
    units.emplace_back(HoleFilling::Config::fromStep(
        step, state.config, HoleFilling::Residuals::eToNeighbours));
  }
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (!state.tracks[t].alive) {
      continue;
    }
    units[state.tracks[t].step].run(state, pool, stats, t);
  }
}

}  // namespace conftrack::detail

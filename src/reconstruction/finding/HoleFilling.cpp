// Hole filling (FinderConfig::finalHoleFilling and the completion of
// newly built tracks): unused hits on layers that a track crosses between
// its first and last hit without a hit on the track, best chi2 first.

#include "conftrack/reconstruction/finding/detail/Extender.hpp"

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

void Extender::fill(std::uint32_t t, bool local) {
  TrackCandidate& track = m_state.tracks[t];
  Chain chain;
  if (!begin(track, false, false, chain)) {
    return;
  }
  bool added = false;
  std::vector<double> hitS;
  while (true) {
    // Arc lengths of the hits, unwrapped along the track.
    hitS.assign(chain.hits.size(), 0.0);
    for (std::size_t k = 1; k < chain.hits.size(); ++k) {
      ConfIndex h = chain.hits[k];
      hitS[k] = chain.arc.arcLength(m_hits.x[h], m_hits.y[h], hitS[k - 1]);
    }
    ConfIndex best = kInvalidIndex;
    double bestS = 0.0;
    findHole(chain, hitS, false, local, best, bestS);
    if (best == kInvalidIndex && m_state.config.scatteringAllowance) {
      findHole(chain, hitS, true, local, best, bestS);
    }
    if (best == kInvalidIndex) {
      break;
    }
    auto pos = std::upper_bound(hitS.begin(), hitS.end(), bestS);
    chain.hits.insert(chain.hits.begin() + (pos - hitS.begin()), best);
    m_state.used[best] = 1;
    m_state.clones.addHit(best, t);
    ++m_stats.extendedHits;
    added = true;
    if (!refit(chain, &chain.uv)) {
      break;
    }
  }
  if (added) {
    store(chain, track);
  }
}

void Extender::findHole(const Chain& chain, const std::vector<double>& hitS,
                        bool allowance, bool local, ConfIndex& best,
                        double& bestS) {
  double bestChi2 = std::numeric_limits<double>::infinity();
  for (std::uint32_t layer : m_pool.layers()) {
    bool present = false;
    for (ConfIndex h : chain.hits) {
      present = present || m_hits.layer[h] == layer;
    }
    if (present) {
      continue;
    }
    predict(layer, chain.arc, chain.sz, 0.0);
    for (const Prediction& p : m_predictions) {
      if (!(p.s < hitS.back())) {
        continue;
      }
      // Only hits near the predicted crossing along the layer (z on
      // barrels, R on disks) can pass the hole cut, kMaxHoleChi2: without
      // the box every hit of the layer's azimuth window is examined.
      const double zAt = chain.sz.z0 + chain.sz.tanLambda * p.s;
      const double rAt = chain.arc.pointAt(p.s).norm();
      m_window.clear();
      m_pool.layerBox(layer, p.phi, m_state.config.extensionPhiWindow,
                      zAt - kHoleWindow, zAt + kHoleWindow, rAt - kHoleWindow,
                      rAt + kHoleWindow, m_window);
      limitWindow(Vector3(rAt * std::cos(p.phi), rAt * std::sin(p.phi), zAt));
      for (ConfIndex h : m_window) {
        if (m_state.used[h] != 0 || onSensorOf(chain.hits, h)) {
          continue;
        }
        double s = chain.arc.arcLength(m_hits.x[h], m_hits.y[h], p.s);
        if (!(s > 0.0 && s < hitS.back())) {
          continue;
        }
        // The hit before the hole along the track.
        const std::size_t before = static_cast<std::size_t>(
            std::upper_bound(hitS.begin(), hitS.end(), s) - hitS.begin() - 1);
        const Scatter ms = allowance
                               ? scatter(chain.uv, chain.sz, chain.hits[before],
                                         h, s - hitS[before])
                               : Scatter{};
        double dUv = chain.uv.deltaChi2(m_hits, h, ms.uv);
        double dSz = chain.sz.deltaChi2(s, m_hits.z[h], m_hits.varZ[h] + ms.z,
                                        m_hits.varRxy[h]);
        const double cut = m_step.chi2CutAt(chain.uv.pt(m_state.bzForPt));
        if (increase(chain.uv.chi2, chain.uv.ndf, dUv) > cut ||
            increase(chain.sz.chi2, chain.sz.ndf, dSz) > cut) {
          continue;
        }
        // A hit in a hole between measured hits is well predicted: an
        // absolute bound keeps neighbours in dense jets out.
        double chi2 =
            local ? localHoleChi2(chain, hitS, before, h, s, ms) : dUv + dSz;
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

double Extender::localHoleChi2(const Chain& chain,
                               const std::vector<double>& hitS,
                               std::size_t before, ConfIndex h, double s,
                               const Scatter& ms) const {
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
  double eUv = uv.residual(m_hits, h, vh) - wa * uv.residual(m_hits, a, va) -
               wb * uv.residual(m_hits, b, vb);
  double varUv = vh + wa * wa * va + wb * wb * vb + ms.uv;
  const SzFitResult& sz = chain.sz;
  double eSz =
      sz.residual(s, m_hits.z[h], m_hits.varZ[h], m_hits.varRxy[h], vh) -
      wa * sz.residual(hitS[before], m_hits.z[a], m_hits.varZ[a],
                       m_hits.varRxy[a], va) -
      wb * sz.residual(hitS[after], m_hits.z[b], m_hits.varZ[b],
                       m_hits.varRxy[b], vb);
  double varSz = vh + wa * wa * va + wb * wb * vb + ms.z;
  return eUv * eUv / varUv + eSz * eSz / varSz;
}

void fillHoles(FinderState& state, const HitPool& pool, StepStats& stats) {
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (!state.tracks[t].alive) {
      continue;
    }
    const FindingStep& step = state.config.steps[state.tracks[t].step];
    Extender extender(state, step, pool, stats);
    extender.fill(t, true);
  }
}

}  // namespace conftrack::detail

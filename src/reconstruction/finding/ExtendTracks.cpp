// ExtendTracks of conformal tracking (algorithm.md 10; paper 4.1.2).
//
// Upstream scans, for the low-pT pass, every hit of the step for every
// track (O(N_tracks x N_hits), algorithm.md 14.11). Here both passes use the
// track's current circle and s-z line to predict where it crosses each layer
// of the step (both crossings of a barrel layer, for loopers) and examine
// only the hits in an azimuth window around each prediction. The acceptance
// criteria are upstream's: angle between the track direction and the new
// cell (1x the step's cuts in the per-layer pass, 3x in the catch-all pass),
// increases of chi2_uv/ndf and chi2_sz/ndf below the step's chi2 cut, no two
// hits on one sensor, and in the catch-all pass no hit on the other side in
// z. The chi2 increments are the exact ones of the quadratic fits, computed
// in O(1) per hit. Of the layers with compatible hits, the one crossed
// first along the track is taken, with its hit of lowest chi2_uv increase.

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace conftrack::detail {

namespace {

/// Margin around a layer's extent when predicting crossings [mm].
constexpr double kLayerMargin = 10.0;

double angleBetween(double ax, double ay, double bx, double by) {
  return std::atan2(std::abs(ax * by - ay * bx), ax * bx + ay * by);
}

struct Prediction {
  double s;
  double phi;
};

class Extender {
 public:
  Extender(FinderState& state, const FindingStep& step, const HitPool& pool,
           StepStats& stats)
      : m_state(state),
        m_hits(state.hits),
        m_step(step),
        m_pool(pool),
        m_stats(stats) {}

  /// Extends track t. `catchAll` selects the loose low-pT pass.
  void extend(std::uint32_t t, bool catchAll) {
    TrackCandidate& track = m_state.tracks[t];
    if (track.hits.size() < 3) {
      return;
    }
    ConformalFitResult uv = fitConformal(m_hits, track.hits, true, &track.uv);
    if (!uv.valid) {
      return;
    }
    ArcFrame arc = makeArcFrame(uv, m_hits, track.hits.front());
    SzFitResult sz = fitSz(m_hits, track.hits, arc);
    if (!sz.valid) {
      return;
    }
    const double factor = catchAll ? 3.0 : 1.0;
    bool added = false;
    while (true) {
      ConfIndex best = 0;
      double bestS = 0.0;
      double bestChi2 = 0.0;
      bool found = false;
      const ConfIndex last = track.hits.back();
      const ConfIndex prev = track.hits[track.hits.size() - 2];
      // Track direction at the last hit from the fitted curve (more
      // precise than the chord of the last two hits).
      double xl = uv.cosA * m_hits.u[last] + uv.sinA * m_hits.v[last];
      double slope = uv.params(1) + 2.0 * uv.params(2) * xl;
      double norm = std::hypot(1.0, slope);
      double tu = (uv.cosA - uv.sinA * slope) / norm;
      double tv = (uv.sinA + uv.cosA * slope) / norm;
      double rzDz = m_hits.z[last] - m_hits.z[prev];
      double rzDr = m_hits.radius[last] - m_hits.radius[prev];
      double rzNorm = std::hypot(rzDz, rzDr);
      const double sLast = sz.lastS;

      for (std::uint32_t layer : m_pool.layers()) {
        predict(layer, arc, sz, sLast, catchAll);
        for (const Prediction& p : m_predictions) {
          m_window.clear();
          m_pool.layerWindow(layer, p.phi, m_state.config.extensionPhiWindow,
                             m_window);
          for (ConfIndex h : m_window) {
            if (m_state.used[h] != 0 || onSensorOf(track, h)) {
              continue;
            }
            if (catchAll && (m_hits.z[h] > 0) != (m_hits.z[last] > 0)) {
              continue;
            }
            if (!catchAll && m_hits.radius[h] <= m_hits.radius[last]) {
              continue;
            }
            double du = m_hits.u[h] - m_hits.u[last];
            double dv = m_hits.v[h] - m_hits.v[last];
            double l = std::hypot(du, dv);
            if (!(l > 0.0) || angleBetween(tu, tv, du / l, dv / l) >
                                  factor * m_step.maxCellAngle) {
              continue;
            }
            double dz = m_hits.z[h] - m_hits.z[last];
            double dr = m_hits.radius[h] - m_hits.radius[last];
            double lr = std::hypot(dz, dr);
            if (rzNorm > 0.0 && lr > 0.0 &&
                angleBetween(rzDz / rzNorm, rzDr / rzNorm, dz / lr, dr / lr) >
                    factor * m_step.maxCellAngleRZ) {
              continue;
            }
            double dUv = uv.deltaChi2(m_hits, h);
            double s = arc.arcLength(m_hits.x[h], m_hits.y[h], p.s);
            if (!(s > sLast)) {
              continue;
            }
            double dSz =
                sz.deltaChi2(s, m_hits.z[h], m_hits.varZ[h], m_hits.varRxy[h]);
            if (increase(uv.chi2, uv.ndf, dUv) > m_step.chi2Cut ||
                increase(sz.chi2, sz.ndf, dSz) > m_step.chi2Cut) {
              continue;
            }
            // First layer along the track; on it the lowest chi2 increase.
            bool better = !found || p.s < bestS - 1e-6 ||
                          (std::abs(p.s - bestS) <= 1e-6 &&
                           (dUv < bestChi2 || (dUv == bestChi2 && h < best)));
            if (better) {
              found = true;
              best = h;
              bestS = p.s;
              bestChi2 = dUv;
            }
          }
        }
      }
      if (!found) {
        break;
      }
      track.hits.push_back(best);
      m_state.used[best] = 1;  // extensions claim hits immediately
      m_state.clones.addHit(best, t);
      ++m_stats.extendedHits;
      added = true;
      ConformalFitResult refit = fitConformal(m_hits, track.hits, true, &uv);
      if (!refit.valid) {
        break;
      }
      uv = refit;
      arc = makeArcFrame(uv, m_hits, track.hits.front());
      SzFitResult szRefit = fitSz(m_hits, track.hits, arc);
      if (!szRefit.valid) {
        break;
      }
      sz = szRefit;
    }
    if (added) {
      track.uv = uv;
      track.sz = sz;
      track.pt = uv.pt(m_state.bzForPt);
    }
  }

 private:
  static double increase(double chi2, int ndf, double delta) {
    double before = ndf > 0 ? chi2 / ndf : 0.0;
    return (chi2 + delta) / (ndf + 1) - before;
  }

  bool onSensorOf(const TrackCandidate& track, ConfIndex h) const {
    for (ConfIndex k : track.hits) {
      if (m_hits.sameSensor(k, h)) {
        return true;
      }
    }
    return false;
  }

  /// Crossings of `layer` after arc length sLast (within one turn).
  void predict(std::uint32_t layer, const ArcFrame& arc, const SzFitResult& sz,
               double sLast, bool catchAll) {
    m_predictions.clear();
    const SensitiveLayer& l = m_state.detector.layers()[layer];
    const double turn = 2.0 * std::numbers::pi * arc.radius;
    auto after = [&](double s) {
      while (s <= sLast + 1e-6) {
        s += turn;
      }
      return s;
    };
    if (!l.isDisk()) {
      // Circle (centre C, radius rho) with the cylinder's circle.
      double cx = arc.centreX;
      double cy = arc.centreY;
      double d = std::hypot(cx, cy);
      double rho = arc.radius;
      double rl = l.r;
      if (d < 1e-9 || rl > d + rho || rl < std::abs(d - rho)) {
        return;
      }
      double a = (rl * rl - rho * rho + d * d) / (2.0 * d);
      double h = std::sqrt(std::max(0.0, rl * rl - a * a));
      double ex = cx / d;
      double ey = cy / d;
      for (int sign : {1, -1}) {
        double px = a * ex - sign * h * ey;
        double py = a * ey + sign * h * ex;
        double s = after(arc.arcLength(px, py, sLast));
        if (!catchAll && s - sLast > 0.5 * turn) {
          continue;  // the per-layer pass follows the outgoing branch only
        }
        double z = sz.z0 + sz.tanLambda * s;
        if (z < l.zMin - kLayerMargin || z > l.zMax + kLayerMargin) {
          continue;
        }
        m_predictions.push_back({s, std::atan2(py, px)});
      }
    } else {
      if (std::abs(sz.tanLambda) < 1e-9) {
        return;
      }
      double s = (l.z() - sz.z0) / sz.tanLambda;
      if (!(s > sLast) || s - sLast > turn) {
        return;
      }
      Vector2 p = arc.pointAt(s);
      double r = p.norm();
      if (r < l.rMin - kLayerMargin || r > l.rMax + kLayerMargin) {
        return;
      }
      m_predictions.push_back({s, std::atan2(p.y(), p.x())});
    }
  }

  FinderState& m_state;
  const ConformalHits& m_hits;
  const FindingStep& m_step;
  const HitPool& m_pool;
  StepStats& m_stats;
  std::vector<Prediction> m_predictions;
  std::vector<ConfIndex> m_window;
};

}  // namespace

void extendTracks(FinderState& state, const FindingStep& step,
                  const HitPool& pool, StepStats& stats) {
  // Hits of all tracks are claimed before extending (algorithm.md 10.2).
  for (const TrackCandidate& t : state.tracks) {
    for (ConfIndex h : t.hits) {
      state.used[h] = 1;
    }
  }
  Extender extender(state, step, pool, stats);
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (state.tracks[t].alive && state.tracks[t].pt >= step.highPtCut) {
      extender.extend(t, false);
    }
  }
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (state.tracks[t].alive) {
      extender.extend(t, true);
    }
  }
}

}  // namespace conftrack::detail

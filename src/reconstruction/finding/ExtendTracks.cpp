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
// z; but the longitudinal angle is measured in the (s, z) plane, where the
// helix is straight, not between (z, R) chords, which curve below a few
// GeV. The chi2 increments are the exact ones of the track's fits, computed
// in O(1) per hit; when no hit of the next crossing passes, that crossing
// is tried again with an allowance for multiple scattering in the hit
// variances (FinderConfig::scatteringAllowance). Upstream always refits with
// the quadratic term here; a track built with the straight-line (prompt) model
// keeps it instead: with the quadratic term free, a vertex-detector track plus
// the tracker hits of a neighbouring particle of the same jet fits as well as
// the right combination, while the prompt model tells them apart by a factor of
// ten in chi2. Of the layers with compatible hits, the one crossed first along
// the track is taken. Upstream takes the hit of lowest chi2_uv increase there;
// in dense jets that greedy choice swaps hits between particles a fraction of a
// mrad apart, because a vertex-detector track cannot predict its curvature well
// enough at the first tracker layer (only the next layers' lever arm tells them
// apart). So when several hits on that layer are compatible, each of the best
// few is scored by its chi2_uv + chi2_sz increase plus that of the best
// continuation on the following layers (a look-ahead of
// FinderConfig::extensionLookahead layers), and the lowest total wins.
// The hits examined per predicted crossing are bounded
// (FinderConfig::maxWindowHits, counted; the nearest to the predicted point
// are kept), so that the cost per track does not grow without bound with
// the hit density.
//
// The Extender (detail/Extender.hpp) is shared with the hole filling
// (HoleFilling.cpp).

#include "conftrack/reconstruction/finding/detail/Extender.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack::detail {

namespace {

/// Margin around a layer's extent when predicting crossings [mm].
constexpr double kLayerMargin = 10.0;
/// The scattering allowance applies to hits on the nearest predicted layer
/// crossing, or at most this much further (the second sensor of a double
/// layer) [mm]: a track whose particle ended must not pick up a hit layers
/// away with an allowance that grows with the distance.
constexpr double kScatterReach = 5.0;
/// Extra half-angle of the (z, R) search cone around a predicted crossing,
/// for hits away from the predicted point [rad].
constexpr double kConeMargin = 0.01;
/// chi2 charged for a predicted layer crossing without a compatible hit in
/// the look-ahead (a missing hit costs about a 4 sigma deviation).
constexpr double kMissingHitChi2 = 16.0;
/// At most this many hits of one layer are followed in the look-ahead.
constexpr std::size_t kLookaheadBranches = 3;

}  // namespace

void Extender::extend(std::uint32_t t, bool catchAll, bool inward) {
  TrackCandidate& track = m_state.tracks[t];
  Chain chain;
  if (!begin(track, catchAll && !inward, inward, chain)) {
    return;
  }
  bool added = false;
  std::vector<Candidate> cands;
  while (true) {
    collect(chain, cands);
    if (cands.empty()) {
      break;
    }
    std::size_t choice = 0;
    if (cands.size() > 1 && m_state.config.extensionLookahead > 0) {
      double best = std::numeric_limits<double>::infinity();
      std::size_t n = std::min(cands.size(), kLookaheadBranches);
      for (std::size_t k = 0; k < n; ++k) {
        double score =
            cands[k].chi2 +
            lookahead(chain, cands[k].hit, m_state.config.extensionLookahead);
        if (score < best) {
          best = score;
          choice = k;
        }
      }
    }
    ConfIndex h = cands[choice].hit;
    if (m_inward) {
      chain.hits.insert(chain.hits.begin(), h);
    } else {
      chain.hits.push_back(h);
    }
    m_state.used[h] = 1;  // extensions claim hits immediately
    m_state.clones.addHit(h, t);
    ++m_stats.extendedHits;
    added = true;
    if (!refit(chain, &chain.uv)) {
      if (m_inward) {
        chain.hits.erase(chain.hits.begin());
      } else {
        chain.hits.pop_back();
      }
      break;
    }
  }
  if (added) {
    store(chain, track);
  }
}

bool Extender::begin(const TrackCandidate& track, bool catchAll, bool inward,
                     Chain& chain) {
  if (track.hits.size() < 3 || track.helix) {
    return false;
  }
  m_catchAll = catchAll;
  m_inward = inward;
  m_quadratic = track.uv.quadratic;
  chain.hits = track.hits;
  return refit(chain, &track.uv);
}

void Extender::store(const Chain& chain, TrackCandidate& track) const {
  track.hits = chain.hits;
  track.uv = chain.uv;
  track.sz = chain.sz;
  track.pt = chain.uv.pt(m_state.bzForPt);
}

double Extender::increase(double chi2, int ndf, double delta) {
  double before = ndf > 0 ? chi2 / ndf : 0.0;
  return (chi2 + delta) / (ndf + 1) - before;
}

bool Extender::refit(Chain& c, const ConformalFitResult* frame) const {
  ConformalFitResult uv = fitConformal(m_hits, c.hits, m_quadratic, frame);
  if (!uv.valid) {
    return false;
  }
  ArcFrame arc = makeArcFrame(uv, m_hits, c.hits.front());
  SzFitResult sz = fitSz(m_hits, c.hits, arc);
  if (!sz.valid) {
    return false;
  }
  c.uv = uv;
  c.arc = arc;
  c.sz = sz;
  return true;
}

double Extender::lookahead(const Chain& chain, ConfIndex h, int depth) {
  Chain next = chain;
  if (m_inward) {
    next.hits.insert(next.hits.begin(), h);
  } else {
    next.hits.push_back(h);
  }
  if (!refit(next, &chain.uv)) {
    return kMissingHitChi2 * depth;
  }
  std::vector<Candidate> cands;
  bool predicted = collect(next, cands, h);
  if (cands.empty()) {
    return predicted ? kMissingHitChi2 : 0.0;
  }
  if (depth <= 1) {
    return cands.front().chi2;
  }
  double best = std::numeric_limits<double>::infinity();
  std::size_t n = std::min(cands.size(), kLookaheadBranches);
  for (std::size_t k = 0; k < n; ++k) {
    best = std::min(best,
                    cands[k].chi2 + lookahead(next, cands[k].hit, depth - 1));
  }
  return best;
}

Scatter Extender::scatter(const ConformalFitResult& uv, const SzFitResult& sz,
                          ConfIndex from, ConfIndex to, double ds) const {
  Scatter out;
  const SensitiveLayer& layer = m_state.detector.layers()[m_hits.layer[from]];
  const double secL = norm2(1.0, sz.tanLambda);
  const double theta0 =
      layerTheta0(layer, uv.pt(m_state.bzForPt) * secL, sz.tanLambda);
  const double d = theta0 * std::abs(ds) * secL;  // displacement [mm]
  const double r2 = m_hits.radius[to] * m_hits.radius[to];
  out.uv = d * d / (r2 * r2);
  out.z = d * d * secL * secL;
  return out;
}

bool Extender::onSensorOf(const std::vector<ConfIndex>& hits,
                          ConfIndex h) const {
  for (ConfIndex k : hits) {
    if (m_hits.sameSensor(k, h)) {
      return true;
    }
  }
  return false;
}

bool Extender::collect(const Chain& chain, std::vector<Candidate>& out,
                       ConfIndex excluded) {
  double nearest = std::numeric_limits<double>::infinity();
  bool predicted = collectWith(chain, out, excluded, nullptr, &nearest);
  if (out.empty() && predicted && !m_catchAll &&
      m_state.config.scatteringAllowance) {
    const double reach = nearest + kScatterReach;
    collectWith(chain, out, excluded, &reach, nullptr);
  }
  return predicted;
}

bool Extender::collectWith(const Chain& chain, std::vector<Candidate>& out,
                           ConfIndex excluded, const double* allowanceReach,
                           double* nearest) {
  out.clear();
  const bool allowance = allowanceReach != nullptr;
  // The end of the chain being extended.
  const std::size_t n = chain.hits.size();
  const ConfIndex last = m_inward ? chain.hits[0] : chain.hits[n - 1];
  const ConformalFitResult& uv = chain.uv;
  const SzFitResult& sz = chain.sz;
  // Inwards the chord to a 2 mm-distant double-layer sensor is as noisy
  // as the cell that failed in the first place: use the loose cuts.
  const double factor = (m_catchAll || m_inward) ? 3.0 : 1.0;
  // Track direction at that hit from the fitted curve (more precise than
  // the chord of the last two hits), reversed when going inwards.
  double xl = uv.cosA * m_hits.u[last] + uv.sinA * m_hits.v[last];
  double slope = uv.params(1) + 2.0 * uv.params(2) * xl;
  double norm = (m_inward ? -1.0 : 1.0) * norm2(1.0, slope);
  double tu = (uv.cosA - uv.sinA * slope) / norm;
  double tv = (uv.sinA + uv.cosA * slope) / norm;
  // The longitudinal angle cut is taken in the (s, z) plane, where the
  // helix is a straight line, against the fitted s-z direction. Upstream
  // compares chords in (z, R); below a few GeV the track curves in that
  // plane (R grows slower than s), and at the outer tracker layers a 1 GeV
  // track's consecutive chords differ by more than 3 x 0.05 rad.
  const double szNorm = (m_inward ? -1.0 : 1.0) * norm2(1.0, sz.tanLambda);
  const double ts = 1.0 / szNorm;
  const double tz = sz.tanLambda / szNorm;
  const double rzCut = factor * m_step.maxCellAngleRZ;
  // Arc length of the end being extended (0 for the first hit).
  const double sLast = m_inward ? 0.0 : sz.lastS;
  const double chi2Cut = m_step.chi2CutAt(uv.pt(m_state.bzForPt));
  bool predicted = false;
  // Arc length of the nearest layer with compatible hits so far, as a
  // distance from the end being extended.
  double firstS = std::numeric_limits<double>::infinity();
  for (std::uint32_t layer : m_pool.layers()) {
    predict(layer, chain.arc, sz, sLast);
    predicted = predicted || !m_predictions.empty();
    for (const Prediction& p : m_predictions) {
      double dist = std::abs(p.s - sLast);
      // (A crossing of the end hit's own layer right at the hit is not
      // the next layer.)
      if (nearest != nullptr && layer != m_hits.layer[last]) {
        *nearest = std::min(*nearest, dist);
      }
      if (dist > firstS + 1e-6 || (allowance && dist > *allowanceReach)) {
        continue;  // a later layer than one that already has hits
      }
      // Only the layer bins near the predicted crossing are searched: a
      // (z, R) cone from the last hit towards it. An (s, z) angle a
      // there spans a (z, R) angle a (1 + t^2) c / (c^2 + t^2), with
      // t = dz/ds and c = dR/ds of the chord (on barrels and disks
      // alike); the cone gets half as much again, plus a margin for
      // hits away from the predicted point.
      const Vector2 at = chain.arc.pointAt(p.s);
      const double coneDz = sz.z0 + sz.tanLambda * p.s - m_hits.z[last];
      const double coneDr = at.norm() - m_hits.radius[last];
      const double coneNorm = norm2(coneDz, coneDr);
      const double chordS = std::abs(p.s - sLast);
      const double c = chordS > 0.0 ? std::abs(coneDr) / chordS : 1.0;
      const double t2 = sz.tanLambda * sz.tanLambda;
      const double spread = c > 0.0 ? (1.0 + t2) * c / (c * c + t2) : 1.5;
      const HitPool::RzCone rzCone{
          m_hits.z[last], m_hits.radius[last], coneDz / coneNorm,
          coneDr / coneNorm, std::min(1.5, 1.5 * rzCut * spread + kConeMargin)};
      m_window.clear();
      m_pool.layerWindow(layer, p.phi, m_state.config.extensionPhiWindow,
                         m_window, coneNorm > 0.0 ? &rzCone : nullptr);
      limitWindow(Vector3(at.x(), at.y(), sz.z0 + sz.tanLambda * p.s));
      for (ConfIndex h : m_window) {
        if (h == excluded || m_state.used[h] != 0 ||
            onSensorOf(chain.hits, h)) {
          continue;
        }
        if (m_catchAll && (m_hits.z[h] > 0) != (m_hits.z[last] > 0)) {
          continue;
        }
        if (!m_catchAll && !m_inward &&
            m_hits.radius[h] <= m_hits.radius[last]) {
          continue;
        }
        if (m_inward && m_hits.radius[h] >= m_hits.radius[last]) {
          continue;
        }
        double du = m_hits.u[h] - m_hits.u[last];
        double dv = m_hits.v[h] - m_hits.v[last];
        double l = std::sqrt(du * du + dv * dv);
        if (!(l > 0.0) || angleBetween(tu, tv, du / l, dv / l) >
                              factor * m_step.maxCellAngle) {
          continue;
        }
        double s = chain.arc.arcLength(m_hits.x[h], m_hits.y[h], p.s);
        if (m_inward ? !(s < sLast) : !(s > sLast)) {
          continue;
        }
        double ds = s - sLast;
        double dz = m_hits.z[h] - m_hits.z[last];
        double lsz = std::sqrt(ds * ds + dz * dz);
        if (!(lsz > 0.0) || angleBetween(ts, tz, ds / lsz, dz / lsz) > rzCut) {
          continue;
        }
        const Scatter ms = allowance ? scatter(uv, sz, last, h, ds) : Scatter{};
        double dUv = uv.deltaChi2(m_hits, h, ms.uv);
        double dSz = sz.deltaChi2(s, m_hits.z[h], m_hits.varZ[h] + ms.z,
                                  m_hits.varRxy[h]);
        if (increase(uv.chi2, uv.ndf, dUv) > chi2Cut ||
            increase(sz.chi2, sz.ndf, dSz) > chi2Cut) {
          continue;
        }
        if (dist < firstS - 1e-6) {
          firstS = dist;
          out.clear();
        }
        out.push_back({h, p.s, dUv + dSz, dUv});
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.chi2 != b.chi2 ? a.chi2 < b.chi2 : a.hit < b.hit;
  });
  return predicted;
}

void Extender::limitWindow(const Vector3& at) {
  const std::size_t limit = m_state.config.maxWindowHits;
  if (m_window.size() <= limit) {
    return;
  }
  m_stats.guard(Guard::eWindowHits).add(m_window.size() - limit);
  m_distances.clear();
  for (ConfIndex h : m_window) {
    const double dx = m_hits.x[h] - at.x();
    const double dy = m_hits.y[h] - at.y();
    const double dz = m_hits.z[h] - at.z();
    m_distances.emplace_back(dx * dx + dy * dy + dz * dz, h);
  }
  std::nth_element(m_distances.begin(),
                   m_distances.begin() + static_cast<std::ptrdiff_t>(limit),
                   m_distances.end());
  m_window.resize(limit);
  for (std::size_t k = 0; k < limit; ++k) {
    m_window[k] = m_distances[k].second;
  }
}

void Extender::predict(std::uint32_t layer, const ArcFrame& arc,
                       const SzFitResult& sz, double sLast) {
  m_predictions.clear();
  const SensitiveLayer& l = m_state.detector.layers()[layer];
  const double turn = 2.0 * std::numbers::pi * arc.radius;
  if (m_outerRadius < 0.0) {
    m_outerRadius = 0.0;
    for (const SensitiveLayer& o : m_state.detector.layers()) {
      m_outerRadius = std::max(m_outerRadius, o.isDisk() ? o.rMax : o.r);
    }
    m_outerRadius += kLayerMargin;
  }
  // A track whose circle leaves the tracker's outer radius ends there:
  // crossings further on (an endcap disk a turn later) belong to another
  // track.
  double sExit = std::numeric_limits<double>::infinity();
  if (!m_inward) {
    const double d = norm2(arc.centreX, arc.centreY);
    const double rho = arc.radius;
    const double ro = m_outerRadius;
    if (d > 1e-9 && ro < d + rho && ro > std::abs(d - rho)) {
      const double a = (ro * ro - rho * rho + d * d) / (2.0 * d);
      const double h = std::sqrt(std::max(0.0, ro * ro - a * a));
      const double ex = arc.centreX / d;
      const double ey = arc.centreY / d;
      for (int sign : {1, -1}) {
        double sx = arc.arcLength(a * ex - sign * h * ey,
                                  a * ey + sign * h * ex, sLast);
        while (sx <= sLast + 1e-6) {
          sx += turn;
        }
        sExit = std::min(sExit, sx);
      }
    }
  }
  auto after = [&](double s) {
    if (m_inward) {
      while (s >= sLast - 1e-6) {
        s -= turn;
      }
      return s;
    }
    while (s <= sLast + 1e-6) {
      s += turn;
    }
    return s;
  };
  if (!l.isDisk()) {
    // Circle (centre C, radius rho) with the cylinder's circle.
    double cx = arc.centreX;
    double cy = arc.centreY;
    double d = norm2(cx, cy);
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
      if (s > sExit) {
        continue;
      }
      if (!m_catchAll && std::abs(s - sLast) > 0.5 * turn) {
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
    bool ahead = m_inward ? s < sLast : s > sLast;
    if (!ahead || std::abs(s - sLast) > turn || s > sExit) {
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

void completeTrack(FinderState& state, const FindingStep& step,
                   const HitPool& pool, StepStats& stats, std::uint32_t t) {
  Extender extender(state, step, pool, stats);
  if (step.direction == SearchDirection::eInsideOut) {
    extender.extend(t, false, true);
  }
  extender.fill(t, false);
}

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

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

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

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

struct Prediction {
  double s;
  double phi;
};

/// A compatible hit on a predicted layer crossing.
struct Candidate {
  ConfIndex hit;
  double s;     ///< predicted arc length of the crossing
  double chi2;  ///< chi2_uv + chi2_sz increase
  double dUv;
};

/// Allowance for multiple scattering at a hit (variances added to the
/// hit's own in the chi2 increments).
struct Scatter {
  double uv = 0.0;  ///< perpendicular to the conformal curve [1/mm^2]
  double z = 0.0;   ///< along z [mm^2]
};

/// A track being extended: hits and fits.
struct Chain {
  std::vector<ConfIndex> hits;
  ConformalFitResult uv;
  ArcFrame arc;
  SzFitResult sz;
};

/// chi2 charged for a predicted layer crossing without a compatible hit in
/// the look-ahead (a missing hit costs about a 4 sigma deviation).
constexpr double kMissingHitChi2 = 16.0;
/// Largest chi2_uv + chi2_sz increase of a hit filled into a hole.
constexpr double kMaxHoleChi2 = 30.0;
/// Half-length along the layer (z on barrels, R on disks) of the search box
/// around a hole's predicted crossing [mm]: 16 sigma of the coarsest strip
/// coordinate (TrackML long strips, 3 mm); a hole hit passing kMaxHoleChi2
/// lies within 5.5 sigma.
constexpr double kHoleWindow = 50.0;
/// At most this many hits of one layer are followed in the look-ahead.
constexpr std::size_t kLookaheadBranches = 3;

class Extender {
 public:
  Extender(FinderState& state, const FindingStep& step, const HitPool& pool,
           StepStats& stats)
      : m_state(state),
        m_hits(state.hits),
        m_step(step),
        m_pool(pool),
        m_stats(stats) {}

  /// Extends track t. `catchAll` selects the loose low-pT pass;
  /// `inward` follows the track back towards the IP from its first hit
  /// (per-layer mode only).
  void extend(std::uint32_t t, bool catchAll, bool inward = false) {
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

  /// Hole filling: adds unused hits on layers that the track crosses
  /// between its first and last hit but has no hit on (a cell that skipped
  /// a layer), best chi2 increase first.
  void fill(std::uint32_t t, bool local) {
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

 private:
  /// Sets the pass and copies track into chain with fresh fits; false if
  /// the track is too short or does not fit.
  bool begin(const TrackCandidate& track, bool catchAll, bool inward,
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

  /// Writes the grown chain back into the track.
  void store(const Chain& chain, TrackCandidate& track) const {
    track.hits = chain.hits;
    track.uv = chain.uv;
    track.sz = chain.sz;
    track.pt = chain.uv.pt(m_state.bzForPt);
  }

  static double increase(double chi2, int ndf, double delta) {
    double before = ndf > 0 ? chi2 / ndf : 0.0;
    return (chi2 + delta) / (ndf + 1) - before;
  }

  /// The best unused hit in a hole of the chain (see fill), with or
  /// without the scattering allowance; `best` stays kInvalidIndex if none.
  /// With `local` a hit is judged by its residuals relative to those of
  /// the track's hits on either side of the hole (localHoleChi2) instead
  /// of its residuals to the fits.
  void findHole(const Chain& chain, const std::vector<double>& hitS,
                bool allowance, bool local, ConfIndex& best, double& bestS) {
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
          const Scatter ms =
              allowance ? scatter(chain.uv, chain.sz, chain.hits[before], h,
                                  s - hitS[before])
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

  /// chi2 of hit h (arc length s) in the hole after the chain's hit
  /// `before`, from its residuals to the fits minus those interpolated
  /// between the hits on either side. Below a few GeV multiple scattering
  /// bends a track away from its fitted circle and s-z line by far more
  /// than the hit resolution (chi2/ndf ~ 100 at 1 GeV), but smoothly: the
  /// neighbours' residuals carry the local deviation, which the
  /// difference removes.
  double localHoleChi2(const Chain& chain, const std::vector<double>& hitS,
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

  bool refit(Chain& c, const ConformalFitResult* frame) const {
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

  /// Best total chi2 increase of the next `depth` layers after adding h.
  double lookahead(const Chain& chain, ConfIndex h, int depth) {
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

  /// The deflection in the material of the layer of hit `from`, seen at
  /// hit `to` a transverse arc length `ds` further on: the conformal fits
  /// know only the hit resolutions, and below a few GeV the outer tracker's
  /// 7 um are far smaller than this (0.4 mm at 1 GeV between two outer
  /// layers), so good hits would fail the chi2 cuts.
  Scatter scatter(const ConformalFitResult& uv, const SzFitResult& sz,
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

  bool onSensorOf(const std::vector<ConfIndex>& hits, ConfIndex h) const {
    for (ConfIndex k : hits) {
      if (m_hits.sameSensor(k, h)) {
        return true;
      }
    }
    return false;
  }

  /// Compatible hits on the first layer crossed after the chain's last hit,
  /// best (lowest chi2 increase) first. `excluded` is a tentative hit of
  /// the look-ahead. Returns whether any crossing was predicted at all.
  /// Hits compatible within the hit resolutions are preferred; only when
  /// there are none are the chi2 increments recomputed with the allowance
  /// for multiple scattering (FinderConfig::scatteringAllowance). In dense
  /// jets the allowance alone let low-pT tracks take hits of neighbours
  /// a fraction of a mm away.
  bool collect(const Chain& chain, std::vector<Candidate>& out,
               ConfIndex excluded = kInvalidIndex) {
    double nearest = std::numeric_limits<double>::infinity();
    bool predicted = collectWith(chain, out, excluded, nullptr, &nearest);
    if (out.empty() && predicted && !m_catchAll &&
        m_state.config.scatteringAllowance) {
      const double reach = nearest + kScatterReach;
      collectWith(chain, out, excluded, &reach, nullptr);
    }
    return predicted;
  }

  /// collect, without (`allowanceReach` null) or with the scattering
  /// allowance in the chi2 increments; with it, only crossings up to that
  /// distance from the end are searched. `nearest` receives the distance
  /// of the nearest predicted crossing.
  bool collectWith(const Chain& chain, std::vector<Candidate>& out,
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
            coneDr / coneNorm,
            std::min(1.5, 1.5 * rzCut * spread + kConeMargin)};
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
          if (!(lsz > 0.0) ||
              angleBetween(ts, tz, ds / lsz, dz / lsz) > rzCut) {
            continue;
          }
          const Scatter ms =
              allowance ? scatter(uv, sz, last, h, ds) : Scatter{};
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
    std::sort(out.begin(), out.end(),
              [](const Candidate& a, const Candidate& b) {
                return a.chi2 != b.chi2 ? a.chi2 < b.chi2 : a.hit < b.hit;
              });
    return predicted;
  }

  /// Keeps at most FinderConfig::maxWindowHits hits of m_window, those
  /// nearest to the predicted crossing `at` (then by index); counts the
  /// cut. The callers choose among the hits by a total order, so the kept
  /// set, not its order, must be deterministic.
  void limitWindow(const Vector3& at) {
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

  /// Crossings of `layer` after arc length sLast (within one turn).
  void predict(std::uint32_t layer, const ArcFrame& arc, const SzFitResult& sz,
               double sLast) {
    m_predictions.clear();
    const SensitiveLayer& l = m_state.detector.layers()[layer];
    const double turn = 2.0 * std::numbers::pi * arc.radius;
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
      if (!ahead || std::abs(s - sLast) > turn) {
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
  bool m_catchAll = false;
  bool m_inward = false;
  bool m_quadratic = true;
  std::vector<Prediction> m_predictions;
  std::vector<ConfIndex> m_window;
  /// Scratch of limitWindow: (squared distance, hit).
  std::vector<std::pair<double, ConfIndex>> m_distances;
};

}  // namespace

void completeTrack(FinderState& state, const FindingStep& step,
                   const HitPool& pool, StepStats& stats, std::uint32_t t) {
  Extender extender(state, step, pool, stats);
  if (step.direction == SearchDirection::eInsideOut) {
    extender.extend(t, false, true);
  }
  extender.fill(t, false);
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

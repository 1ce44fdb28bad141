// The following part of the helix step (HelixFollower.hpp; the file
// comment of HelixTracks.cpp describes the whole step).

#include "conftrack/reconstruction/finding/detail/HelixFollower.hpp"

#include "conftrack/geometry/Helix.hpp"
#include "conftrack/geometry/MagneticField.hpp"
#include "conftrack/reconstruction/finding/detail/OverlapHits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace conftrack::detail {

namespace {

/// Margin around a layer's extent when predicting crossings [mm].
constexpr double kLayerMargin = 5.0;
/// Search windows extend this many standard deviations around a
/// prediction; the chi2 cut decides.
constexpr double kWindowSigmas = 5.0;
/// Crossings nearer than this to the last hit are that hit's own [mm].
constexpr double kMinStep = 0.5;
/// Extensions look for the next hit on layers up to this many times
/// maxSeedLength away (seed hits are at most maxSeedLength apart).
constexpr double kReachFactor = 4.0;
/// At most this many hits (one per sensor) are taken at one layer
/// crossing: TrackML's innermost pixel-disk rings overlap three deep.
constexpr std::size_t kMaxHitsPerCrossing = 3;
/// Alignment floor of the residual difference of two overlap hits [mm].
constexpr double kOverlapFloor = 0.05;
/// Hits of a crossing tried with the look-ahead (the best by chi2).
constexpr std::size_t kLookAheadCandidates = 3;
/// A path's seed hits (its first three), whose overlap partners
/// addSeedPartners takes.
constexpr std::size_t kSeedHits = 3;
/// Smallest window half-width around a predicted crossing [mm].
constexpr double kMinWindow = 0.5;

}  // namespace

HelixFollower::HelixFollower(const FinderState& state, const FindingStep& step,
                             const HitPool& pool)
    : m_state(state),
      m_hits(state.hits),
      m_layers(state.detector.layers()),
      m_step(step),
      m_pool(pool) {
  m_reach.resize(m_layers.size());
  const std::vector<std::uint32_t>& layers = m_pool.layers();
  for (std::uint32_t a : layers) {
    for (std::uint32_t b : layers) {
      if (layerDistance(m_layers[a], m_layers[b]) <=
          kReachFactor * step.maxSeedLength) {
        m_reach[a].push_back(b);
      }
    }
  }
}

void HelixFollower::follow(HelixPath& p, const Limits& limits) {
  m_limits = limits;
  while (true) {
    TransverseCircle c;
    SzState sz;
    if (!nextCrossing(p, c, sz)) {
      return;
    }
    const ConfIndex chosen = choose(p);
    addOverlapPartners(chosen, sz.t, ptOf(c));
    // The chosen hit and its overlap partners, in the order of the
    // track.
    std::sort(m_taken.begin(), m_taken.end(),
              [](const LayerHit& a, const LayerHit& b) {
                return a.arc != b.arc ? a.arc < b.arc : a.hit < b.hit;
              });
    // Past the closest approach now: the crossings ahead are the other
    // leg's.
    m_limits.fromClosestApproach = false;
    const double sLast = p.s.back();
    for (const LayerHit& lh : m_taken) {
      p.hits.push_back(lh.hit);
      p.s.push_back(sLast + lh.arc);
      p.chi2 += lh.chi2;
    }
    // nextCrossing refits the (s, z) line on the new circle's arc lengths.
  }
}

namespace {

/// The path run backwards: its hits from the last to the first, arc
/// lengths from the last hit, its (s, z) line refitted.
HelixPath reversedPath(const ConformalHits& hits, const HelixPath& p) {
  HelixPath r;
  r.hits.assign(p.hits.rbegin(), p.hits.rend());
  r.s.reserve(p.s.size());
  for (auto it = p.s.rbegin(); it != p.s.rend(); ++it) {
    r.s.push_back(p.s.back() - *it);
  }
  r.chi2 = p.chi2;
  fitPathSz(hits, r);
  return r;
}

}  // namespace

void HelixFollower::followInward(HelixPath& p, const Limits& limits) {
  // fitCircle takes the orientation from the hits' order, so follow()
  // moves the reversed path against the particle's motion.
  HelixPath reversed = reversedPath(m_hits, p);
  Limits inward = limits;
  inward.untilClosestApproach = true;
  follow(reversed, inward);
  if (reversed.hits.size() > p.hits.size()) {
    p = reversedPath(m_hits, reversed);
  }
}

void HelixFollower::followPastTurn(HelixPath& p, const Limits& limits,
                                   std::uint32_t minHits) {
  HelixPath reversed = reversedPath(m_hits, p);
  const std::size_t before = reversed.hits.size();
  Limits pastTurn = limits;
  pastTurn.untilClosestApproach = false;
  pastTurn.fromClosestApproach = true;
  follow(reversed, pastTurn);
  if (reversed.hits.size() >= before + minHits) {
    p = reversedPath(m_hits, reversed);
  }
}

ConfIndex HelixFollower::choose(const HelixPath& p) {
  std::sort(m_layerHits.begin(), m_layerHits.end(),
            [](const LayerHit& a, const LayerHit& b) {
              return a.chi2 != b.chi2 ? a.chi2 < b.chi2 : a.hit < b.hit;
            });
  if (m_layerHits.size() == 1) {
    return m_layerHits.front().hit;
  }
  // Look one crossing ahead: with noise and left-over hits around it, the
  // best hit of a crossing at low momentum (wide windows) is often not the
  // track's, and a wrong hit turns the helix away from the next layer's.
  // Each of the best few is tried and judged by its chi2 plus that of the
  // best hit at the next crossing (the step's chi2 cut when there is none).
  m_candidates = m_layerHits;
  const std::size_t tried = std::min(m_candidates.size(), kLookAheadCandidates);
  ConfIndex best = m_candidates.front().hit;
  double bestScore = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < tried; ++k) {
    const LayerHit& lh = m_candidates[k];
    m_trial = p;
    m_trial.hits.push_back(lh.hit);
    m_trial.s.push_back(p.s.back() + lh.arc);
    TransverseCircle c;
    SzState sz;
    double next = m_limits.chi2Cut;
    if (nextCrossing(m_trial, c, sz)) {
      for (const LayerHit& n : m_layerHits) {
        next = std::min(next, n.chi2);
      }
    }
    const double score = lh.chi2 + next;
    if (score < bestScore) {  // ties: the lower chi2 here (sorted)
      bestScore = score;
      best = lh.hit;
    }
  }
  m_layerHits = m_candidates;
  return best;
}

bool HelixFollower::nextCrossing(HelixPath& p, TransverseCircle& c,
                                 SzState& sz) {
  const std::size_t n = p.hits.size();
  const ConfIndex last = p.hits[n - 1];
  if (!fitCircle(m_hits, p.hits, c)) {
    return false;
  }
  // Arc lengths along the current circle, so that the s-z fit and the
  // prediction use one consistent helix.
  if (n > 3) {
    for (std::size_t k = 1; k < n; ++k) {
      const ConfIndex h0 = p.hits[k - 1];
      const ConfIndex h1 = p.hits[k];
      p.s[k] = p.s[k - 1] +
               c.arc(m_hits.x[h0], m_hits.y[h0], m_hits.x[h1], m_hits.y[h1]);
    }
    fitPathSz(m_hits, p);
  }
  sz = filterPathSz(m_hits, p, m_layers, m_step.minPt, ptOf(c));
  // Predictions and residuals follow the circle of the stretch ahead.
  const TransverseCircle cp = nextStretch(p, c, sz);
  const double pt = ptOf(c);
  const double secL = norm2(1.0, sz.t);
  const double ms0 = theta0(m_hits.layer[last], pt, sz.t);
  // The prediction's transverse error: every hit's resolution and every
  // crossed layer's scattering (theta0 / cos(lambda) in azimuth), once per
  // layer crossing (the second hit of an overlap adds no kink).
  predictionErrorInputs(m_hits, m_layers, p.hits, m_step.minPt, pt, sz.t,
                        m_errorSigma, m_errorKink);
  const bool modelled = m_error.reset(p.s, m_errorSigma, m_errorKink);
  // Without a parabola (fewer than three distinct arc lengths): the last
  // hit's error grown with the extrapolation, and the last layer's kink.
  const double lever = std::max(p.s[n - 1] - p.s[0], 1.0);
  const double sigmaLast = transverseSigma(last);
  std::uint32_t missed = 0;
  m_layerHits.clear();
  // Against the particle's motion the radius falls until the helix comes
  // closest to the beam line: the particle was produced there or before.
  // Beyond it the reversed helix climbs out again on the far side of its
  // circle, where a low-momentum track's window finds other particles'
  // hits (a 0.5 GeV strip track took a long-strip hit 760 mm out, and its
  // fit failed on the hit order).
  const double maxRadius = m_limits.untilClosestApproach
                               ? m_hits.radius[last]
                               : std::numeric_limits<double>::infinity();
  // followPastTurn: the arc length from the last hit to the closest
  // approach (the circle's point on the line from its centre to the beam
  // line), before which the crossings are the blind leg's.
  double turnArc = -1.0;
  if (m_limits.fromClosestApproach) {
    const double cn = norm2(cp.cx, cp.cy);
    if (cn > 0.0) {
      turnArc =
          cp.arc(m_hits.x[last], m_hits.y[last], cp.cx - cp.rho * cp.cx / cn,
                 cp.cy - cp.rho * cp.cy / cn);
      // Behind the last hit (a look-ahead from a hit past the turn): no
      // crossing ahead is the blind leg's.
      if (turnArc > std::numbers::pi * cp.rho) {
        turnArc = -1.0;
      }
    }
  }
  for (const Crossing& x : m_crossings) {
    const double rCross = norm2(x.x, x.y);
    if (rCross > maxRadius) {
      break;
    }
    if (x.ds < turnArc) {
      continue;
    }
    const double ratio = x.ds / lever;
    const double growth = sigmaLast * (1.0 + ratio * ratio);
    const double kinkLast = ms0 * secL * x.ds;
    // The least-squares parabola can predict better than the last hit's
    // own error only with many hits; that floor keeps the former estimate.
    const double transverse =
        modelled ? std::max(growth * growth, m_error.resolutionVariance(x.ds)) +
                       m_error.scatteringVariance(x.ds)
                 : growth * growth + kinkLast * kinkLast;
    // The filtered z's own error, and the scattering in the last layer
    // (its slope's variance holds that layer's only once it is left).
    const double msLast = ms0 * secL * secL * x.ds;
    const double extrapZ = std::sqrt(sz.varAt(x.ds) + msLast * msLast);
    const SensitiveLayer& l = m_layers[x.layer];
    double varPhi = l.sigmaU * l.sigmaU + transverse;
    double varV = l.sigmaV * l.sigmaV + extrapZ * extrapZ;
    if (l.isDisk()) {
      // On a disk the transverse errors of the prediction move the
      // crossing radially as much as in azimuth, and an error in the
      // slope moves it along the track.
      varV = l.sigmaV * l.sigmaV + transverse +
             extrapZ * extrapZ / std::max(sz.t * sz.t, 0.01);
    }
    // The crossing is that of the layer's nominal surface; its sensors
    // lie up to overlapMaxGap from it along the normal, where the track
    // is displaced along the layer by the gap over the cosine of its
    // crossing angle. The window covers that; the residuals below are
    // taken at the hit itself.
    const double tx = -cp.orientation * (x.y - cp.cy) / cp.rho;
    const double ty = cp.orientation * (x.x - cp.cx) / cp.rho;
    const double radialT =
        std::abs(tx * x.x + ty * x.y) / std::max(rCross, 1e-9);
    const double alongT = std::sqrt(std::max(0.0, 1.0 - radialT * radialT));
    if (l.isDisk()) {
      // A disk's radial resolution (a strip's length: 0.35 mm and 3 mm in
      // TrackML's strip disks) lies across a track that runs alongT across
      // the radius: a 0.3 GeV track reaches the strip disks at 30-60
      // degrees to the radius.
      varPhi += l.sigmaV * l.sigmaV * alongT * alongT;
    }
    const double normalT = l.isDisk() ? std::abs(sz.t) : radialT;
    const double ds = m_state.config.overlapMaxGap / std::max(normalT, 1e-3);
    const double maxArc = m_state.config.overlapMaxArc;
    const double offsetPhi = std::min(maxArc, ds * alongT);
    const double offsetV =
        std::min(maxArc, ds * (l.isDisk() ? radialT : std::abs(sz.t)));
    const double halfPhi =
        (std::max(kMinWindow, kWindowSigmas * std::sqrt(varPhi)) + offsetPhi) /
        std::max(rCross, 1.0);
    const double halfV =
        std::max(kMinWindow, kWindowSigmas * std::sqrt(varV)) + offsetV;
    m_window.clear();
    m_pool.layerBox(x.layer, std::atan2(x.y, x.x), halfPhi, x.z - halfV,
                    x.z + halfV, rCross - halfV, rCross + halfV, m_window);
    for (ConfIndex h : m_window) {
      if (m_state.used[h] != 0 || onPath(h, p)) {
        continue;
      }
      // The hit itself, too: a disk's window reaches along the radius.
      if (m_hits.radius[h] >= maxRadius) {
        continue;
      }
      // Distance from the circle across the track, and z against the
      // helix at the hit's own arc length.
      const double rPhi =
          norm2(m_hits.x[h] - cp.cx, m_hits.y[h] - cp.cy) - cp.rho;
      double arc =
          cp.arc(m_hits.x[last], m_hits.y[last], m_hits.x[h], m_hits.y[h]);
      if (arc > std::numbers::pi * cp.rho) {
        arc -= 2.0 * std::numbers::pi * cp.rho;  // just behind the last hit
      }
      const double dz = m_hits.z[h] - sz.zAt(arc);
      // On a disk v is radial: a z residual dz is a shift dz / t along
      // the track, radialT of it in radius.
      const double rV =
          l.isDisk() ? dz * radialT / std::max(std::abs(sz.t), 0.1) : dz;
      const double chi2 = rPhi * rPhi / varPhi + rV * rV / varV;
      if (chi2 > m_limits.chi2Cut) {
        continue;
      }
      m_layerHits.push_back({h, chi2, arc, rPhi, dz});
    }
    if (!m_layerHits.empty()) {
      return true;
    }
    // A layer the track already has a hit on is crossed again at its
    // nominal surface next to that hit: the second sensor of an overlap
    // is optional (addOverlapPartners takes its hit with the first),
    // not a missed layer.
    if (x.inside && !onLayerOf(x.layer, p) &&
        ++missed > m_limits.maxMissedLayers) {
      return false;
    }
  }
  return false;
}

TransverseCircle HelixFollower::nextStretch(const HelixPath& p,
                                            const TransverseCircle& c,
                                            const SzState& sz) {
  const ConfIndex last = p.hits.back();
  const double z0 = sz.z - sz.t * p.s.back();
  const MagneticField& field = m_state.detector.field();
  if (field.isUniform()) {
    predict(last, p.s.back(), z0, sz.t, c, m_crossings);
    return c;
  }
  // The field's bending (MagneticField::bendingComponent) along the
  // circle's direction at a point.
  auto bendingAt = [&](double x, double y, double z) {
    const double rx = x - c.cx;
    const double ry = y - c.cy;
    const double rn = std::max(norm2(rx, ry), 1e-9);
    const Vector3 direction(-c.orientation * ry / rn, c.orientation * rx / rn,
                            sz.t);
    return std::abs(
        MagneticField::bendingComponent(field.at(Vector3(x, y, z)), direction));
  };
  double fitted = 0.0;
  for (ConfIndex h : p.hits) {
    fitted += bendingAt(m_hits.x[h], m_hits.y[h], m_hits.z[h]);
  }
  fitted /= static_cast<double>(p.hits.size());
  const double atLast =
      bendingAt(m_hits.x[last], m_hits.y[last], m_hits.z[last]);
  // The circle through the last hit's point of c with its direction there
  // and the radius of the fitted curvature in the bending b.
  auto rescaled = [&](double b) {
    const double k = fitted / std::max(b, 1e-3 * fitted);
    TransverseCircle out = c;
    out.cx = m_hits.x[last] + (c.cx - m_hits.x[last]) * k;
    out.cy = m_hits.y[last] + (c.cy - m_hits.y[last]) * k;
    out.rho = c.rho * k;
    return out;
  };
  TransverseCircle out = rescaled(atLast);
  predict(last, p.s.back(), z0, sz.t, out, m_crossings);
  for (const Crossing& x : m_crossings) {
    if (x.inside) {
      out = rescaled(0.5 * (atLast + bendingAt(x.x, x.y, x.z)));
      predict(last, p.s.back(), z0, sz.t, out, m_crossings);
      break;
    }
  }
  return out;
}

bool HelixFollower::skipsLayer(const HelixPath& p, const TransverseCircle& c) {
  // Only the crossings before the seed's last hit matter: most of the
  // pool's layers lie further than that (predicting them for every
  // triplet was 9 % of the helix steps' work on a real TrackML event).
  predict(p.hits[0], 0.0, p.z0, p.t, c, m_crossings, p.s[2]);
  for (const Crossing& x : m_crossings) {
    if (x.ds >= p.s[2] - 1e-6) {
      break;
    }
    // The seed's own layers are crossed at their nominal surface, which
    // can lie a few mm from the sensor that holds the hit.
    if (x.inside && !onLayerOf(x.layer, p)) {
      return true;
    }
  }
  return false;
}

void HelixFollower::predict(ConfIndex from, double sFrom, double z0, double t,
                            const TransverseCircle& c,
                            std::vector<Crossing>& out, double maxArc) {
  out.clear();
  // The helix through the hit along the circle's tangent there (the
  // crossings are geometry's, shared with the simulation and the fit).
  const double rx = m_hits.x[from] - c.cx;
  const double ry = m_hits.y[from] - c.cy;
  const double rn = norm2(rx, ry);
  if (!(rn > 0.0)) {
    return;
  }
  const double pt = ptOf(c);
  const Vector3 momentum(-c.orientation * ry / rn * pt,
                         c.orientation * rx / rn * pt, t * pt);
  // Counter-clockwise motion is negative curvature in a positive field.
  const Helix helix(Vector3(m_hits.x[from], m_hits.y[from], z0 + t * sFrom),
                    momentum, -c.orientation, std::abs(m_state.bzForPt));
  // A path spans at most half a turn from its first hit: beyond it lies
  // the incoming leg of a looper, which real simulations end (TrackML's
  // loop protection stops particles after half a turn from production)
  // and where the circle's orientation from its first, middle and last
  // hits (fitCircle) and the arc lengths would be ambiguous. Noise hits on
  // that leg otherwise lengthen a correct path into one the fit rejects.
  // The crossings' arc lengths are searched up to sMax; a bound tighter
  // than the half-turn filters them without changing any
  // (Helix::nextCylinderCrossing, nextDiskCrossing).
  const double sMax = std::min(std::numbers::pi * c.rho - sFrom, maxArc);
  if (!(sMax > kMinStep)) {
    return;
  }
  // The transverse arc to a cylinder is at least the radial distance to it.
  const double rFrom = norm2(m_hits.x[from], m_hits.y[from]);
  auto add = [&](std::uint32_t layer, double ds, bool disk) {
    const SensitiveLayer& l = m_layers[layer];
    const Vector3 x = helix.position(ds);
    const double r = x.head<2>().norm();
    const bool inside =
        disk ? r > l.rMin + kHelixEdgeMargin && r < l.rMax - kHelixEdgeMargin
             : x.z() > l.zMin + kHelixEdgeMargin &&
                   x.z() < l.zMax - kHelixEdgeMargin;
    out.push_back({layer, ds, x.x(), x.y(), x.z(), inside});
  };
  for (std::uint32_t layer : m_reach[m_hits.layer[from]]) {
    const SensitiveLayer& l = m_layers[layer];
    if (l.isDisk()) {
      if (layer == m_hits.layer[from]) {
        continue;
      }
      const double ds = helix.nextDiskCrossing(
          l.z(), l.rMin - kLayerMargin, l.rMax + kLayerMargin, kMinStep, sMax);
      if (ds != Helix::kNoCrossing) {
        add(layer, ds, true);
      }
      continue;
    }
    if (std::abs(l.r - rFrom) > sMax + kMinStep) {
      continue;
    }
    // A barrel layer may be crossed twice within the half-turn (out and
    // back in, or its own layer again).
    double after = kMinStep;
    for (int k = 0; k < 2; ++k) {
      const double ds = helix.nextCylinderCrossing(
          l.r, l.zMin - kLayerMargin, l.zMax + kLayerMargin, after, sMax);
      if (ds == Helix::kNoCrossing) {
        break;
      }
      add(layer, ds, false);
      after = ds;
    }
  }
  std::sort(out.begin(), out.end(), [](const Crossing& a, const Crossing& b) {
    return a.ds != b.ds ? a.ds < b.ds : a.layer < b.layer;
  });
}

void HelixFollower::addOverlapPartners(ConfIndex chosen, double t, double pt) {
  m_taken.clear();
  const double deflection = theta0(m_hits.layer[chosen], pt, t);
  const LayerHit first =
      *std::find_if(m_layerHits.begin(), m_layerHits.end(),
                    [&](const LayerHit& lh) { return lh.hit == chosen; });
  m_taken.push_back(first);
  for (const LayerHit& lh : m_layerHits) {
    if (m_taken.size() >= kMaxHitsPerCrossing) {
      break;
    }
    if (m_hits.layer[lh.hit] != m_hits.layer[chosen] ||
        std::any_of(m_taken.begin(), m_taken.end(), [&](const LayerHit& t) {
          return m_hits.sameSensor(t.hit, lh.hit);
        })) {
      continue;
    }
    if (pairChi2(chosen, lh.hit, lh.rPhi - first.rPhi, lh.dz - first.dz, t,
                 deflection) <= m_state.config.overlapMaxChi2) {
      m_taken.push_back(lh);
    }
  }
}

void HelixFollower::addSeedPartners(HelixPath& p) {
  TransverseCircle c;
  if (p.hits.size() < 3 || !fitCircle(m_hits, p.hits, c)) {
    return;
  }
  const double maxArc = m_state.config.overlapMaxArc;
  const double window = maxArc + kMinWindow;
  std::vector<OverlapCandidate> partners;
  std::vector<std::pair<double, ConfIndex>> added;
  for (std::size_t k = 0; k < kSeedHits; ++k) {
    const ConfIndex a = p.hits[k];
    const std::uint32_t layer = m_hits.layer[a];
    std::size_t onLayer = 0;
    for (ConfIndex h : p.hits) {
      onLayer += m_hits.layer[h] == layer ? 1 : 0;
    }
    for (const auto& [s, h] : added) {
      onLayer += m_hits.layer[h] == layer ? 1 : 0;
    }
    if (onLayer >= kMaxHitsPerCrossing) {
      continue;
    }
    const double ra = std::max(m_hits.radius[a], 1.0);
    const double deflection = theta0(layer, ptOf(c), p.t);
    const double rPhiA = norm2(m_hits.x[a] - c.cx, m_hits.y[a] - c.cy) - c.rho;
    m_window.clear();
    m_pool.layerBox(layer, m_hits.phi[a], std::min(1.0, window / ra),
                    m_hits.z[a] - window, m_hits.z[a] + window, ra - window,
                    ra + window, m_window);
    partners.clear();
    for (ConfIndex h : m_window) {
      if (m_state.used[h] != 0 || m_hits.layer[h] != layer || onPath(h, p) ||
          std::any_of(p.hits.begin(), p.hits.end(),
                      [&](ConfIndex q) { return m_hits.sameSensor(q, h); }) ||
          std::any_of(added.begin(), added.end(), [&](const auto& q) {
            return m_hits.sameSensor(q.second, h);
          })) {
        continue;
      }
      double arc = c.arc(m_hits.x[a], m_hits.y[a], m_hits.x[h], m_hits.y[h]);
      if (arc > std::numbers::pi * c.rho) {
        arc -= 2.0 * std::numbers::pi * c.rho;  // before the seed hit
      }
      if (!(std::abs(arc) <= maxArc)) {
        continue;
      }
      const double dPerp =
          norm2(m_hits.x[h] - c.cx, m_hits.y[h] - c.cy) - c.rho - rPhiA;
      const double dz = m_hits.z[h] - m_hits.z[a] - p.t * arc;
      const double chi2 = pairChi2(a, h, dPerp, dz, p.t, deflection);
      if (chi2 <= m_state.config.overlapMaxChi2) {
        partners.push_back({m_hits.module[h], chi2, h, p.s[k] + arc});
      }
    }
    keepBestPerSensor(partners);
    for (const OverlapCandidate& q : partners) {
      if (onLayer >= kMaxHitsPerCrossing) {
        break;
      }
      added.emplace_back(q.s, q.hit);
      p.chi2 += q.chi2;
      ++onLayer;
    }
  }
  if (added.empty()) {
    return;
  }
  for (std::size_t k = 0; k < p.hits.size(); ++k) {
    added.emplace_back(p.s[k], p.hits[k]);
  }
  std::sort(added.begin(), added.end());
  // Arc lengths count from the path's first hit.
  const double s0 = added.front().first;
  p.hits.clear();
  p.s.clear();
  for (const auto& [s, h] : added) {
    p.hits.push_back(h);
    p.s.push_back(s - s0);
  }
  fitPathSz(m_hits, p);
}

double HelixFollower::pairChi2(ConfIndex a, ConfIndex h, double dPerp,
                               double dz, double t, double deflection) const {
  const double sigmaA = transverseSigma(a);
  const double sigmaH = transverseSigma(h);
  const double scatter = overlapScatteringVariance(m_hits, a, h, deflection);
  const double varPerp = sigmaA * sigmaA + sigmaH * sigmaH + scatter +
                         kOverlapFloor * kOverlapFloor;
  // On disks z is exact and the arc length carries the radial error.
  const double varZ = m_hits.varZ[a] + m_hits.varZ[h] +
                      t * t * (m_hits.varRxy[a] + m_hits.varRxy[h]) +
                      scatter * (1.0 + t * t) + kOverlapFloor * kOverlapFloor;
  return dPerp * dPerp / varPerp + dz * dz / varZ;
}

double HelixFollower::transverseSigma(ConfIndex h) const {
  return detail::transverseSigma(m_hits, h);
}

bool HelixFollower::onLayerOf(std::uint32_t layer, const HelixPath& p) const {
  return std::any_of(p.hits.begin(), p.hits.end(),
                     [&](ConfIndex h) { return m_hits.layer[h] == layer; });
}

bool HelixFollower::onPath(ConfIndex h, const HelixPath& p) {
  return std::find(p.hits.begin(), p.hits.end(), h) != p.hits.end();
}

double HelixFollower::theta0(std::uint32_t layer, double pt, double t) const {
  return helixTheta0(m_layers[layer], m_step.minPt, pt, t);
}

double HelixFollower::ptOf(const TransverseCircle& c) const {
  return circlePt(c, m_state.bzForPt);
}

}  // namespace conftrack::detail

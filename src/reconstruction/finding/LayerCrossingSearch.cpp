// The machinery shared by the extension units and the hole filling
// (detail/LayerCrossingSearch.hpp): refits of a growing track, predicted
// layer crossings, bounded hit windows, the scattering allowance.

#include "conftrack/reconstruction/finding/detail/LayerCrossingSearch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace conftrack::detail {

namespace {

/// Margin around a layer's extent when predicting crossings [mm].
constexpr double kLayerMargin = 10.0;

/// Where the circle of `arc` meets the circle of `radius` about the origin,
/// on the `sign` (+1 or -1) side of the line from the origin to its
/// centre; false if the two do not meet.
bool meetRadius(const ArcFrame& arc, double radius, int sign, double& x,
                double& y) {
  const double d = norm2(arc.centreX, arc.centreY);
  const double rho = arc.radius;
  if (d < 1e-9 || radius > d + rho || radius < std::abs(d - rho)) {
    return false;
  }
  const double a = (radius * radius - rho * rho + d * d) / (2.0 * d);
  const double h = std::sqrt(std::max(0.0, radius * radius - a * a));
  const double ex = arc.centreX / d;
  const double ey = arc.centreY / d;
  x = a * ex - sign * h * ey;
  y = a * ey + sign * h * ex;
  return true;
}

/// The arc length of a crossing is known up to whole turns (of length
/// `turn`): the one just beyond the end hit at `sLast` in the direction of
/// the search.
double arcAfter(double turn, double s, double sLast, bool inward) {
  if (inward) {
    while (s >= sLast - 1e-6) {
      s -= turn;
    }
    return s;
  }
  while (s <= sLast + 1e-6) {
    s += turn;
  }
  return s;
}

}  // namespace

bool LayerCrossingSearch::begin(const TrackCandidate& track,
                                Chain& chain) const {
  if (track.hits.size() < 3 || track.helix) {
    return false;
  }
  chain.quadratic = track.uv.quadratic;
  chain.hits = track.hits;
  return refit(chain, &track.uv);
}

bool LayerCrossingSearch::refit(Chain& c,
                                const ConformalFitResult* frame) const {
  ConformalFitResult uv = fitConformal(m_hits, c.hits, c.quadratic, frame);
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

double LayerCrossingSearch::increase(double chi2, int ndf, double delta) {
  double before = ndf > 0 ? chi2 / ndf : 0.0;
  return (chi2 + delta) / (ndf + 1) - before;
}

Scatter LayerCrossingSearch::scatter(const ConformalFitResult& uv,
                                     const SzFitResult& sz, ConfIndex from,
                                     ConfIndex to, double ds) const {
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

bool LayerCrossingSearch::onSensorOf(const std::vector<ConfIndex>& hits,
                                     ConfIndex h) const {
  for (ConfIndex k : hits) {
    if (m_hits.sameSensor(k, h)) {
      return true;
    }
  }
  return false;
}

const std::vector<ConfIndex>& LayerCrossingSearch::coneWindow(
    std::uint32_t layer, double phi, double halfWidth,
    const HitPool::RzCone* cone, const Vector3& at) {
  m_scratch.window.clear();
  m_pool.layerWindow(layer, phi, halfWidth, m_scratch.window, cone);
  limitWindow(at);
  return m_scratch.window;
}

const std::vector<ConfIndex>& LayerCrossingSearch::boxWindow(
    std::uint32_t layer, double phi, double halfWidth, double zLo, double zHi,
    double rLo, double rHi, const Vector3& at) {
  m_scratch.window.clear();
  m_pool.layerBox(layer, phi, halfWidth, zLo, zHi, rLo, rHi, m_scratch.window);
  limitWindow(at);
  return m_scratch.window;
}

void LayerCrossingSearch::limitWindow(const Vector3& at) {
  std::vector<ConfIndex>& window = m_scratch.window;
  std::vector<std::pair<double, ConfIndex>>& distances = m_scratch.distances;
  const std::size_t limit = m_maxWindowHits;
  if (window.size() <= limit) {
    return;
  }
  m_stats.guard(Guard::eWindowHits).add(window.size() - limit);
  distances.clear();
  for (ConfIndex h : window) {
    const double dx = m_hits.x[h] - at.x();
    const double dy = m_hits.y[h] - at.y();
    const double dz = m_hits.z[h] - at.z();
    distances.emplace_back(dx * dx + dy * dy + dz * dz, h);
  }
  std::nth_element(distances.begin(),
                   distances.begin() + static_cast<std::ptrdiff_t>(limit),
                   distances.end());
  window.resize(limit);
  for (std::size_t k = 0; k < limit; ++k) {
    window[k] = distances[k].second;
  }
}

SearchStart LayerCrossingSearch::start(const ArcFrame& arc,
                                       const SzFitResult& sz, double sLast,
                                       Direction direction) {
  SearchStart from{arc, sz, sLast, direction,
                   std::numeric_limits<double>::infinity()};
  if (direction == Direction::eInward) {
    return from;
  }
  // Outward, the track ends where its circle first leaves the tracker
  // (docs/algorithm.md 3.18).
  double& ro = m_scratch.outerRadius;
  if (ro < 0.0) {
    ro = 0.0;
    for (const SensitiveLayer& o : m_state.detector.layers()) {
      ro = std::max(ro, o.isDisk() ? o.rMax : o.r);
    }
    ro += kLayerMargin;
  }
  const double turn = 2.0 * std::numbers::pi * arc.radius;
  for (int sign : {1, -1}) {
    double x = 0.0;
    double y = 0.0;
    if (meetRadius(arc, ro, sign, x, y)) {
      from.sExit = std::min(
          from.sExit, arcAfter(turn, arc.arcLength(x, y, sLast), sLast, false));
    }
  }
  // Where the data's particles end after a fraction of a turn
  // (FinderConfig::maxTrackTurns), measured from the track's first hit.
  if (m_state.config.maxTrackTurns > 0.0) {
    from.sExit = std::min(from.sExit, m_state.config.maxTrackTurns * turn);
  }
  return from;
}

const std::vector<Prediction>& LayerCrossingSearch::predict(
    std::uint32_t layer, const SearchStart& from, Branches branches) {
  std::vector<Prediction>& out = m_scratch.predictions;
  out.clear();
  const ArcFrame& arc = from.arc;
  const SzFitResult& sz = from.sz;
  const double sLast = from.sLast;
  const double sExit = from.sExit;
  const bool inward = from.direction == Direction::eInward;
  const SensitiveLayer& l = m_state.detector.layers()[layer];
  const double turn = 2.0 * std::numbers::pi * arc.radius;
  auto after = [&](double s) { return arcAfter(turn, s, sLast, inward); };
  // In a non-uniform field the circle is the track's in the conformal map
  // of makeConformalHits: it passes the azimuth of a crossing at radius
  // g r, and the arc length of the crossing is that of the mapped point
  // over g (ArcFrame::hitArcLength, as for the hits of the (s, z) fit).
  const PromptBending* bending = m_state.bending;
  if (!l.isDisk()) {
    // The circle with the cylinder's (of radius g r in the map).
    for (int sign : {1, -1}) {
      double px = 0.0;
      double py = 0.0;
      if (!meetRadius(arc, l.r, sign, px, py)) {
        continue;
      }
      double s = after(arc.arcLength(px, py, sLast));
      if (bending != nullptr) {
        const double g = bending->factor(l.r, sz.z0 + sz.tanLambda * s);
        if (!meetRadius(arc, l.r * g, sign, px, py)) {
          continue;
        }
        s = after(arc.arcLength(px, py, s * g) / g);
      }
      if (s > sExit) {
        continue;
      }
      if (branches == Branches::eOutgoing && std::abs(s - sLast) > 0.5 * turn) {
        continue;  // the crossing on the way back in
      }
      double z = sz.z0 + sz.tanLambda * s;
      if (z < l.zMin - kLayerMargin || z > l.zMax + kLayerMargin) {
        continue;
      }
      out.push_back({s, std::atan2(py, px)});
    }
  } else {
    if (std::abs(sz.tanLambda) < 1e-9) {
      return out;
    }
    double s = (l.z() - sz.z0) / sz.tanLambda;
    bool ahead = inward ? s < sLast : s > sLast;
    if (!ahead || std::abs(s - sLast) > turn || s > sExit) {
      return out;
    }
    Vector2 p = arc.pointAt(s);
    double r = p.norm();
    if (bending != nullptr) {
      // The point of the circle at mapped arc length g s (hitArcLength),
      // g taken at its own radius r = |p| / g.
      double g = bending->factor(r, l.z());
      for (int iteration = 0; iteration < 3; ++iteration) {
        p = arc.pointAt(s * g);
        r = p.norm() / g;
        g = bending->factor(r, l.z());
      }
    }
    if (r < l.rMin - kLayerMargin || r > l.rMax + kLayerMargin) {
      return out;
    }
    out.push_back({s, std::atan2(p.y(), p.x())});
  }
  return out;
}

void claimHit(FinderState& state, StepStats& stats, ConfIndex h,
              std::uint32_t t) {
  state.used[h] = 1;
  state.clones.addHit(h, t);
  ++stats.extendedHits;
}

void storeChain(const FinderState& state, const Chain& chain,
                TrackCandidate& track) {
  track.hits = chain.hits;
  track.uv = chain.uv;
  track.sz = chain.sz;
  track.pt = chain.uv.pt(state.bzForPt);
}

void throwBadKey(std::string_view unit, std::string_view key,
                 std::string_view what, double value) {
  throw std::invalid_argument(std::string(unit) + ": key '" + std::string(key) +
                              "' " + std::string(what) + " (got " +
                              std::to_string(value) + ")");
}

}  // namespace conftrack::detail

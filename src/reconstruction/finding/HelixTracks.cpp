// Helix-triplet building of displaced tracks (a conftrack addition; the
// paper and upstream have no such step).
//
// The conformal map is taken about the beam line: a track's circle maps to
// a line only if it passes through the origin, and to a circle of radius
// about 1 / (2 d0) otherwise. Particles produced tens of mm or more from the
// beam line (secondaries of the material, decays) have impact parameters
// comparable to the radii of the layers they cross, so their hits are far
// from any line or parabola in (u, v) and the cellular automaton cannot
// build them. This builder works in real space instead:
// - Seeds are triplets of unused hits on consecutive layers (the straight
//   line between two seed hits must not pass well inside another layer),
//   each within maxSeedLength of the previous one and further out (larger
//   radius on a barrel layer, larger |z| on a disk). The third hit is
//   searched only around the doublet's chord extended to the next layer,
//   as wide as a track of pT >= minPt can bend. The circle through the
//   three, with no beam-line constraint, must have pT >= minPt (within the
//   error of a three-hit curvature) and |d0| <= maxD0, and the slopes of its
//   two segments in the (s, z) plane, where a helix is straight, must agree
//   within maxCellAngleRZ plus three standard deviations of multiple
//   scattering and resolution.
// - The straightest triplets of a seed hit (at most maxSeedCells) are
//   followed outwards along the helix of the circle fitted to all their hits
//   and the straight-line fit of z versus arc length. At the first predicted
//   layer crossing with compatible hits, the one with the lowest chi2 is
//   added; the chi2 has the hit resolution, the multiple scattering in the
//   last layer (Highland) and the extrapolation error of the fit. At most
//   maxMissedLayers crossings well inside a layer pass without a hit.
// - Of the candidates of one seed hit with at least minHits hits, the
//   longest (then lowest chi2 per hit) is kept and claims its hits at once;
//   seed hits are taken innermost first, so the result does not depend on
//   the input order.
// - Once the triplets of the step exceed FinderConfig::maxCellsPerHit per
//   pool hit, the remaining seed hits are skipped (counted): the triplets
//   of a seed grow with the square of the hit density.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Helix.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack::detail {

namespace {

/// Margin around a layer's extent when predicting crossings [mm].
constexpr double kLayerMargin = 5.0;
/// Search windows extend this many standard deviations around a
/// prediction; the chi2 cut decides.
constexpr double kWindowSigmas = 5.0;
/// A crossing this far inside a layer's edges without a hit is a miss [mm].
constexpr double kEdgeMargin = 10.0;
/// Crossings nearer than this to the last hit are that hit's own [mm].
constexpr double kMinStep = 0.5;
/// Extensions look for the next hit on layers up to this many times
/// maxSeedLength away (seed hits are at most maxSeedLength apart).
constexpr double kReachFactor = 4.0;
/// A seed's third hit is searched on the first layer crossed and on those
/// at most this much further along the chord [mm] (double layers,
/// overlapping barrel and disk edges).
constexpr double kFirstLayerSlack = 20.0;
/// At most this many hits (one per sensor) are taken at one layer
/// crossing: TrackML's innermost pixel-disk rings overlap three deep.
constexpr std::size_t kMaxHitsPerCrossing = 3;
/// Alignment floor of the residual difference of two overlap hits [mm].
constexpr double kOverlapFloor = 0.05;
/// Smallest window half-width around a predicted crossing [mm].
constexpr double kMinWindow = 0.5;

/// A circle in the transverse plane with a direction of motion.
struct Circle {
  double cx = 0.0;
  double cy = 0.0;
  double rho = 0.0;
  int orientation = 1;  ///< +1 counter-clockwise

  /// Arc length from point a to point b along the motion, in [0, 2 pi rho).
  double arc(double ax, double ay, double bx, double by) const {
    const double pax = ax - cx;
    const double pay = ay - cy;
    const double pbx = bx - cx;
    const double pby = by - cy;
    double angle =
        orientation * std::atan2(pax * pby - pay * pbx, pax * pbx + pay * pby);
    if (angle < 0.0) {
      angle += 2.0 * std::numbers::pi;
    }
    return rho * angle;
  }
  /// Distance of closest approach to the beam line.
  double d0() const { return std::abs(norm2(cx, cy) - rho); }
};

/// The circle through three points, oriented from the first to the last;
/// false if they are (numerically) on a line.
bool circleThrough(double x1, double y1, double x2, double y2, double x3,
                   double y3, Circle& out) {
  const double ax = x2 - x1;
  const double ay = y2 - y1;
  const double bx = x3 - x1;
  const double by = y3 - y1;
  const double cross = ax * by - ay * bx;
  const double a2 = ax * ax + ay * ay;
  const double b2 = bx * bx + by * by;
  // |cross| = |a| |b| sin(angle): below 1e-12 the radius exceeds any
  // detector by far and the centre is numerically meaningless.
  if (!(std::abs(cross) > 1e-12 * std::sqrt(a2 * b2))) {
    return false;
  }
  const double d = 2.0 * cross;
  const double ux = (by * a2 - ay * b2) / d;
  const double uy = (ax * b2 - bx * a2) / d;
  out.cx = x1 + ux;
  out.cy = y1 + uy;
  out.rho = norm2(ux, uy);
  out.orientation = cross > 0.0 ? 1 : -1;
  return true;
}

/// Least-squares circle through points (algebraic distance, Kasa): exact
/// for three points; false if degenerate or (numerically) straight.
/// `orientation` comes from the first, middle and last points.
bool fitCircle(const ConformalHits& hits, const std::vector<ConfIndex>& idx,
               Circle& out) {
  const std::size_t n = idx.size();
  if (n == 3) {
    return circleThrough(hits.x[idx[0]], hits.y[idx[0]], hits.x[idx[1]],
                         hits.y[idx[1]], hits.x[idx[2]], hits.y[idx[2]], out);
  }
  // Centred on the first point for conditioning.
  const double x0 = hits.x[idx[0]];
  const double y0 = hits.y[idx[0]];
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (ConfIndex h : idx) {
    const double x = hits.x[h] - x0;
    const double y = hits.y[h] - y0;
    const Eigen::Vector3d row(x, y, 1.0);
    const double rhs = -(x * x + y * y);
    a += row * row.transpose();
    b += row * rhs;
  }
  const Eigen::Vector3d sol = a.ldlt().solve(b);
  if (!sol.allFinite()) {
    return false;
  }
  const double cx = -0.5 * sol(0);
  const double cy = -0.5 * sol(1);
  const double r2 = cx * cx + cy * cy - sol(2);
  if (!(r2 > 0.0) || r2 > 1e16) {
    return false;
  }
  const ConfIndex m = idx[n / 2];
  const ConfIndex e = idx[n - 1];
  const double cross =
      (hits.x[m] - x0) * (hits.y[e] - y0) - (hits.y[m] - y0) * (hits.x[e] - x0);
  out.cx = x0 + cx;
  out.cy = y0 + cy;
  out.rho = std::sqrt(r2);
  out.orientation = cross > 0.0 ? 1 : -1;
  return true;
}

/// Smallest distance between two layers' extents [mm].
double layerDistance(const SensitiveLayer& a, const SensitiveLayer& b) {
  auto gap = [](double lo1, double hi1, double lo2, double hi2) {
    return std::max({0.0, lo2 - hi1, lo1 - hi2});
  };
  const double dz = gap(a.zMin, a.zMax, b.zMin, b.zMax);
  const double dr = gap(a.rMin, a.rMax, b.rMin, b.rMax);
  return norm2(dz, dr);
}

/// A candidate being followed: hits with their arc lengths along the
/// track, and the straight-line fit z = z0 + t s.
struct Path {
  std::vector<ConfIndex> hits;
  std::vector<double> s;
  double chi2 = 0.0;
  double z0 = 0.0;
  double t = 0.0;
};

/// The track's z and slope dz/ds after its last hit, filtered hit by hit
/// along s with the multiple scattering of each layer crossed (a Kalman
/// filter in the (s, z) plane): unlike one straight line through all hits,
/// it follows the slope changes that scattering makes at low momentum.
struct SzState {
  double z = 0.0;
  double t = 0.0;
  double varZ = 0.0;
  double covZt = 0.0;
  double varT = 0.0;

  /// Predicted z a distance ds further along, and its variance.
  double zAt(double ds) const { return z + t * ds; }
  double varAt(double ds) const {
    return varZ + 2.0 * ds * covZt + ds * ds * varT;
  }
};

/// A seed: three hits, their circle, and the (s, z) kink in units of its
/// expected spread.
struct Triplet {
  Path path;
  Circle circle;
  double kink = 0.0;
};

/// A hit compatible with a predicted layer crossing: its chi2, arc length
/// from the track's last hit, distance from the circle and z residual.
struct LayerHit {
  ConfIndex hit;
  double chi2;
  double arc;
  double rPhi;
  double dz;
};

/// A predicted crossing of a layer.
struct Crossing {
  std::uint32_t layer;
  double ds;  ///< arc length from the last hit
  double x, y, z;
  bool inside;  ///< well inside the layer's extent
};

class HelixBuilder {
 public:
  HelixBuilder(FinderState& state, const FindingStep& step,
               std::uint16_t stepIndex, const HitPool& pool, StepStats& stats)
      : m_state(state),
        m_hits(state.hits),
        m_layers(state.detector.layers()),
        m_step(step),
        m_stepIndex(stepIndex),
        m_pool(pool),
        m_stats(stats),
        m_minRho(step.minPt /
                 (constants::kPtPerTeslaMm * std::abs(state.bzForPt))) {
    m_maxTheta0.resize(m_layers.size());
    for (std::uint32_t a : m_pool.layers()) {
      m_maxTheta0[a] = theta0(a, step.minPt, 0.0);
    }
    // The pool's layers within maxSeedLength of each layer: the only ones
    // a seed or an extension looks at.
    const std::vector<std::uint32_t>& layers = m_pool.layers();
    m_near.resize(m_layers.size());
    m_reach.resize(m_layers.size());
    for (std::uint32_t a : layers) {
      for (std::uint32_t b : layers) {
        const double d = layerDistance(m_layers[a], m_layers[b]);
        if (d <= step.maxSeedLength) {
          m_near[a].push_back(b);
        }
        if (d <= kReachFactor * step.maxSeedLength) {
          m_reach[a].push_back(b);
        }
      }
    }
  }

  void run() {
    // The step's work budget (FinderConfig::maxCellsPerHit), in triplets:
    // their number per seed grows with the square of the hit density.
    const double budget =
        double(m_state.config.maxCellsPerHit) * double(m_pool.members().size());
    const std::vector<ConfIndex>& members = m_pool.members();
    for (std::size_t k = 0; k < members.size(); ++k) {
      const ConfIndex seed = members[k];
      if (m_state.used[seed] != 0 || !seedAllowed(seed)) {
        continue;
      }
      if (double(m_stats.cells) > budget) {
        std::uint64_t skipped = 0;
        for (std::size_t j = k; j < members.size(); ++j) {
          skipped += m_state.used[members[j]] == 0 && seedAllowed(members[j]);
        }
        m_stats.guard(Guard::eCellsPerHit).add(skipped);
        break;
      }
      ++m_stats.seeds;
      Path best;
      followSeed(seed, best);
      if (best.hits.size() < m_step.minHits) {
        continue;
      }
      accept(best);
    }
  }

 private:
  bool seedAllowed(ConfIndex h) const {
    const auto& seeds = m_step.seedCollections;
    return seeds.empty() || std::find(seeds.begin(), seeds.end(),
                                      m_hits.subdetector[h]) != seeds.end();
  }

  /// True if the straight line from hit a to hit b passes well inside
  /// another layer of the pool (a doublet must not skip a layer; over a
  /// seed's length the helix is close to the chord).
  bool chordSkipsLayer(ConfIndex a, ConfIndex b) const {
    const double ra = m_hits.radius[a];
    const double rb = m_hits.radius[b];
    const double za = m_hits.z[a];
    const double zb = m_hits.z[b];
    for (std::uint32_t layer : m_near[m_hits.layer[a]]) {
      if (layer == m_hits.layer[a] || layer == m_hits.layer[b]) {
        continue;
      }
      const SensitiveLayer& l = m_layers[layer];
      if (l.isDisk()) {
        const double z = l.z();
        if ((z - za) * (z - zb) >= 0.0) {
          continue;
        }
        const double r = ra + (rb - ra) * (z - za) / (zb - za);
        if (r > l.rMin + kEdgeMargin && r < l.rMax - kEdgeMargin) {
          return true;
        }
      } else {
        const double r = l.r;
        if ((r - ra) * (r - rb) >= 0.0) {
          continue;
        }
        const double z = za + (zb - za) * (r - ra) / (rb - ra);
        if (z > l.zMin + kEdgeMargin && z < l.zMax - kEdgeMargin) {
          return true;
        }
      }
    }
    return false;
  }

  /// Seeds move outwards: to a larger radius on a barrel layer, to a
  /// larger |z| on a disk.
  bool outwards(ConfIndex from, ConfIndex to) const {
    return m_layers[m_hits.layer[to]].isDisk()
               ? std::abs(m_hits.z[to]) > std::abs(m_hits.z[from])
               : m_hits.radius[to] > m_hits.radius[from];
  }

  /// Unused pool hits within maxSeedLength of hit `from`, on other layers
  /// than its own, further out (outwards()); sorted by index.
  void neighbours(ConfIndex from, std::vector<ConfIndex>& out) {
    out.clear();
    const double len = m_step.maxSeedLength;
    const double r1 = m_hits.radius[from];
    const double z1 = m_hits.z[from];
    for (std::uint32_t layer : m_near[m_hits.layer[from]]) {
      if (layer == m_hits.layer[from]) {
        continue;
      }
      const SensitiveLayer& l = m_layers[layer];
      double dphi = std::numbers::pi;
      if (l.isDisk()) {
        const double dz = std::abs(l.z() - z1);
        // Towards a disk the particle moves away from z = 0; its radius
        // may shrink at first (a large impact parameter).
        if (dz > len || std::abs(l.z()) <= std::abs(z1)) {
          continue;
        }
        const double reach = std::sqrt(len * len - dz * dz);
        if (reach < r1) {
          dphi = std::asin(reach / r1);
        }
        m_window.clear();
        m_pool.layerBox(layer, m_hits.phi[from], dphi, l.z() - 1.0, l.z() + 1.0,
                        r1 - reach, r1 + reach, m_window);
      } else {
        const double dr = l.r - r1;
        if (dr <= 0.0 || dr > len) {
          continue;
        }
        const double reach = std::sqrt(len * len - dr * dr);
        const double c = (r1 * r1 + l.r * l.r - len * len) / (2.0 * r1 * l.r);
        if (c > -1.0) {
          dphi = std::acos(std::min(1.0, c));
        }
        m_window.clear();
        m_pool.layerBox(layer, m_hits.phi[from], dphi, z1 - reach, z1 + reach,
                        l.r - 1.0, l.r + 1.0, m_window);
      }
      for (ConfIndex h : m_window) {
        if (m_state.used[h] != 0 || !outwards(from, h)) {
          continue;
        }
        const double dx = m_hits.x[h] - m_hits.x[from];
        const double dy = m_hits.y[h] - m_hits.y[from];
        const double dz = m_hits.z[h] - z1;
        if (dx * dx + dy * dy + dz * dz <= len * len &&
            !chordSkipsLayer(from, h)) {
          out.push_back(h);
        }
      }
    }
    std::sort(out.begin(), out.end());
  }

  /// Unused pool hits that can follow the doublet (h1, h2) on a track of
  /// pT >= minPt, sorted by index: on each nearby layer (not theirs), the
  /// window around the doublet's chord extended from h2, as wide as the
  /// bending (the chord's direction differs from the track's at h2 by at
  /// most d12 / (2 rho_min), and a track leaves its tangent by
  /// l^2 / (2 rho_min)) and, along z or R, as the longitudinal deflection
  /// at pT = minPt allows.
  void thirdCandidates(ConfIndex h1, ConfIndex h2,
                       std::vector<ConfIndex>& out) {
    out.clear();
    const double len = m_step.maxSeedLength;
    const double x2 = m_hits.x[h2];
    const double y2 = m_hits.y[h2];
    const double z2 = m_hits.z[h2];
    double ux = x2 - m_hits.x[h1];
    double uy = y2 - m_hits.y[h1];
    const double d12 = norm2(ux, uy);
    if (!(d12 > 0.0)) {
      return;
    }
    ux /= d12;
    uy /= d12;
    const double t12 = (z2 - m_hits.z[h1]) / d12;
    const double secL = norm2(1.0, t12);
    const double kinkZ =
        (m_step.maxCellAngleRZ + 3.0 * m_maxTheta0[m_hits.layer[h2]]) * secL *
        secL;
    const double proj = x2 * ux + y2 * uy;
    const double r2sq = x2 * x2 + y2 * y2;
    // Distance along the chord to each nearby layer; only the first layer
    // crossed well inside its extent, and those just beyond it, are
    // searched (a seed does not skip layers).
    m_layerSteps.clear();
    double first = std::numeric_limits<double>::infinity();
    for (std::uint32_t layer : m_near[m_hits.layer[h2]]) {
      if (layer == m_hits.layer[h1] || layer == m_hits.layer[h2]) {
        continue;
      }
      const SensitiveLayer& l = m_layers[layer];
      double lambda = 0.0;
      bool inside = false;
      if (l.isDisk()) {
        if (std::abs(t12) < 1e-6) {
          continue;
        }
        lambda = (l.z() - z2) / t12;
        const double r = norm2(x2 + lambda * ux, y2 + lambda * uy);
        inside = r > l.rMin + kEdgeMargin && r < l.rMax - kEdgeMargin;
      } else {
        const double disc = proj * proj - (r2sq - l.r * l.r);
        if (disc < 0.0) {
          continue;
        }
        lambda = -proj + std::sqrt(disc);
        const double z = z2 + t12 * lambda;
        inside = z > l.zMin + kEdgeMargin && z < l.zMax - kEdgeMargin;
      }
      if (!(lambda > 0.0) || lambda * secL > len) {
        continue;
      }
      m_layerSteps.emplace_back(lambda, layer);
      if (inside) {
        first = std::min(first, lambda);
      }
    }
    for (const auto& [lambda, layer] : m_layerSteps) {
      if (lambda > first + kFirstLayerSlack) {
        continue;
      }
      const SensitiveLayer& l = m_layers[layer];
      const double px = x2 + lambda * ux;
      const double py = y2 + lambda * uy;
      const double pr = norm2(px, py);
      const double bend = lambda * (d12 + lambda) / (2.0 * m_minRho) + 1.0;
      const double halfPhi =
          bend >= pr ? std::numbers::pi : std::asin(bend / pr);
      const double halfZ = kinkZ * lambda +
                           3.0 * std::sqrt(m_hits.varZ[h2] + m_hits.varZ[h1] +
                                           l.sigmaV * l.sigmaV) +
                           std::abs(t12) * lambda * lambda / (2.0 * m_minRho);
      m_window.clear();
      const double pz = z2 + t12 * lambda;
      m_pool.layerBox(layer, std::atan2(py, px), halfPhi, pz - halfZ,
                      pz + halfZ, pr - bend, pr + bend, m_window);
      for (ConfIndex h : m_window) {
        if (m_state.used[h] == 0 && outwards(h2, h)) {
          out.push_back(h);
        }
      }
    }
    std::sort(out.begin(), out.end());
  }

  /// Variance of the (s, z) slope between two hits a distance ds apart.
  double slopeVariance(ConfIndex a, ConfIndex b, double ds, double t) const {
    const double var = m_hits.varZ[a] + m_hits.varZ[b] +
                       t * t * (m_hits.varRxy[a] + m_hits.varRxy[b]);
    return var / (ds * ds);
  }

  /// Highland width of the deflection in `layer` for a track of
  /// transverse momentum pt (at least minPt) and slope t = tan(lambda).
  double theta0(std::uint32_t layer, double pt, double t) const {
    return layerTheta0(m_layers[layer],
                       std::max(pt, m_step.minPt) * norm2(1.0, t), t);
  }

  /// False if the triplet's curvature exceeds that of pT = minPt by more
  /// than three standard deviations of its measurement (hit resolution and
  /// scattering in the middle layer): the circle through three hits a few
  /// cm apart in the transverse plane (forward tracks) measures the
  /// curvature poorly.
  bool bendAllowed(ConfIndex h1, ConfIndex h2, ConfIndex h3,
                   const Circle& c) const {
    if (c.rho >= m_minRho) {
      return true;
    }
    const double chord =
        norm2(m_hits.x[h3] - m_hits.x[h1], m_hits.y[h3] - m_hits.y[h1]);
    if (!(chord > 0.0)) {
      return false;
    }
    const double sigmaHit =
        std::sqrt(m_hits.varT[h2]) * m_hits.radius[h2] * m_hits.radius[h2];
    const double sigmaRes = 8.0 * 1.22 * sigmaHit / (chord * chord);
    const double sigmaMs = 2.0 * m_maxTheta0[m_hits.layer[h2]] / chord;
    return 1.0 / c.rho <= 1.0 / m_minRho + 3.0 * norm2(sigmaRes, sigmaMs);
  }

  double ptOf(const Circle& c) const {
    return constants::kPtPerTeslaMm * std::abs(m_state.bzForPt) * c.rho;
  }

  void followSeed(ConfIndex h1, Path& best) {
    std::vector<ConfIndex> seconds;
    std::vector<ConfIndex> thirds;
    m_triplets.clear();
    neighbours(h1, seconds);
    for (ConfIndex h2 : seconds) {
      thirdCandidates(h1, h2, thirds);
      for (ConfIndex h3 : thirds) {
        Circle c;
        if (!circleThrough(m_hits.x[h1], m_hits.y[h1], m_hits.x[h2],
                           m_hits.y[h2], m_hits.x[h3], m_hits.y[h3], c) ||
            c.d0() > m_step.maxD0 || !bendAllowed(h1, h2, h3, c)) {
          continue;
        }
        const double s12 =
            c.arc(m_hits.x[h1], m_hits.y[h1], m_hits.x[h2], m_hits.y[h2]);
        const double s23 =
            c.arc(m_hits.x[h2], m_hits.y[h2], m_hits.x[h3], m_hits.y[h3]);
        // Both segments within the outgoing half-turn.
        if (!(s12 > 0.0) || !(s23 > 0.0) ||
            s12 + s23 > std::numbers::pi * c.rho) {
          continue;
        }
        // Kink in the (s, z) plane against multiple scattering in the
        // middle layer plus the hits' resolution.
        const double t12 = (m_hits.z[h2] - m_hits.z[h1]) / s12;
        const double t23 = (m_hits.z[h3] - m_hits.z[h2]) / s23;
        const double dTheta = std::abs(std::atan(t23) - std::atan(t12));
        const double cos2 = 1.0 / (1.0 + t12 * t12);
        const double ms = theta0(m_hits.layer[h2], ptOf(c), t12);
        const double var = ms * ms + cos2 * cos2 *
                                         (slopeVariance(h1, h2, s12, t12) +
                                          slopeVariance(h2, h3, s23, t23));
        if (dTheta > m_step.maxCellAngleRZ + 3.0 * std::sqrt(var)) {
          continue;
        }
        ++m_stats.cells;  // triplets
        Triplet tr;
        tr.path.hits = {h1, h2, h3};
        tr.path.s = {0.0, s12, s12 + s23};
        tr.circle = c;
        tr.kink = dTheta * dTheta / var;
        fitSz(tr.path);
        m_triplets.push_back(std::move(tr));
      }
    }
    // The straightest triplets first; at most maxSeedCells are followed.
    std::sort(m_triplets.begin(), m_triplets.end(),
              [](const Triplet& a, const Triplet& b) {
                return a.kink != b.kink ? a.kink < b.kink
                                        : a.path.hits < b.path.hits;
              });
    std::size_t followed = 0;
    for (Triplet& tr : m_triplets) {
      if (m_step.maxSeedCells > 0 && followed >= m_step.maxSeedCells) {
        break;
      }
      if (skipsLayer(tr.path, tr.circle)) {
        continue;
      }
      ++followed;
      Path& path = tr.path;
      follow(path);
      ++m_stats.paths;
      if (path.hits.size() >= m_step.minHits) {
        ++m_stats.candidates;
        if (better(path, best)) {
          best = std::move(path);
        }
      }
    }
  }

  static bool better(const Path& a, const Path& b) {
    if (a.hits.size() != b.hits.size()) {
      return a.hits.size() > b.hits.size();
    }
    const double qa = a.chi2 / static_cast<double>(a.hits.size());
    const double qb = b.chi2 / static_cast<double>(b.hits.size());
    if (qa != qb) {
      return qa < qb;
    }
    return a.hits < b.hits;
  }

  /// Weighted straight-line fit z = z0 + t s over the path's hits; the
  /// error of s on disks (from the radial resolution) enters through the
  /// previous slope.
  void fitSz(Path& p) const {
    double sw = 0.0, sws = 0.0, swz = 0.0, swss = 0.0, swsz = 0.0;
    for (std::size_t k = 0; k < p.hits.size(); ++k) {
      const ConfIndex h = p.hits[k];
      const double var = m_hits.varZ[h] + p.t * p.t * m_hits.varRxy[h] + 1e-6;
      const double w = 1.0 / var;
      sw += w;
      sws += w * p.s[k];
      swz += w * m_hits.z[h];
      swss += w * p.s[k] * p.s[k];
      swsz += w * p.s[k] * m_hits.z[h];
    }
    const double det = sw * swss - sws * sws;
    if (det > 0.0) {
      p.t = (sw * swsz - sws * swz) / det;
      p.z0 = (swz - p.t * sws) / sw;
    }
  }

  /// Filters the path's hits along s (SzState): starts at the first hit
  /// with the slope of the straight-line fit, then at each further hit
  /// propagates, adds the scattering of the layer just left to the slope's
  /// variance and updates with the hit's z (on a disk its radial error,
  /// moved along the track, enters as t^2 varRxy).
  SzState filterSz(const Path& p, double pt) const {
    SzState st;
    const ConfIndex first = p.hits[0];
    st.t = p.t;
    st.z = m_hits.z[first];
    st.varZ = m_hits.varZ[first] + p.t * p.t * m_hits.varRxy[first] + 1e-6;
    st.varT = 1.0;  // the slope comes from the hits that follow
    for (std::size_t k = 1; k < p.hits.size(); ++k) {
      const ConfIndex h = p.hits[k];
      const double ds = p.s[k] - p.s[k - 1];
      const double secL2 = 1.0 + st.t * st.t;
      const double ms = theta0(m_hits.layer[p.hits[k - 1]], pt, st.t) * secL2;
      // Propagate: z += t ds.
      st.z += st.t * ds;
      st.varZ += 2.0 * ds * st.covZt + ds * ds * st.varT;
      st.covZt += ds * st.varT;
      st.varT += ms * ms;
      // Update with the hit's z.
      const double r = m_hits.varZ[h] + st.t * st.t * m_hits.varRxy[h] + 1e-6;
      const double sVar = st.varZ + r;
      const double kz = st.varZ / sVar;
      const double kt = st.covZt / sVar;
      const double res = m_hits.z[h] - st.z;
      st.z += kz * res;
      st.t += kt * res;
      const double varZ = (1.0 - kz) * st.varZ;
      const double covZt = (1.0 - kz) * st.covZt;
      st.varT -= kt * st.covZt;
      st.varZ = varZ;
      st.covZt = covZt;
    }
    return st;
  }

  /// Predicted crossings of the pool's layers after hit `from` (arc length
  /// sFrom on the line z = z0 + t s), within the outgoing half-turn,
  /// nearest first. `inside` is set for crossings at least kEdgeMargin
  /// inside the layer's extent (where a missing hit is a real miss).
  void predict(ConfIndex from, double sFrom, double z0, double t,
               const Circle& c, std::vector<Crossing>& out) {
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
    const double halfTurn = std::numbers::pi * c.rho;
    auto add = [&](std::uint32_t layer, double ds, bool disk) {
      const SensitiveLayer& l = m_layers[layer];
      const Vector3 x = helix.position(ds);
      const double r = x.head<2>().norm();
      const bool inside =
          disk ? r > l.rMin + kEdgeMargin && r < l.rMax - kEdgeMargin
               : x.z() > l.zMin + kEdgeMargin && x.z() < l.zMax - kEdgeMargin;
      out.push_back({layer, ds, x.x(), x.y(), x.z(), inside});
    };
    for (std::uint32_t layer : m_reach[m_hits.layer[from]]) {
      const SensitiveLayer& l = m_layers[layer];
      if (l.isDisk()) {
        if (layer == m_hits.layer[from]) {
          continue;
        }
        const double ds =
            helix.nextDiskCrossing(l.z(), l.rMin - kLayerMargin,
                                   l.rMax + kLayerMargin, kMinStep, halfTurn);
        if (ds != Helix::kNoCrossing) {
          add(layer, ds, true);
        }
        continue;
      }
      // A barrel layer may be crossed twice within the half-turn (out and
      // back in, or its own layer again).
      double after = kMinStep;
      for (int k = 0; k < 2; ++k) {
        const double ds = helix.nextCylinderCrossing(
            l.r, l.zMin - kLayerMargin, l.zMax + kLayerMargin, after, halfTurn);
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

  /// True if the triplet's helix crosses another layer of the pool well
  /// inside its extent between its first and last hit: a seed must not
  /// skip a layer (the detector's layers are efficient, and a triplet
  /// spread over distant layers is mostly a random combination).
  bool skipsLayer(const Path& p, const Circle& c) {
    predict(p.hits[0], 0.0, p.z0, p.t, c, m_crossings);
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

  /// Extends the path outwards hit by hit (see the file comment).
  void follow(Path& p) {
    std::vector<Crossing> crossings;
    while (true) {
      const std::size_t n = p.hits.size();
      const ConfIndex last = p.hits[n - 1];
      Circle c;
      if (!fitCircle(m_hits, p.hits, c)) {
        return;
      }
      // Arc lengths along the current circle, so that the s-z fit and the
      // prediction use one consistent helix.
      if (n > 3) {
        for (std::size_t k = 1; k < n; ++k) {
          const ConfIndex h0 = p.hits[k - 1];
          const ConfIndex h1 = p.hits[k];
          p.s[k] = p.s[k - 1] + c.arc(m_hits.x[h0], m_hits.y[h0], m_hits.x[h1],
                                      m_hits.y[h1]);
        }
        fitSz(p);
      }
      const SzState sz = filterSz(p, ptOf(c));
      predict(last, p.s.back(), sz.z - sz.t * p.s.back(), sz.t, c, crossings);
      const double secL = norm2(1.0, p.t);
      const double ms0 = theta0(m_hits.layer[last], ptOf(c), p.t);
      // Lever arm of the fitted circle: the path's length.
      const double lever = std::max(p.s[n - 1], 1.0);
      const double sigmaLast = std::sqrt(m_hits.varT[last]) *
                               m_hits.radius[last] * m_hits.radius[last];
      std::uint32_t missed = 0;
      ConfIndex chosen = kInvalidIndex;
      double chosenChi2 = 0.0;
      for (const Crossing& x : crossings) {
        // Scattering in the last layer turns the direction by theta0 / cos
        // (lambda) in azimuth and theta0 / cos(lambda)^2 in dz/ds; the
        // fitted direction carries about as much again from the layers
        // before (factor 2 in the variances).
        const double ms = std::numbers::sqrt2 * ms0 * x.ds * secL;
        const double ratio = x.ds / lever;
        const double extrap = sigmaLast * (1.0 + ratio * ratio);
        // The filtered z's own error, and the scattering in the last layer
        // (its slope's variance holds that layer's only once it is left).
        const double msLast = ms0 * secL * secL * x.ds;
        const double extrapZ = std::sqrt(sz.varAt(x.ds) + msLast * msLast);
        const SensitiveLayer& l = m_layers[x.layer];
        const double varPhi = l.sigmaU * l.sigmaU + ms * ms + extrap * extrap;
        double varV = l.sigmaV * l.sigmaV + extrapZ * extrapZ;
        if (l.isDisk()) {
          // On a disk the transverse errors of the prediction move the
          // crossing radially as much as in azimuth, and an error in the
          // slope moves it along the track.
          varV = l.sigmaV * l.sigmaV + ms * ms + extrap * extrap +
                 extrapZ * extrapZ / std::max(sz.t * sz.t, 0.01);
        }
        const double rCross = norm2(x.x, x.y);
        // The crossing is that of the layer's nominal surface; its sensors
        // lie up to overlapMaxGap from it along the normal, where the track
        // is displaced along the layer by the gap over the cosine of its
        // crossing angle. The window covers that; the residuals below are
        // taken at the hit itself.
        const double tx = -c.orientation * (x.y - c.cy) / c.rho;
        const double ty = c.orientation * (x.x - c.cx) / c.rho;
        const double radialT =
            std::abs(tx * x.x + ty * x.y) / std::max(rCross, 1e-9);
        const double alongT = std::sqrt(std::max(0.0, 1.0 - radialT * radialT));
        const double normalT = l.isDisk() ? std::abs(sz.t) : radialT;
        const double ds =
            m_state.config.overlapMaxGap / std::max(normalT, 1e-3);
        const double maxArc = m_state.config.overlapMaxArc;
        const double offsetPhi = std::min(maxArc, ds * alongT);
        const double offsetV =
            std::min(maxArc, ds * (l.isDisk() ? radialT : std::abs(sz.t)));
        const double halfPhi =
            (std::max(kMinWindow, kWindowSigmas * std::sqrt(varPhi)) +
             offsetPhi) /
            std::max(rCross, 1.0);
        const double halfV =
            std::max(kMinWindow, kWindowSigmas * std::sqrt(varV)) + offsetV;
        m_window.clear();
        m_pool.layerBox(x.layer, std::atan2(x.y, x.x), halfPhi, x.z - halfV,
                        x.z + halfV, rCross - halfV, rCross + halfV, m_window);
        m_layerHits.clear();
        for (ConfIndex h : m_window) {
          if (m_state.used[h] != 0 || onPath(h, p)) {
            continue;
          }
          // Distance from the circle across the track, and z against the
          // helix at the hit's own arc length.
          const double rPhi =
              norm2(m_hits.x[h] - c.cx, m_hits.y[h] - c.cy) - c.rho;
          double arc =
              c.arc(m_hits.x[last], m_hits.y[last], m_hits.x[h], m_hits.y[h]);
          if (arc > std::numbers::pi * c.rho) {
            arc -= 2.0 * std::numbers::pi * c.rho;  // just behind the last hit
          }
          const double dz = m_hits.z[h] - sz.zAt(arc);
          // On a disk v is radial: a z residual dz is a shift dz / t along
          // the track, radialT of it in radius.
          const double rV =
              l.isDisk() ? dz * radialT / std::max(std::abs(sz.t), 0.1) : dz;
          const double chi2 = rPhi * rPhi / varPhi + rV * rV / varV;
          if (chi2 > m_step.chi2Cut) {
            continue;
          }
          m_layerHits.push_back({h, chi2, arc, rPhi, dz});
          if (chosen == kInvalidIndex || chi2 < chosenChi2 ||
              (chi2 == chosenChi2 && h < chosen)) {
            chosen = h;
            chosenChi2 = chi2;
          }
        }
        if (chosen != kInvalidIndex) {
          addOverlapPartners(chosen, sz.t);
          break;
        }
        // A layer the track already has a hit on is crossed again at its
        // nominal surface next to that hit: the second sensor of an overlap
        // is optional (addOverlapPartners takes its hit with the first),
        // not a missed layer.
        if (x.inside && !onLayerOf(x.layer, p) &&
            ++missed > m_step.maxMissedLayers) {
          break;
        }
      }
      if (chosen == kInvalidIndex) {
        return;
      }
      // The chosen hit and its overlap partners, in the order of the
      // track.
      std::sort(m_taken.begin(), m_taken.end(),
                [](const LayerHit& a, const LayerHit& b) {
                  return a.arc != b.arc ? a.arc < b.arc : a.hit < b.hit;
                });
      const double sLast = p.s.back();
      for (const LayerHit& lh : m_taken) {
        p.hits.push_back(lh.hit);
        p.s.push_back(sLast + lh.arc);
        p.chi2 += lh.chi2;
      }
      fitSz(p);
    }
  }

  /// Sets m_taken to the chosen hit of a layer crossing and, on other
  /// sensors of the same layer, the compatible hits of the crossing's
  /// window (m_layerHits), the best per sensor: a particle crossing the
  /// overlap of two sensors leaves a hit on each. A partner is judged by
  /// the difference of its residuals and the chosen hit's (the track's own
  /// prediction error, far larger below a few GeV, cancels over the few
  /// mm between them; OverlapHits does the same for conformal tracks).
  void addOverlapPartners(ConfIndex chosen, double t) {
    m_taken.clear();
    const auto chosenIt =
        std::find_if(m_layerHits.begin(), m_layerHits.end(),
                     [&](const LayerHit& lh) { return lh.hit == chosen; });
    m_taken.push_back(*chosenIt);
    std::sort(m_layerHits.begin(), m_layerHits.end(),
              [](const LayerHit& a, const LayerHit& b) {
                return a.chi2 != b.chi2 ? a.chi2 < b.chi2 : a.hit < b.hit;
              });
    const double sigmaChosen = transverseSigma(chosen);
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
      const double dPerp = lh.rPhi - chosenIt->rPhi;
      const double varPerp = sigmaChosen * sigmaChosen +
                             transverseSigma(lh.hit) * transverseSigma(lh.hit) +
                             kOverlapFloor * kOverlapFloor;
      const double dz = lh.dz - chosenIt->dz;
      // On disks z is exact and the arc length carries the radial error.
      const double varZ =
          m_hits.varZ[chosen] + m_hits.varZ[lh.hit] +
          t * t * (m_hits.varRxy[chosen] + m_hits.varRxy[lh.hit]) +
          kOverlapFloor * kOverlapFloor;
      if (dPerp * dPerp / varPerp + dz * dz / varZ <=
          m_state.config.overlapMaxChi2) {
        m_taken.push_back(lh);
      }
    }
  }

  /// A hit's transverse resolution [mm] (its conformal tangential error
  /// scaled back).
  double transverseSigma(ConfIndex h) const {
    return std::sqrt(m_hits.varT[h]) * m_hits.radius[h] * m_hits.radius[h];
  }

  /// True if the path has a hit on `layer`.
  bool onLayerOf(std::uint32_t layer, const Path& p) const {
    return std::any_of(p.hits.begin(), p.hits.end(),
                       [&](ConfIndex h) { return m_hits.layer[h] == layer; });
  }

  /// True if hit h is already on the path.
  static bool onPath(ConfIndex h, const Path& p) {
    return std::find(p.hits.begin(), p.hits.end(), h) != p.hits.end();
  }

  void accept(const Path& p) {
    TrackCandidate t;
    t.hits = p.hits;
    Circle c;
    const std::size_t n = p.hits.size();
    fitCircle(m_hits, p.hits, c);
    t.uv.valid = true;
    t.uv.centreX = c.cx;
    t.uv.centreY = c.cy;
    t.uv.radius = c.rho;
    t.uv.orientation = c.orientation;
    t.uv.chi2 = p.chi2;
    t.uv.ndf = static_cast<int>(n) - 3;
    t.sz.valid = true;
    t.sz.z0 = p.z0;
    t.sz.tanLambda = p.t;
    t.sz.lastS = p.s.back();
    t.pt = t.uv.pt(m_state.bzForPt);
    t.step = m_stepIndex;
    t.fitBackward = m_step.fitBackward;
    t.helix = true;
    const auto index = static_cast<std::uint32_t>(m_state.tracks.size());
    for (ConfIndex h : p.hits) {
      m_state.used[h] = 1;
      m_state.clones.addHit(h, index);
    }
    m_state.tracks.push_back(std::move(t));
    ++m_stats.accepted;
  }

  FinderState& m_state;
  const ConformalHits& m_hits;
  const std::vector<SensitiveLayer>& m_layers;
  const FindingStep& m_step;
  std::uint16_t m_stepIndex;
  const HitPool& m_pool;
  StepStats& m_stats;
  double m_minRho;
  std::vector<ConfIndex> m_window;
  std::vector<Crossing> m_crossings;
  std::vector<Triplet> m_triplets;
  /// The compatible hits of the current layer crossing, and those taken.
  std::vector<LayerHit> m_layerHits;
  std::vector<LayerHit> m_taken;
  std::vector<std::pair<double, std::uint32_t>> m_layerSteps;
  /// Per detector layer: the scattering angle at pT = minPt, normal
  /// incidence.
  std::vector<double> m_maxTheta0;
  /// Per detector layer: the pool's layers within maxSeedLength (seeds),
  /// and within kReachFactor times that (extensions).
  std::vector<std::vector<std::uint32_t>> m_near;
  std::vector<std::vector<std::uint32_t>> m_reach;
};

}  // namespace

void buildHelixTracks(FinderState& state, const FindingStep& step,
                      std::uint16_t stepIndex, const HitPool& pool,
                      StepStats& stats) {
  HelixBuilder(state, step, stepIndex, pool, stats).run();
}

}  // namespace conftrack::detail

// The seed triplets of the helix step (detail/HelixSeeds.hpp).

#include "conftrack/reconstruction/finding/detail/HelixSeeds.hpp"

#include "conftrack/core/Units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack::detail {

namespace {

/// A seed's third hit is searched on the first layer crossed and on those
/// at most this much further along the chord [mm] (double layers,
/// overlapping barrel and disk edges).
constexpr double kFirstLayerSlack = 20.0;

}  // namespace

HelixSeeds::HelixSeeds(const FinderState& state, const FindingStep& step,
                       const HitPool& pool, const HelixFollower& follower)
    : m_state(state),
      m_hits(state.hits),
      m_layers(state.detector.layers()),
      m_step(step),
      m_pool(pool),
      m_follower(follower),
      m_minRho(step.minPt /
               (constants::kPtPerTeslaMm * std::abs(state.bzForPt))) {
  m_maxTheta0.resize(m_layers.size());
  for (std::uint32_t a : m_pool.layers()) {
    m_maxTheta0[a] = m_follower.theta0(a, step.minPt, 0.0);
  }
  // The pool's layers within maxSeedLength of each layer: the only ones
  // a seed looks at. Adjacent layers up to maxSeedGap apart pair too, a
  // segment between them reaching maxSeedLength beyond their distance
  // (FindingStep::maxSeedGap). Pairs within the seed length reach the
  // length scaled with their distance where that lies between the two
  // bounds (FindingStep::seedLengthPerGap).
  const std::vector<std::uint32_t>& layers = m_pool.layers();
  const std::size_t n = m_layers.size();
  m_near.resize(n);
  m_seedLength.assign(n * n, step.maxSeedLength);
  for (std::uint32_t a : layers) {
    for (std::uint32_t b : layers) {
      const double gap = layerDistance(m_layers[a], m_layers[b]);
      if (gap <= step.maxSeedLength) {
        m_near[a].push_back(b);
        const double scaled = step.seedLengthPerGap * gap;
        if (scaled > step.maxSeedLength && scaled <= step.maxSeedLengthPerGap) {
          m_seedLength[a * n + b] = scaled;
        }
      } else if (gap <= step.maxSeedGap && adjacent(a, b, gap)) {
        m_near[a].push_back(b);
        m_seedLength[a * n + b] = norm2(step.maxSeedLength, gap);
      }
    }
  }
}

void HelixSeeds::triplets(ConfIndex h1, std::vector<HelixTriplet>& out,
                          StepStats& stats) {
  out.clear();
  neighbours(h1, m_seconds);
  for (ConfIndex h2 : m_seconds) {
    thirdCandidates(h1, h2, m_thirds);
    for (ConfIndex h3 : m_thirds) {
      TransverseCircle c;
      if (!circleThrough(m_hits.x[h1], m_hits.y[h1], m_hits.x[h2], m_hits.y[h2],
                         m_hits.x[h3], m_hits.y[h3], c) ||
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
      const double ms =
          m_follower.theta0(m_hits.layer[h2], m_follower.ptOf(c), t12);
      const double var = ms * ms + cos2 * cos2 *
                                       (slopeVariance(h1, h2, s12, t12) +
                                        slopeVariance(h2, h3, s23, t23));
      if (dTheta > m_step.maxCellAngleRZ + 3.0 * std::sqrt(var)) {
        continue;
      }
      ++stats.cells;  // triplets
      HelixTriplet tr;
      tr.path.hits = {h1, h2, h3};
      tr.path.s = {0.0, s12, s12 + s23};
      tr.circle = c;
      tr.kink = dTheta * dTheta / var;
      fitPathSz(m_hits, tr.path);
      out.push_back(std::move(tr));
    }
  }
  // The straightest triplets first.
  std::sort(
      out.begin(), out.end(), [](const HelixTriplet& a, const HelixTriplet& b) {
        return a.kink != b.kink ? a.kink < b.kink : a.path.hits < b.path.hits;
      });
}

bool HelixSeeds::adjacent(std::uint32_t a, std::uint32_t b, double gap) const {
  for (std::uint32_t c : m_pool.layers()) {
    if (c != a && c != b &&
        layerDistance(m_layers[a], m_layers[c]) +
                layerDistance(m_layers[c], m_layers[b]) <=
            gap + 1.0) {
      return false;
    }
  }
  return true;
}

double HelixSeeds::seedLength(std::uint32_t a, std::uint32_t b) const {
  return m_seedLength[a * m_layers.size() + b];
}

bool HelixSeeds::chordSkipsLayer(ConfIndex a, ConfIndex b) const {
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
      if (r > l.rMin + kHelixEdgeMargin && r < l.rMax - kHelixEdgeMargin) {
        return true;
      }
    } else {
      const double r = l.r;
      if ((r - ra) * (r - rb) >= 0.0) {
        continue;
      }
      const double z = za + (zb - za) * (r - ra) / (rb - ra);
      if (z > l.zMin + kHelixEdgeMargin && z < l.zMax - kHelixEdgeMargin) {
        return true;
      }
    }
  }
  return false;
}

bool HelixSeeds::outwards(ConfIndex from, ConfIndex to) const {
  return m_layers[m_hits.layer[to]].isDisk()
             ? std::abs(m_hits.z[to]) > std::abs(m_hits.z[from])
             : m_hits.radius[to] > m_hits.radius[from];
}

void HelixSeeds::neighbours(ConfIndex from, std::vector<ConfIndex>& out) {
  out.clear();
  const double r1 = m_hits.radius[from];
  const double z1 = m_hits.z[from];
  for (std::uint32_t layer : m_near[m_hits.layer[from]]) {
    if (layer == m_hits.layer[from]) {
      continue;
    }
    const double len = seedLength(m_hits.layer[from], layer);
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

void HelixSeeds::thirdCandidates(ConfIndex h1, ConfIndex h2,
                                 std::vector<ConfIndex>& out) {
  out.clear();
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
      inside = r > l.rMin + kHelixEdgeMargin && r < l.rMax - kHelixEdgeMargin;
    } else {
      const double disc = proj * proj - (r2sq - l.r * l.r);
      if (disc < 0.0) {
        continue;
      }
      lambda = -proj + std::sqrt(disc);
      const double z = z2 + t12 * lambda;
      inside = z > l.zMin + kHelixEdgeMargin && z < l.zMax - kHelixEdgeMargin;
    }
    if (!(lambda > 0.0) ||
        lambda * secL > seedLength(m_hits.layer[h2], layer)) {
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
    const double halfPhi = bend >= pr ? std::numbers::pi : std::asin(bend / pr);
    const double halfZ = kinkZ * lambda +
                         3.0 * std::sqrt(m_hits.varZ[h2] + m_hits.varZ[h1] +
                                         l.sigmaV * l.sigmaV) +
                         std::abs(t12) * lambda * lambda / (2.0 * m_minRho);
    m_window.clear();
    const double pz = z2 + t12 * lambda;
    m_pool.layerBox(layer, std::atan2(py, px), halfPhi, pz - halfZ, pz + halfZ,
                    pr - bend, pr + bend, m_window);
    for (ConfIndex h : m_window) {
      if (m_state.used[h] == 0 && outwards(h2, h)) {
        out.push_back(h);
      }
    }
  }
  std::sort(out.begin(), out.end());
}

double HelixSeeds::slopeVariance(ConfIndex a, ConfIndex b, double ds,
                                 double t) const {
  const double var = m_hits.varZ[a] + m_hits.varZ[b] +
                     t * t * (m_hits.varRxy[a] + m_hits.varRxy[b]);
  return var / (ds * ds);
}

bool HelixSeeds::bendAllowed(ConfIndex h1, ConfIndex h2, ConfIndex h3,
                             const TransverseCircle& c) const {
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

}  // namespace conftrack::detail

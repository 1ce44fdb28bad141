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
//   each within maxSeedLength of the previous one (further between
//   adjacent layers up to maxSeedGap apart) and further out (larger
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
//   and of z filtered along the arc length with each layer's scattering.
//   At the first predicted layer crossing with compatible hits, the one
//   with the lowest chi2, taken at the hit itself (sensors lie off the
//   layer's nominal surface), is added with its overlap partners; the chi2
//   has the hit resolution, the multiple scattering in the last layer
//   (Highland) and the extrapolation error. At most maxMissedLayers
//   crossings well inside a layer pass without a hit.
// - Of the candidates of one seed hit with at least minHits hits, the
//   longest (then lowest chi2 per hit) is kept, followed on with up to
//   continueMissedLayers crossings without a hit, and claims its hits at once;
//   seed hits are taken innermost first, so the result does not depend on
//   the input order. With firstPassMinHits, only candidates that long claim
//   at once; the shorter wait for a second pass over the seeds.
// - Once the triplets of the step exceed its budget (cellsPerHitOf) per
//   pool hit, the remaining seed hits are skipped (counted): the triplets
//   of a seed grow with the square of the hit density.
// This file seeds and accepts; the following is detail::HelixFollower
// (HelixFollower.hpp) and the circle and (s, z) fits are in HelixPath.hpp.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Helix.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/HelixFollower.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"

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
/// A seed: three hits, their circle, and the (s, z) kink in units of its
/// expected spread.
struct Triplet {
  HelixPath path;
  TransverseCircle circle;
  double kink = 0.0;
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
                 (constants::kPtPerTeslaMm * std::abs(state.bzForPt))),
        m_follower(state, step, pool),
        m_build{step.maxMissedLayers, step.chi2Cut},
        m_continue{std::max(step.maxMissedLayers, step.continueMissedLayers),
                   std::max(step.chi2Cut, step.continueChi2Cut)} {
    m_maxTheta0.resize(m_layers.size());
    for (std::uint32_t a : m_pool.layers()) {
      m_maxTheta0[a] = m_follower.theta0(a, step.minPt, 0.0);
    }
    // The pool's layers within maxSeedLength of each layer: the only ones
    // a seed looks at. Adjacent layers up to maxSeedGap apart pair too, a
    // segment between them reaching maxSeedLength beyond their distance
    // (FindingStep::maxSeedGap).
    const std::vector<std::uint32_t>& layers = m_pool.layers();
    const std::size_t n = m_layers.size();
    m_near.resize(n);
    m_seedLength.assign(n * n, step.maxSeedLength);
    for (std::uint32_t a : layers) {
      for (std::uint32_t b : layers) {
        const double gap = layerDistance(m_layers[a], m_layers[b]);
        if (gap <= step.maxSeedLength) {
          m_near[a].push_back(b);
        } else if (gap <= step.maxSeedGap && adjacent(a, b, gap)) {
          m_near[a].push_back(b);
          m_seedLength[a * n + b] = norm2(step.maxSeedLength, gap);
        }
      }
    }
  }

  void run() {
    // The step's work budget (FinderConfig::cellsPerHitOf), in triplets:
    // their number per seed grows with the square of the hit density.
    const double budget = double(m_state.config.cellsPerHitOf(m_step)) *
                          double(m_pool.members().size());
    const std::vector<ConfIndex>& members = m_pool.members();
    // With first_pass_min_hits, the first pass accepts only candidates of
    // that many hits and keeps the shorter ones (those of minHits or more)
    // for the second.
    const bool twoPasses = m_step.firstPassMinHits > m_step.minHits;
    const std::uint32_t firstMin =
        twoPasses ? m_step.firstPassMinHits : m_step.minHits;
    std::vector<std::pair<std::size_t, HelixPath>> waiting;
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
      HelixPath best;
      followSeed(seed, best);
      if (best.hits.size() >= firstMin) {
        acceptFollowedOn(best);
      } else if (best.hits.size() >= m_step.minHits) {
        waiting.emplace_back(k, std::move(best));
      }
    }
    // The second pass, innermost seeds first as before. A candidate whose
    // hits are all still free is taken as it is; otherwise its seed is
    // followed again, within the step's work budget (counted like the
    // first pass's skipped seeds). A seed without a candidate in the first
    // pass is not followed again: a hit claimed since could have misled
    // its follower, but following every remaining seed again gave the
    // same TrackML score at 1.6 times the triplets.
    for (auto& [k, best] : waiting) {
      const ConfIndex seed = members[k];
      if (m_state.used[seed] != 0) {
        continue;
      }
      const bool intact =
          std::none_of(best.hits.begin(), best.hits.end(),
                       [&](ConfIndex h) { return m_state.used[h] != 0; });
      if (!intact && double(m_stats.cells) > budget) {
        m_stats.guard(Guard::eCellsPerHit).add(1);
        continue;
      }
      if (!intact) {
        best = HelixPath{};
        followSeed(seed, best);
        if (best.hits.size() < m_step.minHits) {
          continue;
        }
      }
      acceptFollowedOn(best);
    }
  }

 private:
  /// True if no other layer of the pool lies between layers a and b, gap
  /// apart (its distances to both add up to theirs within 1 mm).
  bool adjacent(std::uint32_t a, std::uint32_t b, double gap) const {
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

  /// The longest seed segment from a hit on layer a to one on layer b.
  double seedLength(std::uint32_t a, std::uint32_t b) const {
    return m_seedLength[a * m_layers.size() + b];
  }

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

  /// False if the triplet's curvature exceeds that of pT = minPt by more
  /// than three standard deviations of its measurement (hit resolution and
  /// scattering in the middle layer): the circle through three hits a few
  /// cm apart in the transverse plane (forward tracks) measures the
  /// curvature poorly.
  bool bendAllowed(ConfIndex h1, ConfIndex h2, ConfIndex h3,
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

  void followSeed(ConfIndex h1, HelixPath& best) {
    std::vector<ConfIndex> seconds;
    std::vector<ConfIndex> thirds;
    m_triplets.clear();
    neighbours(h1, seconds);
    for (ConfIndex h2 : seconds) {
      thirdCandidates(h1, h2, thirds);
      for (ConfIndex h3 : thirds) {
        TransverseCircle c;
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
        const double ms =
            m_follower.theta0(m_hits.layer[h2], m_follower.ptOf(c), t12);
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
        fitPathSz(m_hits, tr.path);
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
      if (m_follower.skipsLayer(tr.path, tr.circle)) {
        continue;
      }
      ++followed;
      HelixPath& path = tr.path;
      m_follower.follow(path, m_build);
      m_follower.addSeedPartners(path);
      ++m_stats.paths;
      if (path.hits.size() >= m_step.minHits) {
        ++m_stats.candidates;
        if (better(path, best)) {
          best = std::move(path);
        }
      }
    }
  }

  static bool better(const HelixPath& a, const HelixPath& b) {
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

  /// Follows an accepted candidate on past gaps (continue_missed_layers:
  /// it already is a track, and only its further hits are at stake) and
  /// accepts it.
  void acceptFollowedOn(HelixPath& best) {
    if (m_continue.maxMissedLayers > m_build.maxMissedLayers ||
        m_continue.chi2Cut > m_build.chi2Cut) {
      m_follower.follow(best, m_continue);
    }
    accept(best);
  }

  void accept(const HelixPath& p) {
    TrackCandidate t;
    t.hits = p.hits;
    TransverseCircle c;
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
  HelixFollower m_follower;
  /// The follower's limits while building and when an accepted candidate
  /// is followed on (continue_missed_layers, continue_chi2_cut; 0: the
  /// building ones).
  HelixFollower::Limits m_build;
  HelixFollower::Limits m_continue;
  std::vector<ConfIndex> m_window;
  std::vector<Triplet> m_triplets;
  std::vector<std::pair<double, std::uint32_t>> m_layerSteps;
  /// Per detector layer: the scattering angle at pT = minPt, normal
  /// incidence.
  std::vector<double> m_maxTheta0;
  /// Per detector layer: the pool's layers within maxSeedLength.
  std::vector<std::vector<std::uint32_t>> m_near;
  /// Per pair of detector layers (a * layers + b): the longest seed
  /// segment between them (maxSeedLength, more between adjacent layers
  /// further apart).
  std::vector<double> m_seedLength;
};

}  // namespace

void buildHelixTracks(FinderState& state, const FindingStep& step,
                      std::uint16_t stepIndex, const HitPool& pool,
                      StepStats& stats) {
  HelixBuilder(state, step, stepIndex, pool, stats).run();
}

}  // namespace conftrack::detail

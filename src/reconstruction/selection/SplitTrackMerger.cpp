#include "conftrack/reconstruction/selection/SplitTrackMerger.hpp"

#include "conftrack/reconstruction/fitting/HelixState.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>

namespace conftrack {

namespace {

/// Rounds of merging: a third piece joins the merged pair in the second.
constexpr int kMaxRounds = 3;

/// Transverse arc length along the motion from the perigee (parameters
/// about its reference, the beam line) to the point of the circle nearest
/// to `position` [mm], in (-pi, pi] / |Omega|: negative for a point behind
/// the perigee or more than half a turn on.
double arcFromPerigee(const TrackState& perigee, const Vector3& position) {
  const TrackVector& p = perigee.parameters;
  const double phi0 = p[ePhi0];
  const double omega = p[eOmega];
  const double d0 = p[eD0];
  const double px = perigee.reference.x() - d0 * std::sin(phi0);
  const double py = perigee.reference.y() + d0 * std::cos(phi0);
  const double dx = position.x() - px;
  const double dy = position.y() - py;
  // Nearly straight: the projection on the direction.
  constexpr double kStraight = 1e-7;
  if (std::abs(omega) * std::hypot(dx, dy) < kStraight) {
    return dx * std::cos(phi0) + dy * std::sin(phi0);
  }
  // From the centre C = PCA - n / Omega, n = (-sin, cos)(phi0): the
  // radius vector turns by -Omega s along the motion.
  const double r0x = -std::sin(phi0) / omega;
  const double r0y = std::cos(phi0) / omega;
  const double r1x = dx + r0x;
  const double r1y = dy + r0y;
  const double alpha = std::atan2(r0x * r1y - r0y * r1x, r0x * r1x + r0y * r1y);
  return -alpha / omega;
}

/// The perigee of the piece whose curvature is the better measured: its
/// circle orders the hits of both.
const TrackState& betterMeasured(const Track& a, const Track& b) {
  return a.atIp.covariance(eOmega, eOmega) <= b.atIp.covariance(eOmega, eOmega)
             ? a.atIp
             : b.atIp;
}

bool positiveFinite(double x) { return x > 0.0 && std::isfinite(x); }

double chi2PerNdf(const Track& t) {
  return t.ndf > 0 ? t.chi2 / t.ndf : std::numeric_limits<double>::infinity();
}

/// A track that can be a piece: fitted, with a measurement to spare and no
/// further-turn hits (a looper's turns are the finder's business).
bool mergeable(const Track& t) {
  return t.fitted && t.ndf > 0 && t.outlier.size() == t.hits.size() &&
         t.numTurnHits() == 0;
}

}  // namespace

struct SplitTrackMerger::Candidate {
  double chi2 = 0.0;
  std::size_t first = 0;
  std::size_t second = 0;
};

std::optional<SplitTrackMerger::Problem> SplitTrackMerger::findProblem(
    const Config& c) {
  if (!positiveFinite(c.maxParameterChi2)) {
    return Problem{"max_parameter_chi2", "must be > 0 and finite"};
  }
  if (!positiveFinite(c.maxTanLambdaDifference)) {
    return Problem{"max_tan_lambda_difference", "must be > 0 and finite"};
  }
  if (!positiveFinite(c.maxPhi0Difference) ||
      c.maxPhi0Difference >= std::numbers::pi) {
    return Problem{"max_phi0_difference", "must be in (0, pi)"};
  }
  if (!positiveFinite(c.maxSameLayerDistance)) {
    return Problem{"max_same_layer_distance_mm", "must be > 0 and finite"};
  }
  if (!(c.maxChi2Ratio >= 1.0 && std::isfinite(c.maxChi2Ratio))) {
    return Problem{"max_chi2_ratio", "must be at least 1 and finite"};
  }
  return std::nullopt;
}

SplitTrackMerger::SplitTrackMerger(const KalmanFitter& fitter,
                                   const Config& config)
    : m_fitter(&fitter), m_config(config) {
  if (std::optional<Problem> p = findProblem(m_config)) {
    throw std::invalid_argument("SplitTrackMerger: " + p->key + " " + p->what);
  }
}

std::optional<double> SplitTrackMerger::compatible(std::span<const Hit> hits,
                                                   const Track& a,
                                                   const Track& b) const {
  const TrackVector& pa = a.atIp.parameters;
  const TrackVector& pb = b.atIp.parameters;
  if (a.atIp.reference != b.atIp.reference) {
    return std::nullopt;  // perigees about different lines: not comparable
  }
  if (pa[eOmega] * pb[eOmega] <= 0.0) {
    return std::nullopt;  // opposite charges (or a straight line)
  }
  TrackVector delta = pa - pb;
  delta[ePhi0] = wrapAngle(delta[ePhi0]);
  if (std::abs(delta[ePhi0]) > m_config.maxPhi0Difference) {
    return std::nullopt;
  }
  const Eigen::LDLT<TrackCovariance> ldlt(a.atIp.covariance +
                                          b.atIp.covariance);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
    return std::nullopt;
  }
  const double chi2 = delta.dot(ldlt.solve(delta));
  if (!(chi2 <= m_config.maxParameterChi2)) {
    return std::nullopt;
  }
  // The hits: all on the first half-turn from the perigee of the better-
  // measured piece (so that the arc length orders them), and two on one
  // layer only within an overlap. A piece's hits may lie between the
  // other's: an extension skips a layer that a later step's piece holds.
  const double tolerance = m_config.maxSameLayerDistance;
  const TrackState& better = betterMeasured(a, b);
  for (const Track* t : {&a, &b}) {
    for (HitIndex h : t->hits) {
      if (!(arcFromPerigee(better, hits[h].position) > -tolerance)) {
        return std::nullopt;
      }
    }
  }
  for (HitIndex ha : a.hits) {
    for (HitIndex hb : b.hits) {
      if (ha != hb && hits[ha].detId.sameLayer(hits[hb].detId) &&
          (hits[ha].position - hits[hb].position).norm() > tolerance) {
        return std::nullopt;
      }
    }
  }
  return chi2;
}

std::optional<Track> SplitTrackMerger::merge(std::span<const Hit> hits,
                                             const Track& a,
                                             const Track& b) const {
  // Path order: by arc length (ties by index, for determinism), each
  // computed once; a hit both pieces hold once.
  const TrackState& better = betterMeasured(a, b);
  std::vector<std::pair<double, HitIndex>> byArc;
  byArc.reserve(a.hits.size() + b.hits.size());
  for (const Track* t : {&a, &b}) {
    for (HitIndex h : t->hits) {
      byArc.emplace_back(arcFromPerigee(better, hits[h].position), h);
    }
  }
  std::sort(byArc.begin(), byArc.end());
  byArc.erase(std::unique(byArc.begin(), byArc.end()), byArc.end());
  std::vector<HitIndex> merged;
  merged.reserve(byArc.size());
  for (const auto& [arc, h] : byArc) {
    merged.push_back(h);
  }
  // About the pieces' beam line (their perigees' reference).
  const Track fitted =
      m_fitter->fit(hits, FitInput{merged, false, a.atIp.reference.head<2>()});
  const double worstPiece = std::max({1.0, chi2PerNdf(a), chi2PerNdf(b)});
  if (!fitted.fitted ||
      !(chi2PerNdf(fitted) <= m_config.maxChi2Ratio * worstPiece) ||
      fitted.numOutliers() > a.numOutliers() + b.numOutliers() + 1) {
    return std::nullopt;
  }
  // The merged hits, with the longer piece's finder fields and the fit.
  Track out = a.hits.size() >= b.hits.size() ? a : b;
  out.hits = fitted.hits;
  out.outlier.assign(out.hits.size(), kFittedHit);
  out.takeFit(fitted);
  return out;
}

SplitTrackMerger::Result SplitTrackMerger::run(
    std::span<const Hit> hits, std::vector<Track> tracks) const {
  Result result;
  if (!m_config.enabled) {
    result.tracks = std::move(tracks);
    return result;
  }
  for (const Track& t : tracks) {
    for (HitIndex h : t.hits) {
      if (h >= hits.size()) {
        throw std::out_of_range("SplitTrackMerger: hit index out of range");
      }
    }
  }
  std::vector<bool> alive(tracks.size(), true);
  for (int round = 0; round < kMaxRounds; ++round) {
    // Candidates by tanLambda, so that a pair search is a sweep.
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < tracks.size(); ++i) {
      if (alive[i] && mergeable(tracks[i])) {
        order.push_back(i);
      }
    }
    auto tanLambda = [&](std::size_t i) {
      return tracks[i].atIp.parameters[eTanLambda];
    };
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      return std::make_pair(tanLambda(x), x) < std::make_pair(tanLambda(y), y);
    });
    std::vector<Candidate> candidates;
    for (std::size_t k = 0; k < order.size(); ++k) {
      for (std::size_t l = k + 1; l < order.size(); ++l) {
        if (tanLambda(order[l]) - tanLambda(order[k]) >
            m_config.maxTanLambdaDifference) {
          break;
        }
        const std::size_t i = std::min(order[k], order[l]);
        const std::size_t j = std::max(order[k], order[l]);
        if (std::optional<double> chi2 =
                compatible(hits, tracks[i], tracks[j])) {
          candidates.push_back({*chi2, i, j});
        }
      }
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& x, const Candidate& y) {
                return std::tie(x.chi2, x.first, x.second) <
                       std::tie(y.chi2, y.first, y.second);
              });
    std::vector<bool> taken(tracks.size(), false);
    std::size_t merges = 0;
    for (const Candidate& c : candidates) {
      if (taken[c.first] || taken[c.second]) {
        continue;
      }
      if (std::optional<Track> m =
              merge(hits, tracks[c.first], tracks[c.second])) {
        tracks[c.first] = std::move(*m);
        alive[c.second] = false;
        taken[c.first] = taken[c.second] = true;
        ++merges;
      }
    }
    result.merges += merges;
    if (merges == 0) {
      break;
    }
  }
  result.tracks.reserve(tracks.size());
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    if (alive[i]) {
      result.tracks.push_back(std::move(tracks[i]));
    }
  }
  return result;
}

}  // namespace conftrack

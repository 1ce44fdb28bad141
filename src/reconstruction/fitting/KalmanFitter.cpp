// KalmanFitter: settings, where each hit is measured, the filter passes,
// the smoother and the retries (the propagation is in FitPropagation.cpp,
// the measurement update in FitMeasurement.cpp).

#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"

#include "conftrack/core/PdgTable.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/reconstruction/fitting/detail/FitterState.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

namespace conftrack {

using namespace detail;

namespace {

/// Flags of the hits of a candidate during the fit.
constexpr std::uint8_t kOutlier = 1;      ///< chi2 increment above the cut
constexpr std::uint8_t kUnreachable = 2;  ///< its surface was not reached

}  // namespace

std::optional<double> massHypothesis(std::int32_t pdg) {
  // The charged, long-lived particles a track can be; their masses come
  // from the particle table. Widened before the sign flip: -INT32_MIN does
  // not fit an int32.
  const std::int64_t code = std::abs(static_cast<std::int64_t>(pdg));
  switch (code) {
    case pdg::kElectron:
    case pdg::kMuon:
    case pdg::kPiPlus:
    case pdg::kKPlus:
    case pdg::kProton:
      return pdg::mass(static_cast<std::int32_t>(code));
    default:
      return std::nullopt;
  }
}

const char* knownMassHypotheses() {
  return "11, 13, 211, 321, 2212 and their negatives";
}

namespace {
double requireMass(std::int32_t pdg) {
  std::optional<double> mass = massHypothesis(pdg);
  if (!mass) {
    throw std::invalid_argument("KalmanFitter: unknown PDG code " +
                                std::to_string(pdg) +
                                " (known: " + knownMassHypotheses() + ")");
  }
  return *mass;
}

/// Key of a sensor in KalmanFitter::m_sensorAxes.
std::uint64_t sensorKey(std::uint32_t layer, std::uint32_t module) {
  return (static_cast<std::uint64_t>(layer) << 32) | module;
}

}  // namespace

KalmanFitter::KalmanFitter(const Detector& detector)
    : KalmanFitter(detector, Config()) {}

KalmanFitter::KalmanFitter(const Detector& detector, const Config& config,
                           const std::shared_ptr<const ModuleLayout>& sensors)
    : m_config(config),
      m_bz(detector.bz()),
      m_followField(config.followField && !detector.field().isUniform()),
      m_mass(requireMass(config.pdg)),
      m_electron(m_mass == constants::kElectronMass),
      m_detector(detector),
      m_navigator(detector) {
  if (m_bz == 0.0) {
    throw std::invalid_argument("KalmanFitter: needs a non-zero field");
  }
  if (!(m_config.maxChi2Increment > 0.0)) {
    throw std::invalid_argument("KalmanFitter: maxChi2Increment must be > 0");
  }
  if (!(m_config.initialVariance.array() > 0.0).all() ||
      !m_config.initialVariance.allFinite()) {
    throw std::invalid_argument(
        "KalmanFitter: initialVariance must be positive and finite");
  }
  if (!(m_config.refitCovarianceScale >= 1.0)) {
    throw std::invalid_argument(
        "KalmanFitter: refitCovarianceScale must be >= 1");
  }
  if (m_config.minHits < 3) {
    throw std::invalid_argument("KalmanFitter: minHits must be >= 3");
  }
  if (!(m_config.minCosIncidence > 0.0 && m_config.minCosIncidence <= 1.0)) {
    throw std::invalid_argument(
        "KalmanFitter: minCosIncidence must be in (0, 1]");
  }
  if (!(m_config.fieldStep > 0.0)) {
    throw std::invalid_argument("KalmanFitter: fieldStep must be positive");
  }
  if (m_config.maxCrossingsPerStep == 0) {
    throw std::invalid_argument(
        "KalmanFitter: maxCrossingsPerStep must be positive");
  }
  if (sensors) {
    if (sensors->numLayers() != m_detector.layers().size()) {
      throw std::invalid_argument(
          "KalmanFitter: the module layout was built for another detector");
    }
    m_sensorAxes.reserve(sensors->modules().size());
    for (const PlanarModule& module : sensors->modules()) {
      m_sensorAxes.push_back({sensorKey(module.layer, module.module),
                              {module.uAxis(), module.vAxis()}});
    }
    std::sort(m_sensorAxes.begin(), m_sensorAxes.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
  }
}

KalmanFitter::Measurement KalmanFitter::measurementOf(
    const Hit& hit, std::uint32_t surface) const {
  Measurement m;
  m.surface = surface;
  m.origin = hit.position;
  m.uAxis = hit.uAxis;
  m.vAxis = hit.vAxis;
  const std::uint64_t key = sensorKey(surface, hit.detId.module);
  const auto it = std::lower_bound(
      m_sensorAxes.begin(), m_sensorAxes.end(), key,
      [](const auto& entry, std::uint64_t k) { return entry.first < k; });
  if (it != m_sensorAxes.end() && it->first == key) {
    // The sensor's axes, matched to the hit's so that sigmaU stays along
    // the axis it was given for (a file's hits carry their layer's axes,
    // whose u is r phi or tangential like the sensor's u, up to the
    // conventions of the file).
    Vector3 u = it->second.first;
    Vector3 v = it->second.second;
    if (std::abs(u.dot(hit.uAxis)) < std::abs(v.dot(hit.uAxis))) {
      std::swap(u, v);
    }
    m.uAxis = u;
    m.vAxis = v;
  }
  // Orthonormal (a file's axes may be rounded); the sign of the normal
  // does not matter.
  m.uAxis.normalize();
  m.vAxis = (m.vAxis - m.vAxis.dot(m.uAxis) * m.uAxis).normalized();
  m.normal = m.uAxis.cross(m.vAxis);
  return m;
}

FitStatus KalmanFitter::filter(std::span<const Hit> hits, const FitInput& input,
                               const std::vector<Measurement>& measurements,
                               const std::vector<std::uint32_t>& order,
                               int direction, const HelixState& start,
                               const TrackCovariance& startCov,
                               std::vector<std::uint8_t>& skip,
                               Pass& pass) const {
  pass.nodes.clear();
  pass.nodes.reserve(order.size());
  pass.chi2 = 0.0;
  pass.used = 0;
  Propagation state;
  const Measurement* previous = nullptr;
  for (std::uint32_t index : order) {
    if (skip[index] != 0) {
      continue;
    }
    const Measurement& measurement = measurements[index];
    Propagation trial;
    if (pass.nodes.empty()) {
      trial.pivot = start.pivot;
      trial.params = start.params;
      trial.cov = startCov;
      // The start state may be off its surface (an updated state):
      // measure at its actual crossing. It is on the inner side of the
      // node's material already (the prefit has no side).
      const FitStatus status = moveToMeasurement(trial, measurement);
      if (status != FitStatus::eSuccess) {
        return status;
      }
    } else {
      trial = state;
      trial.jacobian.setIdentity();
      FitStatus status =
          propagateToNode(trial, direction, *previous, measurement);
      if (status == FitStatus::ePropagationFailed) {
        // The predicted track does not reach this hit's surface: the hit
        // cannot belong to it. Flag it and go on from the same state.
        skip[index] = kUnreachable;
        continue;
      }
      if (status != FitStatus::eSuccess) {
        return status;
      }
    }
    Node& node = pass.nodes.emplace_back();
    node.hit = index;
    node.pivot = trial.pivot;
    node.predicted = trial.params;
    node.predictedCov = trial.cov;
    node.jacobian = trial.jacobian;
    node.filtered = trial.params;
    node.filteredCov = trial.cov;

    const Hit& hit = hits[input.hits[index]];
    double chi2 = 0.0;
    const FitStatus status =
        update(hit, measurement, trial.pivot, trial.params, trial.cov,
               node.filtered, node.filteredCov, chi2);
    if (status == FitStatus::eNumericalProblem) {
      return status;
    }
    if (status != FitStatus::eSuccess || chi2 > m_config.maxChi2Increment) {
      // An outlier leaves no node: the filter goes on from the last used
      // node, whose material and surfaces the next propagation crosses
      // anyway. Going on from the outlier's predicted crossing would add
      // nothing but could put the state on another turn of a looper (the
      // crossing of a wrong hit's plane, or a layer's, may be the one
      // nearest to a wrong hit, not the one the track comes through).
      pass.nodes.pop_back();
      skip[index] = kOutlier;
      continue;
    }
    node.used = true;
    pass.chi2 += chi2;
    ++pass.used;
    state.pivot = node.pivot;
    state.params = node.filtered;
    state.cov = node.filteredCov;
    previous = &measurement;
  }
  if (pass.used < m_config.minHits) {
    return FitStatus::eTooFewMeasurements;
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::fitDirection(
    std::span<const Hit> hits, const FitInput& input,
    const std::vector<Measurement>& measurements, int direction, bool diffuse,
    Track& track) const {
  const std::size_t n = input.hits.size();
  const auto prefit = threePointHelix(hits[input.hits.front()].position,
                                      hits[input.hits[n / 2]].position,
                                      hits[input.hits.back()].position);
  if (!prefit) {
    return FitStatus::ePrefitFailed;
  }
  std::vector<std::uint32_t> order(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    order[i] = direction > 0 ? i : static_cast<std::uint32_t>(n - 1 - i);
  }
  // Pass 1: from the prefit.
  HelixState start;
  start.pivot = hits[input.hits[order.front()]].position;
  start.params = direction > 0 ? prefit->atFirst : prefit->atLast;
  TrackCovariance startCov = m_config.initialVariance.asDiagonal();
  if (m_config.prefitOmegaFraction > 0.0 && !diffuse) {
    // The three hits span the whole track: their curvature is a far
    // better start than "anything" (upstream's 1e-4 mm^-2 allows radii
    // down to 100 mm), which on a short lever arm (e.g. the two double
    // disks of the forward vertex detector first) lets the first hits
    // pull Omega so far that the extrapolation to the next layer leaves
    // the linear regime.
    const double sigma =
        m_config.prefitOmegaFraction * std::abs(start.params[eOmega]) +
        m_config.prefitOmegaFloor;
    startCov(eOmega, eOmega) =
        std::min(startCov(eOmega, eOmega), sigma * sigma);
  }
  std::vector<std::uint8_t> skip(n, 0);
  Pass pass;
  FitStatus status = filter(hits, input, measurements, order, direction, start,
                            startCov, skip, pass);
  if (status != FitStatus::eSuccess) {
    return status;
  }
  // Pass 2, the other way, from the last used node of pass 1 with its
  // covariance scaled.
  const int passDirection = -direction;
  {
    const auto lastUsed =
        std::find_if(pass.nodes.rbegin(), pass.nodes.rend(),
                     [](const Node& node) { return node.used; });
    order.clear();
    if (passDirection > 0) {
      for (std::uint32_t i = lastUsed->hit; i < n; ++i) {
        order.push_back(i);
      }
    } else {
      for (std::uint32_t i = lastUsed->hit + 1; i-- > 0;) {
        order.push_back(i);
      }
    }
    start.pivot = lastUsed->pivot;
    start.params = lastUsed->filtered;
    const TrackCovariance cov =
        lastUsed->filteredCov * m_config.refitCovarianceScale;
    // Hits pass 1 could not reach get another chance from a better
    // trajectory; chi2 outliers stay out.
    std::replace(skip.begin(), skip.end(), kUnreachable, std::uint8_t{0});
    Pass second;
    status = filter(hits, input, measurements, order, passDirection, start, cov,
                    skip, second);
    if (status != FitStatus::eSuccess) {
      return status;
    }
    pass = std::move(second);
  }

  // RTS smoother (Frühwirth 1987 eq. 19-21) over the nodes of pass 2:
  // G = C_k|k F^T C_k+1|k^-1, computed as G^T = C_k+1|k^-1 (F C_k|k) with
  // a Cholesky solve.
  std::vector<Node>& nodes = pass.nodes;
  std::vector<TrackVector> smoothed(nodes.size());
  std::vector<TrackCovariance> smoothedCov(nodes.size());
  smoothed.back() = nodes.back().filtered;
  smoothedCov.back() = nodes.back().filteredCov;
  for (std::size_t k = nodes.size() - 1; k-- > 0;) {
    const Node& node = nodes[k];
    const Node& next = nodes[k + 1];
    const Eigen::LDLT<TrackCovariance> ldlt(next.predictedCov);
    if (ldlt.info() != Eigen::Success) {
      return FitStatus::eNumericalProblem;
    }
    const TrackJacobian gainT = ldlt.solve(next.jacobian * node.filteredCov);
    TrackVector diff = smoothed[k + 1] - next.predicted;
    diff[ePhi0] = wrapAngle(diff[ePhi0]);
    smoothed[k] = node.filtered + gainT.transpose() * diff;
    smoothed[k][ePhi0] = wrapAngle(smoothed[k][ePhi0]);
    smoothedCov[k] =
        node.filteredCov +
        gainT.transpose() * (smoothedCov[k + 1] - next.predictedCov) * gainT;
    symmetrize(smoothedCov[k]);
    if (!smoothed[k].allFinite() || !smoothedCov[k].allFinite()) {
      return FitStatus::eNumericalProblem;
    }
  }

  // The i-th node in path order (pass 2 ran along the path or against
  // it).
  auto pathNode = [&](std::size_t i) {
    return passDirection > 0 ? i : nodes.size() - 1 - i;
  };
  const std::size_t innermost = pathNode(0);
  Propagation ip;
  ip.pivot = nodes[innermost].pivot;
  ip.params = smoothed[innermost];
  ip.cov = smoothedCov[innermost];
  status = propagateToIp(ip, measurements[nodes[innermost].hit].surface,
                         input.beamLine);
  if (status != FitStatus::eSuccess) {
    return status;
  }
  if (!ip.params.allFinite() || !ip.cov.allFinite() ||
      !(ip.cov.diagonal().array() > 0.0).all()) {
    return FitStatus::eNumericalProblem;
  }
  std::size_t firstUsed = nodes.size();
  std::size_t lastUsedPath = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[pathNode(i)].used) {
      firstUsed = std::min(firstUsed, i);
      lastUsedPath = i;
    }
  }
  auto stateAt = [&](std::size_t pathIndex) {
    const std::size_t k = pathNode(pathIndex);
    TrackState out;
    out.reference = nodes[k].pivot;
    out.parameters = smoothed[k];
    out.covariance = smoothedCov[k];
    return out;
  };
  track.atIp.reference = ip.pivot;
  track.atIp.parameters = ip.params;
  symmetrize(ip.cov);
  track.atIp.covariance = ip.cov;
  track.atFirstHit = stateAt(firstUsed);
  track.atLastHit = stateAt(lastUsedPath);
  track.chi2 = pass.chi2;
  track.ndf = 2 * static_cast<int>(pass.used) - 5;
  track.fitted = true;
  // Outliers: every hit not used by the final pass (chi2 outliers,
  // unreachable surfaces, hits beyond the last used one of pass 2).
  std::fill(track.outlier.begin(), track.outlier.end(), std::uint8_t{1});
  for (const Node& node : nodes) {
    if (node.used) {
      track.outlier[node.hit] = 0;
    }
  }
  return FitStatus::eSuccess;
}

Track KalmanFitter::fit(std::span<const Hit> hits, const FitInput& input,
                        FitInfo* info) const {
  Track track;
  track.hits.assign(input.hits.begin(), input.hits.end());
  track.outlier.assign(input.hits.size(), 0);
  FitInfo local;
  FitInfo& out = info != nullptr ? *info : local;
  out = FitInfo();

  auto finish = [&](FitStatus status) {
    out.status = status;
    if (out.firstStatus == FitStatus::eSuccess) {
      out.firstStatus = status;
    }
    return track;
  };
  for (const HitIndex h : input.hits) {
    if (h >= hits.size()) {
      throw std::out_of_range("KalmanFitter: hit index out of range");
    }
  }
  if (!input.beamLine.allFinite()) {
    throw std::invalid_argument("KalmanFitter: beam line not finite");
  }
  if (input.hits.size() < m_config.minHits) {
    return finish(FitStatus::eTooFewHits);
  }
  std::vector<Measurement> measurements(input.hits.size());
  for (std::size_t i = 0; i < input.hits.size(); ++i) {
    const Hit& hit = hits[input.hits[i]];
    const auto layer = m_detector.findLayer(hit.detId);
    if (!layer) {
      return finish(FitStatus::eUnknownLayer);
    }
    // Sensitive layers come first in the navigator's list.
    measurements[i] = measurementOf(hit, *layer);
  }

  const int first = input.backward ? -1 : +1;
  Track attempt = track;
  FitStatus status =
      fitDirection(hits, input, measurements, first, false, attempt);
  out.firstStatus = status;
  const bool retry = m_config.retryInverted &&
                     (status != FitStatus::eSuccess ||
                      attempt.numMeasurements() < m_config.maxHitInvertedFit);
  if (retry) {
    out.retried = true;
    Track inverted = track;
    const FitStatus second =
        fitDirection(hits, input, measurements, -first, false, inverted);
    if (second == FitStatus::eSuccess &&
        (status != FitStatus::eSuccess ||
         inverted.numMeasurements() > attempt.numMeasurements())) {
      attempt = std::move(inverted);
      status = second;
      out.inverted = true;
    }
  }
  if (status != FitStatus::eSuccess && m_config.diffuseFallback &&
      m_config.prefitOmegaFraction > 0.0) {
    // A wrong hit among the three of the prefit gives a wrong curvature
    // that the informed start cannot leave: start from "anything".
    out.diffuse = true;
    Track diffuse = track;
    const FitStatus third =
        fitDirection(hits, input, measurements, first, true, diffuse);
    if (third == FitStatus::eSuccess) {
      attempt = std::move(diffuse);
      status = third;
      out.inverted = false;
    }
  }
  if (status == FitStatus::eSuccess && m_config.majorityRefit) {
    refitMajority(hits, input, measurements, first, attempt, out);
  }
  out.status = status;
  if (status == FitStatus::eSuccess) {
    return attempt;
  }
  return track;
}

void KalmanFitter::refitMajority(std::span<const Hit> hits,
                                 const FitInput& input,
                                 const std::vector<Measurement>& measurements,
                                 int direction, Track& attempt,
                                 FitInfo& info) const {
  const std::size_t used = attempt.numMeasurements();
  const std::size_t flagged = attempt.hits.size() - used;
  if (flagged <= used || flagged < m_config.minHits) {
    return;
  }
  // The flagged hits, in path order, with their measurements.
  std::vector<std::uint32_t> positions;
  positions.reserve(flagged);
  for (std::uint32_t i = 0; i < attempt.outlier.size(); ++i) {
    if (attempt.outlier[i] != 0) {
      positions.push_back(i);
    }
  }
  std::vector<HitIndex> subHits(positions.size());
  std::vector<Measurement> subMeasurements(positions.size());
  for (std::size_t k = 0; k < positions.size(); ++k) {
    subHits[k] = input.hits[positions[k]];
    subMeasurements[k] = measurements[positions[k]];
  }
  const FitInput subInput{subHits, input.backward, input.beamLine};
  Track majority;
  majority.hits = subHits;
  majority.outlier.assign(subHits.size(), 0);
  FitStatus status =
      fitDirection(hits, subInput, subMeasurements, direction, false, majority);
  if (status != FitStatus::eSuccess) {
    majority.outlier.assign(subHits.size(), 0);
    status = fitDirection(hits, subInput, subMeasurements, -direction, false,
                          majority);
  }
  if (status != FitStatus::eSuccess || majority.numMeasurements() <= used) {
    return;
  }
  // The majority fit's states with flags over all hits of the track.
  std::vector<std::uint8_t> outlier(attempt.hits.size(), 1);
  for (std::size_t k = 0; k < positions.size(); ++k) {
    outlier[positions[k]] = majority.outlier[k];
  }
  majority.hits = std::move(attempt.hits);
  majority.outlier = std::move(outlier);
  attempt = std::move(majority);
  info.majority = true;
}

FittingResult KalmanFitter::run(std::span<const Hit> hits,
                                std::span<const FitInput> inputs) const {
  const auto start = std::chrono::steady_clock::now();
  FittingResult result;
  result.tracks.reserve(inputs.size());
  for (const FitInput& candidate : inputs) {
    FitInfo info;
    result.tracks.push_back(fit(hits, candidate, &info));
    if (info.retried) {
      ++result.retries;
    }
    if (info.diffuse) {
      ++result.fallbacks;
    }
    if (info.majority) {
      ++result.majorityRefits;
    }
    if (info.status != FitStatus::eSuccess) {
      ++result.failures;
    } else {
      result.outliers += result.tracks.back().numOutliers();
    }
  }
  result.milliseconds = std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - start)
                            .count();
  return result;
}

}  // namespace conftrack

#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"

#include "conftrack/geometry/MaterialInteractions.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <stdexcept>

namespace conftrack {

namespace {

using Matrix25 = Eigen::Matrix<double, 2, 5>;
using Matrix52 = Eigen::Matrix<double, 5, 2>;

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Smallest arc between two crossings, as the simulation (a surface just
/// crossed is not found again within it) [mm].
constexpr double kMinStep = 1e-4 * units::mm;
/// Largest distance along the track between a node's PCA and the crossing
/// of its own surface that is still taken as "the same crossing" [mm]:
/// after an update the PCA moves by about the residual, divided by the
/// cosine of the crossing angle along the track.
constexpr double kOwnCrossingTolerance = 1.0 * units::m;
/// Longest transverse arc searched for the next node [mm].
constexpr double kMaxArc = 100.0 * units::m;
/// The iterated update stops when the exact crossing residual agrees with
/// the linear model within this fraction of the resolution.
constexpr double kLinearTolerance = 0.02;
/// Flags of the hits of a candidate during the fit.
constexpr std::uint8_t kOutlier = 1;      ///< chi2 increment above the cut
constexpr std::uint8_t kUnreachable = 2;  ///< its surface was not reached
/// A point closer than this to a surface is on it [mm].
constexpr double kOnSurface = 1e-9 * units::mm;

/// Crossing of the surface extended to infinity (cylinder in z, disk in
/// r): a hit is on its layer even where the predicted track just misses
/// the layer's edge.
double crossExtended(const Helix& helix, const NavigationSurface& surface,
                     double sMin, double sMax) {
  switch (surface.shape) {
    case SurfaceShape::eCylinder:
      return helix.nextCylinderCrossing(surface.r, -kInf, kInf, sMin, sMax);
    case SurfaceShape::eDisk:
      return helix.nextDiskCrossing(surface.zMin, 0.0, kInf, sMin, sMax);
    case SurfaceShape::eCone:
      return helix.nextConeCrossing(surface.zMin, surface.zMax, surface.coneR1,
                                    surface.coneSlope, sMin, sMax);
  }
  return kInf;
}

/// 2-D measurement of `hit` for the state predicted on its surface: the
/// residual m - h(x) in the local frame, the measurement matrix H and the
/// covariance V. Returns false where the crossing is tangent.
///
/// The predicted crossing X(a) = X(a, s(a)) moves along the track when d0
/// or z0 change: dX/da = (1 - t g^T / (g . t)) dX/da|_s, with
/// dX/dd0|_s = n = (-sin phi0, cos phi0, 0), dX/dz0|_s = z_hat and the other
/// derivatives zero at the pivot (d0 = z0 = s = 0); t = (cos phi0, sin phi0,
/// tanLambda) = dX/ds and g the surface normal (radial for a cylinder, z for
/// a disk).
bool measurementModel(const Hit& hit, const NavigationSurface& surface,
                      const HelixState& state, Vector2& residual, Matrix25& h,
                      Matrix2& v) {
  const Vector3 x = state.pca();
  const double phi = state.params[ePhi0];
  const double tanLambda = state.params[eTanLambda];
  const Vector3 t(std::cos(phi), std::sin(phi), tanLambda);
  const Vector3 n(-t.y(), t.x(), 0.0);
  h.setZero();
  if (surface.shape == SurfaceShape::eCylinder) {
    const double r = x.head<2>().norm();
    if (!(r > 0.0)) {
      return false;
    }
    const Vector3 radial(x.x() / r, x.y() / r, 0.0);
    const Vector3 azimuthal(-radial.y(), radial.x(), 0.0);
    const double ct = radial.dot(t);
    if (std::abs(ct) < 1e-9) {
      return false;
    }
    const Vector3 dd0 = n - t * (radial.dot(n) / ct);
    h(0, eD0) = azimuthal.dot(dd0);
    h(1, eD0) = dd0.z();
    h(1, eZ0) = 1.0;
    // u is the arc on the layer cylinder, as the smearing (HitSmearing).
    const double phiHit = std::atan2(hit.position.y(), hit.position.x());
    residual(0) = r * wrapAngle(phiHit - std::atan2(x.y(), x.x()));
    residual(1) = hit.position.z() - x.z();
  } else {
    if (std::abs(tanLambda) < 1e-9) {
      return false;
    }
    const Vector3 dz0 = Vector3::UnitZ() - t / tanLambda;
    h(0, eD0) = hit.uAxis.dot(n);
    h(0, eZ0) = hit.uAxis.dot(dz0);
    h(1, eD0) = hit.vAxis.dot(n);
    h(1, eZ0) = hit.vAxis.dot(dz0);
    const Vector3 d = hit.position - x;
    residual(0) = d.dot(hit.uAxis);
    residual(1) = d.dot(hit.vAxis);
  }
  v.setZero();
  v(0, 0) = hit.sigmaU * hit.sigmaU;
  v(1, 1) = hit.sigmaV * hit.sigmaV;
  return true;
}

void symmetrize(TrackCovariance& c) { c = 0.5 * (c + c.transpose()).eval(); }

}  // namespace

/// A state on its way between nodes: parameters and covariance relative
/// to `pivot`, and the accumulated transport Jacobian since the last node
/// (without process noise: the RTS smoother needs F, and the predicted
/// covariance F C F^T + Q).
struct KalmanFitter::Propagation {
  Vector3 pivot = Vector3::Zero();
  TrackVector params = TrackVector::Zero();
  TrackCovariance cov = TrackCovariance::Zero();
  TrackJacobian jacobian = TrackJacobian::Identity();
};

/// A hit node of a filter pass.
struct KalmanFitter::Node {
  /// Index of the hit in FoundTrack::hits.
  std::uint32_t hit = 0;
  /// Predicted crossing of the hit's surface: the reference point.
  Vector3 pivot = Vector3::Zero();
  TrackVector predicted = TrackVector::Zero();
  TrackCovariance predictedCov = TrackCovariance::Zero();
  TrackVector filtered = TrackVector::Zero();
  TrackCovariance filteredCov = TrackCovariance::Zero();
  /// Transport from the previous node of the pass.
  TrackJacobian jacobian = TrackJacobian::Identity();
  /// False for outliers.
  bool used = false;
};

/// The nodes and chi2 of one filter pass.
struct KalmanFitter::Pass {
  std::vector<Node> nodes;
  double chi2 = 0.0;
  std::uint32_t used = 0;
};

std::optional<double> massHypothesis(std::int32_t pdg) {
  // Widened before the sign flip: -INT32_MIN does not fit an int32.
  switch (std::abs(static_cast<std::int64_t>(pdg))) {
    case 11:
      return constants::kElectronMass;
    case 13:
      return constants::kMuonMass;
    case 211:
      return constants::kPionMass;
    case 321:
      return constants::kKaonMass;
    case 2212:
      return constants::kProtonMass;
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
}  // namespace

KalmanFitter::KalmanFitter(const Detector& detector)
    : KalmanFitter(detector, Config()) {}

KalmanFitter::KalmanFitter(const Detector& detector, const Config& config)
    : m_config(config),
      m_bz(detector.bz()),
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
  if (m_config.maxCrossingsPerStep == 0) {
    throw std::invalid_argument(
        "KalmanFitter: maxCrossingsPerStep must be positive");
  }
}

FitStatus KalmanFitter::applyMaterial(const NavigationSurface& surface,
                                      int direction, Propagation& state) const {
  if (!(surface.thicknessX0 > 0.0) ||
      (!m_config.multipleScattering && !m_config.energyLoss)) {
    return FitStatus::eSuccess;
  }
  const HelixState helix{state.pivot, state.params};
  // Path length at the actual crossing angle, with the simulation's caps.
  const double xOverX0 =
      surface.xOverX0(helix.pca(), helix.direction(), m_config.minCosIncidence);
  const double omega = state.params[eOmega];
  const double tanLambda = state.params[eTanLambda];
  const double secLambda2 = 1.0 + tanLambda * tanLambda;
  const double p = constants::kPtPerTeslaMm * std::abs(m_bz) /
                   std::max(std::abs(omega), kMinAbsOmega) *
                   std::sqrt(secLambda2);
  const double m = m_mass;
  // Momenta before and after the layer along the motion.
  double pBefore = p;
  double pAfter = p;
  if (m_config.energyLoss) {
    if (direction > 0) {
      const double energy =
          std::hypot(p, m) - betheMeanEnergyLoss(p, m, 1.0, xOverX0);
      if (!(energy > m)) {
        return FitStatus::eParticleStopped;
      }
      pAfter = std::sqrt((energy - m) * (energy + m));
    } else {
      // E_before - loss(p_before) = E_after: a fixed-point iteration (the
      // loss changes by < 1e-3 relative between iterations).
      const double energyAfter = std::hypot(p, m);
      for (int i = 0; i < 3; ++i) {
        const double energy =
            energyAfter + betheMeanEnergyLoss(pBefore, m, 1.0, xOverX0);
        pBefore = std::sqrt((energy - m) * (energy + m));
      }
    }
    if (pAfter < m_config.minMomentum) {
      return FitStatus::eParticleStopped;
    }
    // Omega ~ 1/p at fixed lambda. d(Omega')/d(Omega) = ratio^2 beta/beta'
    // (the p dependence of the loss itself neglected).
    const double pNew = direction > 0 ? pAfter : pBefore;
    const double ratio = p / pNew;
    const double derivative =
        ratio * ratio * (p / std::hypot(p, m)) / (pNew / std::hypot(pNew, m));
    state.params[eOmega] = omega * ratio;
    state.cov.row(eOmega) *= derivative;
    state.cov.col(eOmega) *= derivative;
    state.jacobian.row(eOmega) *= derivative;
  }
  if (m_config.multipleScattering) {
    // Scattering with the momentum before the loss, as the simulation.
    const double beta = pBefore / std::hypot(pBefore, m);
    const double theta0 =
        scatteringTheta0(pBefore, beta, 1.0, xOverX0, m_electron);
    const double var = theta0 * theta0;
    // Two projected angles: d phi = theta1 / cos(lambda), d lambda =
    // theta2; d tanLambda = sec^2 d lambda and, at fixed p, d Omega =
    // Omega tanLambda d lambda.
    state.cov(ePhi0, ePhi0) += var * secLambda2;
    TrackVector g = TrackVector::Zero();
    g[eOmega] = state.params[eOmega] * tanLambda;
    g[eTanLambda] = secLambda2;
    state.cov += var * g * g.transpose();
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::crossing(const HelixState& state,
                                 const NavigationSurface& surface,
                                 HelixState& moved,
                                 TrackJacobian& jacobian) const {
  // The crossing of the (extended) surface nearest to the PCA, searched
  // along and against the motion within kOwnCrossingTolerance. A PCA on
  // the surface stays (the searches exclude s = 0 and would find the next
  // crossing instead).
  moved = state;
  jacobian.setIdentity();
  const Vector3 pca = state.pca();
  const double offSurface = surface.shape == SurfaceShape::eDisk
                                ? pca.z() - surface.zMin
                                : pca.head<2>().norm() - surface.r;
  if (std::abs(offSurface) <= kOnSurface) {
    return FitStatus::eSuccess;
  }
  const Helix forward = makeHelix(state, m_bz, +1);
  const double ahead =
      crossExtended(forward, surface, 0.0, kOwnCrossingTolerance);
  const double behind = crossExtended(makeHelix(state, m_bz, -1), surface, 0.0,
                                      kOwnCrossingTolerance);
  double s = 0.0;
  if (ahead <= behind && ahead < kInf) {
    s = ahead;
  } else if (behind < kInf) {
    s = -behind;
  } else {
    return FitStatus::ePropagationFailed;
  }
  moved.pivot = forward.position(s);
  const double sMoved = movePivot(state.params, state.pivot, moved.pivot, s,
                                  moved.params, &jacobian);
  if (!std::isfinite(sMoved) || !moved.params.allFinite()) {
    return FitStatus::eNumericalProblem;
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::moveToCrossing(Propagation& state,
                                       const NavigationSurface& surface) const {
  HelixState moved;
  TrackJacobian jacobian;
  const FitStatus status =
      crossing({state.pivot, state.params}, surface, moved, jacobian);
  if (status == FitStatus::ePropagationFailed) {
    // The updated helix no longer reaches the surface (a grazing
    // crossing): stay at the PCA, which is as close as it gets.
    return FitStatus::eSuccess;
  }
  if (status != FitStatus::eSuccess) {
    return status;
  }
  if (moved.pivot != state.pivot) {
    state.pivot = moved.pivot;
    state.params = moved.params;
    state.cov = jacobian * state.cov * jacobian.transpose();
    state.jacobian = jacobian * state.jacobian;
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::propagateToSurface(Propagation& state, int direction,
                                           std::uint32_t fromSurface,
                                           std::uint32_t target) const {
  const auto& surfaces = m_navigator.surfaces();
  FitStatus status = moveToCrossing(state, surfaces[fromSurface]);
  if (status != FitStatus::eSuccess) {
    return status;
  }
  if (direction > 0) {
    // Along the motion the material of the node comes after its hit.
    status = applyMaterial(surfaces[fromSurface], +1, state);
    if (status != FitStatus::eSuccess) {
      return status;
    }
  }
  Helix walk = makeHelix({state.pivot, state.params}, m_bz, direction);
  const NavigationSurface& goal = surfaces[target];
  for (unsigned n = 0; n < m_config.maxCrossingsPerStep; ++n) {
    const double sMax = std::min(walk.period(), kMaxArc);
    const double sGoal = crossExtended(walk, goal, kMinStep, sMax);
    if (!(sGoal < kInf)) {
      return FitStatus::ePropagationFailed;
    }
    const SurfaceCrossing next =
        m_navigator.nextCrossing(walk, kMinStep, sGoal);
    const bool arrive = !next.found() || next.surface == target;
    const double s = arrive ? sGoal : next.s;
    const Vector3 position = walk.position(s);
    TrackVector moved;
    TrackJacobian jacobian;
    const double sMoved = movePivot(state.params, state.pivot, position,
                                    direction * s, moved, &jacobian);
    if (!std::isfinite(sMoved) || !moved.allFinite()) {
      return FitStatus::eNumericalProblem;
    }
    state.params = moved;
    state.cov = jacobian * state.cov * jacobian.transpose();
    state.jacobian = jacobian * state.jacobian;
    state.pivot = position;
    if (arrive) {
      // Against the motion the node's material is crossed before its hit;
      // node states stay on the side the particle comes from.
      return direction < 0 ? applyMaterial(goal, -1, state)
                           : FitStatus::eSuccess;
    }
    status = applyMaterial(surfaces[next.surface], direction, state);
    if (status != FitStatus::eSuccess) {
      return status;
    }
    walk = makeHelix({state.pivot, state.params}, m_bz, direction);
  }
  return FitStatus::ePropagationFailed;
}

FitStatus KalmanFitter::propagateToIp(Propagation& state,
                                      std::uint32_t fromSurface) const {
  const Vector3 origin = Vector3::Zero();
  const auto& surfaces = m_navigator.surfaces();
  TrackVector atOrigin;
  // Transverse arc from the current PCA to the PCA to the z axis, within
  // half a turn (physics.md 3).
  double s = movePivot(state.params, state.pivot, origin, 0.0, atOrigin);
  if (!std::isfinite(s)) {
    return FitStatus::eNumericalProblem;
  }
  if (m_config.materialToIp && std::abs(s) > kMinStep) {
    FitStatus status = moveToCrossing(state, surfaces[fromSurface]);
    if (status != FitStatus::eSuccess) {
      return status;
    }
    s = movePivot(state.params, state.pivot, origin, 0.0, atOrigin);
    const int direction = s < 0.0 ? -1 : 1;
    if (direction > 0) {
      // PCA after the innermost hit (not a prompt track): its material
      // comes first.
      status = applyMaterial(surfaces[fromSurface], +1, state);
      if (status != FitStatus::eSuccess) {
        return status;
      }
      s = movePivot(state.params, state.pivot, origin, 0.0, atOrigin);
    }
    Helix walk = makeHelix({state.pivot, state.params}, m_bz, direction);
    for (unsigned n = 0; n < m_config.maxCrossingsPerStep; ++n) {
      const double remaining = std::abs(s);
      if (!(remaining > kMinStep)) {
        break;
      }
      const SurfaceCrossing next =
          m_navigator.nextCrossing(walk, kMinStep, remaining);
      if (!next.found()) {
        break;
      }
      const Vector3 position = walk.position(next.s);
      TrackVector moved;
      TrackJacobian jacobian;
      const double sMoved = movePivot(state.params, state.pivot, position,
                                      direction * next.s, moved, &jacobian);
      if (!std::isfinite(sMoved) || !moved.allFinite()) {
        return FitStatus::eNumericalProblem;
      }
      state.params = moved;
      state.cov = jacobian * state.cov * jacobian.transpose();
      state.pivot = position;
      status = applyMaterial(surfaces[next.surface], direction, state);
      if (status != FitStatus::eSuccess) {
        return status;
      }
      s = movePivot(state.params, state.pivot, origin, 0.0, atOrigin);
      if (!(s * direction > 0.0)) {
        break;
      }
      walk = makeHelix({state.pivot, state.params}, m_bz, direction);
    }
  }
  TrackJacobian jacobian;
  s = movePivot(state.params, state.pivot, origin, 0.0, atOrigin, &jacobian);
  if (!std::isfinite(s) || !atOrigin.allFinite()) {
    return FitStatus::eNumericalProblem;
  }
  state.params = atOrigin;
  state.cov = jacobian * state.cov * jacobian.transpose();
  state.pivot = origin;
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::update(const Hit& hit, const NavigationSurface& layer,
                               const Vector3& pivot, const TrackVector& x0,
                               const TrackCovariance& c0, TrackVector& x,
                               TrackCovariance& c, double& chi2) const {
  Vector2 residual;
  Matrix25 h;
  Matrix2 v;
  if (!measurementModel(hit, layer, {pivot, x0}, residual, h, v)) {
    return FitStatus::ePropagationFailed;  // tangent: no measurement
  }
  // One linearised (EKF) step at xi: x = x0 + K (r(xi) + H(xi) (xi - x0)).
  struct Step {
    TrackVector x;
    Matrix52 gain;
    Matrix25 h;
    double chi2 = 0.0;
  };
  auto linearStep = [&](const TrackVector& xi, const Vector2& ri,
                        const Matrix25& hi, Step& out) {
    TrackVector d = xi - x0;
    d[ePhi0] = wrapAngle(d[ePhi0]);
    const Vector2 innovation = ri + hi * d;
    const Matrix52 pht = c0 * hi.transpose();
    const Matrix2 s = v + hi * pht;
    const double det = s.determinant();
    if (!(det > 0.0) || !std::isfinite(det)) {
      return false;
    }
    const Matrix2 sInv = s.inverse();
    out.gain = pht * sInv;
    out.h = hi;
    out.x = x0 + out.gain * innovation;
    out.x[ePhi0] = wrapAngle(out.x[ePhi0]);
    out.chi2 = innovation.dot(sInv * innovation);
    return out.x.allFinite() && std::isfinite(out.chi2);
  };
  // The exact residual m - h(x) and its Jacobian at x: h(x) is the
  // measurement of the crossing of helix x with the layer.
  auto exact = [&](const TrackVector& xi, Vector2& ri, Matrix25& hi) {
    HelixState atCrossing;
    TrackJacobian toCrossing;
    Matrix2 vi;
    if (crossing({pivot, xi}, layer, atCrossing, toCrossing) !=
            FitStatus::eSuccess ||
        !measurementModel(hit, layer, atCrossing, ri, hi, vi)) {
      return false;
    }
    hi = hi * toCrossing;
    return true;
  };
  Step best;
  if (!linearStep(x0, residual, h, best)) {
    return FitStatus::eNumericalProblem;
  }
  // Iterated update (IEKF, a Gauss-Newton minimisation of
  // J(x) = |m - h(x)|^2_V + |x - x0|^2_C^-1): the crossing point is a
  // non-linear function of the parameters, strongly so near tangent
  // crossings (a square root) or after long extrapolations. Iterate while
  // the exact residual at the new state differs from the linear model by
  // more than kLinearTolerance of the resolution, accepting a step only if
  // J decreases (no divergence in weakly constrained directions).
  std::optional<Eigen::LDLT<TrackCovariance>> priorInverse;
  const Matrix2 vInverse = v.inverse();
  auto costOf = [&](const TrackVector& xc, const Vector2& rc) {
    if (!priorInverse) {
      priorInverse.emplace(c0);
    }
    TrackVector d = xc - x0;
    d[ePhi0] = wrapAngle(d[ePhi0]);
    return rc.dot(vInverse * rc) + d.dot(priorInverse->solve(d));
  };
  // Current linearisation point and the exact residual at `best`.
  TrackVector lin = x0;
  Vector2 rLin = residual;
  Matrix25 hLin = h;
  Vector2 rBest;
  Matrix25 hBest;
  bool haveExact =
      m_config.maxUpdateIterations > 1 && exact(best.x, rBest, hBest);
  for (unsigned iteration = 1;
       haveExact && iteration < m_config.maxUpdateIterations; ++iteration) {
    TrackVector step = best.x - lin;
    step[ePhi0] = wrapAngle(step[ePhi0]);
    const Vector2 deviation = rBest - (rLin - hLin * step);
    if (std::abs(deviation(0)) <= kLinearTolerance * hit.sigmaU &&
        std::abs(deviation(1)) <= kLinearTolerance * hit.sigmaV) {
      break;  // linear enough
    }
    const double costBest = costOf(best.x, rBest);
    Step candidate;
    Vector2 rNext;
    Matrix25 hNext;
    if (!linearStep(best.x, rBest, hBest, candidate) ||
        !exact(candidate.x, rNext, hNext) ||
        !(costOf(candidate.x, rNext) < costBest)) {
      break;  // no improvement: keep the last accepted step
    }
    lin = best.x;
    rLin = rBest;
    hLin = hBest;
    best = candidate;
    rBest = rNext;
    hBest = hNext;
  }
  x = best.x;
  // Joseph form (Frühwirth 1987 eq. 7-9): stays positive definite when the
  // diffuse prior shrinks by many orders of magnitude in one step.
  const TrackJacobian ikh = TrackJacobian::Identity() - best.gain * best.h;
  c = ikh * c0 * ikh.transpose() + best.gain * v * best.gain.transpose();
  symmetrize(c);
  chi2 = best.chi2;
  if (!c.allFinite()) {
    return FitStatus::eNumericalProblem;
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::filter(std::span<const Hit> hits,
                               const FoundTrack& found,
                               const std::vector<std::uint32_t>& surfaces,
                               const std::vector<std::uint32_t>& order,
                               int direction, const HelixState& start,
                               const TrackCovariance& startCov,
                               std::vector<std::uint8_t>& skip,
                               Pass& pass) const {
  const auto& navSurfaces = m_navigator.surfaces();
  pass.nodes.clear();
  pass.nodes.reserve(order.size());
  pass.chi2 = 0.0;
  pass.used = 0;
  Propagation state;
  std::uint32_t previousSurface = kInvalidIndex;
  for (std::uint32_t index : order) {
    if (skip[index] != 0) {
      continue;
    }
    const std::uint32_t surface = surfaces[index];
    Propagation trial;
    if (pass.nodes.empty()) {
      trial.pivot = start.pivot;
      trial.params = start.params;
      trial.cov = startCov;
      // The start state may be off its surface (an updated state):
      // measure at its actual crossing. It is on the inner side of the
      // node's material already (the prefit has no side).
      const FitStatus status = moveToCrossing(trial, navSurfaces[surface]);
      if (status != FitStatus::eSuccess) {
        return status;
      }
    } else {
      trial = state;
      trial.jacobian.setIdentity();
      FitStatus status =
          propagateToSurface(trial, direction, previousSurface, surface);
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

    const Hit& hit = hits[found.hits[index]];
    const NavigationSurface& layer = navSurfaces[surface];
    double chi2 = 0.0;
    const FitStatus status =
        update(hit, layer, trial.pivot, trial.params, trial.cov, node.filtered,
               node.filteredCov, chi2);
    if (status == FitStatus::eNumericalProblem) {
      return status;
    }
    if (status == FitStatus::eSuccess && chi2 <= m_config.maxChi2Increment) {
      node.used = true;
      pass.chi2 += chi2;
      ++pass.used;
    } else {
      node.filtered = trial.params;
      node.filteredCov = trial.cov;
    }
    if (!node.used) {
      skip[index] = kOutlier;
    }
    state.pivot = node.pivot;
    state.params = node.filtered;
    state.cov = node.filteredCov;
    previousSurface = surface;
  }
  if (pass.used < m_config.minHits) {
    return FitStatus::eTooFewMeasurements;
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::fitDirection(std::span<const Hit> hits,
                                     const FoundTrack& found,
                                     const std::vector<std::uint32_t>& surfaces,
                                     int direction, bool diffuse,
                                     Track& track) const {
  const std::size_t n = found.hits.size();
  const auto prefit = threePointHelix(hits[found.hits.front()].position,
                                      hits[found.hits[n / 2]].position,
                                      hits[found.hits.back()].position);
  if (!prefit) {
    return FitStatus::ePrefitFailed;
  }
  std::vector<std::uint32_t> order(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    order[i] = direction > 0 ? i : static_cast<std::uint32_t>(n - 1 - i);
  }
  // Pass 1: from the prefit.
  HelixState start;
  start.pivot = hits[found.hits[order.front()]].position;
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
  FitStatus status = filter(hits, found, surfaces, order, direction, start,
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
    status = filter(hits, found, surfaces, order, passDirection, start, cov,
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
  status = propagateToIp(ip, surfaces[nodes[innermost].hit]);
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
  track.atIp.reference = Vector3::Zero();
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

Track KalmanFitter::fit(std::span<const Hit> hits, const FoundTrack& found,
                        FitInfo* info) const {
  Track track = toTrack(found);
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
  if (found.hits.size() < m_config.minHits) {
    return finish(FitStatus::eTooFewHits);
  }
  std::vector<std::uint32_t> surfaces(found.hits.size());
  for (std::size_t i = 0; i < found.hits.size(); ++i) {
    const HitIndex h = found.hits[i];
    if (h >= hits.size()) {
      throw std::out_of_range("KalmanFitter: hit index out of range");
    }
    const auto layer = m_detector.findLayer(hits[h].detId);
    if (!layer) {
      return finish(FitStatus::eUnknownLayer);
    }
    // Sensitive layers come first in the navigator's list.
    surfaces[i] = *layer;
  }

  const int first = found.fitBackward ? -1 : +1;
  Track attempt = track;
  FitStatus status = fitDirection(hits, found, surfaces, first, false, attempt);
  out.firstStatus = status;
  const bool retry = m_config.retryInverted &&
                     (status != FitStatus::eSuccess ||
                      attempt.numMeasurements() < m_config.maxHitInvertedFit);
  if (retry) {
    out.retried = true;
    Track inverted = track;
    const FitStatus second =
        fitDirection(hits, found, surfaces, -first, false, inverted);
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
        fitDirection(hits, found, surfaces, first, true, diffuse);
    if (third == FitStatus::eSuccess) {
      attempt = std::move(diffuse);
      status = third;
      out.inverted = false;
    }
  }
  out.status = status;
  if (status == FitStatus::eSuccess) {
    return attempt;
  }
  return track;
}

FittingResult KalmanFitter::run(std::span<const Hit> hits,
                                const std::vector<FoundTrack>& found) const {
  const auto start = std::chrono::steady_clock::now();
  FittingResult result;
  result.tracks.reserve(found.size());
  for (const FoundTrack& candidate : found) {
    FitInfo info;
    result.tracks.push_back(fit(hits, candidate, &info));
    if (info.retried) {
      ++result.retries;
    }
    if (info.diffuse) {
      ++result.fallbacks;
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

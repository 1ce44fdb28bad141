// KalmanFitter between nodes: the transport of the state and its
// covariance along the helix from one measurement to the next (or to the
// IP), with the material of every surface crossed, and the moves between
// a layer crossing and a sensor plane.

#include "conftrack/geometry/MaterialInteractions.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/reconstruction/fitting/detail/FitterState.hpp"

#include <algorithm>
#include <cmath>

namespace conftrack {

using namespace detail;

namespace {

/// Largest distance between a hit and the crossing of its plane by the
/// helix of the previous node's state for the two to be the same crossing
/// of their common layer [mm]. Overlapping sensors of one layer are
/// crossed within a few centimetres of each other; a looper's next
/// crossing of the layer is far away except near its turning radius,
/// where the two turns are that close anyway.
constexpr double kSameCrossingDistance = 20.0 * units::mm;
/// Largest transverse arc between the layer crossing and the crossing of
/// a hit's plane [mm], as the simulation's search for the sensors of a
/// layer crossing (ModuleCrossings.cpp): a sensor lies within millimetres
/// of its layer, so a plane crossed farther away belongs to another
/// crossing of the layer (another turn of a looper) or to a wrong hit.
constexpr double kMaxPlaneShift = 200.0 * units::mm;
/// Newton's method on the plane crossing: iterations and convergence in
/// the arc length [mm] (far below the resolution; it converges
/// quadratically).
constexpr int kMaxNewtonIterations = 20;
constexpr double kNewtonTolerance = 1e-9 * units::mm;
/// A segment is split into field steps (Config::fieldStep) only where the
/// bending at its end differs from that at its start by more than this.
constexpr double kMaxBendingChange = 0.01;

}  // namespace

namespace detail {

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

}  // namespace detail

double KalmanFitter::bendingAt(const Vector3& position,
                               const Vector3& direction) const {
  if (!m_followField) {
    return 1.0;
  }
  const Vector3 field = m_detector.field().at(position);
  if (direction.x() == 0.0 && direction.y() == 0.0) {
    return field.z() / m_bz;
  }
  return MagneticField::bendingComponent(field, direction) / m_bz;
}

double KalmanFitter::bendingAt(const HelixState& state) const {
  return m_followField ? bendingAt(state.pca(), state.direction()) : 1.0;
}

Helix KalmanFitter::helixIn(const HelixState& state, double bending,
                            int direction) const {
  if (bending == 1.0) {
    return makeHelix(state, m_bz, direction);
  }
  // Curvature b Omega; the field b B0 keeps pT (and |p|) that of Omega.
  HelixState bent = state;
  bent.params[eOmega] *= bending;
  return makeHelix(bent, m_bz * bending, direction);
}

double KalmanFitter::movePivotIn(const TrackVector& params, const Vector3& from,
                                 const Vector3& to, double sExpected,
                                 double bending, TrackVector& moved,
                                 TrackJacobian* jacobian) const {
  if (bending == 1.0) {
    return movePivot(params, from, to, sExpected, moved, jacobian);
  }
  TrackVector bent = params;
  bent[eOmega] *= bending;
  const double s = movePivot(bent, from, to, sExpected, moved, jacobian);
  moved[eOmega] /= bending;
  if (jacobian != nullptr) {
    // D^-1 J D with D = diag(1, 1, b, 1, 1).
    jacobian->col(eOmega) *= bending;
    jacobian->row(eOmega) /= bending;
  }
  return s;
}

void KalmanFitter::transverseFieldKick(Propagation& state,
                                       const Vector3& middle,
                                       const Vector3& direction,
                                       double transversePath) const {
  const double transverse =
      std::sqrt(direction.x() * direction.x() + direction.y() * direction.y());
  if (!m_followField || !(transverse > 0.0)) {
    return;
  }
  // dpT/dl_T = -q k tanLambda (B_T . n), n = z x t the left normal of the
  // transverse direction t; with Omega = q k B0 / pT:
  // dOmega/dl_T = Omega^2 tanLambda (B_T . n) / B0.
  const Vector3 field = m_detector.field().at(middle);
  const double acrossT =
      (-field.x() * direction.y() + field.y() * direction.x()) / transverse;
  const double tanLambda = direction.z() / transverse;
  const double omega = state.params[eOmega];
  const double change =
      omega * omega * tanLambda * acrossT / m_bz * transversePath;
  if (!(std::abs(change) < 0.5 * std::abs(omega))) {
    return;  // a change this large is outside the first-order model
  }
  const double omegaNew = omega + change;
  const double ratio = omegaNew / omega;
  // |p| fixed: (1 + tanLambda'^2) = (1 + tanLambda^2) (Omega' / Omega)^2.
  const double t = state.params[eTanLambda];
  const double t2 = (1.0 + t * t) * ratio * ratio - 1.0;
  state.params[eOmega] = omegaNew;
  state.params[eTanLambda] = std::copysign(std::sqrt(std::max(t2, 0.0)), t);
  // dOmega'/dOmega = 1 + 2 change / Omega (the rest of the Jacobian is
  // second order).
  const double derivative = 1.0 + 2.0 * change / omega;
  state.cov.row(eOmega) *= derivative;
  state.cov.col(eOmega) *= derivative;
  state.jacobian.row(eOmega) *= derivative;
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
  const double bending = bendingAt(state);
  const Helix forward = helixIn(state, bending, +1);
  const double ahead =
      crossExtended(forward, surface, 0.0, kOwnCrossingTolerance);
  const double behind = crossExtended(helixIn(state, bending, -1), surface, 0.0,
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
  const double sMoved = movePivotIn(state.params, state.pivot, moved.pivot, s,
                                    bending, moved.params, &jacobian);
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
  const NavigationSurface& goal = surfaces[target];
  double bending = bendingAt({state.pivot, state.params});
  Helix walk = helixIn({state.pivot, state.params}, bending, direction);
  // The next surface along `walk`: the goal or one crossed before it.
  SurfaceCrossing next;
  bool arrive = false;
  double s = 0.0;
  auto nextSurface = [&]() {
    const double sMax = std::min(walk.period(), kMaxArc);
    const double sGoal = crossExtended(walk, goal, kMinStep, sMax);
    if (!(sGoal < kInf)) {
      return false;
    }
    next = m_navigator.nextCrossing(walk, kMinStep, sGoal);
    arrive = !next.found() || next.surface == target;
    s = arrive ? sGoal : next.s;
    return true;
  };
  for (unsigned n = 0; n < m_config.maxCrossingsPerStep; ++n) {
    if (!nextSurface()) {
      return FitStatus::ePropagationFailed;
    }
    // In a changing field the segment ends after at most fieldStep of
    // path (a step end, without material), on the helix of the bending at
    // its middle.
    bool stepEnd = false;
    Vector3 middle;
    Vector3 momentum;
    if (m_followField) {
      const double tanLambda = state.params[eTanLambda];
      const double sStep =
          m_config.fieldStep / std::sqrt(1.0 + tanLambda * tanLambda);
      if (s > sStep) {
        Vector3 end;
        walk.positionAndMomentum(s, end, momentum);
        if (std::abs(bendingAt(end, direction * momentum.normalized()) -
                     bending) > kMaxBendingChange) {
          s = sStep;
          stepEnd = true;
        }
      }
      walk.positionAndMomentum(0.5 * s, middle, momentum);
      const double atMiddle =
          bendingAt(middle, direction * momentum.normalized());
      if (atMiddle != bending) {
        bending = atMiddle;
        walk = helixIn({state.pivot, state.params}, bending, direction);
        if (stepEnd) {
          // A surface may now come before the step's end.
          if (!nextSurface()) {
            return FitStatus::ePropagationFailed;
          }
          stepEnd = s > sStep;
          s = std::min(s, sStep);
        } else {
          // The same surface on the new helix (a full navigation only if
          // it is no longer reached).
          const double sSame =
              crossExtended(walk, arrive ? goal : surfaces[next.surface],
                            kMinStep, std::min(walk.period(), kMaxArc));
          if (sSame < kInf) {
            s = sSame;
          } else if (!nextSurface()) {
            return FitStatus::ePropagationFailed;
          }
        }
      }
    }
    const Vector3 position = walk.position(s);
    TrackVector moved;
    TrackJacobian jacobian;
    const double sMoved = movePivotIn(state.params, state.pivot, position,
                                      direction * s, bending, moved, &jacobian);
    if (!std::isfinite(sMoved) || !moved.allFinite()) {
      return FitStatus::eNumericalProblem;
    }
    state.params = moved;
    state.cov = jacobian * state.cov * jacobian.transpose();
    state.jacobian = jacobian * state.jacobian;
    state.pivot = position;
    if (m_followField) {
      walk.positionAndMomentum(0.5 * s, middle, momentum);
      transverseFieldKick(state, middle, direction * momentum.normalized(),
                          direction * s);
    }
    if (!stepEnd) {
      if (arrive) {
        // Against the motion the node's material is crossed before its
        // hit; node states stay on the side the particle comes from.
        return direction < 0 ? applyMaterial(goal, -1, state)
                             : FitStatus::eSuccess;
      }
      status = applyMaterial(surfaces[next.surface], direction, state);
      if (status != FitStatus::eSuccess) {
        return status;
      }
    }
    bending = bendingAt({state.pivot, state.params});
    walk = helixIn({state.pivot, state.params}, bending, direction);
  }
  return FitStatus::ePropagationFailed;
}

FitStatus KalmanFitter::propagateToIp(Propagation& state,
                                      std::uint32_t fromSurface,
                                      const Vector2& beamLine) const {
  // The perigee's reference: the beam line at z = 0 (LCIO's reference
  // point; d0 and z0 are measured from it).
  const Vector3 origin(beamLine.x(), beamLine.y(), 0.0);
  const auto& surfaces = m_navigator.surfaces();
  TrackVector atOrigin;
  // One bending for the whole way in: that halfway between the innermost
  // node and the beam line (the field changes little over it).
  const HelixState innermost{state.pivot, state.params};
  const double bending =
      bendingAt(0.5 * (innermost.pca() + origin), innermost.direction());
  // Transverse arc from the current PCA to the PCA to the beam line,
  // within half a turn (physics.md 3).
  double s =
      movePivotIn(state.params, state.pivot, origin, 0.0, bending, atOrigin);
  if (!std::isfinite(s)) {
    return FitStatus::eNumericalProblem;
  }
  if (m_config.materialToIp && std::abs(s) > kMinStep) {
    FitStatus status = moveToCrossing(state, surfaces[fromSurface]);
    if (status != FitStatus::eSuccess) {
      return status;
    }
    s = movePivotIn(state.params, state.pivot, origin, 0.0, bending, atOrigin);
    const int direction = s < 0.0 ? -1 : 1;
    if (direction > 0) {
      // PCA after the innermost hit (not a prompt track): its material
      // comes first.
      status = applyMaterial(surfaces[fromSurface], +1, state);
      if (status != FitStatus::eSuccess) {
        return status;
      }
      s = movePivotIn(state.params, state.pivot, origin, 0.0, bending,
                      atOrigin);
    }
    Helix walk = helixIn({state.pivot, state.params}, bending, direction);
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
      const double sMoved =
          movePivotIn(state.params, state.pivot, position, direction * next.s,
                      bending, moved, &jacobian);
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
      s = movePivotIn(state.params, state.pivot, origin, 0.0, bending,
                      atOrigin);
      if (!(s * direction > 0.0)) {
        break;
      }
      walk = helixIn({state.pivot, state.params}, bending, direction);
    }
  }
  TrackJacobian jacobian;
  s = movePivotIn(state.params, state.pivot, origin, 0.0, bending, atOrigin,
                  &jacobian);
  if (!std::isfinite(s) || !atOrigin.allFinite()) {
    return FitStatus::eNumericalProblem;
  }
  state.params = atOrigin;
  state.cov = jacobian * state.cov * jacobian.transpose();
  state.pivot = origin;
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::planeCrossing(const HelixState& state,
                                      const Measurement& measurement,
                                      HelixState& moved,
                                      TrackJacobian& jacobian) const {
  moved = state;
  jacobian.setIdentity();
  const Vector3& g = measurement.normal;
  const double bending = bendingAt(state);
  const Helix helix = helixIn(state, bending, +1);
  // From the PCA (s = 0), which is at or near the layer crossing: the
  // plane crossing nearest to it. s < 0 is behind the PCA (the Helix
  // formulae hold for both signs).
  const double s =
      helix.planeCrossing(measurement.origin, g, 0.0, kMaxPlaneShift,
                          kMaxNewtonIterations, kNewtonTolerance, kOnSurface);
  if (s == Helix::kNoCrossing) {
    return FitStatus::ePropagationFailed;
  }
  if (s == 0.0) {
    return FitStatus::eSuccess;
  }
  moved.pivot = helix.position(s);
  const double sMoved = movePivotIn(state.params, state.pivot, moved.pivot, s,
                                    bending, moved.params, &jacobian);
  if (!std::isfinite(sMoved) || !moved.params.allFinite()) {
    return FitStatus::eNumericalProblem;
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::measurementCrossing(const HelixState& state,
                                            const Measurement& measurement,
                                            HelixState& moved,
                                            TrackJacobian& jacobian) const {
  if (m_config.sensorPlanes) {
    return planeCrossing(state, measurement, moved, jacobian);
  }
  return crossing(state, m_navigator.surfaces()[measurement.surface], moved,
                  jacobian);
}

namespace {

/// Moves `state` to `moved` (pivot, parameters, covariance and the
/// accumulated Jacobian).
void applyMove(const HelixState& moved, const TrackJacobian& jacobian,
               Vector3& pivot, TrackVector& params, TrackCovariance& cov,
               TrackJacobian& accumulated) {
  pivot = moved.pivot;
  params = moved.params;
  cov = jacobian * cov * jacobian.transpose();
  accumulated = jacobian * accumulated;
}

}  // namespace

FitStatus KalmanFitter::moveToMeasurement(
    Propagation& state, const Measurement& measurement) const {
  if (!m_config.sensorPlanes) {
    return moveToCrossing(state, m_navigator.surfaces()[measurement.surface]);
  }
  HelixState moved;
  TrackJacobian jacobian;
  const FitStatus status =
      planeCrossing({state.pivot, state.params}, measurement, moved, jacobian);
  if (status != FitStatus::eSuccess) {
    // Unlike a layer, a plane through a wrong hit (another phi) may not be
    // crossed near the layer crossing at all: a residual taken off the
    // plane would be meaningless, so the hit is unreachable.
    return status;
  }
  if (moved.pivot != state.pivot) {
    applyMove(moved, jacobian, state.pivot, state.params, state.cov,
              state.jacobian);
  }
  return FitStatus::eSuccess;
}

FitStatus KalmanFitter::propagateToNode(Propagation& state, int direction,
                                        const Measurement& from,
                                        const Measurement& to) const {
  if (m_config.sensorPlanes && to.surface == from.surface) {
    // Another hit of the same crossing of the layer (overlapping sensors):
    // plane to plane, without the layer's material, which is applied once
    // per crossing when leaving it.
    HelixState moved;
    TrackJacobian jacobian;
    const FitStatus status =
        planeCrossing({state.pivot, state.params}, to, moved, jacobian);
    if (status == FitStatus::eNumericalProblem) {
      return status;
    }
    if (status == FitStatus::eSuccess &&
        (moved.pca() - to.origin).norm() <= kSameCrossingDistance) {
      applyMove(moved, jacobian, state.pivot, state.params, state.cov,
                state.jacobian);
      return FitStatus::eSuccess;
    }
    // Else a later crossing of the same layer (a looper): navigate.
  }
  const FitStatus status =
      propagateToSurface(state, direction, from.surface, to.surface);
  if (status != FitStatus::eSuccess) {
    return status;
  }
  return m_config.sensorPlanes ? moveToMeasurement(state, to)
                               : FitStatus::eSuccess;
}

}  // namespace conftrack

// KalmanFitter at a node: the measurement model of a hit (on its sensor
// plane or on its layer) and the iterated measurement update.

#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/reconstruction/fitting/detail/FitterState.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <optional>

namespace conftrack {

using namespace detail;

namespace {

/// The iterated update stops when the exact crossing residual agrees with
/// the linear model within this fraction of the resolution.
constexpr double kLinearTolerance = 0.02;
/// |g . t| below this (relative) is a crossing along the surface: no
/// measurement.
constexpr double kMinCrossingCosine = 1e-9;

// Both models: the residual m - h(x) in the local frame and the
// measurement matrix H = dh/dx for a state whose PCA is the predicted
// crossing of the measurement surface. Return false where the crossing is
// tangent.
//
// The predicted crossing X(a) = X(a, s(a)) moves along the track when d0
// or z0 change: dX/da = (1 - t g^T / (g . t)) dX/da|_s, with
// dX/dd0|_s = n = (-sin phi0, cos phi0, 0), dX/dz0|_s = z_hat and the other
// derivatives zero at the pivot (d0 = z0 = s = 0); t = (cos phi0, sin phi0,
// tanLambda) = dX/ds and g the surface normal.

/// On the plane through `origin` with normal g and axes u, v: the
/// residual (origin - X) . (u, v).
bool planeModel(const Vector3& origin, const Vector3& u, const Vector3& v,
                const Vector3& g, const HelixState& state, Vector2& residual,
                Matrix25& h) {
  const Vector3 x = state.pca();
  const double phi = state.params[ePhi0];
  const Vector3 t(std::cos(phi), std::sin(phi), state.params[eTanLambda]);
  const Vector3 n(-t.y(), t.x(), 0.0);
  const double gt = g.dot(t);
  if (!(std::abs(gt) >= kMinCrossingCosine * t.norm())) {
    return false;
  }
  const Vector3 dd0 = n - t * (g.dot(n) / gt);
  const Vector3 dz0 = Vector3::UnitZ() - t * (g.z() / gt);
  h.setZero();
  h(0, eD0) = u.dot(dd0);
  h(0, eZ0) = u.dot(dz0);
  h(1, eD0) = v.dot(dd0);
  h(1, eZ0) = v.dot(dz0);
  const Vector3 d = origin - x;
  residual(0) = d.dot(u);
  residual(1) = d.dot(v);
  return true;
}

/// On the layer's navigation surface (Config::sensorPlanes false): on a
/// cylinder u is the arc r phi and v = z, as the ideal simulation smears;
/// on a disk the projections on the hit's axes u, v (the plane model with
/// g = z).
bool layerModel(const Vector3& position, const Vector3& u, const Vector3& v,
                const NavigationSurface& surface, const HelixState& state,
                Vector2& residual, Matrix25& h) {
  if (surface.shape != SurfaceShape::eCylinder) {
    return planeModel(position, u, v, Vector3::UnitZ(), state, residual, h);
  }
  const Vector3 x = state.pca();
  const double phi = state.params[ePhi0];
  const Vector3 t(std::cos(phi), std::sin(phi), state.params[eTanLambda]);
  const Vector3 n(-t.y(), t.x(), 0.0);
  const double r = x.head<2>().norm();
  if (!(r > 0.0)) {
    return false;
  }
  const Vector3 radial(x.x() / r, x.y() / r, 0.0);
  const Vector3 azimuthal(-radial.y(), radial.x(), 0.0);
  const double ct = radial.dot(t);
  if (std::abs(ct) < kMinCrossingCosine) {
    return false;
  }
  const Vector3 dd0 = n - t * (radial.dot(n) / ct);
  h.setZero();
  h(0, eD0) = azimuthal.dot(dd0);
  h(1, eD0) = dd0.z();
  h(1, eZ0) = 1.0;
  const double phiHit = std::atan2(position.y(), position.x());
  residual(0) = r * wrapAngle(phiHit - std::atan2(x.y(), x.x()));
  residual(1) = position.z() - x.z();
  return true;
}

}  // namespace

FitStatus KalmanFitter::update(const Hit& hit, const Measurement& measurement,
                               const Vector3& pivot, const TrackVector& x0,
                               const TrackCovariance& c0, TrackVector& x,
                               TrackCovariance& c, double& chi2) const {
  const NavigationSurface& layer = m_navigator.surfaces()[measurement.surface];
  // The model h(x) of the crossing at `state` (on the measurement surface).
  auto model = [&](const HelixState& state, Vector2& r, Matrix25& hm) {
    if (m_config.sensorPlanes) {
      return planeModel(measurement.origin, measurement.uAxis,
                        measurement.vAxis, measurement.normal, state, r, hm);
    }
    return layerModel(hit.position, measurement.uAxis, measurement.vAxis, layer,
                      state, r, hm);
  };
  Vector2 residual;
  Matrix25 h;
  if (!model({pivot, x0}, residual, h)) {
    return FitStatus::ePropagationFailed;  // tangent: no measurement
  }
  Matrix2 v = Matrix2::Zero();
  v(0, 0) = hit.sigmaU * hit.sigmaU;
  v(1, 1) = hit.sigmaV * hit.sigmaV;
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
    if (measurementCrossing({pivot, xi}, measurement, atCrossing, toCrossing) !=
            FitStatus::eSuccess ||
        !model(atCrossing, ri, hi)) {
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

}  // namespace conftrack

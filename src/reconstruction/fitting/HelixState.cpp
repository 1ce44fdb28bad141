#include "conftrack/reconstruction/fitting/HelixState.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Omega kept away from 0 (sign preserved, +0 counts as positive).
double safeOmega(double omega) {
  return std::abs(omega) >= kMinAbsOmega ? omega
                                         : std::copysign(kMinAbsOmega, omega);
}

}  // namespace

double wrapAngle(double phi) {
  double r = std::remainder(phi, kTwoPi);  // [-pi, pi]
  return r <= -std::numbers::pi ? r + kTwoPi : r;
}

Vector3 HelixState::pca() const {
  const double phi = params[ePhi0];
  return {pivot.x() - params[eD0] * std::sin(phi),
          pivot.y() + params[eD0] * std::cos(phi), pivot.z() + params[eZ0]};
}

Vector3 HelixState::direction() const {
  const double phi = params[ePhi0];
  const double tl = params[eTanLambda];
  const double cosLambda = 1.0 / std::sqrt(1.0 + tl * tl);
  return {cosLambda * std::cos(phi), cosLambda * std::sin(phi), cosLambda * tl};
}

Vector3 HelixState::momentum(double bz) const {
  const double pt = constants::kPtPerTeslaMm * std::abs(bz) /
                    std::abs(safeOmega(params[eOmega]));
  const double phi = params[ePhi0];
  return {pt * std::cos(phi), pt * std::sin(phi), pt * params[eTanLambda]};
}

double movePivot(const TrackVector& params, const Vector3& from,
                 const Vector3& to, double sExpected, TrackVector& moved,
                 TrackJacobian* jacobian) {
  const double d0 = params[eD0];
  const double phi0 = params[ePhi0];
  const double omega = safeOmega(params[eOmega]);
  const double tanLambda = params[eTanLambda];
  const double c = std::cos(phi0);
  const double sn = std::sin(phi0);
  const Vector3 delta = to - from;
  const double u = delta.x() * c + delta.y() * sn;
  const double w = delta.y() * c - delta.x() * sn;
  const double q = 1.0 - omega * d0;
  const double sigma = q < 0.0 ? -1.0 : 1.0;
  const double x = omega * u;
  const double y = q + omega * w;
  const double qNew = sigma * std::hypot(x, y);
  if (qNew == 0.0) {
    moved.setConstant(std::numeric_limits<double>::quiet_NaN());
    return std::numeric_limits<double>::quiet_NaN();
  }
  // Turning angle from the old to the new PCA: sin = -x/q', cos = y/q'.
  const double dphi = std::atan2(-sigma * x, sigma * y);
  double s = -dphi / omega;
  const double period = kTwoPi / std::abs(omega);
  const double turns = std::round((sExpected - s) / period);
  if (std::isfinite(turns) && turns != 0.0) {
    s += turns * period;
  }
  moved[eD0] = d0 - (2.0 * q * w + omega * (u * u + w * w)) / (q + qNew);
  moved[ePhi0] = wrapAngle(phi0 + dphi);
  moved[eOmega] = params[eOmega];
  moved[eZ0] = params[eZ0] + s * tanLambda - delta.z();
  moved[eTanLambda] = tanLambda;
  if (jacobian != nullptr) {
    TrackJacobian& j = *jacobian;
    j.setIdentity();
    const double q2 = qNew * qNew;
    const double halfSinOverOmega = std::sin(0.5 * dphi) / omega;
    j(eD0, eD0) = y / qNew;
    j(eD0, ePhi0) = q * u / qNew;
    j(eD0, eOmega) = -2.0 * halfSinOverOmega * halfSinOverOmega;
    j(ePhi0, eD0) = -omega * omega * u / q2;
    j(ePhi0, ePhi0) = q * y / q2;
    j(ePhi0, eOmega) = -u / q2;
    const double dsdD0 = omega * u / q2;
    const double dsdPhi0 = (y * w + omega * u * u) / q2;
    const double dsdOmega = (u / q2 - s) / omega;
    j(eZ0, eD0) = tanLambda * dsdD0;
    j(eZ0, ePhi0) = tanLambda * dsdPhi0;
    j(eZ0, eOmega) = tanLambda * dsdOmega;
    j(eZ0, eTanLambda) = s;
  }
  return s;
}

TrackVector helixParametersAt(const Vector3& position, const Vector3& momentum,
                              double charge, double bz,
                              const Vector3& reference) {
  const double pt = momentum.head<2>().norm();
  TrackVector local;
  local[eD0] = 0.0;
  local[ePhi0] = std::atan2(momentum.y(), momentum.x());
  local[eOmega] = charge * constants::kPtPerTeslaMm * bz / pt;
  local[eZ0] = 0.0;
  local[eTanLambda] = momentum.z() / pt;
  TrackVector out;
  movePivot(local, position, reference, 0.0, out);
  return out;
}

Helix makeHelix(const HelixState& state, double bz, int direction) {
  const double omega = safeOmega(state.params[eOmega]);
  const double pt = constants::kPtPerTeslaMm * std::abs(bz) / std::abs(omega);
  const double phi = state.params[ePhi0];
  const double dir = direction < 0 ? -1.0 : 1.0;
  const Vector3 momentum =
      dir * pt *
      Vector3(std::cos(phi), std::sin(phi), state.params[eTanLambda]);
  // Helix::omega() = charge kPtPerTeslaMm bz / pt = dir * Omega.
  const double charge =
      dir * (omega < 0.0 ? -1.0 : 1.0) * (bz < 0.0 ? -1.0 : 1.0);
  return Helix(state.pca(), momentum, charge, bz);
}

std::optional<ThreePointHelix> threePointHelix(const Vector3& p1,
                                               const Vector3& p2,
                                               const Vector3& p3) {
  const Vector2 d12 = (p2 - p1).head<2>();
  const Vector2 d13 = (p3 - p1).head<2>();
  const Vector2 d23 = (p3 - p2).head<2>();
  const double a = d12.norm();
  const double b = d23.norm();
  const double c = d13.norm();
  if (!(a > 0.0 && b > 0.0 && c > 0.0)) {
    return std::nullopt;
  }
  const double cross = d12.x() * d13.y() - d12.y() * d13.x();
  // Signed Menger curvature; a left turn (cross > 0) is counter-clockwise,
  // i.e. Omega < 0 (phi decreases along s for Omega > 0, physics.md 2).
  const double omega = -2.0 * cross / (a * b * c);
  const double absOmega = std::abs(omega);
  double s12 = 0.0;
  double s23 = 0.0;
  double phi1 = 0.0;
  if (absOmega * std::max({a, b, c}) < 0.1) {
    // Stiff: arcs below half a turn; the chord p1 p2 points along the
    // direction at the middle of its arc, phi1 - Omega s12 / 2.
    auto arc = [&](double chord) {
      return absOmega > 0.0 ? 2.0 * std::asin(0.5 * absOmega * chord) / absOmega
                            : chord;
    };
    s12 = arc(a);
    s23 = arc(b);
    phi1 = std::atan2(d12.y(), d12.x()) + 0.5 * omega * s12;
  } else {
    // Curved: angles around the circumcentre in the direction of motion.
    const double den = 2.0 * cross;
    const Vector2 centre =
        p1.head<2>() +
        Vector2(d13.y() * d12.squaredNorm() - d12.y() * d13.squaredNorm(),
                d12.x() * d13.squaredNorm() - d13.x() * d12.squaredNorm()) /
            den;
    const Vector2 r1 = p1.head<2>() - centre;
    const Vector2 r2 = p2.head<2>() - centre;
    const Vector2 r3 = p3.head<2>() - centre;
    const double sense = omega > 0.0 ? -1.0 : 1.0;  // +1 counter-clockwise
    auto turned = [&](const Vector2& from, const Vector2& to) {
      const double alpha =
          std::atan2(from.x() * to.y() - from.y() * to.x(), from.dot(to));
      double psi = sense * alpha;
      return psi < 0.0 ? psi + kTwoPi : psi;
    };
    s12 = turned(r1, r2) / absOmega;
    s23 = turned(r2, r3) / absOmega;
    // The left normal n = (-sin phi, cos phi) is Omega (p - centre).
    const Vector2 n = omega * r1;
    phi1 = std::atan2(-n.x(), n.y());
  }
  const double arcLength = s12 + s23;
  if (!(arcLength > 0.0) || !std::isfinite(omega)) {
    return std::nullopt;
  }
  ThreePointHelix out;
  out.arcLength = arcLength;
  out.atFirst << 0.0, wrapAngle(phi1), omega, 0.0,
      (p3.z() - p1.z()) / arcLength;
  out.atLast = out.atFirst;
  out.atLast[ePhi0] = wrapAngle(phi1 - omega * arcLength);
  return out;
}

}  // namespace conftrack

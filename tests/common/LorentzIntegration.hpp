#pragma once

// An independent reference for tracks in a non-uniform field: fine
// Runge-Kutta integration of the Lorentz force (simulation and geometry
// tests).

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/MagneticField.hpp"

#include <Eigen/Geometry>

#include <array>
#include <cmath>

namespace conftrack::test {

/// A charged track from the beam line into the forward disks, along +x in
/// the transverse plane.
struct ForwardTrack {
  double charge;
  double pt;
  double eta;
  Vector3 momentum() const { return {pt, 0.0, pt * std::sinh(eta)}; }
};

/// The field tests' tracks: 0.5-2 GeV, eta 1.5-2.5, both charges.
inline constexpr std::array<ForwardTrack, 4> kForwardTracks{
    {{1.0, 0.5, 1.8}, {-1.0, 1.0, 2.2}, {1.0, 2.0, 1.5}, {-1.0, 0.7, 2.5}}};

/// Position where the track reaches z = zTarget (> x.z()), by RK4 in
/// 0.05 mm steps of path length of dp/dl = q k (d x B(x)), |p| fixed.
inline Vector3 rungeKuttaAtZ(const MagneticField& field, Vector3 x, Vector3 p,
                             double charge, double zTarget) {
  const double h = 0.05;
  const double magnitude = p.norm();
  auto derivative = [&](const Vector3& position, const Vector3& momentum,
                        Vector3& dx, Vector3& dp) {
    const Vector3 direction = momentum / magnitude;
    dx = direction;
    dp =
        charge * constants::kPtPerTeslaMm * direction.cross(field.at(position));
  };
  while (x.z() < zTarget) {
    Vector3 k1x, k1p, k2x, k2p, k3x, k3p, k4x, k4p;
    derivative(x, p, k1x, k1p);
    derivative(x + 0.5 * h * k1x, p + 0.5 * h * k1p, k2x, k2p);
    derivative(x + 0.5 * h * k2x, p + 0.5 * h * k2p, k3x, k3p);
    derivative(x + h * k3x, p + h * k3p, k4x, k4p);
    const Vector3 xNext = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const Vector3 pNext = p + h / 6.0 * (k1p + 2 * k2p + 2 * k3p + k4p);
    if (xNext.z() >= zTarget) {
      const double f = (zTarget - x.z()) / (xNext.z() - x.z());
      return x + f * (xNext - x);
    }
    x = xNext;
    p = pNext * (magnitude / pNext.norm());
  }
  return x;
}

}  // namespace conftrack::test

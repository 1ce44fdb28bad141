#pragma once

/// @file MagneticField.hpp
/// The tracker's magnetic field: uniform along z, or the field of a finite
/// solenoid, whose bending weakens towards its ends (the real TrackML
/// events: docs/validation.md, item 9).

#include "conftrack/core/Types.hpp"

namespace conftrack {

/// An axially symmetric field about the z axis. Uniform (solenoidRadius
/// 0) or the field of a thin solenoid sheet of radius a and half-length L
/// centred on the origin, in the paraxial expansion about the axis:
///   B_z(r, z) = B0 / g(0) (g(z) - r^2 / 4 g''(z)),
///   B_r(r, z) = B0 / g(0) (-r / 2 g'(z) + r^3 / 16 g'''(z)),
/// with the on-axis profile g(z) = f(L - z) + f(L + z), f(u) = u /
/// sqrt(u^2 + a^2). div B = 0 exactly, curl B = O(r^3); the expansion
/// holds for r well inside a. The TrackML fit (a = 1.43 m, L = 2.65 m,
/// tracker r < 1.03 m) uses it as an effective model of the measured
/// bending: its curl reaches 11 % of B0 / a at r = 1 m near the ends
/// (below 2 % for r < 0.5 m).
class MagneticField {
 public:
  struct Config {
    /// B_z at the centre [T]; >= 0 (0: field-free), > 0 for a solenoid.
    double centralBz = 0.0;
    /// Solenoid radius a [mm]; 0: uniform field.
    double solenoidRadius = 0.0;
    /// Solenoid half-length L [mm]; > 0 when solenoidRadius > 0.
    double solenoidHalfLength = 0.0;
  };

  /// Throws std::invalid_argument if centralBz < 0, the radius is
  /// negative, or a solenoid has a non-positive half-length or field.
  explicit MagneticField(const Config& config);

  const Config& config() const { return m_config; }
  /// B_z at the origin [T].
  double centralBz() const { return m_config.centralBz; }
  /// True for a field without gradient.
  bool isUniform() const { return m_config.solenoidRadius == 0.0; }
  /// The field vector at a point [T].
  Vector3 at(const Vector3& position) const;
  /// The part of `field` [T] that bends the transverse motion of a
  /// particle moving along `direction` (any length, not along z):
  /// B_z - tanLambda (B_T . t), t the transverse direction. The force
  /// across t is q k (B_z cos(lambda) - sin(lambda) B_T . t) per unit path,
  /// so a transverse field bends a track moving outwards from a
  /// solenoid's end as much as B_z does (PromptBending, KalmanFitter).
  static double bendingComponent(const Vector3& field,
                                 const Vector3& direction);

 private:
  /// g and its first three derivatives at z.
  void profile(double z, double& g, double& g1, double& g2, double& g3) const;

  Config m_config;
  /// B0 / g(0).
  double m_scale = 1.0;
};

}  // namespace conftrack

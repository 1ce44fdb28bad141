#pragma once

/// @file PromptBending.hpp
/// How much less than the central field a non-uniform field bends a track
/// from the beam line on its way to a point (r, z): the factor that turns
/// its path into the circle of a uniform field, so that the conformal
/// finder's straight lines stay straight (docs/algorithm.md 3.19).

#include "conftrack/geometry/MagneticField.hpp"

#include <vector>

namespace conftrack {

/// The bending factor g(r, z) of a track from the beam line (near z = 0)
/// that reaches the point (r, z) along the straight line in (r, z) from
/// the origin:
///
///     g(r, z) = 2 / r^2 * integral_0^r (r - rho) b(rho, z rho / r) drho,
///     b = (B_z - (z / r) B_r) / B0,
///
/// b being the local bending of a track with slope dz/dr = z / r (the
/// radial field bends it azimuthally as much as B_z does, with the ratio
/// of the longitudinal and radial velocities), and g its weighted mean
/// along the path: to first order in the curvature the track's azimuthal
/// deflection at (r, z) is that of a uniform field g B0, so the track
/// crosses the azimuth of (r, z) where a circle of the central field's
/// curvature crosses radius g r. Moving each hit to radius g r (conformal
/// coordinates divided by g) gives tracks that are circles through the
/// origin again, whose curvature is that of the central field.
///
/// g = 1 for a uniform field. Tabulated once on a grid in r and |z| over
/// the tracker envelope and interpolated bilinearly (the table is of
/// O(100) x O(100) nodes; g varies on the scale of the solenoid's length).
class PromptBending {
 public:
  /// The factor for `field` over r < envelopeR, |z| < envelopeZ [mm]
  /// (points outside take the value at the nearest edge). Throws
  /// std::invalid_argument for a non-positive envelope.
  PromptBending(const MagneticField& field, double envelopeR, double envelopeZ);

  /// True if g = 1 everywhere (a uniform field).
  bool isUniform() const { return m_table.empty(); }
  /// g(r, z) at transverse radius r and z [mm].
  double factor(double r, double z) const;

  /// g(r, z) by direct integration of the field (what the table holds at
  /// its nodes; for tests and the table itself).
  static double integrate(const MagneticField& field, double r, double z);

 private:
  double m_stepR = 0.0;
  double m_stepZ = 0.0;
  int m_nodesR = 0;
  int m_nodesZ = 0;
  /// g at (i stepR, j stepZ), index i * m_nodesZ + j; empty if uniform.
  std::vector<double> m_table;
};

}  // namespace conftrack

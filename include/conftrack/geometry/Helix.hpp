#pragma once

/// @file Helix.hpp
/// The exact trajectory of a charged particle in a uniform solenoid field,
/// with analytic intersections with cylinders and disks and a bracketed
/// root search for cones (physics.md section 2).

#include "conftrack/core/Types.hpp"
#include "conftrack/core/Units.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack {

/// A helix in the field B = Bz z, parametrised by the transverse arc length
/// s from its start point (s > 0 along the momentum).
///
/// With t = (cos phi0, sin phi0) the transverse direction and
/// n = (-sin phi0, cos phi0) its left normal at the start point P0, and
/// w = Omega s (physics.md section 2, expanded so that no 1/Omega cancels):
///
///     P(s) = P0 + t sin(w)/Omega - n 2 sin^2(w/2)/Omega,
///     z(s) = z0 + s tan(lambda),  phi(s) = phi0 - w.
///
/// This is physics.md's x(s) = x0 + [sin phi0 - sin(phi0 - w)]/Omega, ...
/// rewritten with sin phi0 - sin(phi0 - w) = 2 cos(phi0 - w/2) sin(w/2).
/// Omega = q kPtPerTeslaMm Bz / pT is the signed curvature, positive for a
/// positive charge in a positive field: positive particles turn clockwise
/// seen from +z. Omega = 0 (no field) is the straight line; small |Omega|
/// is handled without loss of precision by the same formulas.
class Helix {
 public:
  /// The value returned by the intersection methods for "no crossing".
  static constexpr double kNoCrossing = std::numeric_limits<double>::infinity();

  /// A helix through `position` with `momentum` [GeV] and `charge` [e] in
  /// the field `bz` [T]. Requires a non-zero transverse momentum.
  Helix(const Vector3& position, const Vector3& momentum, double charge,
        double bz)
      : m_position(position) {
    m_pt = momentum.head<2>().norm();
    m_cosPhi = momentum.x() / m_pt;
    m_sinPhi = momentum.y() / m_pt;
    m_tanLambda = momentum.z() / m_pt;
    m_omega = charge * constants::kPtPerTeslaMm * bz / m_pt;
    // Projections of the start point on t and n (used by the crossings).
    m_d = position.x() * m_cosPhi + position.y() * m_sinPhi;
    m_e = -position.x() * m_sinPhi + position.y() * m_cosPhi;
    computeRadialRange();
  }

  /// Start point [mm].
  const Vector3& origin() const { return m_position; }
  /// Signed curvature Omega = q/rho [1/mm].
  double omega() const { return m_omega; }
  /// tan(lambda) = pz/pT.
  double tanLambda() const { return m_tanLambda; }
  /// Transverse momentum [GeV] (constant along the helix).
  double pt() const { return m_pt; }
  /// Transverse period 2 pi/|Omega| [mm]; infinite for a straight line.
  double period() const {
    return m_omega == 0.0 ? kNoCrossing
                          : 2.0 * std::numbers::pi / std::abs(m_omega);
  }
  /// Three-dimensional path length of the transverse arc s: s/cos(lambda).
  double pathLength(double s) const {
    return s * std::sqrt(1.0 + m_tanLambda * m_tanLambda);
  }

  /// Position at transverse arc length s [mm].
  Vector3 position(double s) const {
    double a = s;    // sin(w)/Omega
    double b = 0.0;  // (1 - cos w)/Omega = 2 sin^2(w/2)/Omega
    if (m_omega != 0.0) {
      // One sincos of the half angle: sin w = 2 sin(w/2) cos(w/2).
      const double half = 0.5 * m_omega * s;
      const double h = std::sin(half);
      const double c = std::cos(half);
      a = 2.0 * h * c / m_omega;
      b = 2.0 * h * h / m_omega;
    }
    return {m_position.x() + a * m_cosPhi + b * m_sinPhi,
            m_position.y() + a * m_sinPhi - b * m_cosPhi,
            m_position.z() + s * m_tanLambda};
  }

  /// Momentum [GeV] at transverse arc length s (|p| is constant).
  Vector3 momentum(double s) const {
    const double w = m_omega * s;
    const double c = std::cos(w);
    const double sn = std::sin(w);
    // phi(s) = phi0 - w.
    return {m_pt * (m_cosPhi * c + m_sinPhi * sn),
            m_pt * (m_sinPhi * c - m_cosPhi * sn), m_pt * m_tanLambda};
  }

  /// Position and momentum at s together (one sincos instead of two).
  void positionAndMomentum(double s, Vector3& position,
                           Vector3& momentum) const {
    double a = s;
    double b = 0.0;
    double cosW = 1.0;
    double sinW = 0.0;
    if (m_omega != 0.0) {
      const double half = 0.5 * m_omega * s;
      const double h = std::sin(half);
      const double c = std::cos(half);
      sinW = 2.0 * h * c;
      cosW = 1.0 - 2.0 * h * h;
      a = sinW / m_omega;
      b = 2.0 * h * h / m_omega;
    }
    position = {m_position.x() + a * m_cosPhi + b * m_sinPhi,
                m_position.y() + a * m_sinPhi - b * m_cosPhi,
                m_position.z() + s * m_tanLambda};
    momentum = {m_pt * (m_cosPhi * cosW + m_sinPhi * sinW),
                m_pt * (m_sinPhi * cosW - m_cosPhi * sinW), m_pt * m_tanLambda};
  }

  /// Smallest distance of the transverse circle (or line) from the z axis
  /// [mm]: with maxRadius() the radii the helix can reach. Computed without
  /// the 1/Omega cancellation: |C| - rho = (r0^2 |Omega| - 2 E sgn Omega) /
  /// (1 + |Omega||C|), with |Omega||C| = sqrt(1 - 2 Omega E + Omega^2 r0^2).
  double minRadius() const { return m_minRadius; }
  /// Largest distance from the z axis, rho + |C| [mm]; infinite for a line.
  double maxRadius() const { return m_maxRadius; }
  /// |Omega| |C|, the distance of the circle centre from the axis in units
  /// of the radius (1 for a straight line).
  double centreDistanceOverRadius() const { return m_omegaC; }
  /// dr/ds at the start point: the radial component of the transverse
  /// direction (0 on the axis).
  double radialDirection() const {
    const double r0 = m_position.head<2>().norm();
    return r0 > 0.0 ? m_d / r0 : 0.0;
  }

  /// Next crossing with the cylinder of radius `r` around the z axis, with
  /// z in [zMin, zMax], at s in (sMin, sMax]: the smallest such s, or
  /// kNoCrossing. Analytic (circle-circle intersection, see Helix.cpp);
  /// for loopers every turn is considered.
  double nextCylinderCrossing(double r, double zMin, double zMax, double sMin,
                              double sMax) const;

  /// Crossing with the plane z = `z` if rMin <= r <= rMax there and
  /// s in (sMin, sMax]: s = (z - z0)/tan(lambda), else kNoCrossing.
  double nextDiskCrossing(double z, double rMin, double rMax, double sMin,
                          double sMax) const;

  /// Crossing with the plane through `point` with unit normal `normal`
  /// nearest to sStart (a tilted sensor near its layer crossing), by
  /// Newton's method on normal . (P(s) - point) from sStart: the arc length,
  /// or kNoCrossing if the helix runs along the plane, an iterate leaves
  /// |s - sStart| <= maxShift, or `maxIterations` steps do not bring the
  /// step below `tolerance`. A start within `onPlane` of the plane is
  /// returned as is. Used by the simulation (sensor crossings) and the
  /// fit (measurement planes), so both find the same point.
  double planeCrossing(const Vector3& point, const Vector3& normal,
                       double sStart, double maxShift, int maxIterations,
                       double tolerance, double onPlane = 0.0) const;

  /// Next crossing with the cone r = r1 + (z - zMin) slope, zMin <= z <=
  /// zMax, at s in (sMin, sMax]. A root search (see Helix.cpp): steps that
  /// provably contain no root (bounds on the first and second derivative
  /// of the radial distance) bracket the first sign change, a safeguarded
  /// Newton iteration refines it. Pairs of crossings closer than
  /// `kConeMinStep` in s (grazing) may be missed. slope = 0 is a cylinder
  /// and solved analytically.
  double nextConeCrossing(double zMin, double zMax, double r1, double slope,
                          double sMin, double sMax) const;

  /// Smallest step of the cone root search [mm].
  static constexpr double kConeMinStep = 0.05 * units::mm;

 private:
  /// Fills m_omegaC, m_minRadius and m_maxRadius.
  void computeRadialRange();

  Vector3 m_position;
  double m_pt = 0.0;
  double m_cosPhi = 1.0;
  double m_sinPhi = 0.0;
  double m_tanLambda = 0.0;
  double m_omega = 0.0;
  double m_d = 0.0;
  double m_e = 0.0;
  double m_omegaC = 1.0;
  double m_minRadius = 0.0;
  double m_maxRadius = 0.0;
};

}  // namespace conftrack

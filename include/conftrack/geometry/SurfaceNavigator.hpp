#pragma once

/// @file SurfaceNavigator.hpp
/// Finds the next surface a helix crosses among all sensitive layers and
/// passive surfaces of a detector.

#include "conftrack/core/Types.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/Helix.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace conftrack {

/// One material surface as the navigator sees it.
struct NavigationSurface {
  /// Cylinder, disk or cone.
  SurfaceShape shape = SurfaceShape::eCylinder;
  /// Cylinder radius [mm].
  double r = 0.0;
  /// z range [mm] (disk: zMin = zMax = its z).
  double zMin = 0.0;
  double zMax = 0.0;
  /// r range [mm] (disk extent; cone radii range).
  double rMin = 0.0;
  double rMax = 0.0;
  /// Cone: radius at zMin [mm] and dr/dz.
  double coneR1 = 0.0;
  double coneSlope = 0.0;
  /// Material at normal incidence [X0].
  double thicknessX0 = 0.0;
  /// Smallest |cos(incidence)| that makes geometric sense on a curved
  /// surface: a track tangent to a shell of radius r and thickness t
  /// (silicon-equivalent, thicknessX0 * X0(Si)) traverses at most
  /// sqrt(2 r t) = t / sqrt(t / (2 r)) across the shell's curvature, in
  /// the plane perpendicular to the generator line (z for cylinders), so
  /// the floor is grazingCos times the direction's part in that plane. 0
  /// for disks (flat).
  double grazingCos = 0.0;
  /// Index into Detector::layers() for sensitive layers, -1 for passive.
  std::int32_t layer = -1;

  /// True for sensitive layers.
  bool isSensitive() const { return layer >= 0; }
  /// Unit normal at a point on the surface: radial for cylinders, z for
  /// disks, perpendicular to the generator line in the r-z plane for cones
  /// ((r_hat - slope z_hat)/sqrt(1 + slope^2)). The sign is arbitrary.
  Vector3 normal(const Vector3& position) const;
  /// Material traversed by a track crossing at `position` along the unit
  /// `direction`: thicknessX0 / |cos alpha| (physics.md 4), with |cos alpha|
  /// floored at max(minCosIncidence, grazingCos |d_perp|) (d_perp: the part
  /// of `direction` across the generator line). The one definition shared
  /// by the simulation and the fit, so that both see the same material.
  double xOverX0(const Vector3& position, const Vector3& direction,
                 double minCosIncidence) const;
};

/// The result of a search: transverse arc length and surface index.
struct SurfaceCrossing {
  /// Transverse arc length to the crossing [mm]; Helix::kNoCrossing if none.
  double s = Helix::kNoCrossing;
  /// Index into SurfaceNavigator::surfaces(); invalid if none.
  std::uint32_t surface = kInvalidIndex;

  /// True if a crossing was found.
  bool found() const { return surface != kInvalidIndex; }
};

/// All surfaces of a detector, ordered for a fast nearest-crossing search.
///
/// Cylinders are kept sorted by radius and disks by z. Since the transverse
/// arc length is at least the radial distance travelled (|dr/ds| <= 1;
/// a cylinder behind the radial motion needs a turn at the helix's extreme
/// radius first) and disks are reached at s = dz/tanL, both lists are
/// walked away from the current point and each walk stops as soon as the
/// lower bound exceeds the best crossing found so far: only the few nearby
/// surfaces are intersected. Cones (a handful) are all tried after cheap
/// bounds on their window. A brute-force comparison is in the tests.
class SurfaceNavigator {
 public:
  /// Builds the surface lists of `detector` (copied; no reference kept).
  explicit SurfaceNavigator(const Detector& detector);

  /// All surfaces: sensitive layers first (index = layer index), then the
  /// passive surfaces in Detector::passives() order.
  const std::vector<NavigationSurface>& surfaces() const { return m_surfaces; }

  /// The nearest crossing of `helix` with any surface at s in (sMin, sMax).
  SurfaceCrossing nextCrossing(const Helix& helix, double sMin,
                               double sMax) const;

 private:
  std::vector<NavigationSurface> m_surfaces;
  /// Cylinder surface indices sorted by radius, with the radii alongside.
  std::vector<std::uint32_t> m_cylinders;
  std::vector<double> m_cylinderRadii;
  /// Disk surface indices sorted by z, with the z values alongside.
  std::vector<std::uint32_t> m_disks;
  std::vector<double> m_diskZ;
  /// Cone surface indices.
  std::vector<std::uint32_t> m_cones;
};

}  // namespace conftrack

#pragma once

/// @file Surfaces.hpp
/// The surface types of a conftrack detector: sensitive layers (cylinders
/// and disks) and passive material (cylinders, disks, cones).

#include "conftrack/core/DetectorId.hpp"
#include "conftrack/core/Types.hpp"

#include <cstdint>
#include <string>

namespace conftrack {

/// Shape of a surface. All are symmetric around the z axis.
enum class SurfaceShape : std::uint8_t {
  eCylinder,  ///< radius r, zMin <= z <= zMax
  eDisk,      ///< plane z, rMin <= r <= rMax
  eCone,      ///< from (z1, r1) to (z2, r2)
};

/// A sensitive layer: a barrel cylinder or an endcap disk on one side.
///
/// Barrel layers are modelled as cylinders at the sensor mid-plane radius
/// (flat staves and staggered modules are approximated, see README);
/// endcap disks are flat at z, one object per side.
struct SensitiveLayer {
  /// Name, unique in the detector (endcaps get a "_neg"/"_pos" suffix).
  std::string name;
  /// Identifier of the layer; its module field is 0.
  DetectorId id;
  /// eCylinder (barrel) or eDisk (endcap).
  SurfaceShape shape = SurfaceShape::eCylinder;
  /// Cylinder radius [mm] (barrel).
  double r = 0.0;
  /// z extent [mm]: barrel [zMin, zMax]; disk zMin = zMax = z.
  double zMin = 0.0;
  double zMax = 0.0;
  /// Radial extent [mm]: barrel rMin = rMax = r.
  double rMin = 0.0;
  double rMax = 0.0;
  /// Material at normal incidence, fraction of X0 (module plus support).
  double thicknessX0 = 0.0;
  /// Resolution along u = r-phi [mm].
  double sigmaU = 0.0;
  /// Resolution along v: z on barrels, radial on disks [mm].
  double sigmaV = 0.0;
  /// Segmentation into modules, for module ids: azimuthal sectors and
  /// z slices (barrel) or radial rings (disk).
  std::uint32_t nPhiModules = 1;
  std::uint32_t nZModules = 1;
  /// TrackML volume_id and layer_id of this layer.
  std::uint32_t trackmlVolume = 0;
  std::uint32_t trackmlLayer = 0;

  /// Disk plane position (signed) [mm]; only for disks.
  double z() const { return zMin; }
  /// True for endcap disks.
  bool isDisk() const { return shape == SurfaceShape::eDisk; }
  /// Module number of a point on this layer (phi sector, z slice / ring).
  std::uint32_t moduleAt(const Vector3& position) const;
  /// Local measurement axes (u, v) at a point on this layer:
  /// barrel u = phi direction, v = z; disk u = phi direction, v = radial.
  void localAxes(const Vector3& position, Vector3& uAxis, Vector3& vAxis) const;
};

/// A passive material surface (beam pipe, support, cables).
struct PassiveSurface {
  std::string name;
  SurfaceShape shape = SurfaceShape::eCylinder;
  /// Cylinder: radius and z range. Disk: z (= zMin = zMax) and r range.
  /// Cone: (zMin, rMin) to (zMax, rMax) along the generator line, with
  /// coneR1/coneR2 the radii at zMin/zMax.
  double r = 0.0;
  double zMin = 0.0;
  double zMax = 0.0;
  double rMin = 0.0;
  double rMax = 0.0;
  double coneR1 = 0.0;
  double coneR2 = 0.0;
  /// Material at normal incidence, fraction of X0.
  double thicknessX0 = 0.0;
};

}  // namespace conftrack

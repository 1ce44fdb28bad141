#pragma once

/// @file PlanarModule.hpp
/// One flat silicon sensor of a sensitive layer: a rectangle or a
/// trapezoid with its own frame, thickness, material and resolution.

#include "conftrack/core/Types.hpp"

#include <array>
#include <cstdint>

namespace conftrack {

/// A flat sensor (rectangle or symmetric trapezoid) of a sensitive layer.
///
/// The local frame has u across the sensor (r-phi on barrels, tangential on
/// disks), v along it (z on barrels, radial on disks) and w = u x v normal
/// to it, with the origin at the centre of the sensor. The sensor spans
/// |v| <= halfV and, at v, |u| <= halfUAt(v), which goes linearly from
/// minHalfU at v = -halfV to maxHalfU at v = +halfV (a rectangle when both
/// are equal). The measurement is (u, v) on the mid-plane w = 0.
struct PlanarModule {
  /// Index into Detector::layers() of the layer the sensor belongs to.
  std::uint32_t layer = 0;
  /// Module number within the layer (DetectorId::module of its hits).
  std::uint32_t module = 0;
  /// Centre of the sensor [mm].
  Vector3 center = Vector3::Zero();
  /// Local to global rotation: the columns are the u, v and w axes.
  Matrix3 rotation = Matrix3::Identity();
  /// Half widths along u at v = -halfV and v = +halfV [mm].
  double minHalfU = 0.0;
  double maxHalfU = 0.0;
  /// Half length along v [mm].
  double halfV = 0.0;
  /// Silicon thickness [mm].
  double thickness = 0.0;
  /// Material of the sensor at normal incidence, fraction of X0.
  double thicknessX0 = 0.0;
  /// Single-point resolutions along u and v [mm].
  double sigmaU = 0.0;
  double sigmaV = 0.0;

  /// Unit axes in global coordinates.
  Vector3 uAxis() const { return rotation.col(0); }
  Vector3 vAxis() const { return rotation.col(1); }
  Vector3 normal() const { return rotation.col(2); }
  /// Half width along u at local v [mm] (clamped to the sensor's v range).
  double halfUAt(double v) const;
  /// True if the local point (u, v) lies on the sensor.
  bool contains(double u, double v) const;
  /// Local (u, v, w) of a global point.
  Vector3 toLocal(const Vector3& global) const {
    return rotation.transpose() * (global - center);
  }
  /// Global point of the local (u, v) on the mid-plane.
  Vector3 toGlobal(double u, double v) const {
    return center + u * uAxis() + v * vAxis();
  }
  /// The four corners in global coordinates.
  std::array<Vector3, 4> corners() const;
};

}  // namespace conftrack

#pragma once

/// @file Hit.hpp
/// A reconstructed (measured) hit.

#include "conftrack/core/DetectorId.hpp"
#include "conftrack/core/Types.hpp"

#include <cstdint>

namespace conftrack {

/// A two-dimensional measurement on a planar sensor.
///
/// The local measurement frame is given by two orthonormal axes in global
/// coordinates: on barrel layers u is along r-phi and v along z, on disks u is
/// tangential and v radial (detectors.md 1.7). sigmaU and sigmaV are the
/// single-point resolutions along those axes. Hits are stored by value in
/// contiguous arrays; their position in the array is their HitIndex.
struct Hit {
  /// Stable external id (TrackML `hit_id`); unique within an event.
  std::uint64_t id = 0;
  /// Measured global position [mm].
  Vector3 position = Vector3::Zero();
  /// Sensitive element the hit was measured on.
  DetectorId detId;
  /// Unit vector of the local u axis (r-phi / tangential) in global frame.
  Vector3 uAxis = Vector3::UnitX();
  /// Unit vector of the local v axis (z on barrels, radial on disks).
  Vector3 vAxis = Vector3::UnitZ();
  /// Resolution along u [mm].
  double sigmaU = 0.0;
  /// Resolution along v [mm].
  double sigmaV = 0.0;
};

/// The local measurement axes (u, v) at `position` on a barrel cylinder
/// (`disk` false: u along phi, v = z) or an endcap disk (`disk` true: u
/// along phi, v radial), in global coordinates. On the z axis phi is taken
/// as 0 (u = y).
inline void localMeasurementAxes(const Vector3& position, bool disk,
                                 Vector3& uAxis, Vector3& vAxis) {
  double r = position.head<2>().norm();
  double c = r > 0.0 ? position.x() / r : 1.0;
  double s = r > 0.0 ? position.y() / r : 0.0;
  uAxis = Vector3(-s, c, 0.0);
  vAxis = disk ? Vector3(c, s, 0.0) : Vector3(0.0, 0.0, 1.0);
}

/// Truth information of one hit (simulation only; never seen by the
/// reconstruction).
struct HitTruth {
  /// Id of the particle that made the hit (0: noise).
  std::uint64_t particleId = 0;
  /// True position of the crossing [mm].
  Vector3 position = Vector3::Zero();
  /// True momentum at the crossing [GeV].
  Vector3 momentum = Vector3::Zero();
  /// Time of the crossing [ns], relative to the physics bunch crossing.
  double time = 0.0;
  /// TrackML score weight of the hit (0 where unknown).
  double weight = 0.0;
};

}  // namespace conftrack

#pragma once

/// @file ConformalHits.hpp
/// Hits prepared for conformal tracking: conformal coordinates, their
/// errors, and the layer identity, in a structure of arrays.

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Types.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/PromptBending.hpp"

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace conftrack {

/// Internal index of a conformal hit (position in ConformalHits).
using ConfIndex = std::uint32_t;

/// The hits of one event in conformal representation.
///
/// Hits are stored sorted by (conformal radius descending, hit id), i.e.
/// innermost real radius first, which makes every later loop independent of
/// the input order. `original[i]` maps back to the event's HitIndex.
///
/// Conformal errors are propagated with the Jacobian of the mapping
/// u = x/R^2, v = y/R^2 (upstream.md 2.1, suggested improvement): a
/// tangential displacement d maps to d/R^2 along the tangential direction,
/// a radial one to d/R^2 along the radial direction (with opposite sign,
/// irrelevant for variances).
struct ConformalHits {
  std::vector<HitIndex> original;  ///< index into the event's hits
  std::vector<std::uint64_t> id;   ///< stable hit id (tie-breaks)
  /// Position [mm]: x and y relative to the beam line (the beamSpot of
  /// makeConformalHits), z global.
  std::vector<double> x, y, z;
  std::vector<double> radius;  ///< R = sqrt(x^2 + y^2) [mm]
  std::vector<double> u, v;    ///< conformal coordinates [1/mm]
  std::vector<double> rc;      ///< conformal radius |(u, v)| [1/mm]
  std::vector<double> phi;     ///< azimuth atan2(y, x) in (-pi, pi]
  std::vector<double> varT;    ///< tangential variance, conformal
  std::vector<double> varR;    ///< radial variance, conformal
  std::vector<double> covUU, covUV, covVV;  ///< (u, v) covariance
  std::vector<double> varZ;                 ///< z variance [mm^2] (0 on disks)
  std::vector<double> varRxy;        ///< radial variance [mm^2] (0 barrel)
  std::vector<std::uint32_t> layer;  ///< index into Detector::layers()
  std::vector<std::uint16_t> subdetector;
  std::vector<std::int8_t> side;  ///< -1, 0, +1
  std::vector<std::uint32_t> module;

  std::size_t size() const { return id.size(); }
  /// True if both hits are on the same (subdetector, side, layer).
  bool sameLayer(ConfIndex a, ConfIndex b) const {
    return layer[a] == layer[b];
  }
  /// True if both hits are on the same sensor.
  bool sameSensor(ConfIndex a, ConfIndex b) const {
    return layer[a] == layer[b] && module[a] == module[b];
  }
  bool isEndcap(ConfIndex a) const { return side[a] != 0; }
  /// The factor g of the field map (PromptBending): hit a's conformal
  /// point is that of its position moved to radius g R; exactly 1 in a
  /// uniform field.
  double mapFactor(ConfIndex a) const {
    const double g = 1.0 / (radius[a] * rc[a]);
    return std::abs(g - 1.0) < 1e-12 ? 1.0 : g;
  }

  /// Covariance of (u, v) of hit i.
  Matrix2 covariance(ConfIndex i) const;
};

/// Builds the conformal representation. Throws InputError for a hit on the
/// z axis or on a layer the detector does not have.
///
/// With `bending` (a non-uniform field), each hit's conformal coordinates
/// and their errors are divided by its bending factor g(r, z): the hit
/// moves to radius g r at its azimuth, where the circle of a track from
/// the beam line in the central field passes (PromptBending), so that
/// such tracks are straight lines in the conformal plane again. x, y, z,
/// radius and phi are those of the measured position, not of the moved
/// one.
///
/// `beamSpot` is the transverse position of the beam line [mm]: the map
/// is taken about it (u = (x - x0) / R'^2 with R' the distance from it),
/// so that the tracks of particles from the luminous region are straight
/// lines through the origin of the conformal plane wherever the beams
/// collide, and x, y, radius and phi are stored relative to it. The
/// detector's layers stay where they are: they are cylinders and disks
/// about the detector axis, which the finder's layer crossings, a few
/// millimetres of window wide, treat as centred on the beam line
/// (docs/algorithm.md 3.24).
ConformalHits makeConformalHits(std::span<const Hit> hits,
                                const Detector& detector,
                                const PromptBending* bending = nullptr,
                                const Vector2& beamSpot = Vector2::Zero());

}  // namespace conftrack

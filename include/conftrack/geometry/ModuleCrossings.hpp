#pragma once

/// @file ModuleCrossings.hpp
/// Where a helix crosses the flat sensors of a layer, near its crossing of
/// the layer's navigation surface.

#include "conftrack/geometry/Helix.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"

#include <cstdint>
#include <vector>

namespace conftrack {

/// One crossing of a sensor's mid-plane inside the sensor.
struct ModuleCrossing {
  /// Transverse arc length on the helix [mm].
  double s = 0.0;
  /// Index into ModuleLayout::modules().
  std::uint32_t module = 0;
  /// Local (u, v) of the crossing on the sensor [mm].
  double u = 0.0;
  double v = 0.0;
};

/// Finds the sensors of `layer` that `helix` crosses near its crossing of
/// the layer surface at arc length `sLayer`.
///
/// The sensors lie within ModuleLayout::shellHalfThickness of the layer
/// surface, so a crossing is at most shell / |cos alpha| (alpha: angle of
/// incidence on the layer surface) away from the layer crossing: the
/// candidates are the sensors of the grid within that distance, and each
/// candidate's mid-plane crossing is the root of n . (P(s) - centre) found
/// by Newton's method from sLayer, kept if it lies in the sensor and at
/// s > sMin. Appends to `crossings` in increasing s; `scratch` holds the
/// candidates (reused between calls, no allocation once grown).
/// A track that turns inside the shell without crossing the layer surface
/// is not looked at here (its navigation never reaches the layer).
void findModuleCrossings(const Helix& helix, double sLayer, double sMin,
                         std::uint32_t layer, const ModuleLayout& layout,
                         std::vector<std::uint32_t>& scratch,
                         std::vector<ModuleCrossing>& crossings);

}  // namespace conftrack

#pragma once

/// @file TrackmlModuleLayout.hpp
/// The sensors of the TrackML detector file as a ModuleLayout, for a
/// module-level simulation of the TrackML detector.

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"

#include <vector>

namespace conftrack {

/// Every module of a TrackML module table (detectors.csv) as a sensor of
/// `detector` (buildTrackmlDetector of the same table, or a detector file
/// with the same TrackML volume and layer ids):
/// - on the layer of its (volume_id, layer_id), module number = module_id;
/// - the exact centre, rotation, trapezoid half-lengths and thickness;
/// - material thickness / options.moduleX0 at normal incidence;
/// - resolution pitch / sqrt(12) along u and v (see TrackmlDetector.hpp for
///   why also the strip modules measure v to pitch_v / sqrt(12));
/// - per layer, options.supportThickness / options.supportX0 of support.
/// Throws InputError for a module whose (volume_id, layer_id) the detector
/// does not have.
ModuleLayout buildTrackmlModuleLayout(
    const std::vector<TrackmlModule>& modules, const Detector& detector,
    const TrackmlDetectorOptions& options = {});

}  // namespace conftrack

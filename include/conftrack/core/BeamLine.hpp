#pragma once

/// @file BeamLine.hpp
/// The range of beam lines (where the beams collide, off the detector
/// axis) that simulation and reconstruction accept alike.

#include "conftrack/core/Units.hpp"

namespace conftrack {

/// Largest distance of a beam line from the detector axis, per coordinate
/// [mm]: the finder's beamSpotX/Y and --beam-spot, and the simulation's
/// TrackML beam line (--beam-line). Well inside the innermost layers of
/// any tracker (CLICdet 31 mm, TrackML 32 mm), whose crossings the finder
/// takes as centred on the beam line.
inline constexpr double kMaxBeamLineOffset = 10.0 * units::mm;

}  // namespace conftrack

#pragma once

/// @file FitInput.hpp
/// What the track fit needs of a candidate: its hits, the direction to fit
/// first and the beam line its perigee is taken about. The fitter knows
/// nothing of how the candidate was found.

#include "conftrack/core/Types.hpp"

#include <span>

namespace conftrack {

/// One candidate for KalmanFitter::fit.
struct FitInput {
  /// Event hit indices in path order (innermost first for prompt tracks).
  /// A view: the indices must outlive the fit call.
  std::span<const HitIndex> hits;
  /// Run the first filter pass against the path order (the finder's
  /// choice for tracks built outside-in), else along it.
  bool backward = false;
  /// Transverse position (x, y) [mm] of the beam line, the line parallel
  /// to z about which the perigee (Track::atIp) is taken: d0 and z0 are
  /// measured from its point (x, y, 0), which becomes the state's
  /// reference. The detector axis by default; the finder's beam line
  /// (FinderConfig::beamSpotX/Y, or the event's BeamSpotPrepass estimate)
  /// in Reconstruction, so that a prompt track's d0 is its distance from
  /// the luminous region, not from the axis. Must be finite.
  Vector2 beamLine = Vector2::Zero();
};

}  // namespace conftrack

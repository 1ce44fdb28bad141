#pragma once

/// @file FitInput.hpp
/// What the track fit needs of a candidate: its hits and the direction to
/// fit first. The fitter knows nothing of how the candidate was found.

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
};

}  // namespace conftrack

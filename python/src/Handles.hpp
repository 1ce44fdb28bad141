#pragma once

/// @file Handles.hpp
/// The C++ objects the Python module hands out: a detector, an event and a
/// reconstruction result, each keeping alive what it refers to.

#include "conftrack/core/Event.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"

#include <memory>
#include <string>
#include <vector>

namespace conftrack::python {

/// A detector and the name or file it was loaded from (names the default
/// chain, as the CLI's --detector).
struct DetectorHandle {
  std::shared_ptr<const Detector> detector;
  std::string source;
};

/// An event (read or simulated) and the detector its hits refer to (null:
/// read with raw TrackML ids).
struct EventHandle {
  std::shared_ptr<const Event> event;
  std::shared_ptr<const Detector> detector;
};

/// The reconstruction of one event: the hits it ran on (the tracks' hit
/// indices point into them) and its result.
struct ResultHandle {
  std::vector<Hit> hits;
  Reconstruction::Result result;
  /// Field of the detector [T], for the tracks' pT.
  double bz = 0.0;
  /// Time spent turning the Python hits into Hits [ms].
  double conversionMs = 0.0;
};

}  // namespace conftrack::python

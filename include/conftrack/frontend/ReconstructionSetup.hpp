#pragma once

/// @file ReconstructionSetup.hpp
/// The reconstruction of a detector as the command line and the Python
/// module set it up: the finding chain (chains/), the fit's mass hypothesis
/// and the sensors on whose planes the fit measures hits read from files.

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"

#include <memory>
#include <optional>
#include <string>

namespace conftrack {

/// What a user chooses about the reconstruction.
struct ReconstructionChoice {
  /// Detector name or TOML file, as given (names the default chain).
  std::string detector = "clicdet";
  /// Chain file or shipped name; empty: the chain named like the detector.
  std::string chain;
  /// Fit the candidates (Reconstruction::Config::fit).
  bool fit = true;
  /// Mass hypothesis of the fit (PDG code).
  int fitPdg = 211;
  /// Transverse position of the beam line [mm], replacing the chain's
  /// (FinderConfig::beamSpotX, beamSpotY); unset: the chain's.
  std::optional<Vector2> beamSpot;
};

/// The sensors on whose planes the fit measures hits read from files
/// (which carry only their layer's axes), by DetectorId module number: for
/// the TrackML detector its modules (data/trackml/detectors.csv.gz, whose
/// module_id the hit files use); for another detector with `moduleLevel`
/// its shipped layout (the hits of simulate --module-level); else none.
/// InputError if `moduleLevel` and the detector has no layout file.
std::shared_ptr<const ModuleLayout> loadSensorLayout(const Detector& detector,
                                                     bool moduleLevel);

/// The shipped module layout of `detector` (data/layouts/,
/// geometry/LayoutFile); InputError "--module-level: ..." if it has none.
std::shared_ptr<const ModuleLayout> loadShippedLayout(const Detector& detector);

/// The Reconstruction configuration for `detector` (reads the chain).
Reconstruction::Config makeReconstructionConfig(
    const ReconstructionChoice& choice, const Detector& detector);

}  // namespace conftrack

#pragma once

/// @file ReconstructionOptions.hpp
/// Command-line options of the reconstruction (detector, chain, fit) shared
/// by reconstruct, run, evaluate and bench.

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

namespace conftrack::cli {

struct ReconstructionOptions {
  std::string detector = "clicdet";
  /// Chain file or shipped name; empty: the chain named like the detector.
  std::string chain;
  bool noFit = false;
  /// Mass hypothesis of the fit (PDG code).
  int fitPdg = 211;
};

/// Adds --detector, --chain, --no-fit, --fit-pdg.
void addReconstructionOptions(CLI::App& cmd, ReconstructionOptions& options);

/// The sensors on whose planes the fit measures hits read from files
/// (which carry only their layer's axes), by DetectorId module number: for
/// the TrackML detector its modules (data/trackml/detectors.csv.gz, whose
/// module_id the hit files use); for another detector with `moduleLevel`
/// its shipped layout (the hits of simulate --module-level); else none.
std::shared_ptr<const ModuleLayout> loadSensorLayout(const Detector& detector,
                                                     bool moduleLevel);

/// The Reconstruction configuration for `detector` (reads the chain).
Reconstruction::Config makeReconstructionConfig(
    const ReconstructionOptions& options, const Detector& detector);

}  // namespace conftrack::cli

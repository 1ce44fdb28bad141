#pragma once

/// @file ReconstructionOptions.hpp
/// Command-line options of the reconstruction (detector, chain, fit) shared
/// by reconstruct, run, evaluate and bench.

#include "conftrack/frontend/ReconstructionSetup.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

namespace conftrack::cli {

struct ReconstructionOptions {
  std::string detector = "clicdet";
  /// Chain file or shipped name; empty: the chain named like the detector.
  std::string chain;
  bool noFit = false;
  /// Mass hypothesis of the fit (PDG code).
  int fitPdg = 211;
  /// --beam-spot X,Y [mm]; empty: the chain's.
  std::vector<double> beamSpot;
};

/// Adds --detector, --chain, --no-fit, --fit-pdg, --beam-spot.
void addReconstructionOptions(CLI::App& cmd, ReconstructionOptions& options);

/// loadSensorLayout (frontend/ReconstructionSetup.hpp), used unqualified
/// by the subcommands.
using conftrack::loadSensorLayout;

/// The Reconstruction configuration for `detector` (reads the chain).
Reconstruction::Config makeReconstructionConfig(
    const ReconstructionOptions& options, const Detector& detector);

}  // namespace conftrack::cli

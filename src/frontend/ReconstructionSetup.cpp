#include "conftrack/frontend/ReconstructionSetup.hpp"

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/geometry/LayoutFile.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include <cmath>
#include <filesystem>
#include <string>

namespace conftrack {

std::shared_ptr<const ModuleLayout> loadShippedLayout(
    const Detector& detector) {
  const std::filesystem::path file = shippedLayoutFile(detector);
  if (!std::filesystem::exists(file)) {
    throw InputError("--module-level: detector " + detector.name() +
                     " has no layout file " + file.string() +
                     " (CLICdet and CLD have one)");
  }
  return std::make_shared<const ModuleLayout>(
      readLayoutModules(file, detector));
}

std::shared_ptr<const ModuleLayout> loadSensorLayout(const Detector& detector,
                                                     bool moduleLevel) {
  if (detector.name() == "TrackML") {
    const std::filesystem::path csv =
        dataDirectory() / "data" / "trackml" / "detectors.csv.gz";
    TrackmlDetectorOptions options;
    options.source = csv.string();
    return std::make_shared<const ModuleLayout>(buildTrackmlModuleLayout(
        parseTrackmlModules(readTextFile(csv), csv.string()), detector,
        options));
  }
  if (!moduleLevel) {
    return nullptr;
  }
  return loadShippedLayout(detector);
}

Reconstruction::Config makeReconstructionConfig(
    const ReconstructionChoice& choice, const Detector& detector) {
  std::string chain = choice.chain;
  if (chain.empty()) {
    // The shipped chain of a shipped detector has the detector's file name.
    chain = std::filesystem::path(choice.detector).stem().string();
  }
  // The finder's tables and the selection's [selection] table.
  Reconstruction::Config c =
      readReconstructionConfig(resolveChainPath(chain), detector);
  c.fit = choice.fit;
  c.fitter.pdg = choice.fitPdg;
  if (choice.beamSpot) {
    const Vector2& b = *choice.beamSpot;
    for (int k = 0; k < 2; ++k) {
      if (!(std::abs(b[k]) <= kMaxBeamLineOffset)) {
        throw InputError(
            "--beam-spot: " + std::string(k == 0 ? "x" : "y") +
            " must be finite and within " +
            std::to_string(static_cast<int>(kMaxBeamLineOffset / units::mm)) +
            " mm of the detector axis");
      }
    }
    c.chain.beamSpotX = b.x();
    c.chain.beamSpotY = b.y();
  }
  return c;
}

}  // namespace conftrack

#include "ReconstructionOptions.hpp"

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"
#include "conftrack/io/LayoutFile.hpp"
#include "conftrack/io/TextFile.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include <filesystem>

#include "OptionChecks.hpp"

namespace conftrack::cli {

void addReconstructionOptions(CLI::App& cmd, ReconstructionOptions& o) {
  cmd.add_option("--detector", o.detector, "Detector name or TOML file")
      ->capture_default_str();
  cmd.add_option("--chain", o.chain,
                 "Finding chain name or TOML file (default: the detector's)");
  cmd.add_flag("--no-fit", o.noFit, "Finding only, no Kalman fit");
  cmd.add_option(
         "--fit-pdg", o.fitPdg,
         "Mass hypothesis of the fit (PDG code: 211, 13, 11, 321, 2212)")
      ->capture_default_str()
      ->check(pdgCode());
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
  const std::filesystem::path file = shippedLayoutFile(detector);
  if (!std::filesystem::exists(file)) {
    throw InputError("--module-level: detector " + detector.name() +
                     " has no layout file " + file.string() +
                     " (CLICdet and CLD have one)");
  }
  return std::make_shared<const ModuleLayout>(
      readLayoutModules(file, detector));
}

Reconstruction::Config makeReconstructionConfig(const ReconstructionOptions& o,
                                                const Detector& detector) {
  std::string chain = o.chain;
  if (chain.empty()) {
    // The shipped chain of a shipped detector has the detector's file name.
    chain = std::filesystem::path(o.detector).stem().string();
  }
  Reconstruction::Config c =
      readReconstructionConfig(resolveChainPath(chain), detector);
  c.fit = !o.noFit;
  c.fitter.pdg = o.fitPdg;
  return c;
}

}  // namespace conftrack::cli

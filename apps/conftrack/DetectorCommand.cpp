#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "Commands.hpp"
#include "OptionChecks.hpp"

namespace conftrack::cli {

namespace {

const char* shapeName(SurfaceShape s) {
  switch (s) {
    case SurfaceShape::eCylinder:
      return "cylinder";
    case SurfaceShape::eDisk:
      return "disk";
    case SurfaceShape::eCone:
      return "cone";
  }
  return "?";
}

const char* sideName(Side s) {
  switch (s) {
    case Side::eNegative:
      return "-z";
    case Side::ePositive:
      return "+z";
    case Side::eBarrel:
      break;
  }
  return "";
}

void printDetector(const Detector& det) {
  using units::mm;
  using units::um;
  std::printf("%s (%s): Bz = %.2f T, tracker r < %.1f mm, |z| < %.1f mm\n",
              det.name().c_str(), det.model().c_str(), det.bz() / units::T,
              det.envelopeR() / mm, det.envelopeZ() / mm);
  std::printf("\nSensitive layers (%zu; endcap disks listed per side)\n",
              det.layers().size());
  std::printf("%-20s %-20s %4s %5s %9s %9s %9s %9s %7s %7s %7s %8s\n", "name",
              "subdetector", "side", "layer", "r[mm]", "z[mm]", "rmin[mm]",
              "rmax[mm]", "X/X0[%]", "su[um]", "sv[um]", "trackml");
  for (const Subdetector& sub : det.subdetectors()) {
    for (std::uint32_t li : sub.layers) {
      const SensitiveLayer& l = det.layers()[li];
      char zbuf[32];
      char rbuf[32];
      if (l.isDisk()) {
        std::snprintf(zbuf, sizeof zbuf, "%9.2f", l.z() / mm);
        std::snprintf(rbuf, sizeof rbuf, "%9s", "-");
      } else {
        std::snprintf(zbuf, sizeof zbuf, "%9s", "-");
        std::snprintf(rbuf, sizeof rbuf, "%9.3f", l.r / mm);
      }
      std::printf(
          "%-20s %-20s %4s %5u %s %s %9.2f %9.2f %7.3f %7.1f %7.1f %4u/%u\n",
          l.name.c_str(), sub.name.c_str(), sideName(l.id.side),
          static_cast<unsigned>(l.id.layer), rbuf, zbuf,
          (l.isDisk() ? l.rMin : l.zMin) / mm,
          (l.isDisk() ? l.rMax : l.zMax) / mm, 100.0 * l.thicknessX0,
          l.sigmaU / um, l.sigmaV / um, l.trackmlVolume, l.trackmlLayer);
    }
  }
  std::printf("(barrel rows: rmin/rmax columns give the z range)\n");
  std::printf("\nPassive material (%zu surfaces)\n", det.passives().size());
  std::printf("%-44s %-8s %9s %9s %9s %9s %7s\n", "name", "shape", "zmin[mm]",
              "zmax[mm]", "rmin[mm]", "rmax[mm]", "X/X0[%]");
  for (const PassiveSurface& p : det.passives()) {
    double r1 = p.shape == SurfaceShape::eCone ? p.coneR1 : p.rMin;
    double r2 = p.shape == SurfaceShape::eCone ? p.coneR2 : p.rMax;
    std::printf("%-44s %-8s %9.2f %9.2f %9.2f %9.2f %7.3f\n", p.name.c_str(),
                shapeName(p.shape), p.zMin / mm, p.zMax / mm, r1 / mm, r2 / mm,
                100.0 * p.thicknessX0);
  }
}

}  // namespace

void addDetectorCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("detector", "Detector descriptions");
  cmd->require_subcommand(1);
  auto name = std::make_shared<std::string>();
  CLI::App* show =
      cmd->add_subcommand("show", "Print the layout of a detector as a table");
  show->add_option("detector", *name,
                   "Shipped detector name (clicdet, cld, ...) or TOML path")
      ->required();
  show->callback([name]() { printDetector(loadDetector(*name)); });

  auto csv = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  // Not named "import": clang-format takes it for the C++20 keyword.
  CLI::App* importCommand = cmd->add_subcommand(
      "import-trackml",
      "Build a detector file from the TrackML detectors.csv(.gz)");
  importCommand->add_option("csv", *csv, "detectors.csv or detectors.csv.gz")
      ->required();
  importCommand->add_option("-o,--output", *out, "TOML file (default: stdout)");
  importCommand->callback([csv, out]() {
    if (!out->empty()) {
      prepareOutputFile(*out, "-o");
    }
    TrackmlDetectorOptions options;
    options.source = *csv;
    std::string toml = buildTrackmlDetectorToml(
        parseTrackmlModules(readTextFile(*csv), *csv), options);
    // Validate before writing: the result must load.
    parseDetector(toml, "generated TrackML detector");
    if (out->empty()) {
      std::fwrite(toml.data(), 1, toml.size(), stdout);
    } else {
      writeTextFile(*out, toml, false);
    }
  });
}

}  // namespace conftrack::cli

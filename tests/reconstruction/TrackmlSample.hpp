#pragma once

/// @file TrackmlSample.hpp
/// Test helpers shared by the TrackML reconstruction tests: the particles
/// of Kaggle event 1001, the module-level simulation of the TrackML
/// detector as `conftrack simulate-trackml` runs it, and a count of the
/// hits that found tracks hold of their own particles.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Event.hpp"
#include "conftrack/evaluation/TruthMatching.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"
#include "conftrack/simulation/generators/HepMCText.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace conftrack::test {

namespace fs = std::filesystem;

inline const fs::path kTrackmlData =
    fs::path(CONFTRACK_TEST_DATA_DIR) / "trackml";

/// The Kaggle particles file (particle_id,vx,vy,vz,px,py,pz,q,nhits; mm,
/// GeV), as the io reader fills it: no PDG code, status 1, sorted by id.
inline std::vector<Particle> readKaggleParticles(const fs::path& file) {
  std::istringstream in(hepmc::loadFile(file));
  std::string line;
  std::getline(in, line);
  if (line.rfind("particle_id,vx,vy,vz,px,py,pz,q,nhits", 0) != 0) {
    throw InputError(file.string(), "unexpected header '" + line + "'");
  }
  std::vector<Particle> particles;
  while (std::getline(in, line)) {
    if (line.empty()) {
      continue;
    }
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    Particle p;
    double v[7] = {};
    row >> p.id >> v[0] >> v[1] >> v[2] >> v[3] >> v[4] >> v[5] >> v[6] >>
        p.nHits;
    if (!row) {
      throw InputError(file.string(), "malformed row '" + line + "'");
    }
    p.vertex = Vector3(v[0], v[1], v[2]);
    p.momentum = Vector3(v[3], v[4], v[5]);
    p.charge = v[6];
    particles.push_back(p);
  }
  std::sort(particles.begin(), particles.end(),
            [](const Particle& a, const Particle& b) { return a.id < b.id; });
  return particles;
}

/// The particles of Kaggle event 1001.
inline std::vector<Particle> event1001Particles() {
  return readKaggleParticles(kTrackmlData / "train_100_events_no_truth" /
                             "event000001001-particles.csv.gz");
}

/// The prompt particles of event 1001 at 0.2-0.6 GeV and |eta| 1.8-2.6:
/// they cross the first pixel-barrel layers steeply, then the pixel disks,
/// and scatter there by more than the hit errors.
inline std::vector<Particle> forwardLowPtParticles() {
  std::vector<Particle> forward;
  for (const Particle& p : event1001Particles()) {
    const double pt = p.momentum.head<2>().norm();
    const double eta = std::abs(std::asinh(p.momentum.z() / pt));
    if (p.vertex.head<2>().norm() < 1.0 && pt >= 0.2 && pt <= 0.6 &&
        eta >= 1.8 && eta <= 2.6) {
      forward.push_back(p);
    }
  }
  return forward;
}

/// Noise in a TrackML-like sample: none, or the real files' rate per
/// sensor (kTrackmlNoisePerSensor), as `conftrack simulate-trackml` adds.
enum class SampleNoise { eNone, eReal };

/// `particles` through the module-level simulation of the TrackML
/// detector as `conftrack simulate-trackml` runs it (the real sensors of
/// detectors.csv, pT > 0.15 GeV, seed 1) with `noise` and, where given,
/// the interactions moved to `region`.
inline Event simulateTrackml(
    const std::vector<Particle>& particles, SampleNoise noise,
    std::optional<LuminousRegion::Config> region = {}) {
  static const fs::path modulesFile = kTrackmlData / "detectors.csv.gz";
  static const std::vector<TrackmlModule> modules =
      parseTrackmlModules(hepmc::loadFile(modulesFile), modulesFile.string());
  static const Detector simDetector = buildTrackmlDetector(modules);
  static const auto sensors = std::make_shared<const ModuleLayout>(
      buildTrackmlModuleLayout(modules, simDetector));
  TrackmlEventSimulation::Config simConfig;
  simConfig.noisePerSensor =
      noise == SampleNoise::eReal ? kTrackmlNoisePerSensor : 0.0;
  simConfig.minPt = 0.15;
  simConfig.seed = 1;
  simConfig.luminousRegion = region;
  return TrackmlEventSimulation(simDetector, sensors, simConfig)
      .simulate(1001, particles);
}

/// The hit lists of `tracks` (Track or FoundTrack), as the evaluation's
/// matching and the TrackML score take them.
template <typename TrackType>
std::vector<std::vector<HitIndex>> hitLists(
    const std::vector<TrackType>& tracks) {
  std::vector<std::vector<HitIndex>> lists;
  lists.reserve(tracks.size());
  for (const TrackType& t : tracks) {
    lists.push_back(t.hits);
  }
  return lists;
}

/// `event` reconstructed with the shipped TrackML chain after `change`
/// (e.g. one setting switched off, for a with/without comparison).
inline Reconstruction::Result reconstructWithTrackmlChain(
    const Event& event,
    const std::function<void(Reconstruction::Config&)>& change) {
  const Detector detector = loadDetector("trackml");
  Reconstruction::Config config =
      readReconstructionConfig(resolveChainPath("trackml"), detector);
  change(config);
  return Reconstruction(detector, config).run(event.hits);
}

/// Hits of their majority particle on the found tracks, summed (tracks
/// whose majority is noise count none), by the evaluation's matching.
inline std::size_t majorityHits(const Event& event,
                                const FindingResult& found) {
  std::size_t own = 0;
  for (const TrackMatch& m :
       matchTracks(event, hitLists(found.tracks)).tracks) {
    own += m.particle != kInvalidIndex ? m.nMajority : 0;
  }
  return own;
}

}  // namespace conftrack::test

/// @file TrackmlChainTests.cpp
/// The shipped TrackML chain (chains/trackml.toml) on one TrackML-like
/// event with truth: the particles of Kaggle event 1001 through the fast
/// simulation of the TrackML detector with 17 % noise and pT > 0.15 GeV, as
/// `conftrack simulate-trackml` makes it, then finding, fit and selection
/// as `conftrack reconstruct --detector trackml`, scored with the TrackML
/// score (truth used only to score).

#include "conftrack/core/Error.hpp"
#include "conftrack/evaluation/TrackmlScore.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"
#include "conftrack/simulation/generators/HepMCText.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace conftrack {
namespace {

namespace fs = std::filesystem;

const fs::path kTrackmlData = fs::path(CONFTRACK_SHARED_DIR) / "data/trackml";

/// The Kaggle particles file (particle_id,vx,vy,vz,px,py,pz,q,nhits; mm,
/// GeV), as the io reader fills it: no PDG code, status 1, sorted by id.
std::vector<Particle> readKaggleParticles(const fs::path& file) {
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

TEST(TrackmlChain, ScoreOnSimulatedEvent1001) {
  // The simulation as `conftrack simulate-trackml` (defaults: noise 17 %,
  // pT > 0.15 GeV, seed 1, real module ids from detectors.csv).
  const fs::path modulesFile = kTrackmlData / "detectors.csv.gz";
  const std::vector<TrackmlModule> modules =
      parseTrackmlModules(hepmc::loadFile(modulesFile), modulesFile.string());
  const Detector simDetector = buildTrackmlDetector(modules);
  const TrackmlModuleMap moduleMap(modules);
  TrackmlEventSimulation::Config simConfig;
  simConfig.noiseFraction = 0.17;
  simConfig.minPt = 0.15;
  simConfig.seed = 1;
  const TrackmlEventSimulation sim(simDetector, &moduleMap, simConfig);
  const Event event = sim.simulate(
      1001, readKaggleParticles(kTrackmlData / "train_100_events_no_truth" /
                                "event000001001-particles.csv.gz"));
  ASSERT_GT(event.hits.size(), 90000u);

  // Reconstruction as `conftrack reconstruct --detector trackml` (the
  // shipped detector file and its chain).
  const Detector detector = loadDetector("trackml");
  Reconstruction::Config config;
  config.chain = readChain(resolveChainPath("trackml"), detector);
  const Reconstruction reco(detector, config);
  const auto t0 = std::chrono::steady_clock::now();
  const Reconstruction::Result result = reco.run(event.hits);
  const double ms = std::chrono::duration<double, std::milli>(
                        std::chrono::steady_clock::now() - t0)
                        .count();

  std::vector<std::vector<HitIndex>> tracks;
  tracks.reserve(result.tracks.size());
  for (const Track& t : result.tracks) {
    tracks.push_back(t.hits);
  }
  const TrackmlScore score = scoreTrackml(event, tracks);
  std::printf(
      "[ trackml 1001 ] %zu hits, %zu tracks: TrackML score %.4f, efficiency "
      "%.4f, fake rate %.4f; finding %.0f ms, fitting %.0f ms, total %.0f ms\n",
      event.hits.size(), result.tracks.size(), score.score, score.efficiency,
      score.fakeRate, result.findingMs, result.fittingMs, ms);
  // Measured 0.7593 (README "TrackML"); the goal of 0.90 is not
  // reached (see the chain file). This guards the current level with a
  // margin of 0.02.
  EXPECT_GE(score.score, 0.74);
  EXPECT_LE(score.fakeRate, 0.30);
}

}  // namespace
}  // namespace conftrack

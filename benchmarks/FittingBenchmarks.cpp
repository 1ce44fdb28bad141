// Track-fit throughput: all candidates of one CLICdet 3 TeV ttbar event
// with 30 bunch crossings of gamma gamma -> hadrons (readout window on; the
// conformal finder's output, found once), fitted on one core; the
// selection of the fitted tracks; one 10 GeV muon.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/reconstruction/selection/TrackSelector.hpp"
#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/Simulator.hpp"
#include "conftrack/simulation/generators/ParticleGun.hpp"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace conftrack;

/// The simulated event and the finder's candidates, made once.
struct TtbarSample {
  Detector detector = loadDetector("clicdet");
  Event event;
  std::vector<FoundTrack> found;
  std::vector<FitInput> candidates;

  TtbarSample() {
    EventSimulation::Config config;
    config.sample = "ttbar3tev";
    config.overlayBx = 30;
    config.seed = 2019;
    event = EventSimulation(detector, config).simulate(1);
    const ConformalTrackFinder finder(
        detector, {readChain(resolveChainPath("clicdet"), detector)});
    found = finder.run(event.hits).tracks;
    for (const FoundTrack& f : found) {
      candidates.push_back(fitInput(f));
    }
  }
};

const TtbarSample& ttbar() {
  static const TtbarSample sample;
  return sample;
}

void fitTtbarEvent(benchmark::State& state) {
  const TtbarSample& sample = ttbar();
  const KalmanFitter fitter(sample.detector);
  std::size_t failures = 0;
  for (auto _ : state) {
    FittingResult result = fitter.run(sample.event.hits, sample.candidates);
    failures = result.failures;
    benchmark::DoNotOptimize(result.tracks.data());
  }
  state.counters["candidates"] = static_cast<double>(sample.candidates.size());
  state.counters["hits"] = static_cast<double>(sample.event.hits.size());
  state.counters["failures"] = static_cast<double>(failures);
  state.SetItemsProcessed(state.iterations() *
                          static_cast<std::int64_t>(sample.candidates.size()));
}
BENCHMARK(fitTtbarEvent)->Unit(benchmark::kMillisecond);

void selectTtbarEvent(benchmark::State& state) {
  const TtbarSample& sample = ttbar();
  const FittingResult fitted =
      KalmanFitter(sample.detector).run(sample.event.hits, sample.candidates);
  const TrackSelector selector;
  std::size_t kept = 0;
  for (auto _ : state) {
    SelectionResult result = selector.run(sample.event.hits, fitted.tracks);
    kept = result.tracks.size();
    benchmark::DoNotOptimize(result.tracks.data());
  }
  state.counters["kept"] = static_cast<double>(kept);
}
BENCHMARK(selectTtbarEvent)->Unit(benchmark::kMillisecond);

/// One 10 GeV muon at theta = 50 deg from its truth hits.
void fitSingleMuon(benchmark::State& state) {
  const Detector detector = loadDetector("clicdet");
  ParticleGun::Config gun;
  gun.momentumMin = gun.momentumMax = 10.0 * units::GeV;
  gun.thetaMin = gun.thetaMax = 50.0 * units::degree;
  RandomEngine rng = makeEngine(2, 0, RandomStream::eSignalGenerator);
  const std::vector<Particle> particles = ParticleGun(gun).generate(rng);
  Event event;
  RandomEngine simRng = makeEngine(2, 0, RandomStream::eSimulation);
  Simulator(detector).simulate(particles, simRng, event);
  std::vector<HitIndex> candidate;
  for (std::size_t h = 0; h < event.hits.size(); ++h) {
    candidate.push_back(static_cast<HitIndex>(h));
  }
  KalmanFitter::Config config;
  config.pdg = 13;
  const KalmanFitter fitter(detector, config);
  for (auto _ : state) {
    Track track = fitter.fit(event.hits, {candidate});
    benchmark::DoNotOptimize(track.atIp.parameters.data());
  }
  state.counters["hits"] = static_cast<double>(candidate.size());
}
BENCHMARK(fitSingleMuon)->Unit(benchmark::kMicrosecond);

}  // namespace

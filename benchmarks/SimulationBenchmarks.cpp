// Fast-simulation throughput: an event's worth of soft charged pions
// (about the charged multiplicity of a 3 TeV ttbar event with 30 bunch
// crossings of gamma gamma -> hadrons) in CLICdet, a CLICdet tt-bar event
// with 30 BX, and a real TrackML event's particles on the TrackML sensors.

#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/LayoutFile.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/Simulator.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

namespace {

using namespace conftrack;

/// `n` pions from the beam spot: exponential pT with mean 0.4 GeV (many
/// loopers below 0.1 GeV), flat in |eta| < 3 and phi, both charges.
std::vector<Particle> softPions(std::size_t n) {
  RandomEngine rng(12345);
  std::exponential_distribution<double> pt(1.0 / (0.4 * units::GeV));
  std::uniform_real_distribution<double> eta(-3.0, 3.0);
  std::uniform_real_distribution<double> phi(-std::numbers::pi,
                                             std::numbers::pi);
  std::normal_distribution<double> spot(0.0, 1.0);
  std::vector<Particle> particles;
  particles.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    Particle p;
    p.id = i + 1;
    p.charge = i % 2 == 0 ? 1.0 : -1.0;
    p.pdg = 211 * static_cast<int>(p.charge);
    const double t = pt(rng);
    const double f = phi(rng);
    p.momentum = {t * std::cos(f), t * std::sin(f), t * std::sinh(eta(rng))};
    p.vertex = {0.01 * spot(rng), 0.01 * spot(rng), 40.0 * spot(rng)};
    particles.push_back(p);
  }
  return particles;
}

/// Arguments: number of particles, material effects on (1) or off (0).
void simulateSoftPions(benchmark::State& state) {
  const Detector detector = loadDetector("clicdet");
  Simulator::Config config;
  config.multipleScattering = state.range(1) != 0;
  config.energyLoss = state.range(1) != 0;
  const Simulator simulator(detector, config);
  const std::vector<Particle> particles =
      softPions(static_cast<std::size_t>(state.range(0)));
  std::uint64_t eventNumber = 0;
  std::size_t hits = 0;
  for (auto _ : state) {
    Event event;
    RandomEngine rng = makeEngine(1, eventNumber++, RandomStream::eSimulation);
    simulator.simulate(particles, rng, event);
    hits = event.hits.size();
    benchmark::DoNotOptimize(event.hits.data());
  }
  state.counters["hits"] = static_cast<double>(hits);
  state.SetItemsProcessed(state.iterations() *
                          static_cast<std::int64_t>(particles.size()));
}

BENCHMARK(simulateSoftPions)
    ->Args({3000, 1})
    ->Args({3000, 0})
    ->Unit(benchmark::kMillisecond);

}  // namespace

namespace {

/// One tt-bar event with 30 BX of gamma gamma -> hadrons, generation and
/// simulation (issue target: under 30 ms on one core), on CLICdet (first
/// argument 0) or CLD (1), with the ideal layers
/// (second argument 0) or the sensors of the detector's layout file (1,
/// --module-level; docs/validation.md, "CLICdet and CLD sensors"). Always
/// events 1-20 (the time varies by a factor of 3 between events), so that
/// the four variants time the same events.
void simulateTtbar30Bx(benchmark::State& state) {
  static const conftrack::Detector clicdet = conftrack::loadDetector("clicdet");
  static const conftrack::Detector cld = conftrack::loadDetector("cld");
  const conftrack::Detector& det = state.range(0) == 0 ? clicdet : cld;
  conftrack::EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = 30;
  if (state.range(1) == 1) {
    cfg.modules = std::make_shared<const conftrack::ModuleLayout>(
        conftrack::readLayoutModules(conftrack::shippedLayoutFile(det), det));
  }
  conftrack::EventSimulation sim(det, cfg);
  std::uint64_t event = 1;
  std::size_t hits = 0;
  for (auto _ : state) {
    conftrack::Event ev = sim.simulate(event++);
    hits = ev.hits.size();
    benchmark::DoNotOptimize(ev);
  }
  state.counters["hits"] = static_cast<double>(hits);
}
BENCHMARK(simulateTtbar30Bx)
    ->Iterations(20)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace

namespace {

/// The particles of real TrackML event 1001 through the TrackML-like
/// simulation (17 % noise, pT > 0.15 GeV). Argument 1: the module-level
/// simulation of simulate-trackml (the real sensors, half-turn loopers,
/// interactions); 0: the ideal layers with loopers followed for 10 turns
/// (the simulation before module level). Issue target: under 2 s.
void simulateTrackmlEvent(benchmark::State& state) {
  using namespace conftrack;
  const std::filesystem::path data(CONFTRACK_TEST_DATA_DIR);
  static const std::vector<TrackmlModule> modules = parseTrackmlModules(
      readTextFile(data / "trackml/detectors.csv.gz"), "detectors.csv.gz");
  static const Detector detector = buildTrackmlDetector(modules);
  static const auto sensors = std::make_shared<const ModuleLayout>(
      buildTrackmlModuleLayout(modules, detector));
  static const Event real =
      readEvent(data / "trackml/train_100_events_no_truth", 1001, nullptr,
                ReadOptions{false, true});
  const bool moduleLevel = state.range(0) != 0;
  TrackmlEventSimulation::Config config;
  config.minPt = 0.15;
  if (moduleLevel) {
    // The real files' noise, as `conftrack simulate-trackml`.
    config.noisePerSensor = kTrackmlNoisePerSensor;
  } else {
    // Ideal layers have no sensors to carry a rate (--ideal-layers).
    config.noiseFraction = 0.17;
    config.simulator = Simulator::Config();
  }
  const TrackmlEventSimulation simulation(
      detector, moduleLevel ? sensors : nullptr, config);
  std::size_t hits = 0;
  for (auto _ : state) {
    const Event event = simulation.simulate(1001, real.particles);
    hits = event.hits.size();
    benchmark::DoNotOptimize(event.hits.data());
  }
  state.counters["hits"] = static_cast<double>(hits);
  state.counters["particles"] = static_cast<double>(real.particles.size());
}
BENCHMARK(simulateTrackmlEvent)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

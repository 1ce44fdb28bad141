// Conformal finding on simulated CLICdet tt-bar events with 0, 10, 30 and
// 60 bunch crossings of gamma gamma -> hadrons (one event per setting,
// simulated once; seed fixed so figures are comparable between runs). The
// readout time window is off here so that every overlaid crossing adds hits
// (with it, crossings after +20 fall outside the 10 ns window and 60 BX
// looks like 30): the point is the cost versus the number of hits.

#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <benchmark/benchmark.h>

#include <map>

namespace {

using namespace conftrack;

const Detector& clicdet() {
  static const Detector det = loadDetector("clicdet");
  return det;
}

const Event& ttbarEvent(std::size_t bx) {
  static std::map<std::size_t, Event> cache;
  auto it = cache.find(bx);
  if (it == cache.end()) {
    EventSimulation::Config cfg;
    cfg.sample = "ttbar3tev";
    cfg.overlayBx = bx;
    cfg.seed = 2019;
    cfg.applyTimeWindow = false;
    EventSimulation sim(clicdet(), cfg);
    it = cache.emplace(bx, sim.simulate(1)).first;
  }
  return it->second;
}

void findTtbar(benchmark::State& state) {
  const auto bx = static_cast<std::size_t>(state.range(0));
  const Event& event = ttbarEvent(bx);
  ConformalTrackFinder finder(
      clicdet(), {readChain(resolveChainPath("clicdet"), clicdet())});
  std::size_t tracks = 0;
  for (auto _ : state) {
    FindingResult r = finder.run(event.hits);
    tracks = r.tracks.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["hits"] = static_cast<double>(event.hits.size());
  state.counters["tracks"] = static_cast<double>(tracks);
}
BENCHMARK(findTtbar)
    ->Arg(0)
    ->Arg(10)
    ->Arg(30)
    ->Arg(60)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

}  // namespace

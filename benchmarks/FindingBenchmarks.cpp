// Conformal finding on simulated CLICdet tt-bar events with gamma gamma ->
// hadrons overlay (seed fixed so figures are comparable between runs).
// - findTtbar: 0, 10, 30 and 60 bunch crossings, one event per setting,
//   with the readout time window off so that every overlaid crossing adds
//   hits (with it, crossings after +20 fall outside the 10 ns window and
//   60 BX looks like 30): the cost versus the number of hits.
// - findTtbarReadout: the target configuration, tt-bar + 30 BX with
//   the 10 ns window, ten events taken in turn (one per iteration).

#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <tuple>
#include <vector>

namespace {

using namespace conftrack;

const Detector& clicdet() {
  static const Detector det = loadDetector("clicdet");
  return det;
}

/// The first `n` simulated tt-bar events with `bx` overlaid crossings, with
/// or without the readout window; simulated once.
const std::vector<Event>& ttbarEvents(std::size_t bx, bool readoutWindow,
                                      std::size_t n) {
  static std::map<std::tuple<std::size_t, bool, std::size_t>,
                  std::vector<Event>>
      cache;
  const auto key = std::make_tuple(bx, readoutWindow, n);
  auto it = cache.find(key);
  if (it == cache.end()) {
    EventSimulation::Config cfg;
    cfg.sample = "ttbar3tev";
    cfg.overlayBx = bx;
    cfg.seed = 2019;
    cfg.applyTimeWindow = readoutWindow;
    EventSimulation sim(clicdet(), cfg);
    std::vector<Event> events;
    for (std::uint64_t e = 1; e <= n; ++e) {
      events.push_back(sim.simulate(e));
    }
    it = cache.emplace(key, std::move(events)).first;
  }
  return it->second;
}

void findTtbar(benchmark::State& state) {
  const auto bx = static_cast<std::size_t>(state.range(0));
  const Event& event = ttbarEvents(bx, false, 1).front();
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

void findTtbarReadout(benchmark::State& state) {
  const auto bx = static_cast<std::size_t>(state.range(0));
  const std::vector<Event>& events = ttbarEvents(bx, true, 10);
  ConformalTrackFinder finder(
      clicdet(), {readChain(resolveChainPath("clicdet"), clicdet())});
  std::size_t next = 0;
  double hits = 0.0;
  for (auto _ : state) {
    const Event& event = events[next];
    next = (next + 1) % events.size();
    FindingResult r = finder.run(event.hits);
    hits += static_cast<double>(event.hits.size());
    benchmark::DoNotOptimize(r);
  }
  state.counters["hits"] =
      benchmark::Counter(hits / static_cast<double>(std::max<std::int64_t>(
                                    1, state.iterations())));
}
BENCHMARK(findTtbarReadout)
    ->Arg(0)
    ->Arg(10)
    ->Arg(30)
    ->Arg(60)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

}  // namespace

namespace {

/// The whole TrackML chain on real Kaggle event 1001 (93,680 hits), as
/// `reconstruct --detector trackml --no-fit` runs it: the issue 15 target
/// (about 90 % of its finding time is the pixel builds' automaton and the
/// HitPool searches under it).
void findTrackmlReal(benchmark::State& state) {
  static const Detector det = loadDetector("trackml");
  const std::vector<Hit> hits =
      readHits(std::filesystem::path(CONFTRACK_TEST_DATA_DIR) /
                   "trackml/train_100_events_no_truth/"
                   "event000001001-hits.csv.gz",
               &det.trackmlLayerMap());
  ConformalTrackFinder finder(det,
                              {readChain(resolveChainPath("trackml"), det)});
  std::size_t tracks = 0;
  for (auto _ : state) {
    FindingResult r = finder.run(hits);
    tracks = r.tracks.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["hits"] = static_cast<double>(hits.size());
  state.counters["tracks"] = static_cast<double>(tracks);
}
BENCHMARK(findTrackmlReal)->Unit(benchmark::kMillisecond);

}  // namespace

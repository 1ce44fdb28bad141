/// @file LoadBenchmarks.cpp
/// The whole reconstruction (finding, fit, selection; chains/trackml.toml)
/// under load: real TrackML events overlaid into one
/// (docs/robustness.md). Arguments: the first `events` of the five real
/// events 1001, 1003, 1005, 1009, 1010, each added `copies` times, copy k
/// rotated by k rad in azimuth (5 events x 2 copies: the 1.04M-hit event of
/// `conftrack overlay --copies 2`). One iteration each: that case takes
/// minutes on one core. Counters: hits, tracks, the guards'
/// bites (summed over steps) and the peak RSS of the process so far.

#include "conftrack/evaluation/ResourceUsage.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/simulation/EventOverlay.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <span>
#include <vector>

namespace {

using namespace conftrack;

const Detector& trackml() {
  static const Detector det = loadDetector("trackml");
  return det;
}

/// The five real events, read once.
const std::vector<Event>& realEvents() {
  static const std::vector<Event> events = [] {
    const std::filesystem::path dir =
        std::filesystem::path(CONFTRACK_TEST_DATA_DIR) /
        "trackml/train_100_events_no_truth";
    std::vector<Event> out;
    for (std::uint64_t n : {1001, 1003, 1005, 1009, 1010}) {
      out.push_back(readEvent(dir, n, &trackml().trackmlLayerMap(),
                              ReadOptions{false, false}));
    }
    return out;
  }();
  return events;
}

void reconstructTrackmlOverlay(benchmark::State& state) {
  const std::vector<Event>& real = realEvents();
  const auto n = static_cast<std::size_t>(state.range(0));
  const Event event = overlayEvents(
      std::span(real.data(), std::min(n, real.size())),
      EventOverlayConfig{static_cast<std::uint32_t>(state.range(1)), 1.0});
  Reconstruction::Config cfg;
  cfg.chain = readChain(resolveChainPath("trackml"), trackml());
  const Reconstruction reco(trackml(), cfg);
  std::size_t tracks = 0;
  double bites = 0.0;
  for (auto _ : state) {
    Reconstruction::Result r = reco.run(event.hits);
    tracks = r.tracks.size();
    bites = 0.0;
    for (const StepStats& s : r.steps) {
      for (const GuardCount& g : s.guards) {
        bites += static_cast<double>(g.bites);
      }
    }
    benchmark::DoNotOptimize(r);
  }
  state.counters["hits"] = static_cast<double>(event.hits.size());
  state.counters["tracks"] = static_cast<double>(tracks);
  state.counters["guard_bites"] = bites;
  state.counters["peak_rss_MiB"] = peakRssMb();
}
BENCHMARK(reconstructTrackmlOverlay)
    ->ArgNames({"events", "copies"})
    ->Args({1, 1})
    ->Args({2, 1})
    ->Args({5, 1})
    ->Args({5, 2})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace

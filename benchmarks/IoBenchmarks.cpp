/// @file IoBenchmarks.cpp
/// Throughput of the TrackML CSV reader and writer on a real Kaggle event
/// (event 1001: 93,680 hits).

#include "conftrack/core/TextFile.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/io/TrackmlWriter.hpp"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

const fs::path kHits = fs::path(CONFTRACK_TEST_DATA_DIR) /
                       "trackml/train_100_events_no_truth/"
                       "event000001001-hits.csv.gz";

/// Decompression plus parsing: what readEvent costs per event.
void BM_ReadTrackmlHitsGz(benchmark::State& state) {
  std::size_t n = 0;
  for (auto _ : state) {
    auto hits = conftrack::readHits(kHits, nullptr);
    n = hits.size();
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["hits"] = static_cast<double>(n);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
}
BENCHMARK(BM_ReadTrackmlHitsGz)->Unit(benchmark::kMillisecond);

/// As above with the TrackML detector: each hit is also checked against
/// the layer it names, as `reconstruct --detector trackml` reads it.
void BM_ReadTrackmlHitsGzDetector(benchmark::State& state) {
  const conftrack::Detector detector = conftrack::loadDetector("trackml");
  std::size_t n = 0;
  for (auto _ : state) {
    auto hits = conftrack::readHits(kHits, &detector.trackmlLayerMap());
    n = hits.size();
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["hits"] = static_cast<double>(n);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
}
BENCHMARK(BM_ReadTrackmlHitsGzDetector)->Unit(benchmark::kMillisecond);

/// Decompression alone, to separate zlib from parsing.
void BM_GunzipTrackmlHits(benchmark::State& state) {
  for (auto _ : state) {
    std::string text = conftrack::readTextFile(kHits);
    benchmark::DoNotOptimize(text.data());
  }
}
BENCHMARK(BM_GunzipTrackmlHits)->Unit(benchmark::kMillisecond);

/// Writing the same hits, plain (arg 0) or gzip at the default level (arg 1).
void BM_WriteTrackmlHits(benchmark::State& state) {
  const bool gzip = state.range(0) != 0;
  auto hits = conftrack::readHits(kHits, nullptr);
  fs::path file = fs::temp_directory_path() /
                  ("conftrack_bench_" + std::to_string(::getpid()) +
                   "-hits.csv" + (gzip ? ".gz" : ""));
  for (auto _ : state) {
    conftrack::writeHits(file, hits, nullptr);
  }
  fs::remove(file);
  state.SetItemsProcessed(
      static_cast<std::int64_t>(state.iterations() * hits.size()));
}
BENCHMARK(BM_WriteTrackmlHits)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

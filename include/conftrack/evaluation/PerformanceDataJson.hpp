#pragma once

/// @file PerformanceDataJson.hpp
/// The mergeable form of a performance report (performance_data.json,
/// docs/formats.md): the run metadata, the evaluation settings and every
/// raw count behind the report (ratios as passed/total, histograms bin by
/// bin including under- and overflow, the residual list, time sums and
/// per-step counters), never a rate. Shards of one run, each evaluated in
/// its own process (`--shard K/N`), are merged from these files into the
/// numbers one process would have produced (ShardMerge.hpp).
///
/// Doubles are written in their shortest round-trip form, so a value read
/// back is bit-identical to the one written; NaN is written as null.

#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/PerformanceReport.hpp"

#include <nlohmann/json_fwd.hpp>

#include <string_view>

namespace conftrack {

/// Format version written and understood (the key "format_version").
inline constexpr int kPerformanceDataFormatVersion = 1;

/// A report's results as saved: what a merge needs.
struct SavedPerformance {
  RunMetadata metadata;
  PerformanceConfig config;
  PerformanceData data;
  /// Peak resident memory of the process (largest of the shards after a
  /// merge) [MiB].
  double peakRssMb = 0.0;
};

/// The JSON of `summary`'s data and settings with `metadata`.
nlohmann::ordered_json makePerformanceDataJson(
    const RunMetadata& metadata, const PerformanceSummary& summary);

/// The evaluation settings as saved (the "config" key): equal settings give
/// equal JSON.
nlohmann::ordered_json makePerformanceConfigJson(
    const PerformanceConfig& config);

/// Reads makePerformanceDataJson()'s output back. Throws InputError
/// "<source>: key <path>: <problem>" for a missing or mistyped key, a
/// negative or non-integer count, a passed count above its total, bin
/// edges that differ from this version's, or an unknown format version.
SavedPerformance parsePerformanceDataJson(const nlohmann::json& json,
                                          std::string_view source);

}  // namespace conftrack

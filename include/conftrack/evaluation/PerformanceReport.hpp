#pragma once

/// @file PerformanceReport.hpp
/// The numbers of a PerformanceSummary as data: summary.json's content and
/// the human-readable table. The files of a report (summary.json, CSV
/// files, index.html, plots) are written at the edges, by the CLI and the
/// Python module (frontend/ReportFiles.hpp):
///
///   summary.json                      run metadata and headline numbers
///   efficiency_vs_{pt,pt_all,theta,phi,vertex_radius,proximity}.csv
///   fake_rate_vs_{pt,theta}.csv, duplicate_rate_vs_{pt,theta}.csv
///       ratio CSV: low,high,numerator,denominator,value,uncertainty,
///       lower,upper (binomial error; Wilson 68 % interval); pT in GeV,
///       angles in degrees, radius in mm, proximity in rad
///   time_per_event.csv                count CSV: low,high,count [ms]
///   time_steps.csv                    step,ms_per_event,share,counters...,
///                                     <guard>_bites,<guard>_cut per guard
///   resolutions.csv, pulls.csv, pull_<name>.csv   single-particle samples
///   index.html, *.png                 from the plot script

#include "conftrack/evaluation/PerformanceCollector.hpp"

#include <nlohmann/json_fwd.hpp>

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace conftrack {

/// The part of a run that one process evaluates (`--shard K/N`): events
/// [firstEvent, firstEvent + events evaluated) of the run's numbering.
struct RunShard {
  std::size_t index = 0;
  std::size_t count = 1;
  /// Index of the shard's first event within the run (0-based).
  std::uint64_t firstEvent = 0;
};

/// Run metadata supplied by the caller.
struct RunMetadata {
  /// Program version; empty: the build's CONFTRACK_VERSION.
  std::string version;
  /// Detector name as in its file, e.g. "CLICdet" or "CLD" (the plot script
  /// draws the ideal-resolution anchors for these).
  std::string detector;
  /// Sample description, e.g. "ttbar3tev" or "muons".
  std::string sample;
  std::size_t overlayBx = 0;
  /// Events requested (0: take the number evaluated).
  std::size_t events = 0;
  std::uint64_t seed = 0;
  /// Threads of the process (of each shard after a merge; 0 if they
  /// differed).
  std::size_t threads = 0;
  /// Which shard of the run this is (index 0 of 1: the whole run).
  RunShard shard;
  /// Number of shard reports merged into this one (0: one process).
  std::size_t mergedShards = 0;
};

/// The summary as JSON (key order as written below; NaN becomes null).
///
/// Keys: version, detector, sample, overlay_bx, events, seed, threads,
/// shard {index, count, first_event} (a shard of a run only),
/// merged_shards (a merge only), bz_T, events_evaluated,
/// reconstructable_particles, reconstructed_tracks, fitted_tracks, efficiency
/// {all, pt_above_1GeV, pt_0p1_to_1GeV}, fake_rate, duplicate_rate,
/// time_ms_per_event {simulation, finding, fitting, reconstruction, steps
/// {name: ms}}, time_ms_total {simulation, finding, fitting}, timing_note (a
/// merge only), peak_rss_mb; single-particle samples: pulls {d0, z0, phi0,
/// omega, tanlambda, pt, theta: {mean, width, mean_error, width_error,
/// entries}} and resolutions [{quantity, unit, theta_deg, pt_GeV, entries,
/// sigma, sigma_error, mean}]. Extras: definitions {...}, efficiency_signal,
/// efficiency_background, efficiency_plot_cuts {theta_plot, pt_plot, all_cuts},
/// fake_rate_selected, duplicate_rate_selected (nHits >= min_track_hits),
/// acts {matching_ratio, efficiency, fake_rate, duplicate_rate}, counts
/// {name: {passed, total, value, uncertainty}} for every ratio, steps
/// [{name, ms_per_event, counters..., cell_cache_flushes, guards {<guard
/// key>: {bites, cut}}}] (the finder's combinatorics guards, StepStats.hpp).
nlohmann::ordered_json makeSummaryJson(const RunMetadata& metadata,
                                       const PerformanceSummary& summary);

/// The rows of the human-readable summary (label, value): the table of
/// printSummaryTable and of the report's index.html.
std::vector<std::pair<std::string, std::string>> summaryTableRows(
    const RunMetadata& metadata, const PerformanceSummary& summary);

/// Prints the headline numbers as an aligned table.
void printSummaryTable(std::ostream& out, const RunMetadata& metadata,
                       const PerformanceSummary& summary);

}  // namespace conftrack

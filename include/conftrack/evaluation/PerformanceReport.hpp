#pragma once

/// @file PerformanceReport.hpp
/// Output of a PerformanceSummary: summary.json, one CSV per distribution,
/// a human-readable table, an index.html, and the plots made by
/// scripts/conftrack_plots.py.
///
/// Output folder layout (all written by writePerformanceReport()):
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
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace conftrack {

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
  std::size_t threads = 0;
};

/// The summary as JSON (key order as written below; NaN becomes null).
///
/// Keys: version, detector, sample, overlay_bx, events, seed, threads,
/// bz_T, events_evaluated, reconstructable_particles, reconstructed_tracks,
/// fitted_tracks, efficiency {all, pt_above_1GeV, pt_0p1_to_1GeV},
/// fake_rate, duplicate_rate, time_ms_per_event {simulation, finding,
/// fitting, reconstruction, steps {name: ms}}, peak_rss_mb; single-particle
/// samples: pulls {d0, z0, phi0, omega, tanlambda, pt, theta: {mean, width,
/// mean_error, width_error, entries}} and resolutions [{quantity, unit,
/// theta_deg, pt_GeV, entries, sigma, sigma_error, mean}]. Extras:
/// definitions {...}, efficiency_signal, efficiency_background,
/// efficiency_plot_cuts {theta_plot, pt_plot, all_cuts},
/// fake_rate_selected, duplicate_rate_selected (nHits >= min_track_hits),
/// acts {matching_ratio, efficiency, fake_rate, duplicate_rate}, counts
/// {name: {passed, total, value, uncertainty}} for every ratio, steps
/// [{name, ms_per_event, counters..., cell_cache_flushes, guards {<guard
/// key>: {bites, cut}}}] (the finder's combinatorics guards, StepStats.hpp).
nlohmann::ordered_json makeSummaryJson(const RunMetadata& metadata,
                                       const PerformanceSummary& summary);

/// Writes makeSummaryJson() to `file` (indented). Throws
/// std::runtime_error if the file cannot be written.
void writeSummaryJson(const std::filesystem::path& file,
                      const RunMetadata& metadata,
                      const PerformanceSummary& summary);

/// Writes one ratio histogram as CSV; x values are divided by `unit`
/// (e.g. units::degree to write degrees).
void writeRatioCsv(const std::filesystem::path& file,
                   const RatioHistogram& histogram, double unit = 1.0);

/// Writes one count histogram as CSV (low,high,count); x divided by `unit`.
void writeCountCsv(const std::filesystem::path& file,
                   const CountHistogram& histogram, double unit = 1.0);

/// Writes every distribution of `summary` into `directory` (see the file
/// comment); returns the file names written, in writing order.
std::vector<std::string> writeHistogramCsvs(
    const std::filesystem::path& directory, const PerformanceSummary& summary);

/// Prints the headline numbers as an aligned table.
void printSummaryTable(std::ostream& out, const RunMetadata& metadata,
                       const PerformanceSummary& summary);

/// Writes a plain index.html (the table and links to the CSV files): the
/// report when the plot script cannot run; the script replaces it.
void writeIndexHtml(const std::filesystem::path& directory,
                    const RunMetadata& metadata,
                    const PerformanceSummary& summary,
                    const std::vector<std::string>& files);

/// scripts/conftrack_plots.py under the data folder: the CONFTRACK_DATA_DIR
/// environment variable if set, else the build's CONFTRACK_DATA_DIR.
std::filesystem::path plotScriptPath();

/// The first of $CONFTRACK_PYTHON, python3 (PATH) and /usr/bin/python3
/// that can import matplotlib and numpy; empty if none can.
std::string findPlotInterpreter();

/// What runPlotScript() did.
struct PlotScriptResult {
  /// The script ran and exited with 0 (plots and index.html written).
  bool plotted = false;
  /// One line for the user.
  std::string message;
};

/// Runs `python3 plotScriptPath() directory`. The interpreter is the first
/// of $CONFTRACK_PYTHON, python3 on the PATH and /usr/bin/python3 that can
/// import matplotlib and numpy (a python3 on the PATH from pyenv or a venv
/// often lacks Debian's python3-matplotlib). Without matplotlib the script
/// still runs (it writes an index.html listing the CSV files); without any
/// python3 nothing runs. Either way it prints how to get them (apt-get
/// install python3-matplotlib python3-numpy) to `log` and returns; it never
/// throws for a missing interpreter, module or script.
PlotScriptResult runPlotScript(const std::filesystem::path& directory,
                               std::ostream& log);

/// Writes the whole report into `directory` (created if needed):
/// summary.json, the CSV files, a plain index.html, then, if `plots`, runs
/// the plot script (which adds the PNGs and a full index.html). Returns the
/// plot script's result (plotted = false when `plots` is false).
PlotScriptResult writePerformanceReport(const std::filesystem::path& directory,
                                        const RunMetadata& metadata,
                                        const PerformanceSummary& summary,
                                        bool plots, std::ostream& log);

}  // namespace conftrack

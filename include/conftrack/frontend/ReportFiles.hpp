#pragma once

/// @file ReportFiles.hpp
/// The files of a performance report (evaluation/PerformanceReport.hpp for
/// the folder layout): summary.json, one CSV per distribution, index.html,
/// and the plots of scripts/conftrack_plots.py.

#include "conftrack/evaluation/PerformanceDataJson.hpp"
#include "conftrack/evaluation/PerformanceReport.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace conftrack {

/// Writes makeSummaryJson() to `file` (indented). Throws
/// std::runtime_error if the file cannot be written.
void writeSummaryJson(const std::filesystem::path& file,
                      const RunMetadata& metadata,
                      const PerformanceSummary& summary);

/// The file of a report that holds its mergeable results.
inline constexpr const char* kPerformanceDataFile = "performance_data.json";

/// Writes makePerformanceDataJson() to `file` through a temporary file
/// that is renamed at the end: a report folder that has it is complete.
/// Throws InputError if the file cannot be written.
void writePerformanceData(const std::filesystem::path& file,
                          const RunMetadata& metadata,
                          const PerformanceSummary& summary);

/// Reads a performance_data.json (parsePerformanceDataJson). Throws
/// MissingFileError if it does not exist, InputError "file: problem" if it
/// cannot be read or parsed.
SavedPerformance readPerformanceData(const std::filesystem::path& file);

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
/// the plot script (which adds the PNGs and a full index.html), and last
/// performance_data.json (the mark of a complete report). Returns the
/// plot script's result (plotted = false when `plots` is false).
PlotScriptResult writePerformanceReport(const std::filesystem::path& directory,
                                        const RunMetadata& metadata,
                                        const PerformanceSummary& summary,
                                        bool plots, std::ostream& log);

}  // namespace conftrack

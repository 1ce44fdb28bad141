#include "conftrack/frontend/ReportFiles.hpp"

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/JsonEntry.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <stdexcept>
#include <sys/wait.h>

namespace conftrack {

namespace {

namespace fs = std::filesystem;

const char* const kInstallHint =
    "apt-get install python3-matplotlib python3-numpy";

std::ofstream openForWriting(const fs::path& file) {
  std::ofstream out(file);
  if (!out) {
    throw std::runtime_error(file.string() + ": cannot open for writing");
  }
  out << std::setprecision(10);
  return out;
}

void finish(std::ofstream& out, const fs::path& file) {
  out.flush();
  if (!out) {
    throw std::runtime_error(file.string() + ": write failed");
  }
}

std::string htmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// Single-quotes a word for /bin/sh.
std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

int runShell(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1) {
    return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Interpreters to try, in order.
std::vector<std::string> interpreterCandidates() {
  std::vector<std::string> candidates;
  if (const char* py = std::getenv("CONFTRACK_PYTHON"); py != nullptr && *py) {
    candidates.emplace_back(py);
  }
  candidates.emplace_back("python3");
  candidates.emplace_back("/usr/bin/python3");
  return candidates;
}

}  // namespace

void writeSummaryJson(const fs::path& file, const RunMetadata& metadata,
                      const PerformanceSummary& summary) {
  std::ofstream out = openForWriting(file);
  out << makeSummaryJson(metadata, summary).dump(2) << '\n';
  finish(out, file);
}

void writePerformanceData(const fs::path& file, const RunMetadata& metadata,
                          const PerformanceSummary& summary) {
  writeTextFile(file, makePerformanceDataJson(metadata, summary).dump() + "\n",
                false);
}

SavedPerformance readPerformanceData(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    throw MissingFileError(file.string(), "no such file");
  }
  const std::string source = file.string();
  return parsePerformanceDataJson(parseJsonObject(readTextFile(file), source),
                                  source);
}

void writeRatioCsv(const fs::path& file, const RatioHistogram& h, double unit) {
  std::ofstream out = openForWriting(file);
  out << "low,high,numerator,denominator,value,uncertainty,lower,upper\n";
  for (std::size_t i = 0; i < h.size(); ++i) {
    const Ratio r = h.bin(i);
    const auto [lower, upper] = r.wilsonInterval();
    out << h.lowerEdge(i) / unit << ',' << h.upperEdge(i) / unit << ','
        << r.passed << ',' << r.total << ',' << r.value() << ','
        << r.uncertainty() << ',' << lower << ',' << upper << '\n';
  }
  finish(out, file);
}

void writeCountCsv(const fs::path& file, const CountHistogram& h, double unit) {
  std::ofstream out = openForWriting(file);
  out << "low,high,count\n";
  for (int i = 0; i < h.axis().size(); ++i) {
    out << h.axis().bin(i).lower() / unit << ','
        << h.axis().bin(i).upper() / unit << ',' << h.at(i) << '\n';
  }
  finish(out, file);
}

std::vector<std::string> writeHistogramCsvs(const fs::path& dir,
                                            const PerformanceSummary& s) {
  const PerformanceData& d = s.data;
  std::vector<std::string> files;
  const auto ratio = [&](const std::string& name, const RatioHistogram& h,
                         double unit) {
    writeRatioCsv(dir / name, h, unit);
    files.push_back(name);
  };
  ratio("efficiency_vs_pt.csv", d.efficiencyVsPt, units::GeV);
  ratio("efficiency_vs_pt_all.csv", d.efficiencyVsPtAll, units::GeV);
  ratio("efficiency_vs_theta.csv", d.efficiencyVsTheta, units::degree);
  ratio("efficiency_vs_phi.csv", d.efficiencyVsPhi, units::degree);
  ratio("efficiency_vs_vertex_radius.csv", d.efficiencyVsVertexRadius,
        units::mm);
  ratio("efficiency_vs_proximity.csv", d.efficiencyVsProximity, 1.0);
  ratio("fake_rate_vs_pt.csv", d.fakeRateVsPt, units::GeV);
  ratio("fake_rate_vs_theta.csv", d.fakeRateVsTheta, units::degree);
  ratio("duplicate_rate_vs_pt.csv", d.duplicateRateVsPt, units::GeV);
  ratio("duplicate_rate_vs_theta.csv", d.duplicateRateVsTheta, units::degree);

  writeCountCsv(dir / "time_per_event.csv", d.reconstructionMsPerEvent, 1.0);
  files.push_back("time_per_event.csv");
  {
    const fs::path file = dir / "time_steps.csv";
    std::ofstream out = openForWriting(file);
    out << "step,ms_per_event,share_of_finding,seeds,cells,paths,candidates,"
           "accepted,extended_hits,hits_used,path_overflows,cell_overflows,"
           "recovered,cell_cache_flushes";
    for (std::size_t i = 0; i < kGuardCount; ++i) {
      const std::string key = guardKey(static_cast<Guard>(i));
      out << ',' << key << "_bites," << key << "_cut";
    }
    out << '\n';
    for (const StepStats& st : d.steps) {
      out << st.name << ','
          << (d.events > 0 ? st.milliseconds / double(d.events) : 0.0) << ','
          << (d.findingMs > 0.0 ? st.milliseconds / d.findingMs : 0.0) << ','
          << st.seeds << ',' << st.cells << ',' << st.paths << ','
          << st.candidates << ',' << st.accepted << ',' << st.extendedHits
          << ',' << st.hitsUsed << ',' << st.guard(Guard::ePathsPerSeed).bites
          << ',' << st.guard(Guard::eCellsPerSeed).bites << ',' << st.recovered
          << ',' << st.cellCacheFlushes;
      for (const GuardCount& g : st.guards) {
        out << ',' << g.bites << ',' << g.cut;
      }
      out << '\n';
    }
    finish(out, file);
    files.push_back("time_steps.csv");
  }

  if (!s.pulls.empty()) {
    {
      const fs::path file = dir / "resolutions.csv";
      std::ofstream out = openForWriting(file);
      out << "quantity,unit,theta_deg,pt_low_GeV,pt_high_GeV,pt_mean_GeV,"
             "entries,core_entries,mean,mean_error,sigma,sigma_error,"
             "converged\n";
      for (const ResolutionPoint& p : s.resolutions) {
        const double k = residualScale(p.quantity);
        out << residualName(p.quantity) << ',' << residualUnit(p.quantity)
            << ',' << p.theta / units::degree << ',' << p.ptLow / units::GeV
            << ',' << p.ptHigh / units::GeV << ',' << p.ptMean / units::GeV
            << ',' << p.fit.entries << ',' << p.fit.coreEntries << ','
            << p.fit.mean * k << ',' << p.fit.meanError * k << ','
            << p.fit.sigma * k << ',' << p.fit.sigmaError * k << ','
            << (p.fit.converged ? 1 : 0) << '\n';
      }
      finish(out, file);
      files.push_back("resolutions.csv");
    }
    {
      const fs::path file = dir / "pulls.csv";
      std::ofstream out = openForWriting(file);
      out << "quantity,entries,mean,mean_error,width,width_error,converged\n";
      for (const PullResult& p : s.pulls) {
        out << pullName(p.quantity) << ',' << p.fit.entries << ',' << p.fit.mean
            << ',' << p.fit.meanError << ',' << p.fit.sigma << ','
            << p.fit.sigmaError << ',' << (p.fit.converged ? 1 : 0) << '\n';
      }
      finish(out, file);
      files.push_back("pulls.csv");
    }
    for (const PullResult& p : s.pulls) {
      const std::string name =
          "pull_" + std::string(pullName(p.quantity)) + ".csv";
      writeCountCsv(dir / name, p.histogram, 1.0);
      files.push_back(name);
    }
  }
  return files;
}

void writeIndexHtml(const fs::path& dir, const RunMetadata& metadata,
                    const PerformanceSummary& summary,
                    const std::vector<std::string>& files) {
  const fs::path file = dir / "index.html";
  std::ofstream out = openForWriting(file);
  out << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">"
         "<title>conftrack performance</title>"
         "<style>body{font-family:sans-serif;margin:2em}"
         "td,th{padding:2px 10px;text-align:left}</style></head><body>\n"
      << "<h1>conftrack performance: " << htmlEscape(metadata.sample)
      << "</h1>\n<table>\n";
  for (const auto& [label, value] : summaryTableRows(metadata, summary)) {
    out << "<tr><th>" << htmlEscape(label) << "</th><td>" << htmlEscape(value)
        << "</td></tr>\n";
  }
  out << "</table>\n<p>No plots: run <code>python3 "
      << htmlEscape(plotScriptPath().string())
      << " &lt;this folder&gt;</code> (needs " << kInstallHint
      << ").</p>\n<h2>Files</h2>\n<ul>\n"
      << "<li><a href=\"summary.json\">summary.json</a></li>\n";
  for (const std::string& f : files) {
    out << "<li><a href=\"" << htmlEscape(f) << "\">" << htmlEscape(f)
        << "</a></li>\n";
  }
  out << "</ul>\n</body></html>\n";
  finish(out, file);
}

std::string findPlotInterpreter() {
  for (const std::string& py : interpreterCandidates()) {
    if (runShell(shellQuote(py) +
                 " -c 'import matplotlib, numpy' >/dev/null 2>&1") == 0) {
      return py;
    }
  }
  return {};
}

fs::path plotScriptPath() {
  return dataDirectory() / "scripts" / "conftrack_plots.py";
}

PlotScriptResult runPlotScript(const fs::path& dir, std::ostream& log) {
  PlotScriptResult result;
  const fs::path script = plotScriptPath();
  if (!fs::exists(script)) {
    result.message = "no plots: plot script " + script.string() +
                     " not found (set CONFTRACK_DATA_DIR to the conftrack "
                     "source folder)";
    log << result.message << '\n';
    return result;
  }
  const std::string withMatplotlib = findPlotInterpreter();
  std::string anyPython = withMatplotlib;
  if (anyPython.empty()) {
    for (const std::string& py : interpreterCandidates()) {
      if (runShell(shellQuote(py) + " -c pass >/dev/null 2>&1") == 0) {
        anyPython = py;
        break;
      }
    }
  }
  if (anyPython.empty()) {
    result.message =
        std::string("no plots: python3 not found; install it with: ") +
        "apt-get install python3 python3-matplotlib python3-numpy";
    log << result.message << '\n';
    return result;
  }
  const std::string python =
      withMatplotlib.empty() ? anyPython : withMatplotlib;
  const int rc =
      runShell(shellQuote(python) + " " + shellQuote(script.string()) + " " +
               shellQuote(dir.string()));
  if (withMatplotlib.empty()) {
    result.message = std::string("no plots: matplotlib/numpy not found for ") +
                     python + "; install them with: " + kInstallHint +
                     " (index.html lists the CSV files)";
  } else if (rc != 0) {
    result.message = "plot script failed (exit code " + std::to_string(rc) +
                     "); the CSV files and summary.json are written";
  } else {
    result.plotted = true;
    result.message = "plots and index.html written to " + dir.string();
  }
  log << result.message << '\n';
  return result;
}

PlotScriptResult writePerformanceReport(const fs::path& dir,
                                        const RunMetadata& metadata,
                                        const PerformanceSummary& summary,
                                        bool plots, std::ostream& log) {
  fs::create_directories(dir);
  writeSummaryJson(dir / "summary.json", metadata, summary);
  const std::vector<std::string> files = writeHistogramCsvs(dir, summary);
  writeIndexHtml(dir, metadata, summary, files);
  PlotScriptResult result{false, "plots not requested"};
  if (plots) {
    result = runPlotScript(dir, log);
  }
  writePerformanceData(dir / kPerformanceDataFile, metadata, summary);
  return result;
}

}  // namespace conftrack

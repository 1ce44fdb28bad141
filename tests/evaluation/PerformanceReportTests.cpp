// summary.json keys, CSV format, the summary table, the plain index.html,
// and the plot script (skipped without python3 + matplotlib).

#include "conftrack/evaluation/PerformanceReport.hpp"
#include "conftrack/frontend/ReportFiles.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "EvaluationTestEvents.hpp"

namespace conftrack {
namespace {

namespace fs = std::filesystem;

/// A fresh folder under the temporary directory, removed at the end.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : m_path(fs::temp_directory_path() /
               ("conftrack_eval_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(m_path);
    fs::create_directories(m_path);
  }
  ~TempDir() {
    if (std::getenv("CONFTRACK_KEEP_TEST_OUTPUT") == nullptr) {
      fs::remove_all(m_path);
    }
  }
  const fs::path& path() const { return m_path; }

 private:
  fs::path m_path;
};

std::string readFile(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    out.push_back(line);
  }
  return out;
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, ',');) {
    out.push_back(f);
  }
  return out;
}

RunMetadata ttbarMetadata() {
  RunMetadata m;
  m.version = "test";
  m.detector = "CLICdet";
  m.sample = "ttbar3tev";
  m.overlayBx = 30;
  m.events = 4;
  m.seed = 5;
  m.threads = 2;
  return m;
}

/// Four reference events with times and two steps.
PerformanceSummary ttbarSummary() {
  PerformanceConfig withBackground;
  withBackground.includeBackground = true;  // the reference event's P3
  PerformanceCollector collector(withBackground);
  const test::EventWithTracks e = test::referenceEvent();
  for (std::size_t i = 0; i < 4; ++i) {
    collector.addEvent(i, e.event, e.tracks, 4.0,
                       test::twoSteps(20.0 + i, 80.0),
                       EventTimes{50.0, 100.0 + i, 30.0});
  }
  return collector.summary();
}

/// Muons at the five polar angles and three pT values.
PerformanceSummary muonSummary(std::size_t perPoint) {
  PerformanceConfig config = PerformanceConfig::singleParticleSample();
  config.includeBackground = true;
  PerformanceCollector collector(config);
  std::mt19937_64 rng(3);
  std::size_t index = 0;
  for (double theta : {10.0, 30.0, 50.0, 70.0, 89.0}) {
    for (double pt : {1.0, 10.0, 100.0}) {
      for (std::size_t k = 0; k < perPoint; ++k, ++index) {
        const test::EventWithTracks e =
            test::muonEvent(index, theta, pt, 4.0, rng);
        collector.addEvent(index, e.event, e.tracks, 4.0,
                           test::twoSteps(0.2, 0.1), EventTimes{1.0, 0.3, 0.2});
      }
    }
  }
  return collector.summary();
}

TEST(PerformanceReport, SummaryJsonHasTheAgreedKeys) {
  const nlohmann::ordered_json j =
      makeSummaryJson(ttbarMetadata(), ttbarSummary());
  for (const char* key : {"version",
                          "detector",
                          "sample",
                          "overlay_bx",
                          "events",
                          "seed",
                          "threads",
                          "reconstructable_particles",
                          "reconstructed_tracks",
                          "efficiency",
                          "fake_rate",
                          "duplicate_rate",
                          "time_ms_per_event",
                          "peak_rss_mb",
                          "counts",
                          "acts",
                          "efficiency_signal",
                          "efficiency_background",
                          "efficiency_plot_cuts",
                          "steps"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j.begin().key(), "version");  // order as documented
  EXPECT_EQ(j["version"], "test");
  EXPECT_EQ(j["detector"], "CLICdet");
  EXPECT_EQ(j["overlay_bx"], 30);
  EXPECT_EQ(j["events"], 4);
  EXPECT_EQ(j["reconstructable_particles"], 12);
  EXPECT_EQ(j["reconstructed_tracks"], 20);
  EXPECT_DOUBLE_EQ(j["efficiency"]["all"].get<double>(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(j["efficiency"]["pt_above_1GeV"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["efficiency"]["pt_0p1_to_1GeV"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["fake_rate"].get<double>(), 0.4);
  EXPECT_DOUBLE_EQ(j["duplicate_rate"].get<double>(), 0.4);
  EXPECT_EQ(j["counts"]["fake_rate"]["passed"], 8);
  EXPECT_EQ(j["counts"]["fake_rate"]["total"], 20);
  const auto& t = j["time_ms_per_event"];
  EXPECT_DOUBLE_EQ(t["simulation"].get<double>(), 50.0);
  EXPECT_DOUBLE_EQ(t["finding"].get<double>(), 101.5);
  EXPECT_DOUBLE_EQ(t["fitting"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(t["reconstruction"].get<double>(), 131.5);
  EXPECT_DOUBLE_EQ(t["steps"]["vertex_barrel"].get<double>(), 21.5);
  EXPECT_DOUBLE_EQ(t["steps"]["displaced"].get<double>(), 80.0);
  EXPECT_GT(j["peak_rss_mb"].get<double>(), 0.0);
  EXPECT_FALSE(j.contains("pulls"));  // not a single-particle sample
}

TEST(PerformanceReport, SummaryJsonOfMuonsHasPulls) {
  const nlohmann::ordered_json j =
      makeSummaryJson(RunMetadata{}, muonSummary(12));
  ASSERT_TRUE(j.contains("pulls"));
  for (const char* q : {"d0", "z0", "phi0", "omega", "tanlambda"}) {
    ASSERT_TRUE(j["pulls"].contains(q)) << q;
    EXPECT_TRUE(j["pulls"][q]["mean"].is_number()) << q;
    EXPECT_NEAR(j["pulls"][q]["width"].get<double>(), 1.0, 0.2) << q;
  }
  ASSERT_TRUE(j.contains("resolutions"));
  // 5 angles x 3 pT x 6 quantities.
  EXPECT_EQ(j["resolutions"].size(), 90u);
  EXPECT_EQ(j["version"], CONFTRACK_VERSION);  // the build's by default
  EXPECT_EQ(j["events"], 180);                 // evaluated when not given
}

TEST(PerformanceReport, CsvFormat) {
  TempDir dir("csv");
  const PerformanceSummary s = ttbarSummary();
  const std::vector<std::string> files = writeHistogramCsvs(dir.path(), s);
  for (const char* name :
       {"efficiency_vs_pt.csv", "efficiency_vs_theta.csv",
        "efficiency_vs_phi.csv", "efficiency_vs_vertex_radius.csv",
        "efficiency_vs_proximity.csv", "fake_rate_vs_pt.csv",
        "fake_rate_vs_theta.csv", "duplicate_rate_vs_pt.csv", "time_steps.csv",
        "time_per_event.csv"}) {
    EXPECT_NE(std::find(files.begin(), files.end(), name), files.end()) << name;
    EXPECT_TRUE(fs::exists(dir.path() / name)) << name;
  }
  const auto rows = lines(readFile(dir.path() / "efficiency_vs_pt.csv"));
  ASSERT_EQ(rows.size(), 38u);  // header + 37 bins
  EXPECT_EQ(rows[0],
            "low,high,numerator,denominator,value,uncertainty,lower,upper");
  double previousHigh = 0.1;
  std::uint64_t numerator = 0;
  std::uint64_t denominator = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto f = fields(rows[i]);
    ASSERT_EQ(f.size(), 8u) << rows[i];
    EXPECT_NEAR(std::stod(f[0]), previousHigh, 1e-9);  // contiguous bins
    previousHigh = std::stod(f[1]);
    numerator += std::stoull(f[2]);
    denominator += std::stoull(f[3]);
    const double low = std::stod(f[0]);
    if (low <= 5.0 && 5.0 < std::stod(f[1])) {  // P1, found in all 4 events
      EXPECT_EQ(f[2], "4");
      EXPECT_EQ(f[3], "4");
      EXPECT_EQ(f[4], "1");
      EXPECT_EQ(f[5], "0");
    }
    if (f[3] == "0") {
      EXPECT_EQ(f[4], "nan");
    }
  }
  EXPECT_NEAR(previousHigh, 501.187, 1e-3);
  EXPECT_EQ(numerator, 8u);
  EXPECT_EQ(denominator, 8u);

  // Theta in degrees.
  const auto theta = lines(readFile(dir.path() / "efficiency_vs_theta.csv"));
  ASSERT_EQ(theta.size(), 91u);
  EXPECT_EQ(fields(theta.back())[1], "180");
  const auto steps = lines(readFile(dir.path() / "time_steps.csv"));
  ASSERT_EQ(steps.size(), 3u);
  EXPECT_EQ(fields(steps[1])[0], "vertex_barrel");
  EXPECT_EQ(fields(steps[1])[1], "21.5");
}

TEST(PerformanceReport, MuonCsvs) {
  TempDir dir("muon_csv");
  const std::vector<std::string> files =
      writeHistogramCsvs(dir.path(), muonSummary(12));
  for (const char* name : {"resolutions.csv", "pulls.csv", "pull_d0.csv",
                           "pull_tanlambda.csv", "pull_pt.csv"}) {
    EXPECT_TRUE(fs::exists(dir.path() / name)) << name;
  }
  const auto res = lines(readFile(dir.path() / "resolutions.csv"));
  ASSERT_EQ(res.size(), 91u);
  EXPECT_EQ(fields(res[0]).size(), 13u);
  EXPECT_EQ(fields(res[1])[0], "d0");
  EXPECT_EQ(fields(res[1])[1], "um");
  EXPECT_EQ(fields(res[1])[2], "10");
  const auto pulls = lines(readFile(dir.path() / "pulls.csv"));
  EXPECT_EQ(pulls.size(), 8u);  // header + 7 quantities
  const auto hist = lines(readFile(dir.path() / "pull_d0.csv"));
  EXPECT_EQ(hist[0], "low,high,count");
  EXPECT_EQ(hist.size(), 51u);
}

TEST(PerformanceReport, SummaryTableIsAligned) {
  std::ostringstream out;
  printSummaryTable(out, ttbarMetadata(), ttbarSummary());
  const std::string text = out.str();
  if (std::getenv("CONFTRACK_KEEP_TEST_OUTPUT") != nullptr) {
    std::cout << text;
  }
  EXPECT_NE(text.find("efficiency"), std::string::npos);
  EXPECT_NE(text.find("66.67 +- 13.61 %"), std::string::npos) << text;
  EXPECT_NE(text.find("step vertex_barrel"), std::string::npos);
  // Values start in one column.
  std::size_t column = std::string::npos;
  for (const std::string& line : lines(text)) {
    if (line.rfind("  fake rate", 0) == 0 ||
        line.rfind("  reconstructed tracks", 0) == 0) {
      const std::size_t c = line.find_first_not_of(' ', line.find("  ", 2));
      if (column == std::string::npos) {
        column = c;
      }
      EXPECT_EQ(c, column) << line;
    }
  }
  EXPECT_NE(column, std::string::npos);
}

/// Sets an environment variable for the scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : m_name(name) {
    if (const char* old = std::getenv(name)) {
      m_old = old;
      m_had = true;
    }
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (m_had) {
      ::setenv(m_name, m_old.c_str(), 1);
    } else {
      ::unsetenv(m_name);
    }
  }

 private:
  const char* m_name;
  std::string m_old;
  bool m_had = false;
};

TEST(PerformanceReport, WithoutThePlotScriptEverythingElseIsWritten) {
  TempDir dir("noscript");
  TempDir data("nodata");
  ScopedEnv env("CONFTRACK_DATA_DIR", data.path().string());
  EXPECT_EQ(plotScriptPath(), data.path() / "scripts" / "conftrack_plots.py");
  std::ostringstream log;
  const PlotScriptResult r = writePerformanceReport(dir.path(), ttbarMetadata(),
                                                    ttbarSummary(), true, log);
  EXPECT_FALSE(r.plotted);
  EXPECT_NE(log.str().find("not found"), std::string::npos) << log.str();
  EXPECT_TRUE(fs::exists(dir.path() / "summary.json"));
  const std::string html = readFile(dir.path() / "index.html");
  EXPECT_NE(html.find("efficiency_vs_pt.csv"), std::string::npos);
  EXPECT_NE(html.find("apt-get install python3-matplotlib"), std::string::npos);
  // summary.json parses back.
  const auto j = nlohmann::json::parse(readFile(dir.path() / "summary.json"));
  EXPECT_EQ(j["sample"], "ttbar3tev");
}

TEST(PerformanceReport, ScriptWithoutMatplotlibListsTheCsvFiles) {
  // Needs a python3 that lacks matplotlib (e.g. a pyenv or venv one).
  std::string bare;
  for (const char* py : {"python3", "/usr/bin/python3"}) {
    const std::string q = std::string("'") + py + "'";
    if (std::system((q + " -c pass >/dev/null 2>&1").c_str()) == 0 &&
        std::system((q + " -c 'import matplotlib' >/dev/null 2>&1").c_str()) !=
            0) {
      bare = py;
      break;
    }
  }
  if (bare.empty()) {
    GTEST_SKIP() << "no python3 without matplotlib to test with";
  }
  TempDir dir("bare_python");
  std::ostringstream log;
  writePerformanceReport(dir.path(), ttbarMetadata(), ttbarSummary(), false,
                         log);
  const std::string command = "'" + bare + "' '" + plotScriptPath().string() +
                              "' '" + dir.path().string() + "' >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3);  // "no matplotlib", not a failure
  const std::string html = readFile(dir.path() / "index.html");
  EXPECT_NE(html.find("fake_rate_vs_pt.csv"), std::string::npos);
  EXPECT_NE(html.find("CLICdp, 30 BX"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
}

TEST(PerformanceReport, PlotScriptWritesPngsAndHtml) {
  if (findPlotInterpreter().empty()) {
    GTEST_SKIP() << "python3 with matplotlib and numpy not found (apt-get "
                    "install python3-matplotlib python3-numpy)";
  }
  ASSERT_TRUE(fs::exists(plotScriptPath())) << plotScriptPath();
  {
    TempDir dir("plots_ttbar");
    std::ostringstream log;
    const PlotScriptResult r = writePerformanceReport(
        dir.path(), ttbarMetadata(), ttbarSummary(), true, log);
    ASSERT_TRUE(r.plotted) << log.str();
    for (const char* png :
         {"efficiency_vs_pt.png", "efficiency_vs_theta.png",
          "efficiency_vs_phi.png", "efficiency_vs_vertex_radius.png",
          "efficiency_vs_proximity.png", "fake_rate_vs_pt.png",
          "fake_rate_vs_theta.png", "duplicate_rate_vs_pt.png",
          "time_steps.png", "time_per_event.png"}) {
      EXPECT_GT(fs::file_size(dir.path() / png), 1000u) << png;
    }
    const std::string html = readFile(dir.path() / "index.html");
    EXPECT_NE(html.find("<img src=\"efficiency_vs_pt.png\""),
              std::string::npos);
    EXPECT_NE(html.find("CLICdp, 30 BX"), std::string::npos);
    EXPECT_NE(html.find("summary.json"), std::string::npos);
  }
  {
    TempDir dir("plots_muons");
    RunMetadata m;
    m.detector = "CLICdet";
    m.sample = "muons";
    std::ostringstream log;
    const PlotScriptResult r =
        writePerformanceReport(dir.path(), m, muonSummary(12), true, log);
    ASSERT_TRUE(r.plotted) << log.str();
    for (const char* png : {"resolution_pt_over_pt2.png", "resolution_d0.png",
                            "resolution_z0.png", "resolution_phi0.png",
                            "resolution_theta.png", "pulls.png"}) {
      EXPECT_GT(fs::file_size(dir.path() / png), 1000u) << png;
    }
    const std::string html = readFile(dir.path() / "index.html");
    EXPECT_NE(html.find("resolution_pt_over_pt2.png"), std::string::npos);
    EXPECT_NE(html.find("Pull d0"), std::string::npos);
  }
}

}  // namespace
}  // namespace conftrack

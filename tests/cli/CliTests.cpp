// End-to-end checks of the conftrack program: determinism across thread
// counts, exit codes and one-line errors.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "TempDir.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string err;
};

/// Runs `conftrack args`; returns the exit code and stderr.
Result conftrack(const std::string& args) {
  fs::path err = conftrack::test::perTestPath("stderr.txt");
  std::string cmd = std::string(CONFTRACK_BINARY) + " " + args +
                    " > /dev/null 2> " + err.string();
  int status = std::system(cmd.c_str());
  std::ifstream in(err);
  std::stringstream s;
  s << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, s.str()};
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path tempDir(const std::string& name) {
  fs::path d = conftrack::test::perTestPath(name);
  fs::remove_all(d);
  return d;
}

TEST(Cli, SimulationIsByteIdenticalForOneAndTwoThreads) {
  fs::path a = tempDir("sim1");
  fs::path b = tempDir("sim2");
  std::string common =
      "-q simulate --sample ttbar3tev --overlay-bx 5 -n 4 --seed 7 -o ";
  ASSERT_EQ(conftrack(common + a.string() + " -j 1").code, 0);
  ASSERT_EQ(conftrack(common + b.string() + " -j 2").code, 0);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(a)) {
    fs::path other = b / entry.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(slurp(entry.path()), slurp(other)) << entry.path().filename();
    ++files;
  }
  EXPECT_EQ(files, 12u);  // hits, truth, particles for 4 events
}

/// summary.json without the keys that hold times or machine figures.
nlohmann::json withoutTimes(nlohmann::json j) {
  j.erase("time_ms_per_event");
  j.erase("peak_rss_mb");
  j.erase("threads");
  if (j.contains("steps")) {
    for (auto& s : j["steps"]) {
      if (s.is_object()) {
        s.erase("ms");
        s.erase("milliseconds");
        s.erase("time_ms");
        s.erase("ms_per_event");
      }
    }
  }
  return j;
}

TEST(Cli, RunSummaryIsIdenticalForOneAndTwoThreads) {
  fs::path a = tempDir("run1");
  fs::path b = tempDir("run2");
  std::string common =
      "-q run --sample ttbar3tev --overlay-bx 3 -n 4 --seed 3 --no-plots -o ";
  ASSERT_EQ(conftrack(common + a.string() + " -j 1").code, 0);
  ASSERT_EQ(conftrack(common + b.string() + " -j 2").code, 0);
  nlohmann::json ja = nlohmann::json::parse(slurp(a / "summary.json"));
  nlohmann::json jb = nlohmann::json::parse(slurp(b / "summary.json"));
  EXPECT_EQ(ja["threads"], 1);
  EXPECT_EQ(jb["threads"], 2);
  for (const char* key :
       {"version", "detector", "sample", "overlay_bx", "events", "seed",
        "reconstructable_particles", "reconstructed_tracks", "efficiency",
        "fake_rate", "duplicate_rate", "time_ms_per_event", "peak_rss_mb"}) {
    EXPECT_TRUE(ja.contains(key)) << key;
  }
  EXPECT_EQ(withoutTimes(ja), withoutTimes(jb));
}

TEST(Cli, ModuleLevelSimulationIsDeterministicAndReadBack) {
  // --module-level on CLICdet (spiral vertex petals up to 20.7 mm from
  // their layer's mean z) and CLD: the same files for one and two
  // threads, different from the ideal layers, and read back by
  // reconstruct (hits within 25 mm of their layer).
  for (const std::string detector : {"clicdet", "cld"}) {
    fs::path a = tempDir(detector + "_ml1");
    fs::path b = tempDir(detector + "_ml2");
    fs::path ideal = tempDir(detector + "_ideal");
    const std::string common = "-q simulate --detector " + detector +
                               " --sample ttbar3tev --overlay-bx 3 -n 2 "
                               "--seed 5 -o ";
    ASSERT_EQ(conftrack(common + a.string() + " -j 1 --module-level").code, 0);
    ASSERT_EQ(conftrack(common + b.string() + " -j 2 --module-level").code, 0);
    ASSERT_EQ(conftrack(common + ideal.string()).code, 0);
    const std::string hits = "event000000001-hits.csv";
    EXPECT_EQ(slurp(a / hits), slurp(b / hits)) << detector;
    EXPECT_NE(slurp(a / hits), slurp(ideal / hits)) << detector;
    const Result r =
        conftrack("-q reconstruct -i " + a.string() + " --detector " +
                  detector + " -o " + tempDir(detector + "_tracks").string());
    EXPECT_EQ(r.code, 0) << r.err;
  }
  const Result r = conftrack(
      "simulate --detector trackml -n 1 --module-level "
      "-o " +
      tempDir("trackml_ml").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("trackml_layout.json.gz"), std::string::npos) << r.err;
}

TEST(Cli, BadInputIsOneLineAndExitCodeOne) {
  Result r = conftrack("detector show no-such-detector");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  r = conftrack("reconstruct -i /nonexistent-folder -o /tmp/x");
  EXPECT_EQ(r.code, 1) << r.err;
  r = conftrack("simulate --sample nonsense -n 1 -o " +
                tempDir("bad").string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("nonsense"), std::string::npos) << r.err;
  r = conftrack("simulate --gen p_GeV=-3 --sample muons -n 1 -o " +
                tempDir("bad2").string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  r = conftrack("run --no-such-option");
  EXPECT_EQ(r.code, 1);
  r = conftrack("--help");
  EXPECT_EQ(r.code, 0);
}

TEST(Cli, DetectorShowListsEveryLayer) {
  fs::path out = conftrack::test::perTestPath("show.txt");
  std::string cmd = std::string(CONFTRACK_BINARY) +
                    " detector show clicdet > " + out.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::string text = slurp(out);
  for (const char* name : {"VXD_B_L0", "VXD_E_L5_pos", "IT_B_L2", "IT_E_L6_neg",
                           "OT_B_L2", "OT_E_L3_pos", "BeamPipe"}) {
    EXPECT_NE(text.find(name), std::string::npos) << name;
  }
  EXPECT_NE(text.find("31.165"), std::string::npos);
  EXPECT_NE(text.find("1487.851"), std::string::npos);
}

TEST(Cli, ValidateTrackmlComparesWithTheRealFiles) {
  const fs::path out = tempDir("validate");
  const fs::path printed = conftrack::test::perTestPath("validate.txt");
  const fs::path repo = fs::path(CONFTRACK_TEST_DATA_DIR).parent_path();
  const std::string cmd =
      std::string(CONFTRACK_BINARY) + " validate-trackml -i " +
      (repo / "data/trackml/train_100_events_no_truth").string() +
      " --events 1001 -o " + out.string() + " > " + printed.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const std::string text = slurp(printed);
  EXPECT_NE(text.find("Bins with >= 100 particles:"), std::string::npos)
      << text;
  EXPECT_NE(text.find("Hits per (volume, layer)"), std::string::npos);

  // 4 pT x 8 |eta| x prompt/displaced bins, and every real hit of event
  // 1001 (93,680) in the layer table.
  std::ifstream bins(out / "hit_counts.csv");
  std::string line;
  std::size_t rows = 0;
  std::getline(bins, line);
  EXPECT_EQ(line.rfind("pt_min_GeV,pt_max_GeV,abs_eta_min", 0), 0u) << line;
  while (std::getline(bins, line)) {
    ++rows;
  }
  EXPECT_EQ(rows, 64u);
  std::ifstream layers(out / "layer_hits.csv");
  std::getline(layers, line);
  ASSERT_EQ(line, "volume_id,layer_id,real_hits,simulated_hits");
  std::size_t realHits = 0;
  std::size_t simulatedHits = 0;
  std::size_t layerRows = 0;
  while (std::getline(layers, line)) {
    std::stringstream row(line);
    std::string field;
    std::vector<std::size_t> values;
    while (std::getline(row, field, ',')) {
      values.push_back(std::stoull(field));
    }
    ASSERT_EQ(values.size(), 4u) << line;
    realHits += values[2];
    simulatedHits += values[3];
    ++layerRows;
  }
  EXPECT_EQ(realHits, 93680u);
  EXPECT_GT(simulatedHits, 50000u);
  EXPECT_EQ(layerRows, 48u);  // the TrackML detector's layers
}

}  // namespace

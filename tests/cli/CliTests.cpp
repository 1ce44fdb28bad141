// End-to-end checks of the conftrack program: determinism across thread
// counts, exit codes and one-line errors.

#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
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
  j.erase("time_ms_total");
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

/// Rows of a CSV file written by validate-trackml, as numbers.
std::vector<std::vector<double>> readNumbers(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string field;
    rows.emplace_back();
    while (std::getline(row, field, ',')) {
      rows.back().push_back(std::stod(field));
    }
  }
  return rows;
}

TEST(Cli, TrackmlSimulationAgreesWithTheRealFiles) {
  // The module-level simulation of the particles of real events 1001 and
  // 1005 against their real nhits and hits per layer (docs/validation.md),
  // the mean of three simulations. Measured: 28 of the 40 bins with >= 100
  // particles within 5 %, the worst 11.4 % off; 42 of 48 layers within
  // 10 %, the worst 21.1 % off. Guarded with margins of 3 bins, 3 points,
  // 3 layers and 3 points: a simulation change that moves it away from
  // the real data fails here.
  const fs::path out = tempDir("agreement");
  const fs::path repo = fs::path(CONFTRACK_TEST_DATA_DIR).parent_path();
  const std::string cmd =
      std::string(CONFTRACK_BINARY) + " -q validate-trackml -i " +
      (repo / "data/trackml/train_100_events_no_truth").string() +
      " --events 1001 1005 --repeat 3 -o " + out.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::size_t bins = 0;
  std::size_t within = 0;
  double worst = 0.0;
  // pt_min, pt_max, eta_min, eta_max, displaced, particles, real, simulated
  for (const auto& row : readNumbers(out / "hit_counts.csv")) {
    ASSERT_EQ(row.size(), 8u);
    if (row[5] < 100.0) {
      continue;
    }
    const double deviation = std::abs(row[7] / row[6] - 1.0);
    ++bins;
    within += deviation <= 0.05 ? 1 : 0;
    worst = std::max(worst, deviation);
  }
  EXPECT_EQ(bins, 40u);
  EXPECT_GE(within, 25u);
  EXPECT_LE(worst, 0.145);
  std::size_t layersWithin = 0;
  double worstLayer = 0.0;
  const auto layers = readNumbers(out / "layer_hits.csv");
  for (const auto& row : layers) {
    ASSERT_EQ(row.size(), 4u);
    const double deviation = std::abs(row[3] / row[2] - 1.0);
    layersWithin += deviation <= 0.10 ? 1 : 0;
    worstLayer = std::max(worstLayer, deviation);
  }
  EXPECT_EQ(layers.size(), 48u);
  EXPECT_GE(layersWithin, 39u);
  EXPECT_LE(worstLayer, 0.241);
}

TEST(Cli, ReconstructLogsTheVertexRegionsAtDebugLevel) {
  // The TrackML chain's vertex pre-pass: with -vv one line per event lists
  // the regions its prompt steps seeded about (here the Kaggle luminous
  // region, sigma_z 5.5 mm: within +-20 mm); without -vv nothing.
  const fs::path real = fs::path(CONFTRACK_TEST_DATA_DIR) / "trackml" /
                        "train_100_events_no_truth";
  const fs::path sim = tempDir("vz_sim");
  ASSERT_EQ(conftrack("-q simulate-trackml --min-pt 1 -i " + real.string() +
                      " -o " + sim.string())
                .code,
            0);
  const std::string reco = "reconstruct --detector trackml --no-fit -i " +
                           sim.string() + " -o " + tempDir("vz_out").string();
  const Result debug = conftrack("-vv " + reco);
  ASSERT_EQ(debug.code, 0) << debug.err;
  std::istringstream lines(debug.err);
  std::string line;
  int events = 0;
  const std::regex pattern(
      R"(event (\d+): vertex pre-pass, (\d+) regions?:((?: \[-?\d+\.\d, -?\d+\.\d\])+) mm)");
  while (std::getline(lines, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, pattern)) {
      continue;
    }
    ++events;
    std::istringstream regions(m[3].str());
    double lo = 0.0;
    double hi = 0.0;
    char c = 0;
    int n = 0;
    double previous = -1e9;
    while (regions >> c >> lo >> c >> hi >> c) {
      EXPECT_LE(lo, hi) << line;
      EXPECT_GT(lo, previous) << line;
      EXPECT_GT(lo, -20.0) << line;
      EXPECT_LT(hi, 20.0) << line;
      previous = hi;
      ++n;
    }
    EXPECT_EQ(n, std::stoi(m[2].str())) << line;
  }
  EXPECT_EQ(events, 5) << debug.err;
  const Result quiet = conftrack(reco);
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("vertex pre-pass"), std::string::npos) << quiet.err;
}

// simulate-trackml: the real vertices by default; with --luminous-region
// hllhc the interactions of the five real events move to a z spread of 50
// mm (713 interaction points: standard error 1.33 mm, 5 of them allowed),
// each as a whole, the same for one and two threads and for the same seed.
// --min-pt 1e6: no particle is propagated, only the vertices matter here.
TEST(Cli, SimulateTrackmlLuminousRegion) {
  const fs::path real = fs::path(CONFTRACK_TEST_DATA_DIR) / "trackml" /
                        "train_100_events_no_truth";
  const std::string common =
      "-q simulate-trackml --min-pt 1e6 -i " + real.string() + " -o ";
  const fs::path kept = tempDir("kept");
  const fs::path a = tempDir("hllhc1");
  const fs::path b = tempDir("hllhc2");
  const fs::path other = tempDir("seed2");
  ASSERT_EQ(conftrack(common + kept.string()).code, 0);
  ASSERT_EQ(
      conftrack(common + a.string() + " --luminous-region hllhc -j 1").code, 0);
  ASSERT_EQ(
      conftrack(common + b.string() + " --luminous-region hllhc -j 2").code, 0);
  ASSERT_EQ(
      conftrack(common + other.string() + " --luminous-region hllhc --seed 2")
          .code,
      0);
  const auto particlesOf = [](const fs::path& dir, std::uint64_t event) {
    return conftrack::readEvent(dir, event, nullptr, {false, true}).particles;
  };
  std::vector<double> z;
  for (std::uint64_t event : {1001, 1003, 1005, 1009, 1010}) {
    const std::string name =
        "event00000" + std::to_string(event) + "-particles.csv";
    EXPECT_EQ(slurp(a / name), slurp(b / name)) << name;
    EXPECT_NE(slurp(a / name), slurp(other / name)) << name;
    const auto input = particlesOf(real, event);
    const auto unchanged = particlesOf(kept, event);
    const auto moved = particlesOf(a, event);
    ASSERT_EQ(unchanged.size(), input.size());
    ASSERT_EQ(moved.size(), input.size());
    std::map<std::uint64_t, double> shift;  // per vertex id
    for (std::size_t i = 0; i < input.size(); ++i) {
      ASSERT_EQ(unchanged[i].id, input[i].id);
      ASSERT_EQ(moved[i].id, input[i].id);
      EXPECT_EQ(unchanged[i].vertex, input[i].vertex);
      EXPECT_EQ(moved[i].vertex.x(), input[i].vertex.x());
      EXPECT_EQ(moved[i].vertex.y(), input[i].vertex.y());
      const double dz = moved[i].vertex.z() - input[i].vertex.z();
      const auto [it, first] =
          shift.emplace(conftrack::trackmlVertexId(input[i].id), dz);
      if (!first) {
        ASSERT_NEAR(dz, it->second, 1e-9) << input[i].id;
      }
    }
    for (const auto& interaction : conftrack::findTrackmlInteractions(moved)) {
      if (interaction.vertex) {
        z.push_back(interaction.vertex->z());
      }
    }
  }
  ASSERT_EQ(z.size(), 713u);
  double mean = 0.0;
  for (double v : z) {
    mean += v / static_cast<double>(z.size());
  }
  double sum2 = 0.0;
  for (double v : z) {
    sum2 += (v - mean) * (v - mean);
  }
  EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(z.size() - 1)), 50.0,
              5.0 * 1.33);
}

TEST(Cli, SimulateTrackmlBeamLine) {
  // --beam-line X,Y: every particle of the real events moves by (X, Y),
  // the beams then collide off the detector axis.
  const fs::path real = fs::path(CONFTRACK_TEST_DATA_DIR) / "trackml" /
                        "train_100_events_no_truth";
  const fs::path off = tempDir("beamline");
  ASSERT_EQ(conftrack("-q simulate-trackml --min-pt 1e6 -i " + real.string() +
                      " -o " + off.string() + " --beam-line 0.5,-0.25")
                .code,
            0);
  const auto input =
      conftrack::readEvent(real, 1005, nullptr, {false, true}).particles;
  const auto moved =
      conftrack::readEvent(off, 1005, nullptr, {false, true}).particles;
  ASSERT_EQ(moved.size(), input.size());
  for (std::size_t i = 0; i < input.size(); ++i) {
    ASSERT_EQ(moved[i].id, input[i].id);
    EXPECT_NEAR(moved[i].vertex.x() - input[i].vertex.x(), 0.5, 1e-9);
    EXPECT_NEAR(moved[i].vertex.y() - input[i].vertex.y(), -0.25, 1e-9);
    EXPECT_EQ(moved[i].vertex.z(), input[i].vertex.z());
  }
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

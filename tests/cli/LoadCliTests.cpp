// The load-test tools of the program (docs/robustness.md): `conftrack
// overlay` and the report of the finder's combinatorics guards (warning
// line, summary.json, step table).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "TempDir.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string out;
  std::string err;
};

/// Runs `conftrack args`; returns the exit code, stdout and stderr.
Result run(const std::string& args) {
  const fs::path out = conftrack::test::perTestPath("stdout.txt");
  const fs::path err = conftrack::test::perTestPath("stderr.txt");
  const std::string cmd = std::string(CONFTRACK_BINARY) + " " + args + " > " +
                          out.string() + " 2> " + err.string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

fs::path tempDir(const std::string& name) {
  fs::path d = conftrack::test::perTestPath(name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const fs::path kRepo = fs::path(CONFTRACK_TEST_DATA_DIR).parent_path();
const std::string kRealEvents =
    (kRepo / "data/trackml/train_100_events_no_truth").string();

TEST(LoadCli, OverlayWritesTwoRotatedCopiesWithNewIds) {
  const fs::path out = tempDir("overlay");
  const Result r = run("overlay -i " + kRealEvents +
                       " --detector trackml --events 1001 --copies 2 "
                       "--number 7 -o " +
                       out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("187360 hits from 1 events x 2 copies"),
            std::string::npos)
      << r.out;
  std::ifstream in(out / "event000000007-hits.csv");
  ASSERT_TRUE(in.good());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("hit_id,x,y,z,volume_id,layer_id,module_id", 0), 0u)
      << line;
  std::set<std::uint64_t> ids;
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    ids.insert(std::stoull(line.substr(0, line.find(','))));
    ++rows;
  }
  EXPECT_EQ(rows, 187360u);  // 93,680 hits of event 1001, twice
  EXPECT_EQ(ids.size(), rows);
  EXPECT_EQ(*ids.begin(), 1u);
  EXPECT_EQ(*ids.rbegin(), rows);
}

TEST(LoadCli, OverlayRejectsBadInput) {
  const fs::path out = tempDir("overlay-bad");
  Result r = run("overlay -i " + kRealEvents +
                 " --detector trackml --events 999 -o " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("no hits file of event 999"), std::string::npos)
      << r.err;
  r = run("overlay -i " + kRealEvents + " --detector trackml --copies 0 -o " +
          out.string());
  EXPECT_EQ(r.code, 1) << r.err;
}

TEST(LoadCli, GuardBitesAreWarnedAndReported) {
  // The CLICdet chain with a guard of one seed cell per seed: it bites in
  // every event.
  const fs::path dir = tempDir("guards");
  std::ifstream in(kRepo / "chains/clicdet.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string chain = text.str();
  const std::string key = "max_seed_neighbours = 256";
  const auto at = chain.find(key);
  ASSERT_NE(at, std::string::npos);
  chain.replace(at, key.size(), "max_seed_neighbours = 1");
  std::ofstream(dir / "tight.toml") << chain;
  const Result r =
      run("run --sample muons -n 2 -j 1 --no-plots --chain " +
          (dir / "tight.toml").string() + " -o " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("event 1: combinatorics guards truncated the search "
                       "(step VXDBarrel: max_seed_neighbours cut "),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("guard max_seed_neighbours"), std::string::npos)
      << r.out;
  std::ifstream summary(dir / "out/summary.json");
  const nlohmann::json j = nlohmann::json::parse(summary);
  // The steps as the step table lists them: the vertex pre-pass first.
  const auto step = std::find_if(
      j["steps"].begin(), j["steps"].end(),
      [](const nlohmann::json& s) { return s["name"] == "VXDBarrel"; });
  ASSERT_NE(step, j["steps"].end());
  const auto& guard = (*step)["guards"]["max_seed_neighbours"];
  EXPECT_GT(guard["bites"].get<std::uint64_t>(), 0u);
  EXPECT_GE(guard["cut"].get<std::uint64_t>(),
            guard["bites"].get<std::uint64_t>());
  EXPECT_EQ((*step)["guards"]["max_window_hits"]["bites"], 0);
}

}  // namespace

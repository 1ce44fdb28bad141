// Runs split into shards (--shard K/N) and merged (conftrack merge) give
// the report of one process over the same events: every count, histogram
// bin and fitted resolution, only the wall times differ. The Slurm job
// scripts (conftrack slurm --dry-run) are run here by hand, task by task,
// as the array job would run them; tests/slurm/ runs them on a real Slurm
// cluster.

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

/// Runs a shell command line; returns its exit code.
int sh(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Runs `conftrack -q args`, output discarded; returns the exit code.
int conftrack(const std::string& args) {
  return sh(std::string(CONFTRACK_BINARY) + " -q " + args + " > /dev/null");
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// summary.json without what depends on the process: times, memory,
/// threads, and the shard bookkeeping.
nlohmann::json physics(const fs::path& summary) {
  nlohmann::json j = nlohmann::json::parse(slurp(summary));
  for (const char* key : {"time_ms_per_event", "time_ms_total", "peak_rss_mb",
                          "threads", "merged_shards", "timing_note"}) {
    j.erase(key);
  }
  for (auto& step : j["steps"]) {
    step.erase("ms_per_event");
  }
  return j;
}

/// Every report file of `single` (but the wall-time tables) is in
/// `merged` with the same bytes, and summary.json has the same physics.
void expectSameReport(const fs::path& single, const fs::path& merged) {
  ASSERT_TRUE(fs::exists(merged / "summary.json")) << merged;
  EXPECT_EQ(physics(single / "summary.json"), physics(merged / "summary.json"))
      << merged;
  std::size_t compared = 0;
  for (const auto& entry : fs::directory_iterator(single)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".csv" || name.rfind("time_", 0) == 0) {
      continue;
    }
    EXPECT_EQ(slurp(entry.path()), slurp(merged / name)) << merged / name;
    ++compared;
  }
  EXPECT_GE(compared, 10u);
  const nlohmann::json j =
      nlohmann::json::parse(slurp(merged / "summary.json"));
  EXPECT_TRUE(j.contains("merged_shards"));
  EXPECT_TRUE(j.contains("timing_note"));
}

TEST(Shards, RunStudyShardsMergeToTheSingleProcessReport) {
  const fs::path dir = conftrack::test::perTestPath("study");
  fs::remove_all(dir);
  // Three reports of 10 events each: the 4 shards cut across their
  // sub-samples.
  const std::string run = "run --study displaced -n 2 --seed 5 --no-plots -o ";
  ASSERT_EQ(conftrack(run + (dir / "single").string()), 0);
  std::string inputs;
  for (int k = 3; k >= 0; --k) {
    const fs::path shard = dir / ("shard-" + std::to_string(k));
    ASSERT_EQ(conftrack(run + shard.string() + " --shard " + std::to_string(k) +
                        "/4" + (k == 2 ? " -j 2" : " -j 1")),
              0);
    inputs += " " + shard.string();
  }
  ASSERT_EQ(conftrack("merge --no-plots -i" + inputs + " -o " +
                      (dir / "merged").string()),
            0);
  for (const char* report :
       {"displaced_p1", "displaced_p10", "displaced_p100"}) {
    expectSameReport(dir / "single" / report, dir / "merged" / report);
  }
  fs::remove_all(dir);
}

TEST(Shards, SimulateReconstructEvaluateInShards) {
  const fs::path dir = conftrack::test::perTestPath("chain");
  fs::remove_all(dir);
  const std::string events = (dir / "events").string();
  const std::string tracks = (dir / "tracks").string();
  // Shards of simulate and reconstruct write disjoint files into one
  // folder; the files equal those of one process.
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(conftrack("simulate --sample muons -n 7 --seed 2 -o " + events +
                        " --shard " + std::to_string(k) + "/3"),
              0);
  }
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(conftrack("reconstruct -i " + events + " -o " + tracks +
                        " --shard " + std::to_string(k) + "/3"),
              0);
  }
  ASSERT_EQ(conftrack("simulate --sample muons -n 7 --seed 2 -o " +
                      (dir / "events1").string()),
            0);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "events1")) {
    EXPECT_EQ(slurp(entry.path()),
              slurp(dir / "events" / entry.path().filename()))
        << entry.path().filename();
    ++files;
  }
  EXPECT_EQ(files, 21u);

  const std::string evaluate = "evaluate --single-particle --no-plots -i " +
                               events + " -t " + tracks + " -o ";
  ASSERT_EQ(conftrack(evaluate + (dir / "single").string()), 0);
  std::string inputs;
  for (int k = 0; k < 2; ++k) {
    const fs::path shard = dir / ("eval-" + std::to_string(k));
    ASSERT_EQ(conftrack(evaluate + shard.string() + " --shard " +
                        std::to_string(k) + "/2"),
              0);
    inputs += " " + shard.string();
  }
  ASSERT_EQ(conftrack("merge --no-plots -i" + inputs + " -o " +
                      (dir / "merged").string()),
            0);
  expectSameReport(dir / "single", dir / "merged");
  fs::remove_all(dir);
}

TEST(Shards, SlurmJobScriptsRunTaskByTaskAndResume) {
  const fs::path dir = conftrack::test::perTestPath("slurm");
  fs::remove_all(dir);
  const std::string study = (dir / "study").string();
  const std::string command =
      " -- run --sample muons -n 6 --seed 9 --gen pt_GeV=5";
  ASSERT_EQ(
      conftrack("slurm --dry-run --no-plots --shards 3 -o " + study + command),
      0);
  const fs::path scripts = dir / "study" / "slurm";
  ASSERT_TRUE(fs::exists(scripts / "shard.sh"));
  ASSERT_TRUE(fs::exists(scripts / "merge.sh"));
  // The array job: one task per shard.
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(sh("SLURM_ARRAY_TASK_ID=" + std::to_string(k) + " bash " +
                 (scripts / "shard.sh").string() + " > /dev/null 2>&1"),
              0)
        << "shard " << k;
    EXPECT_TRUE(fs::exists(dir / "study" / ("shard-" + std::to_string(k)) /
                           "COMPLETE"));
  }
  ASSERT_EQ(sh("bash " + (scripts / "merge.sh").string() + " > /dev/null"), 0);
  ASSERT_EQ(conftrack("run --sample muons -n 6 --seed 9 --gen pt_GeV=5 "
                      "--no-plots -o " +
                      (dir / "single").string()),
            0);
  expectSameReport(dir / "single", dir / "study" / "merged");

  // Resume: only the shard without its COMPLETE mark is submitted again.
  fs::remove(dir / "study" / "shard-1" / "COMPLETE");
  const fs::path out = dir / "resume.txt";
  ASSERT_EQ(sh(std::string(CONFTRACK_BINARY) + " -q slurm --dry-run --resume " +
               "--shards 3 -o " + study + command + " > " + out.string()),
            0);
  EXPECT_NE(slurp(out).find("--array=1 "), std::string::npos) << slurp(out);
  fs::remove_all(dir);
}

}  // namespace

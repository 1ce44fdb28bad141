// The mergeable form of the performance data (performance_data.json) and
// the merge of shards: a run split into shards, each saved and read back,
// merges into exactly the summary of the whole run; shards that do not
// belong together are refused with a message naming the file.

#include "conftrack/core/Error.hpp"
#include "conftrack/evaluation/PerformanceDataJson.hpp"
#include "conftrack/evaluation/ShardMerge.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <regex>

#include "EvaluationTestEvents.hpp"

namespace conftrack {
namespace {

PerformanceConfig config() {
  PerformanceConfig c = PerformanceConfig::singleParticleSample();
  c.minFitEntries = 5;
  return c;
}

RunMetadata runMetadata(std::size_t events) {
  RunMetadata m;
  m.version = "test";
  m.detector = "CLICdet";
  m.sample = "muons";
  m.events = events;
  m.seed = 11;
  m.threads = 2;
  return m;
}

/// Summary JSON without the process's memory.
std::string summaryText(const RunMetadata& m, const PerformanceSummary& s) {
  nlohmann::ordered_json j = makeSummaryJson(m, s);
  j.erase("peak_rss_mb");
  j.erase("merged_shards");
  j.erase("timing_note");
  return j.dump();
}

/// Saved JSON text of shard `k` of `count` over `events` (as a process
/// with --shard k/count would write it), read back through text.
ShardInput savedShard(const std::vector<PerformanceData>& events, std::size_t k,
                      std::size_t count) {
  const std::size_t first = events.size() * k / count;
  const std::size_t last = events.size() * (k + 1) / count;
  PerformanceCollector collector(config(), first);
  for (std::size_t i = first; i < last; ++i) {
    collector.add(i, events[i]);
  }
  RunMetadata m = runMetadata(events.size());
  m.shard = {k, count, first};
  const std::string text =
      makePerformanceDataJson(m, collector.summary()).dump();
  const std::string source = "shard-" + std::to_string(k) + ".json";
  return {parsePerformanceDataJson(nlohmann::json::parse(text), source),
          source};
}

class ShardMergeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    PerformanceCollector whole(config());
    events = test::mixedRun(whole, 45);
    for (std::size_t i = 0; i < events.size(); ++i) {
      whole.add(i, events[i]);
    }
    expected = summaryText(runMetadata(events.size()), whole.summary());
  }

  std::vector<ShardInput> shards(std::size_t count) const {
    std::vector<ShardInput> out;
    for (std::size_t k = count; k-- > 0;) {  // any order
      out.push_back(savedShard(events, k, count));
    }
    return out;
  }

  std::vector<PerformanceData> events;
  std::string expected;
};

TEST_F(ShardMergeTest, SavedDataReadsBackBitIdentical) {
  const ShardInput one = savedShard(events, 0, 1);
  PerformanceSummary summary =
      summarizePerformance(one.saved.config, one.saved.data);
  EXPECT_EQ(summaryText(one.saved.metadata, summary), expected);
  // Residuals, NaN pulls among them (written as null), come back as they
  // were.
  std::vector<TrackResidual> original;
  for (const PerformanceData& e : events) {
    original.insert(original.end(), e.residuals.begin(), e.residuals.end());
  }
  const auto nans = [](const std::vector<TrackResidual>& list) {
    std::size_t n = 0;
    for (const TrackResidual& r : list) {
      for (double p : r.pulls) {
        n += std::isnan(p) ? 1 : 0;
      }
    }
    return n;
  };
  ASSERT_FALSE(original.empty());
  ASSERT_EQ(one.saved.data.residuals.size(), original.size());
  EXPECT_EQ(nans(one.saved.data.residuals), nans(original));
  for (std::size_t i = 0; i < original.size(); ++i) {
    for (std::size_t q = 0; q < eNumResidualQuantities; ++q) {
      EXPECT_EQ(one.saved.data.residuals[i].residuals[q],
                original[i].residuals[q]);
    }
  }
  EXPECT_EQ(one.saved.metadata.seed, 11u);
  EXPECT_EQ(one.saved.config.minFitEntries, 5u);
}

TEST_F(ShardMergeTest, MergedShardsGiveTheWholeRunsSummary) {
  for (std::size_t count : {2u, 4u, 7u, 45u, 60u}) {
    SavedPerformance merged = mergeShards(shards(count));
    EXPECT_EQ(merged.metadata.mergedShards, count);
    EXPECT_EQ(merged.metadata.shard.count, 1u);
    EXPECT_EQ(merged.data.events, events.size());
    PerformanceSummary summary =
        summarizePerformance(merged.config, merged.data);
    // Time sums are added in another order: compare all but the times.
    nlohmann::json a = nlohmann::json::parse(expected);
    nlohmann::json b =
        nlohmann::json::parse(summaryText(runMetadata(events.size()), summary));
    for (auto* j : {&a, &b}) {
      j->erase("time_ms_per_event");
      j->erase("time_ms_total");
      for (auto& step : (*j)["steps"]) {
        step.erase("ms_per_event");
      }
    }
    EXPECT_EQ(a, b) << count << " shards";
  }
}

/// The message of the InputError that `fn` throws.
template <class Fn>
std::string errorOf(Fn fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(ShardMergeTest, RefusesShardsThatDoNotBelongTogether) {
  std::vector<ShardInput> missing = shards(4);
  missing.erase(missing.begin() + 1);  // shard 2
  EXPECT_EQ(errorOf([&] { mergeShards(missing); }),
            "merge: shard 2 of 4 of the run of shard-0.json is missing (run "
            "it, then merge again)");

  std::vector<ShardInput> twice = shards(3);
  twice.push_back(savedShard(events, 1, 3));
  twice.back().source = "copy.json";
  EXPECT_EQ(errorOf([&] { mergeShards(twice); }),
            "copy.json: shard 1 of 3 is also in shard-1.json");

  std::vector<ShardInput> otherSeed = shards(2);
  otherSeed[0].saved.metadata.seed = 12;  // shard 1 (inputs are reversed)
  EXPECT_EQ(errorOf([&] { mergeShards(otherSeed); }),
            "shard-1.json: not a shard of the run of shard-0.json: seed 12, "
            "not 11");

  std::vector<ShardInput> otherCount = shards(2);
  otherCount[0] = savedShard(events, 1, 3);
  EXPECT_EQ(errorOf([&] { mergeShards(otherCount); }),
            "shard-1.json: not a shard of the run of shard-0.json: shard "
            "count 3, not 2");

  std::vector<ShardInput> otherConfig = shards(2);
  otherConfig[0].saved.config.matching.purity = 0.5;
  EXPECT_EQ(errorOf([&] { mergeShards(otherConfig); }),
            "shard-1.json: not a shard of the run of shard-0.json: other "
            "evaluation settings (key 'config')");

  std::vector<ShardInput> gap = shards(2);
  gap[0].saved.metadata.shard.firstEvent += 1;
  EXPECT_EQ(errorOf([&] { mergeShards(gap); }),
            "shard-1.json: shard starts at event index 23, expected 22");

  EXPECT_EQ(errorOf([&] { mergeShards({}); }), "merge: no shard results given");
}

TEST_F(ShardMergeTest, BadSavedDataNamesTheKey) {
  RunMetadata m = runMetadata(3);
  PerformanceCollector collector(config());
  for (std::size_t i = 0; i < 3; ++i) {
    collector.add(i, events[i]);
  }
  const nlohmann::json good = nlohmann::json::parse(
      makePerformanceDataJson(m, collector.summary()).dump());
  struct Case {
    const char* pointer;
    nlohmann::json value;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"/format_version", 2,
       "f.json: key 'format_version': version 2 is not the 1 this conftrack "
       "reads"},
      {"/data/ratios/fakes", nlohmann::json::array({5, 4}),
       "f.json: key 'data.ratios.fakes': expected [passed, total] with "
       "passed <= total"},
      {"/data/events", -1,
       "f.json: key 'data.events': expected a whole number between 0 and "
       "9007199254740992"},
      {"/data/histograms/efficiency_vs_pt/edges", nlohmann::json::array({1, 2}),
       ""},
      {"/data/histograms/efficiency_vs_theta/passed/3", 1000000,
       "f.json: key 'data.histograms.efficiency_vs_theta.passed[3]': more "
       "passed than total entries"},
      {"/data/residuals/0", nlohmann::json::array({1, 2}),
       "f.json: key 'data.residuals[0]': expected an array of 15 numbers or "
       "nulls"},
      {"/metadata/shard_index", 1,
       "f.json: key 'metadata.shard_index': expected a whole number between "
       "0 and 0"},
      {"/config/matching_double", "yes",
       "f.json: key 'config.matching_double': expected true or false"},
  };
  for (const Case& c : cases) {
    nlohmann::json bad = good;
    bad[nlohmann::json::json_pointer(c.pointer)] = c.value;
    const std::string message =
        errorOf([&] { parsePerformanceDataJson(bad, "f.json"); });
    if (std::string(c.message).empty()) {
      EXPECT_TRUE(std::regex_search(
          message, std::regex("^f\\.json: key "
                              "'data\\.histograms\\.efficiency_vs_pt\\.edges'"
                              ": bin edges differ from this version's")))
          << message;
    } else {
      EXPECT_EQ(message, c.message) << c.pointer;
    }
  }
  nlohmann::json noData = good;
  noData.erase("data");
  EXPECT_EQ(errorOf([&] { parsePerformanceDataJson(noData, "f.json"); }),
            "f.json: key 'data': missing");
}

TEST_F(ShardMergeTest, AGuardNewerThanTheSavedDataReadsAsNeverBitten) {
  // Saved data of a conftrack from before a guard existed (the fuzz
  // corpus's files predate max_triplets_per_seed) lacks its key: the guard
  // did not exist, so it cut nothing. The others are read as written.
  PerformanceSummary summary = PerformanceCollector(config()).summary();
  StepStats written;
  written.name = "Old";
  for (GuardCount& g : written.guards) {
    g = GuardCount{3, 7};
  }
  summary.data.steps = {written};
  nlohmann::json saved = nlohmann::json::parse(
      makePerformanceDataJson(runMetadata(1), summary).dump());
  nlohmann::json& step = saved["data"]["steps"][0];
  ASSERT_EQ(step["guards"].erase("max_triplets_per_seed"), 1u);
  const SavedPerformance read = parsePerformanceDataJson(saved, "old.json");
  ASSERT_EQ(read.data.steps.size(), 1u);
  const StepStats& s = read.data.steps[0];
  EXPECT_EQ(s.guard(Guard::eTriplets).bites, 0u);
  EXPECT_EQ(s.guard(Guard::eTriplets).cut, 0u);
  EXPECT_EQ(s.guard(Guard::eWindowHits).bites, 3u);
  EXPECT_EQ(s.guard(Guard::eWindowHits).cut, 7u);
  // A guard that is there must be well formed.
  step["guards"]["max_window_hits"] = {3};
  EXPECT_NE(errorOf([&] {
              parsePerformanceDataJson(saved, "old.json");
            }).find("max_window_hits"),
            std::string::npos);
}
}  // namespace
}  // namespace conftrack

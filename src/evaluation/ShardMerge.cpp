#include "conftrack/evaluation/ShardMerge.hpp"

#include "conftrack/core/Error.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace conftrack {

namespace {

/// The first difference between what identifies the run of `a` and `b`
/// ("detector CLICdet, not CLD"); empty if none.
std::string runDifference(const SavedPerformance& a,
                          const SavedPerformance& b) {
  const RunMetadata& x = a.metadata;
  const RunMetadata& y = b.metadata;
  auto differ = [](const std::string& what, const auto& u, const auto& v) {
    std::ostringstream s;
    s << what << " " << v << ", not " << u;
    return s.str();
  };
  if (x.version != y.version) {
    return differ("conftrack version", x.version, y.version);
  }
  if (x.detector != y.detector) {
    return differ("detector", x.detector, y.detector);
  }
  if (x.sample != y.sample) {
    return differ("sample", x.sample, y.sample);
  }
  if (x.overlayBx != y.overlayBx) {
    return differ("overlay of", x.overlayBx, y.overlayBx) + " BX";
  }
  if (x.seed != y.seed) {
    return differ("seed", x.seed, y.seed);
  }
  if (x.events != y.events) {
    return differ("run of", x.events, y.events) + " events";
  }
  if (x.shard.count != y.shard.count) {
    return differ("shard count", x.shard.count, y.shard.count);
  }
  // The settings compared as saved: the same text means the same numbers.
  if (makePerformanceConfigJson(a.config) !=
      makePerformanceConfigJson(b.config)) {
    return "other evaluation settings (key 'config')";
  }
  return {};
}

}  // namespace

SavedPerformance mergeShards(std::vector<ShardInput> shards) {
  if (shards.empty()) {
    throw InputError("merge: no shard results given");
  }
  // Stable: of two copies of a shard, the error names the later one.
  std::stable_sort(shards.begin(), shards.end(),
                   [](const ShardInput& a, const ShardInput& b) {
                     return a.saved.metadata.shard.index <
                            b.saved.metadata.shard.index;
                   });
  const ShardInput& first = shards.front();
  const std::size_t count = first.saved.metadata.shard.count;
  for (std::size_t k = 0; k < shards.size(); ++k) {
    const ShardInput& s = shards[k];
    if (s.saved.metadata.mergedShards > 0) {
      throw InputError(s.source,
                       "already a merge of " +
                           std::to_string(s.saved.metadata.mergedShards) +
                           " shards: merge the shards themselves");
    }
    const std::string difference = runDifference(first.saved, s.saved);
    if (!difference.empty()) {
      throw InputError(s.source, "not a shard of the run of " + first.source +
                                     ": " + difference);
    }
    if (k > 0 && s.saved.metadata.shard.index ==
                     shards[k - 1].saved.metadata.shard.index) {
      throw InputError(s.source,
                       "shard " + std::to_string(s.saved.metadata.shard.index) +
                           " of " + std::to_string(count) + " is also in " +
                           shards[k - 1].source);
    }
  }
  for (std::size_t k = 0; k < count; ++k) {
    if (k >= shards.size() || shards[k].saved.metadata.shard.index != k) {
      throw InputError("merge: shard " + std::to_string(k) + " of " +
                       std::to_string(count) + " of the run of " +
                       first.source + " is missing (run it, then merge again)");
    }
  }
  // The shards must tile the run's events in order: each starts where the
  // previous one ended.
  std::uint64_t nextEvent = 0;
  for (const ShardInput& s : shards) {
    if (s.saved.metadata.shard.firstEvent != nextEvent) {
      throw InputError(s.source,
                       "shard starts at event index " +
                           std::to_string(s.saved.metadata.shard.firstEvent) +
                           ", expected " + std::to_string(nextEvent));
    }
    nextEvent += s.saved.data.events;
  }
  if (first.saved.metadata.events > 0 &&
      nextEvent != first.saved.metadata.events) {
    throw InputError("merge: the shards of " + first.source + " hold " +
                     std::to_string(nextEvent) + " events, the run has " +
                     std::to_string(first.saved.metadata.events));
  }

  SavedPerformance merged = std::move(shards.front().saved);
  for (std::size_t k = 1; k < shards.size(); ++k) {
    const SavedPerformance& s = shards[k].saved;
    merged.data.merge(s.data);
    if (std::isnan(merged.peakRssMb) || s.peakRssMb > merged.peakRssMb) {
      merged.peakRssMb = s.peakRssMb;
    }
    if (s.metadata.threads != merged.metadata.threads) {
      merged.metadata.threads = 0;
    }
  }
  merged.metadata.shard = RunShard{};
  merged.metadata.mergedShards = count;
  return merged;
}

}  // namespace conftrack

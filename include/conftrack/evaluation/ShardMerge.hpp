#pragma once

/// @file ShardMerge.hpp
/// Merging the saved results of the shards of one run (`--shard K/N`,
/// performance_data.json) into the results of the whole run: every count
/// and histogram bin is the sum over the shards, the residual list is the
/// shards' lists in event order, so that the summary made from the merge is
/// identical to that of one process over the same events. Only the wall
/// times differ: they are summed, and their per-event means are over all
/// events.

#include "conftrack/evaluation/PerformanceDataJson.hpp"

#include <string>
#include <vector>

namespace conftrack {

/// One shard's saved results and where they were read from (for errors).
struct ShardInput {
  SavedPerformance saved;
  std::string source;
};

/// Merges the shards of one run. Throws InputError naming the file when
/// they do not belong together: different version, detector, sample,
/// overlay, seed, event count or evaluation settings; a shard given twice;
/// a shard missing ("shard 2 of 4 is missing"); or event ranges that do
/// not tile the run. The result has shard 0 of 1, mergedShards = number of
/// shards, the largest peak memory, and the shards' thread count (0 if
/// they differ).
SavedPerformance mergeShards(std::vector<ShardInput> shards);

}  // namespace conftrack

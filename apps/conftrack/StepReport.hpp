#pragma once

/// @file StepReport.hpp
/// The finder's per-step statistics on the command line: a table summed
/// over events, and a one-line warning for each event in which a
/// combinatorics guard cut work.

#include "conftrack/reconstruction/finding/StepStats.hpp"

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace conftrack::cli {

/// Adds the steps of one event to `total` (matched by name, in order).
void accumulateSteps(std::vector<StepStats>& total,
                     std::span<const StepStats> event);

/// Prints one row per step: time per event and the counters (totals over
/// `events` events), the guards' counts included.
void printStepTable(std::FILE* out, std::span<const StepStats> steps,
                    std::size_t events);

/// Logs a warning naming `event` and every guard that bit in it (nothing
/// if none did).
void warnIfTruncated(const std::string& event,
                     std::span<const StepStats> steps);

/// Logs (debug level, -vv) the vertex regions of event `event` as "N
/// regions: [lo, hi] ... mm" (0.1 mm precision); nothing for an empty list
/// (no pre-pass in the chain, or none found).
void logVertexRegions(std::uint64_t event,
                      std::span<const std::pair<double, double>> regions);

}  // namespace conftrack::cli

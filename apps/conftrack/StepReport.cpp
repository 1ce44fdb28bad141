#include "StepReport.hpp"

#include "conftrack/core/Log.hpp"

#include <algorithm>
#include <cstdio>

namespace conftrack::cli {

void accumulateSteps(std::vector<StepStats>& total,
                     std::span<const StepStats> event) {
  for (const StepStats& s : event) {
    auto it = std::find_if(total.begin(), total.end(), [&](const StepStats& t) {
      return t.name == s.name;
    });
    if (it == total.end()) {
      total.push_back(s);
    } else {
      *it += s;
    }
  }
}

void printStepTable(std::FILE* out, std::span<const StepStats> steps,
                    std::size_t events) {
  const double n = events > 0 ? static_cast<double>(events) : 1.0;
  std::fprintf(out, "%-12s %10s %9s %11s %10s %10s %9s %9s %9s\n", "step",
               "ms/event", "seeds", "cells", "paths", "candidates", "accepted",
               "extended", "hits used");
  for (const StepStats& s : steps) {
    std::fprintf(out,
                 "%-12s %10.1f %9llu %11llu %10llu %10llu %9llu %9llu %9llu\n",
                 s.name.c_str(), s.milliseconds / n,
                 static_cast<unsigned long long>(s.seeds),
                 static_cast<unsigned long long>(s.cells),
                 static_cast<unsigned long long>(s.paths),
                 static_cast<unsigned long long>(s.candidates),
                 static_cast<unsigned long long>(s.accepted),
                 static_cast<unsigned long long>(s.extendedHits),
                 static_cast<unsigned long long>(s.hitsUsed));
  }
  for (const StepStats& s : steps) {
    for (std::size_t i = 0; i < kGuardCount; ++i) {
      const GuardCount& g = s.guards[i];
      if (g.bites > 0) {
        const auto guard = static_cast<Guard>(i);
        std::fprintf(
            out, "%-12s guard %s: %llu %s cut in %llu %s\n", s.name.c_str(),
            guardKey(guard), static_cast<unsigned long long>(g.cut),
            guardCutUnit(guard), static_cast<unsigned long long>(g.bites),
            guardBiteUnit(guard));
      }
    }
    if (s.droppedTracks > 0) {
      // The shared-hit resolution's, and a step's tracks without an
      // overlap pair (overlap_pair_below_hits).
      std::fprintf(out, "%-12s dropped %llu tracks\n", s.name.c_str(),
                   static_cast<unsigned long long>(s.droppedTracks));
    }
    if (s.cellCacheFlushes > 0) {
      std::fprintf(out,
                   "%-12s cell cache emptied %llu times (max_cached_cells; "
                   "memory bound)\n",
                   s.name.c_str(),
                   static_cast<unsigned long long>(s.cellCacheFlushes));
    }
  }
}

void warnIfTruncated(const std::string& event,
                     std::span<const StepStats> steps) {
  const std::string cut = describeTruncation(steps);
  if (!cut.empty()) {
    CONFTRACK_WARNING(event << ": combinatorics guards truncated the search ("
                            << cut << ")");
  }
}

void logVertexRegions(std::uint64_t event,
                      std::span<const std::pair<double, double>> regions) {
  if (regions.empty() || log::level() > log::Level::eDebug) {
    return;
  }
  std::string text = std::to_string(regions.size()) +
                     (regions.size() == 1 ? " region:" : " regions:");
  char buffer[64];
  for (const auto& [lo, hi] : regions) {
    std::snprintf(buffer, sizeof buffer, " [%.1f, %.1f]", lo, hi);
    text += buffer;
  }
  CONFTRACK_DEBUG("event " << event << ": vertex pre-pass, " << text << " mm");
}

}  // namespace conftrack::cli

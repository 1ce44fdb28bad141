#include "conftrack/reconstruction/finding/StepStats.hpp"

namespace conftrack {

namespace {
struct GuardText {
  const char* key;
  const char* biteUnit;
  const char* cutUnit;
};
constexpr std::array<GuardText, kGuardCount> kGuardTexts{{
    {"max_seed_neighbours", "seeds", "seed cells"},
    {"max_cell_neighbours", "cells", "children"},
    {"max_cells_per_seed", "seeds", "unexpanded cells"},
    {"max_paths_per_seed", "seeds", "leaves reduced to their straightest path"},
    {"max_leaves_per_seed", "seeds", "leaves"},
    {"max_window_hits", "windows", "hits"},
    {"max_cells_per_hit", "steps", "seeds"},
    {"max_triplets_per_seed", "seeds", "triplets not looked at"},
}};
const GuardText& text(Guard g) {
  return kGuardTexts[static_cast<std::size_t>(g)];
}
}  // namespace

const char* guardKey(Guard guard) { return text(guard).key; }
const char* guardBiteUnit(Guard guard) { return text(guard).biteUnit; }
const char* guardCutUnit(Guard guard) { return text(guard).cutUnit; }

bool StepStats::truncated() const {
  for (const GuardCount& g : guards) {
    if (g.bites > 0) {
      return true;
    }
  }
  return false;
}

StepStats& StepStats::operator+=(const StepStats& o) {
  seeds += o.seeds;
  cells += o.cells;
  paths += o.paths;
  candidates += o.candidates;
  accepted += o.accepted;
  extendedHits += o.extendedHits;
  overlapHits += o.overlapHits;
  mergedTracks += o.mergedTracks;
  droppedTracks += o.droppedTracks;
  hitsUsed += o.hitsUsed;
  recovered += o.recovered;
  cellCacheFlushes += o.cellCacheFlushes;
  for (std::size_t i = 0; i < kGuardCount; ++i) {
    guards[i] += o.guards[i];
  }
  milliseconds += o.milliseconds;
  return *this;
}

std::string describeTruncation(std::span<const StepStats> steps) {
  std::string out;
  for (const StepStats& s : steps) {
    std::string step;
    for (std::size_t i = 0; i < kGuardCount; ++i) {
      const GuardCount& g = s.guards[i];
      if (g.bites == 0) {
        continue;
      }
      const auto guard = static_cast<Guard>(i);
      step += (step.empty() ? "" : ", ") + std::string(guardKey(guard)) +
              " cut " + std::to_string(g.cut) + " " + guardCutUnit(guard) +
              " in " + std::to_string(g.bites) + " " + guardBiteUnit(guard);
    }
    if (!step.empty()) {
      out += (out.empty() ? "step " : "; step ") + s.name + ": " + step;
    }
  }
  return out;
}

}  // namespace conftrack

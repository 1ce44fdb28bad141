#pragma once

/// @file StepStats.hpp
/// Counters and time of one finding step, including what the combinatorics
/// guards of the finder (FinderConfig, docs/robustness.md) cut.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace conftrack {

/// The combinatorics guards of the finder. Each bounds one kind of work
/// that otherwise grows with the hit density; the FinderConfig field and
/// chain key are named in guardKey().
enum class Guard : std::uint8_t {
  eSeedNeighbours,  ///< seed cells per seed hit (max_seed_neighbours)
  eCellNeighbours,  ///< children per cell (max_cell_neighbours)
  eCellsPerSeed,    ///< cells of one seed's automaton (max_cells_per_seed)
  ePathsPerSeed,    ///< paths enumerated per seed (max_paths_per_seed)
  eLeavesPerSeed,   ///< path ends evaluated per seed (max_leaves_per_seed)
  eWindowHits,      ///< hits examined per extension window (max_window_hits)
  eCellsPerHit,     ///< cells of a build step per hit (max_cells_per_hit)
  eTriplets,        ///< triplets followed per seed (max_triplets_per_seed)
};
inline constexpr std::size_t kGuardCount = 8;

/// The chain key of a guard ("max_cell_neighbours").
const char* guardKey(Guard guard);
/// What a bite of the guard is counted per ("seeds", "cells", "windows").
const char* guardBiteUnit(Guard guard);
/// What the guard cuts ("seed cells", "children", "hits").
const char* guardCutUnit(Guard guard);

/// How often a guard bit and how much it cut.
struct GuardCount {
  std::uint64_t bites = 0;  ///< searches, seeds or cells it truncated
  std::uint64_t cut = 0;    ///< items dropped (or left unexpanded)

  void add(std::uint64_t dropped) {
    ++bites;
    cut += dropped;
  }
  GuardCount& operator+=(const GuardCount& o) {
    bites += o.bites;
    cut += o.cut;
    return *this;
  }
};

/// Counters and time of one finding step (instrumentation).
struct StepStats {
  std::string name;
  std::uint64_t seeds = 0;          ///< seed hits processed
  std::uint64_t cells = 0;          ///< cells created
  std::uint64_t paths = 0;          ///< paths enumerated
  std::uint64_t candidates = 0;     ///< candidates passing the chi2 cuts
  std::uint64_t accepted = 0;       ///< tracks added (net of clones)
  std::uint64_t extendedHits = 0;   ///< hits added by extensions
  std::uint64_t overlapHits = 0;    ///< overlap hits added (OverlapHits)
  std::uint64_t mergedTracks = 0;   ///< tracks merged into another
  std::uint64_t droppedTracks = 0;  ///< tracks dropped (shared hits)
  std::uint64_t hitsUsed = 0;       ///< hits marked used at the end of step
  std::uint64_t recovered = 0;      ///< candidates saved by the recovery
  /// Times the step's cell cache was emptied at FinderConfig::
  /// maxCachedCells (memory bound, FindingChain.hpp).
  std::uint64_t cellCacheFlushes = 0;
  /// Per Guard: how often it bit in this step and what it cut.
  std::array<GuardCount, kGuardCount> guards{};
  double milliseconds = 0.0;

  GuardCount& guard(Guard g) { return guards[static_cast<std::size_t>(g)]; }
  const GuardCount& guard(Guard g) const {
    return guards[static_cast<std::size_t>(g)];
  }
  /// True if any guard bit.
  bool truncated() const;

  StepStats& operator+=(const StepStats& o);
};

/// One line naming every guard that bit in `steps` (one event): "step
/// PixelPrompt: max_cell_neighbours cut 1234 children in 56 cells; ...".
/// Empty if none bit.
std::string describeTruncation(std::span<const StepStats> steps);

}  // namespace conftrack

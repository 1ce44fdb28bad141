// BuildNewTracks of conformal tracking (upstream.md 5, 6, 8; paper 4.1.1):
// per seed hit, a forward cellular automaton of cells (segments between
// hits) in the conformal plane, then paths from the leaf cells back to the
// seed, fits, chi2 cuts and the clone treatment.
//
// Differences from upstream, each for a reason given in upstream.md 14:
// - angles between cells from direction vectors (no NaN for vertical
//   cells; kinks that reverse direction are rejected);
// - the longitudinal angle between cells is taken in (s, z), s the
//   transverse arc length, where a helix is a straight line; upstream's
//   (z, R) chords bend at low pT by more than the cut (makeCell);
// - paths are enumerated from leaf cells only; every shorter upstream path
//   is a prefix of a leaf path, so failing leaf paths are truncated from
//   the far end down to min_hits instead (same candidates, no repeats);
// - the enumeration is bounded per seed (maxPathsPerSeed); beyond it each
//   remaining leaf contributes its straightest path (graceful degradation
//   instead of upstream's TooManyTracks abort of the step);
// - the combinatorics guards of FinderConfig (seed cells per seed, children
//   per cell, cells, paths and leaves per seed) bound the work per seed at
//   any hit density; each cuts by the order of the searches (nearest
//   first) or of the leaves (longest first) and is counted in StepStats;
// - a seed that is already on a track accepted in this step is skipped: its
//   candidates would be subsets of that track and lose the clone treatment;
// - a candidate is compared with the clones accepted earlier in the step
//   as they were built, before their completion added hits (compared with
//   the completed track, the seed visited first won a tie of two clones
//   whatever their chi2: docs/algorithm.md 3.3);
// - the children of a cell depend only on the cell (its end hit and
//   direction fix the search window) and the used flags, which change
//   during a build only where the completion of a new track claims hits.
//   So cells and their children are computed once per step and shared by
//   all seeds; a seed's automaton is the subgraph reachable from its seed
//   cells, the cells upstream rebuilds for it (but for hits claimed by
//   completions since the cells were made), at the cost of an integer
//   graph traversal. The cache is emptied when it grows beyond
//   FinderConfig::maxCachedCells (memory bound): cells made again after
//   that see the claims made since, so where the bound acts the results
//   can differ slightly from those of an unbounded cache.
//
// The automaton is in SeedAutomaton.hpp (cells: SeedAutomaton.cpp; paths:
// SeedPaths.cpp); this file runs it over the seeds of a step.

#include "conftrack/reconstruction/finding/detail/SeedAutomaton.hpp"

#include <algorithm>
#include <vector>

namespace conftrack::detail {

namespace {
/// Dead (clone) tracks tolerated in the list before it is compacted.
constexpr std::size_t kCompactAfter = 4096;

/// Releases the hits that the completion (inward extension, hole filling)
/// of the tracks the last accepted candidate replaced as clones had
/// claimed, where no live track holds them. Otherwise they stay used but on
/// no track: the new track, built from nearly the same hits, cannot take
/// them, nor can the overlap search after the step (on TrackML, 85 such
/// hits per event after the first step, most of them the second hit of a
/// layer the new track crosses).
void releaseHitsOfClones(FinderState& state) {
  for (std::uint32_t k : state.clones.killed()) {
    for (ConfIndex h : state.tracks[k].hits) {
      if (state.used[h] != 0 && !state.clones.held(h, state.tracks)) {
        state.used[h] = 0;
      }
    }
  }
}
}  // namespace

void buildTracks(FinderState& state, const FindingStep& step,
                 std::uint16_t stepIndex, const HitPool& pool,
                 StepStats& stats) {
  SeedAutomaton automaton(state, step, pool, stats);
  std::vector<ConfIndex> seeds = pool.members();  // innermost first
  if (!step.seedCollections.empty()) {
    std::erase_if(seeds, [&](ConfIndex h) {
      return std::find(step.seedCollections.begin(), step.seedCollections.end(),
                       state.hits.subdetector[h]) == step.seedCollections.end();
    });
  }
  if (step.direction == SearchDirection::eOutsideIn) {
    std::reverse(seeds.begin(), seeds.end());
  }
  // Hits on tracks accepted in this step (they stay unused until the end
  // of the step, as upstream, so candidates may share them).
  std::vector<std::uint8_t> onNewTrack(state.hits.size(), 0);
  const std::size_t firstNew = state.tracks.size();
  std::vector<TrackCandidate> candidates;
  const double cellBudget =
      double(state.config.cellsPerHitOf(step)) * double(pool.members().size());
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    const ConfIndex seed = seeds[k];
    if (state.used[seed] != 0 || onNewTrack[seed] != 0) {
      continue;
    }
    if (double(stats.cells) > cellBudget) {
      // The step's work budget is spent: the remaining seeds are skipped.
      std::uint64_t skipped = 0;
      for (std::size_t j = k; j < seeds.size(); ++j) {
        skipped += state.used[seeds[j]] == 0 && onNewTrack[seeds[j]] == 0;
      }
      stats.guard(Guard::eCellsPerHit).add(skipped);
      break;
    }
    // Candidates replaced as clones stay in the list until compacted: in a
    // dense event most accepted candidates are replaced later, and keeping
    // them all made the memory grow with the number of candidates. The
    // tracks of earlier steps are never clones of new ones (their hits are
    // used), so they keep their places before firstNew.
    if (state.clones.dead() >
        std::max<std::size_t>(kCompactAfter, state.tracks.size() / 2)) {
      state.compact();
    }
    ++stats.seeds;
    candidates.clear();
    automaton.run(seed, candidates);
    std::sort(candidates.begin(), candidates.end(), betterCandidate);
    for (TrackCandidate& c : candidates) {
      c.step = stepIndex;
      // The clone treatment compares this step's candidates as built
      // (CloneIndex::offer), not after the completion of the earlier one.
      c.builtHits = c.hits.size();
      c.builtQuality = c.quality();
      if (state.clones.offer(state.tracks, std::move(c),
                             state.config.cloneSharedHits)) {
        auto t = static_cast<std::uint32_t>(state.tracks.size() - 1);
        releaseHitsOfClones(state);
        completeTrack(state, step, pool, stats, t);
        for (ConfIndex h : state.tracks[t].hits) {
          onNewTrack[h] = 1;
        }
      }
    }
  }
  for (std::size_t t = firstNew; t < state.tracks.size(); ++t) {
    stats.accepted += state.tracks[t].alive ? 1 : 0;
    state.tracks[t].builtHits = 0;  // later stages compare the tracks
  }
}

}  // namespace conftrack::detail

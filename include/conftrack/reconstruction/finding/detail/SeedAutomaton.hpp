#pragma once

/// @file SeedAutomaton.hpp
/// The cellular automaton of a build step (internal; BuildTracks.cpp
/// describes the algorithm): cells and their children, cached for the
/// whole step (SeedAutomaton.cpp), and per seed the subgraph of cells
/// reachable from its seed cells, whose paths become candidates
/// (SeedPaths.cpp).

#include "conftrack/reconstruction/finding/detail/CellIds.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace conftrack::detail {

/// A segment between two hits in the conformal plane.
struct Cell {
  ConfIndex start;
  ConfIndex end;
  double du, dv;  // unit direction in (u, v)
  double dz, ds;  // unit direction in (s, z), s the transverse arc length
};

/// The automaton of one build step, run once per seed hit.
class SeedAutomaton {
 public:
  SeedAutomaton(FinderState& state, const FindingStep& step,
                const HitPool& pool, StepStats& stats)
      : m_state(state),
        m_hits(state.hits),
        m_step(step),
        m_pool(pool),
        m_stats(stats),
        m_insideOut(step.direction == SearchDirection::eInsideOut),
        m_cosCellAngle(std::cos(step.maxCellAngle)),
        m_cosCellAngleRZ(std::cos(step.maxCellAngleRZ)),
        m_zWindows(std::isfinite(step.vertexWindow)
                       ? ZWindows(state.stepVertexRegions, 0.0)
                       : ZWindows()) {}

  /// Runs the automaton for one seed; appends passing candidates.
  void run(ConfIndex seed, std::vector<TrackCandidate>& candidates);

 private:
  static constexpr std::uint32_t kNotExpanded =
      std::numeric_limits<std::uint32_t>::max();

  bool acceptNeighbour(ConfIndex from, ConfIndex n) const;

  Cell makeCell(ConfIndex a, ConfIndex b) const;

  bool anglesPass(const Cell& parent, const Cell& child) const;

  /// Transverse arc length from the origin to radius r < 1 / k on a circle
  /// through the origin with curvature 2k (k = 1 / (2 Rc)).
  static double arcLength(double r, double k);

  /// Arc lengths from the origin of hits a and b along the circle through
  /// the origin and both (a prompt track's; l: their conformal distance),
  /// or their radii where that circle cannot reach them.
  std::pair<double, double> promptArcs(ConfIndex a, ConfIndex b,
                                       double l) const;

  static std::uint64_t key(ConfIndex a, ConfIndex b) {
    return (static_cast<std::uint64_t>(a) << 32) | b;
  }

  /// The step-wide cells (a -> b) for every b in `ends`, created on first
  /// use, appended to `out`.
  void cellsOf(ConfIndex a, const std::vector<ConfIndex>& ends,
               std::vector<std::uint32_t>& out);

  /// Empties the step's cell cache (FinderConfig::maxCachedCells), giving
  /// its memory back.
  void flushCache();

  /// Children of cell c: cells (end -> n) with n in the search window
  /// around the "virtual hit" on the cell's prolongation (upstream.md 4)
  /// that pass the angle cuts. Computed once per step.
  void expand(std::uint32_t c);

  /// The cuts on a seed cell (seed -> n).
  bool seedCellPasses(ConfIndex seed, ConfIndex n) const;

  /// z at the beam line of the prompt track through hits a and b: their
  /// (s, z) line at s = 0, s the arc length along the circle through the
  /// origin and both hits (the (R, z) chord where that circle cannot reach
  /// them), and the lever arm of that extrapolation (inner s over the
  /// cells' ds). False if there is none (equal s) or the circle bends
  /// beyond kMaxSeedArcRatio between the hits.
  bool seedCellZ0(ConfIndex a, ConfIndex b, double& z0, double& lever) const;

  /// With a z0 cut, the seed cells lie in the (z, R) cone with apex at the
  /// seed spanned by the lines from (-z0max, 0) and (+z0max, 0) through it
  /// (outwards; inwards the opposite cone), those z0 moved away from the
  /// seed's z by kMaxSeedArcRatio - 1 times their distance (the arc's
  /// chords are steeper than its (s, z) line). Returns false without a
  /// cut.
  bool seedRzCone(ConfIndex seed, HitPool::RzCone& cone) const;

  void seedCells(ConfIndex seed);

  /// The seed's automaton: all cells reachable from its seed cells.
  void collectSubgraph();

  void extractPaths(std::vector<TrackCandidate>& candidates);

  /// Cell of local index i in the current subgraph.
  const Cell& cell(std::uint32_t i) const { return m_cells[m_sub[i]]; }

  /// Depth-first enumeration of all paths from `leaf` back to seed cells,
  /// at most `budget` of them; returns false if the budget cut it short.
  bool enumerate(std::uint32_t leaf, std::uint32_t& budget,
                 std::vector<TrackCandidate>& candidates);

  /// The path that always continues with the parent of smallest kink.
  void straightestPath(std::uint32_t leaf,
                       std::vector<TrackCandidate>& candidates);

  /// m_path: cells from the seed cell to the leaf.
  void evaluate(std::vector<TrackCandidate>& candidates);

  /// Remove-one-hit-and-refit recovery (paper 4.1.1): the best candidate
  /// with one hit removed, if it passes the cuts.
  bool recover(const std::vector<ConfIndex>& hits,
               std::vector<TrackCandidate>& candidates);

  FinderState& m_state;
  const ConformalHits& m_hits;
  const FindingStep& m_step;
  const HitPool& m_pool;
  StepStats& m_stats;
  bool m_insideOut;
  double m_cosCellAngle;
  double m_cosCellAngleRZ;
  /// The event's vertex regions, for the seeds' z0 windows (empty: none).
  ZWindows m_zWindows;
  /// Largest growth of a seed cell's vertex window with its lever arm
  /// (FindingStep::vertexWindow).
  static constexpr double kMaxVertexLever = 10.0;
  /// Largest ratio of a seed cell's (R, z) chord slope to the slope from
  /// its z0 to its hit, ds/dR over s/R (>= 1: s(R) is convex): 2 is
  /// reached where the circle has turned by 60 degrees (R = 1.7 times its
  /// radius), beyond any vertex detector for a track above 0.1 GeV in 4 T
  /// (CLICdet: 1.27 at most, at the endcaps' 102 mm) or 0.15 GeV in 2 T
  /// (TrackML pixels: 1.07).
  static constexpr double kMaxSeedArcRatio = 2.0;

  // Step-wide cell graph (children computed once per cell).
  std::vector<Cell> m_cells;
  /// Cell ids by (start hit, end hit).
  CellIds m_cellIds;
  std::vector<std::uint32_t> m_childBegin;
  std::vector<std::uint32_t> m_childCount;
  std::vector<std::uint32_t> m_childPool;
  std::vector<std::uint32_t> m_visit;  // stamp of the last seed that saw it
  std::uint32_t m_stamp = 0;

  // The current seed's subgraph (local indices into m_sub).
  std::vector<std::uint32_t> m_seedCells;
  std::vector<std::uint32_t> m_sub;
  /// Cells m_sub[0, m_expanded) were expanded for the current seed.
  std::size_t m_expanded = 0;
  std::vector<std::uint32_t> m_local;  // global -> local index
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_edges;  // child,
                                                                 // parent
  /// extractPaths(): scratch of the counting sort of m_edges by child.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_sortedEdges;
  std::vector<std::uint32_t> m_edgeSlot;
  std::vector<std::uint32_t> m_weight;
  std::vector<ConfIndex> m_nb;
  std::vector<std::uint32_t> m_parentBegin;
  std::vector<std::uint32_t> m_children;
  std::vector<std::uint32_t> m_order;
  std::vector<std::uint32_t> m_leaves;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_stack;
  std::vector<std::uint32_t> m_path;
  std::vector<ConfIndex> m_chain;  // evaluate(): the path's hits
};

}  // namespace conftrack::detail

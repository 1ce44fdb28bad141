// BuildNewTracks of conformal tracking (algorithm.md 5, 6, 8; paper 4.1.1):
// per seed hit, a forward cellular automaton of cells (segments between
// hits) in the conformal plane, then paths from the leaf cells back to the
// seed, fits, chi2 cuts and the clone treatment.
//
// Differences from upstream, each for a reason given in algorithm.md 14:
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

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

namespace conftrack::detail {

namespace {

struct Cell {
  ConfIndex start;
  ConfIndex end;
  double du, dv;  // unit direction in (u, v)
  double dz, ds;  // unit direction in (s, z), s the transverse arc length
};

/// Cell ids by (start hit, end hit) key: an open-addressing hash table
/// (linear probing, at most half full). The cells leaving a hit grow with
/// the hit density, so a list per start hit, searched linearly, made the
/// look-ups quadratic in it. Ids do not depend on the table's layout.
class CellIds {
 public:
  /// The id stored for `key`, or `id` stored for it now (second: true).
  std::pair<std::uint32_t, bool> insert(std::uint64_t key, std::size_t id) {
    if (2 * (m_size + 1) > m_keys.size()) {
      grow();
    }
    std::size_t i = slot(key);
    while (m_keys[i] != kEmpty) {
      if (m_keys[i] == key) {
        return {m_ids[i], false};
      }
      i = (i + 1) & (m_keys.size() - 1);
    }
    m_keys[i] = key;
    m_ids[i] = static_cast<std::uint32_t>(id);
    ++m_size;
    return {m_ids[i], true};
  }
  /// Forgets every entry and gives the memory back.
  void release() {
    std::vector<std::uint64_t>().swap(m_keys);
    std::vector<std::uint32_t>().swap(m_ids);
    m_size = 0;
  }

 private:
  static constexpr std::uint64_t kEmpty =
      std::numeric_limits<std::uint64_t>::max();
  std::size_t slot(std::uint64_t key) const {
    // Fibonacci hashing: the high bits of the product.
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> m_shift);
  }
  void grow() {
    std::vector<std::uint64_t> keys = std::move(m_keys);
    std::vector<std::uint32_t> ids = std::move(m_ids);
    const std::size_t capacity = keys.empty() ? 1024 : 2 * keys.size();
    m_shift = 64 - std::countr_zero(capacity);
    m_keys.assign(capacity, kEmpty);
    m_ids.assign(capacity, 0);
    m_size = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] != kEmpty) {
        insert(keys[i], ids[i]);
      }
    }
  }
  std::vector<std::uint64_t> m_keys;
  std::vector<std::uint32_t> m_ids;
  std::size_t m_size = 0;
  int m_shift = 64;
};

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
        m_cosCellAngleRZ(std::cos(step.maxCellAngleRZ)) {}

  /// Runs the automaton for one seed; appends passing candidates.
  void run(ConfIndex seed, std::vector<TrackCandidate>& candidates) {
    if (m_cells.size() > m_state.config.maxCachedCells) {
      flushCache();
    }
    ++m_stamp;
    m_sub.clear();
    seedCells(seed);
    collectSubgraph();
    m_stats.cells += m_sub.size();
    extractPaths(candidates);
  }

 private:
  static constexpr std::uint32_t kNotExpanded =
      std::numeric_limits<std::uint32_t>::max();

  bool acceptNeighbour(ConfIndex from, ConfIndex n) const {
    if (n == from || m_state.used[n] != 0 || m_hits.sameLayer(from, n)) {
      return false;
    }
    if (m_hits.isEndcap(from) && m_hits.isEndcap(n) &&
        m_hits.side[from] != m_hits.side[n]) {
      return false;
    }
    return m_insideOut ? m_hits.rc[n] < m_hits.rc[from]
                       : m_hits.rc[n] > m_hits.rc[from];
  }

  Cell makeCell(ConfIndex a, ConfIndex b) const {
    Cell c{a, b, 0, 0, 0, 0};
    double du = m_hits.u[b] - m_hits.u[a];
    double dv = m_hits.v[b] - m_hits.v[a];
    // sqrt rather than hypot: no overflow is possible here, and this is
    // the innermost loop of the automaton.
    double l = std::sqrt(du * du + dv * dv);
    c.du = du / l;
    c.dv = dv / l;
    double dz = m_hits.z[b] - m_hits.z[a];
    // The helix is a straight line in (s, z), not in (R, z): R grows
    // slower than s by cos(psi), sin(psi) = R / (2 Rc), so a 0.2 GeV track
    // in 2 T bends by 0.02 rad in (z, R) across the TrackML pixel barrel.
    // The cell's conformal line lies 1 / (2 Rc) from the origin (circles
    // through the origin), which gives s(R) = 2 Rc asin(R / (2 Rc)).
    // A hit beyond the reach of that circle (R > 2 Rc: a cell of a
    // displaced track, whose conformal image is a circle, not a line)
    // keeps the (z, R) chord.
    const double k =
        std::abs(m_hits.u[a] * m_hits.v[b] - m_hits.u[b] * m_hits.v[a]) / l;
    const double ra = m_hits.radius[a];
    const double rb = m_hits.radius[b];
    const double ds = std::max(ra, rb) * k < 1.0
                          ? arcLength(rb, k) - arcLength(ra, k)
                          : rb - ra;
    const double ls = std::sqrt(dz * dz + ds * ds);
    c.dz = ls > 0.0 ? dz / ls : 0.0;
    c.ds = ls > 0.0 ? ds / ls : 1.0;
    return c;
  }

  bool anglesPass(const Cell& parent, const Cell& child) const {
    // Between unit vectors, angle <= cut is dot >= cos(cut) (cut in
    // [0, pi]).
    return parent.du * child.du + parent.dv * child.dv >= m_cosCellAngle &&
           parent.dz * child.dz + parent.ds * child.ds >= m_cosCellAngleRZ;
  }

  /// Transverse arc length from the origin to radius r < 1 / k on a circle
  /// through the origin with curvature 2k (k = 1 / (2 Rc)).
  static double arcLength(double r, double k) {
    const double x = r * k;
    if (x < 0.3) {
      // asin(x) / x to 3e-5: no asin in the automaton's innermost loop for
      // most cells.
      const double x2 = x * x;
      return r * (1.0 + x2 * (1.0 / 6.0 + x2 * (3.0 / 40.0)));
    }
    return std::asin(x) / k;
  }

  static std::uint64_t key(ConfIndex a, ConfIndex b) {
    return (static_cast<std::uint64_t>(a) << 32) | b;
  }

  /// The step-wide cells (a -> b) for every b in `ends`, created on first
  /// use, appended to `out`.
  void cellsOf(ConfIndex a, const std::vector<ConfIndex>& ends,
               std::vector<std::uint32_t>& out) {
    for (ConfIndex b : ends) {
      auto [id, inserted] = m_cellIds.insert(key(a, b), m_cells.size());
      if (inserted) {
        m_cells.push_back(makeCell(a, b));
        m_childBegin.push_back(kNotExpanded);
        m_childCount.push_back(0);
        m_visit.push_back(0);
        m_local.push_back(0);
      }
      out.push_back(id);
    }
  }

  /// Empties the step's cell cache (FinderConfig::maxCachedCells), giving
  /// its memory back.
  void flushCache() {
    m_cellIds.release();
    for (auto* v :
         {&m_childBegin, &m_childCount, &m_childPool, &m_visit, &m_local}) {
      std::vector<std::uint32_t>().swap(*v);
    }
    std::vector<Cell>().swap(m_cells);
    ++m_stats.cellCacheFlushes;
  }

  /// Children of cell c: cells (end -> n) with n in the search window
  /// around the "virtual hit" on the cell's prolongation (algorithm.md 4)
  /// that pass the angle cuts. Computed once per step.
  void expand(std::uint32_t c) {
    if (m_childBegin[c] != kNotExpanded) {
      return;
    }
    const Cell parent = m_cells[c];
    ConfIndex last = parent.end;
    double d = m_step.maxDistance;
    if (m_insideOut && d > m_hits.rc[last]) {
      d = 1.2 * m_hits.rc[last];
    }
    double cu = m_hits.u[last] + 0.5 * d * parent.du;
    double cv = m_hits.v[last] + 0.5 * d * parent.dv;
    // Only hits inside the (u, v) angle cut can make or link a cell.
    // The neighbour and angle cuts are applied inside the search, before
    // its sort: in a long barrel most hits of the (u, v) cone lie at the
    // wrong z. A cell depends only on its hits, so this is also the test of
    // an existing cell.
    // The search cone is in (z, R), about the parent's chord: wide enough
    // for the angle cut in (s, z) plus the change of bending from parent
    // to child, which is below the parent's own bending for cells of
    // similar length (with 3x instead of 1.5x the default run finds the
    // same tracks, 3 % slower).
    const double dz = m_hits.z[last] - m_hits.z[parent.start];
    const double dr = m_hits.radius[last] - m_hits.radius[parent.start];
    const double lr = std::sqrt(dz * dz + dr * dr);
    const double rz = lr > 0.0 ? dz / lr : 0.0;
    const double rr = lr > 0.0 ? dr / lr : 1.0;
    const double bend = angleBetween(rz, rr, parent.dz, parent.ds);
    const HitPool::RzCone rzCone{
        m_hits.z[last], m_hits.radius[last], rz, rr,
        std::min(1.5, m_step.maxCellAngleRZ + 1.5 * bend)};
    m_pool.cone(
        m_hits.u[last], m_hits.v[last], parent.du, parent.dv,
        m_step.maxCellAngle, cu, cv, 0.625 * d, m_nb,
        [&](ConfIndex n) {
          return acceptNeighbour(last, n) &&
                 anglesPass(parent, makeCell(last, n));
        },
        &rzCone);
    const std::uint32_t maxChildren = m_state.config.maxCellNeighbours;
    if (m_nb.size() > maxChildren) {
      m_stats.guard(Guard::eCellNeighbours).add(m_nb.size() - maxChildren);
      m_nb.resize(maxChildren);
    }
    m_children.clear();
    cellsOf(last, m_nb, m_children);
    m_childBegin[c] = static_cast<std::uint32_t>(m_childPool.size());
    m_childCount[c] = static_cast<std::uint32_t>(m_children.size());
    m_childPool.insert(m_childPool.end(), m_children.begin(), m_children.end());
  }

  /// The cuts on a seed cell (seed -> n).
  bool seedCellPasses(ConfIndex seed, ConfIndex n) const {
    if (!acceptNeighbour(seed, n)) {
      return false;
    }
    const double dx = m_hits.x[n] - m_hits.x[seed];
    const double dy = m_hits.y[n] - m_hits.y[seed];
    double dxy = std::sqrt(dx * dx + dy * dy);
    double dz = std::abs(m_hits.z[n] - m_hits.z[seed]);
    if (dz > m_step.slopeZRange * dxy) {
      return false;
    }
    if (m_step.maxSeedZ0 < std::numeric_limits<double>::infinity()) {
      // z of the cell's (R, z) line at R = 0: |z_s - dz/dR R_s| <= cut,
      // multiplied out (no division for equal radii).
      double dr = m_hits.radius[n] - m_hits.radius[seed];
      double zr = m_hits.z[seed] * dr -
                  (m_hits.z[n] - m_hits.z[seed]) * m_hits.radius[seed];
      if (std::abs(zr) > m_step.maxSeedZ0 * std::abs(dr)) {
        return false;
      }
    }
    const double du = m_hits.u[n] - m_hits.u[seed];
    const double dv = m_hits.v[n] - m_hits.v[seed];
    if (du * du + dv * dv > m_step.maxDistance * m_step.maxDistance) {
      return false;
    }
    if (dxy * dxy + dz * dz > m_step.maxSeedLength * m_step.maxSeedLength) {
      return false;
    }
    double dphi = std::abs(m_hits.phi[n] - m_hits.phi[seed]);
    return std::min(dphi, 2.0 * std::numbers::pi - dphi) <=
           m_step.maxSeedDeltaPhi;
  }

  /// With a z0 cut, the seed cells lie in the (z, R) cone with apex at the
  /// seed spanned by the lines from (-z0max, 0) and (+z0max, 0) through it
  /// (outwards; inwards the opposite cone). Returns false without a cut.
  bool seedRzCone(ConfIndex seed, HitPool::RzCone& cone) const {
    if (!(m_step.maxSeedZ0 < std::numeric_limits<double>::infinity())) {
      return false;
    }
    const double zs = m_hits.z[seed];
    const double rs = m_hits.radius[seed];
    const double sign = m_insideOut ? 1.0 : -1.0;
    double az = zs + m_step.maxSeedZ0;
    double ar = rs;
    double an = std::hypot(az, ar);
    double bz = zs - m_step.maxSeedZ0;
    double br = rs;
    double bn = std::hypot(bz, br);
    double cz = az / an + bz / bn;
    double cr = ar / an + br / bn;
    double cn = std::hypot(cz, cr);
    cone = {zs, rs, sign * cz / cn, sign * cr / cn,
            0.5 * std::acos(
                      std::clamp((az * bz + ar * br) / (an * bn), -1.0, 1.0))};
    return true;
  }

  void seedCells(ConfIndex seed) {
    auto passes = [&](ConfIndex n) { return seedCellPasses(seed, n); };
    if (m_step.radialSearch) {
      // Only hits within the seed azimuth cap (and the z0 cone) can make a
      // seed cell: the cuts are applied inside the search, before its sort.
      HitPool::RzCone cone{};
      bool useCone = seedRzCone(seed, cone);
      m_pool.discWindow(m_hits.u[seed], m_hits.v[seed], m_step.maxDistance,
                        m_hits.phi[seed], m_step.maxSeedDeltaPhi, m_nb, passes,
                        useCone ? &cone : nullptr);
    } else {
      m_pool.azimuthWindow(m_hits.phi[seed], m_state.config.thetaRange, m_nb);
      std::erase_if(m_nb, [&](ConfIndex n) { return !passes(n); });
    }
    // The nearest neighbours only (the searches return them nearest
    // first): the seed cells of a fixed window grow with the hit density,
    // these do not.
    if (m_step.maxSeedCells > 0 && m_nb.size() > m_step.maxSeedCells) {
      m_nb.resize(m_step.maxSeedCells);
    }
    const std::uint32_t guard = m_state.config.maxSeedNeighbours;
    if (m_nb.size() > guard) {
      m_stats.guard(Guard::eSeedNeighbours).add(m_nb.size() - guard);
      m_nb.resize(guard);
    }
    m_seedCells.clear();
    cellsOf(seed, m_nb, m_seedCells);
  }

  /// The seed's automaton: all cells reachable from its seed cells.
  void collectSubgraph() {
    m_expanded = 0;
    for (std::uint32_t c : m_seedCells) {
      if (m_visit[c] != m_stamp) {
        m_visit[c] = m_stamp;
        m_sub.push_back(c);
      }
    }
    for (std::size_t i = 0; i < m_sub.size(); ++i) {
      std::uint32_t c = m_sub[i];
      expand(c);
      for (std::uint32_t k = 0; k < m_childCount[c]; ++k) {
        std::uint32_t child = m_childPool[m_childBegin[c] + k];
        if (m_visit[child] == m_stamp) {
          continue;
        }
        if (m_sub.size() >= m_state.config.maxCellsPerSeed) {
          // The cells after i stay unexpanded (leaves of the paths).
          m_expanded = i + 1;
          m_stats.guard(Guard::eCellsPerSeed).add(m_sub.size() - m_expanded);
          return;
        }
        m_visit[child] = m_stamp;
        m_sub.push_back(child);
      }
    }
    m_expanded = m_sub.size();
  }

  void extractPaths(std::vector<TrackCandidate>& candidates) {
    const std::size_t n = m_sub.size();
    if (n == 0) {
      return;
    }
    // Local numbering of the subgraph; edges (child, parent) inside it.
    for (std::uint32_t i = 0; i < n; ++i) {
      m_local[m_sub[i]] = i;
    }
    m_edges.clear();
    m_children.assign(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      std::uint32_t c = m_sub[i];
      if (i >= m_expanded) {
        // Cut off by the cell cap: a leaf, even if another seed expanded
        // the cell (the result must not depend on the cache's history).
        continue;
      }
      for (std::uint32_t k = 0; k < m_childCount[c]; ++k) {
        std::uint32_t child = m_childPool[m_childBegin[c] + k];
        if (m_visit[child] == m_stamp) {
          m_edges.emplace_back(m_local[child], i);
          ++m_children[i];
        }
      }
    }
    // Parents in CSR form.
    std::sort(m_edges.begin(), m_edges.end());
    m_parentBegin.assign(n + 1, 0);
    for (const auto& e : m_edges) {
      ++m_parentBegin[e.first + 1];
    }
    std::partial_sum(m_parentBegin.begin(), m_parentBegin.end(),
                     m_parentBegin.begin());
    // Weights: longest chain from a seed cell. Parents start further from
    // the seed's opposite end, so ordering cells by the conformal-hit index
    // of their start hit is a topological order.
    m_order.resize(n);
    std::iota(m_order.begin(), m_order.end(), 0);
    std::sort(m_order.begin(), m_order.end(),
              [&](std::uint32_t a, std::uint32_t b) {
                ConfIndex sa = cell(a).start;
                ConfIndex sb = cell(b).start;
                if (sa != sb) {
                  return m_insideOut ? sa < sb : sa > sb;
                }
                return a < b;
              });
    m_weight.assign(n, 0);
    for (std::uint32_t c : m_order) {
      std::uint32_t w = 0;
      for (std::uint32_t k = m_parentBegin[c]; k < m_parentBegin[c + 1]; ++k) {
        w = std::max(w, m_weight[m_edges[k].second] + 1);
      }
      m_weight[c] = w;
    }
    const std::uint32_t minWeight =
        m_step.minHits >= 2 ? m_step.minHits - 2 : 0;
    m_leaves.clear();
    for (std::uint32_t c = 0; c < n; ++c) {
      if (m_children[c] == 0 && m_weight[c] >= minWeight) {
        m_leaves.push_back(c);
      }
    }
    std::sort(m_leaves.begin(), m_leaves.end(),
              [&](std::uint32_t a, std::uint32_t b) {
                if (m_weight[a] != m_weight[b]) {
                  return m_weight[a] > m_weight[b];
                }
                return key(cell(a).start, cell(a).end) <
                       key(cell(b).start, cell(b).end);
              });
    const std::uint32_t maxLeaves = m_state.config.maxLeavesPerSeed;
    if (m_leaves.size() > maxLeaves) {
      m_stats.guard(Guard::eLeavesPerSeed).add(m_leaves.size() - maxLeaves);
      m_leaves.resize(maxLeaves);
    }
    // The step's own path limit is a setting; only the guard's is counted.
    const std::uint32_t guardPaths = m_state.config.maxPathsPerSeed;
    const bool guardBinds =
        m_step.maxPaths == 0 || guardPaths < m_step.maxPaths;
    std::uint32_t budget = guardBinds ? guardPaths : m_step.maxPaths;
    std::uint64_t reduced = 0;
    for (std::uint32_t leaf : m_leaves) {
      if (budget > 0) {
        reduced += enumerate(leaf, budget, candidates) ? 0 : 1;
      } else {
        straightestPath(leaf, candidates);
        ++reduced;
      }
    }
    if (reduced > 0 && guardBinds) {
      m_stats.guard(Guard::ePathsPerSeed).add(reduced);
    }
  }

  /// Cell of local index i in the current subgraph.
  const Cell& cell(std::uint32_t i) const { return m_cells[m_sub[i]]; }

  /// Depth-first enumeration of all paths from `leaf` back to seed cells,
  /// at most `budget` of them; returns false if the budget cut it short.
  bool enumerate(std::uint32_t leaf, std::uint32_t& budget,
                 std::vector<TrackCandidate>& candidates) {
    // Stack of (cell, next parent slot).
    m_stack.clear();
    m_stack.emplace_back(leaf, m_parentBegin[leaf]);
    while (!m_stack.empty() && budget > 0) {
      auto& [cell, slot] = m_stack.back();
      if (m_parentBegin[cell] == m_parentBegin[cell + 1]) {
        // A seed cell: the stack holds a complete path.
        m_path.clear();
        for (auto it = m_stack.rbegin(); it != m_stack.rend(); ++it) {
          m_path.push_back(it->first);
        }
        --budget;
        evaluate(candidates);
        m_stack.pop_back();
        continue;
      }
      if (slot == m_parentBegin[cell + 1]) {
        m_stack.pop_back();
        continue;
      }
      std::uint32_t parent = m_edges[slot].second;
      ++slot;
      m_stack.emplace_back(parent, m_parentBegin[parent]);
    }
    // Complete if no cell left on the stack has a parent still to follow.
    return std::all_of(m_stack.begin(), m_stack.end(), [&](const auto& e) {
      return e.second == m_parentBegin[e.first + 1];
    });
  }

  /// The path that always continues with the parent of smallest kink.
  void straightestPath(std::uint32_t leaf,
                       std::vector<TrackCandidate>& candidates) {
    m_path.clear();
    std::uint32_t c = leaf;
    m_path.push_back(c);
    while (m_parentBegin[c] != m_parentBegin[c + 1]) {
      std::uint32_t best = m_edges[m_parentBegin[c]].second;
      double bestAngle = 10.0;
      for (std::uint32_t k = m_parentBegin[c]; k < m_parentBegin[c + 1]; ++k) {
        const Cell& p = cell(m_edges[k].second);
        double a = angleBetween(p.du, p.dv, cell(c).du, cell(c).dv);
        if (a < bestAngle) {
          bestAngle = a;
          best = m_edges[k].second;
        }
      }
      c = best;
      m_path.push_back(c);
    }
    std::reverse(m_path.begin(), m_path.end());
    evaluate(candidates);
  }

  /// m_path: cells from the seed cell to the leaf.
  void evaluate(std::vector<TrackCandidate>& candidates) {
    ++m_stats.paths;
    // Hits in seed-to-leaf order.
    std::vector<ConfIndex> chain;
    chain.reserve(m_path.size() + 1);
    chain.push_back(cell(m_path.front()).start);
    for (std::uint32_t c : m_path) {
      chain.push_back(cell(c).end);
    }
    const std::size_t minHits = m_step.minHits;
    TrackCandidate cand;
    cand.fitBackward = m_step.fitBackward;
    for (std::size_t len = chain.size(); len >= minHits; --len) {
      std::vector<ConfIndex> hits(chain.begin(),
                                  chain.begin() + static_cast<long>(len));
      if (!m_insideOut) {
        // Fits and extensions work along the particle's path: inner first.
        std::reverse(hits.begin(), hits.end());
      }
      if (fitCandidate(m_state, m_step, hits, cand)) {
        candidates.push_back(std::move(cand));
        ++m_stats.candidates;
        return;
      }
      if (len == chain.size() && m_step.recovery && recover(hits, candidates)) {
        return;
      }
    }
  }

  /// Remove-one-hit-and-refit recovery (paper 4.1.1): the best candidate
  /// with one hit removed, if it passes the cuts.
  bool recover(const std::vector<ConfIndex>& hits,
               std::vector<TrackCandidate>& candidates) {
    if (hits.size() <= m_step.minHits) {
      return false;
    }
    TrackCandidate best;
    bool found = false;
    for (std::size_t skip = 0; skip < hits.size(); ++skip) {
      std::vector<ConfIndex> reduced;
      reduced.reserve(hits.size() - 1);
      for (std::size_t k = 0; k < hits.size(); ++k) {
        if (k != skip) {
          reduced.push_back(hits[k]);
        }
      }
      TrackCandidate cand;
      cand.fitBackward = m_step.fitBackward;
      if (fitCandidate(m_state, m_step, std::move(reduced), cand) &&
          (!found || betterCandidate(cand, best))) {
        best = std::move(cand);
        found = true;
      }
    }
    if (found) {
      candidates.push_back(std::move(best));
      ++m_stats.candidates;
      ++m_stats.recovered;
    }
    return found;
  }

  FinderState& m_state;
  const ConformalHits& m_hits;
  const FindingStep& m_step;
  const HitPool& m_pool;
  StepStats& m_stats;
  bool m_insideOut;
  double m_cosCellAngle;
  double m_cosCellAngleRZ;
  // Step-wide cell graph (children computed once per cell).
  std::vector<Cell> m_cells;
  /// Per start hit: (end hit, cell) of the cells created so far.
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
  std::vector<std::uint32_t> m_weight;
  std::vector<ConfIndex> m_nb;
  std::vector<std::uint32_t> m_parentBegin;
  std::vector<std::uint32_t> m_children;
  std::vector<std::uint32_t> m_order;
  std::vector<std::uint32_t> m_leaves;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_stack;
  std::vector<std::uint32_t> m_path;
};

/// Dead (clone) tracks tolerated in the list before it is compacted.
constexpr std::size_t kCompactAfter = 4096;

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
  for (ConfIndex seed : seeds) {
    if (state.used[seed] != 0 || onNewTrack[seed] != 0) {
      continue;
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
      if (state.clones.offer(state.tracks, std::move(c),
                             state.config.cloneSharedHits)) {
        auto t = static_cast<std::uint32_t>(state.tracks.size() - 1);
        completeTrack(state, step, pool, stats, t);
        for (ConfIndex h : state.tracks[t].hits) {
          onNewTrack[h] = 1;
        }
      }
    }
  }
  for (std::size_t t = firstNew; t < state.tracks.size(); ++t) {
    stats.accepted += state.tracks[t].alive ? 1 : 0;
  }
}

}  // namespace conftrack::detail

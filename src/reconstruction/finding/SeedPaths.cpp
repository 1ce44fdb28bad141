// Paths of a seed's automaton (SeedAutomaton.hpp): longest chains, leaves,
// the bounded enumeration of paths back to the seed cells, their fits and
// the recovery.

#include "conftrack/reconstruction/finding/detail/SeedAutomaton.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace conftrack::detail {

void SeedAutomaton::extractPaths(std::vector<TrackCandidate>& candidates) {
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
  // Parents in CSR form: the edges grouped by child with a counting sort.
  // They were made by ascending parent, and the scatter keeps that order
  // within each child, so the groups are those that sorting the (child,
  // parent) pairs gave, at a fraction of its cost (the sort took 2 % of
  // CLICdet's finding).
  m_parentBegin.assign(n + 1, 0);
  for (const auto& e : m_edges) {
    ++m_parentBegin[e.first + 1];
  }
  std::partial_sum(m_parentBegin.begin(), m_parentBegin.end(),
                   m_parentBegin.begin());
  m_edgeSlot.assign(m_parentBegin.begin(), m_parentBegin.end() - 1);
  m_sortedEdges.resize(m_edges.size());
  for (const auto& e : m_edges) {
    m_sortedEdges[m_edgeSlot[e.first]++] = e;
  }
  m_edges.swap(m_sortedEdges);
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
  const std::uint32_t minWeight = m_step.minHits >= 2 ? m_step.minHits - 2 : 0;
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
  const bool guardBinds = m_step.maxPaths == 0 || guardPaths < m_step.maxPaths;
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

bool SeedAutomaton::enumerate(std::uint32_t leaf, std::uint32_t& budget,
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

void SeedAutomaton::straightestPath(std::uint32_t leaf,
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

void SeedAutomaton::evaluate(std::vector<TrackCandidate>& candidates) {
  ++m_stats.paths;
  // Hits in seed-to-leaf order.
  std::vector<ConfIndex>& chain = m_chain;
  chain.clear();
  chain.push_back(cell(m_path.front()).start);
  for (std::uint32_t c : m_path) {
    chain.push_back(cell(c).end);
  }
  const std::size_t minHits = m_step.minHits;
  TrackCandidate cand;
  cand.fitBackward = m_step.fitBackward;
  for (std::size_t len = chain.size(); len >= minHits; --len) {
    // The candidate's own buffer, back from the failed fit before (no
    // allocation per shortened path).
    std::vector<ConfIndex> hits = std::move(cand.hits);
    hits.assign(chain.begin(), chain.begin() + static_cast<long>(len));
    if (!m_insideOut) {
      // Fits and extensions work along the particle's path: inner first.
      std::reverse(hits.begin(), hits.end());
    }
    // The hits move into the candidate, and stay there if the fit fails.
    if (fitCandidate(m_state, m_step, std::move(hits), cand)) {
      candidates.push_back(std::move(cand));
      ++m_stats.candidates;
      return;
    }
    if (len == chain.size() && m_step.recovery &&
        recover(cand.hits, candidates)) {
      return;
    }
  }
}

bool SeedAutomaton::recover(const std::vector<ConfIndex>& hits,
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

}  // namespace conftrack::detail

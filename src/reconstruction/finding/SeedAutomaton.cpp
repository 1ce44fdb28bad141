// The cell graph of a build step (SeedAutomaton.hpp): seed cells, cells and
// their children, cached for the step, and the subgraph of one seed.

#include "conftrack/reconstruction/finding/detail/SeedAutomaton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack::detail {

void SeedAutomaton::run(ConfIndex seed,
                        std::vector<TrackCandidate>& candidates) {
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

bool SeedAutomaton::acceptNeighbour(ConfIndex from, ConfIndex n) const {
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

Cell SeedAutomaton::makeCell(ConfIndex a, ConfIndex b) const {
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
  const auto [sa, sb] = promptArcs(a, b, l);
  const double ds = sb - sa;
  const double ls = std::sqrt(dz * dz + ds * ds);
  c.dz = ls > 0.0 ? dz / ls : 0.0;
  c.ds = ls > 0.0 ? ds / ls : 1.0;
  return c;
}

bool SeedAutomaton::anglesPass(const Cell& parent, const Cell& child) const {
  // Between unit vectors, angle <= cut is dot >= cos(cut) (cut in
  // [0, pi]).
  return parent.du * child.du + parent.dv * child.dv >= m_cosCellAngle &&
         parent.dz * child.dz + parent.ds * child.ds >= m_cosCellAngleRZ;
}

std::pair<double, double> SeedAutomaton::promptArcs(ConfIndex a, ConfIndex b,
                                                    double l) const {
  // The cells' conformal line lies 1 / (2 Rc) from the origin (circles
  // through the origin), which gives s(R) = 2 Rc asin(R / (2 Rc)). A hit
  // beyond the reach of that circle (R > 2 Rc: a displaced track's cell,
  // whose conformal image is a circle, not a line) keeps the chord.
  const double k =
      l > 0.0
          ? std::abs(m_hits.u[a] * m_hits.v[b] - m_hits.u[b] * m_hits.v[a]) / l
          : 0.0;
  const double ra = m_hits.radius[a];
  const double rb = m_hits.radius[b];
  if (std::max(ra, rb) * k < 1.0) {
    return {arcLength(ra, k), arcLength(rb, k)};
  }
  return {ra, rb};
}

double SeedAutomaton::arcLength(double r, double k) {
  const double x = r * k;
  if (x < 0.3) {
    // asin(x) / x to 3e-5: no asin in the automaton's innermost loop for
    // most cells.
    const double x2 = x * x;
    return r * (1.0 + x2 * (1.0 / 6.0 + x2 * (3.0 / 40.0)));
  }
  return std::asin(x) / k;
}

void SeedAutomaton::cellsOf(ConfIndex a, const std::vector<ConfIndex>& ends,
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

void SeedAutomaton::flushCache() {
  m_cellIds.release();
  for (auto* v :
       {&m_childBegin, &m_childCount, &m_childPool, &m_visit, &m_local}) {
    std::vector<std::uint32_t>().swap(*v);
  }
  std::vector<Cell>().swap(m_cells);
  ++m_stats.cellCacheFlushes;
}

void SeedAutomaton::expand(std::uint32_t c) {
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
  // The filter captures one pointer: a lambda holding the three it needs
  // would not fit std::function's inline buffer (16 bytes in libstdc++),
  // which then allocated once per expanded cell.
  const struct {
    const SeedAutomaton* self;
    ConfIndex last;
    Cell parent;
  } filter{this, last, parent};
  m_pool.cone(
      m_hits.u[last], m_hits.v[last], parent.du, parent.dv, m_step.maxCellAngle,
      cu, cv, 0.625 * d, m_nb,
      [f = &filter](ConfIndex n) {
        return f->self->acceptNeighbour(f->last, n) &&
               f->self->anglesPass(f->parent, f->self->makeCell(f->last, n));
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

bool SeedAutomaton::seedCellZ0(ConfIndex a, ConfIndex b, double& z0,
                               double& lever) const {
  // Along the prompt circle the helix is straight in z. The (R, z) chord
  // of a low-momentum track curves: its z0 missed the vertex by
  // millimetres to centimetres (CLICdet, 0.1 GeV in 4 T, tan lambda 1,
  // from R = 31 to 58 mm: 1 mm, ten times that for a pair on two disks).
  const double du = m_hits.u[b] - m_hits.u[a];
  const double dv = m_hits.v[b] - m_hits.v[a];
  const auto [sa, sb] = promptArcs(a, b, std::sqrt(du * du + dv * dv));
  const double ds = sb - sa;
  // The arc grows faster than R along the whole circle (s(R) is convex),
  // so the (R, z) chord from a hit to another is steeper than the line
  // from the origin to it by the ratio of the two secants,
  // kMaxSeedArcRatio at most here: seedRzCone() widens its z range by
  // that much.
  const double ra = m_hits.radius[a];
  if (ds == 0.0 || std::abs(ds) * ra > kMaxSeedArcRatio *
                                           std::abs(m_hits.radius[b] - ra) *
                                           sa) {
    return false;
  }
  z0 = m_hits.z[a] - (m_hits.z[b] - m_hits.z[a]) * sa / ds;
  lever = std::min(sa, sb) / std::abs(ds);
  return true;
}

bool SeedAutomaton::seedCellPasses(ConfIndex seed, ConfIndex n) const {
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
  const double du = m_hits.u[n] - m_hits.u[seed];
  const double dv = m_hits.v[n] - m_hits.v[seed];
  if (du * du + dv * dv > m_step.maxDistance * m_step.maxDistance) {
    return false;
  }
  if (dxy * dxy + dz * dz > m_step.maxSeedLength * m_step.maxSeedLength) {
    return false;
  }
  double dphi = std::abs(m_hits.phi[n] - m_hits.phi[seed]);
  if (std::min(dphi, 2.0 * std::numbers::pi - dphi) > m_step.maxSeedDeltaPhi) {
    return false;
  }
  // The z0 cuts last: the arc's z0 costs an arcsine where the others cost
  // a product.
  const bool fixedZ0 =
      m_step.maxSeedZ0 < std::numeric_limits<double>::infinity();
  if (!fixedZ0 && m_zWindows.empty()) {
    return true;
  }
  double z0 = 0.0;
  double lever = 0.0;
  if (!seedCellZ0(seed, n, z0, lever)) {
    return false;
  }
  if (fixedZ0 && std::abs(z0) > m_step.maxSeedZ0) {
    return false;
  }
  // Within the step's window of a vertex region (VertexZPrepass), grown
  // with the cell's lever arm: the error of z0 is that of the cell's
  // slope times the path from the beam line to its inner hit.
  return m_zWindows.empty() ||
         m_zWindows.near(
             z0, std::clamp(lever, 1.0, kMaxVertexLever) * m_step.vertexWindow);
}

bool SeedAutomaton::seedRzCone(ConfIndex seed, HitPool::RzCone& cone) const {
  const bool fixedZ0 =
      m_step.maxSeedZ0 < std::numeric_limits<double>::infinity();
  if (!fixedZ0 && m_zWindows.empty()) {
    return false;
  }
  // The seed cells' lines meet R = 0 within [lo, hi]: the fixed cut and
  // the hull of the vertex windows.
  double lo =
      fixedZ0 ? -m_step.maxSeedZ0 : -std::numeric_limits<double>::infinity();
  double hi =
      fixedZ0 ? m_step.maxSeedZ0 : std::numeric_limits<double>::infinity();
  if (!m_zWindows.empty()) {
    const double grow = kMaxVertexLever * m_step.vertexWindow;
    lo = std::max(lo, m_zWindows.lowest() - grow);
    hi = std::max(lo, std::min(hi, m_zWindows.highest() + grow));
  }
  const double zs = m_hits.z[seed];
  const double rs = m_hits.radius[seed];
  // A seed cell's z0 is taken along the arc (seedCellZ0()); the (R, z)
  // chord to its other hit meets R = 0 at z0 + (z0 - zs) (Q - 1), where Q
  // in [1, kMaxSeedArcRatio] is the ratio of the chord's slope to that of
  // the line from z0 to the seed hit.
  const double beyond = kMaxSeedArcRatio - 1.0;
  lo = std::min(lo, lo + (lo - zs) * beyond);
  hi = std::max(hi, hi + (hi - zs) * beyond);
  const double sign = m_insideOut ? 1.0 : -1.0;
  double az = zs - lo;
  double ar = rs;
  double an = std::hypot(az, ar);
  double bz = zs - hi;
  double br = rs;
  double bn = std::hypot(bz, br);
  double cz = az / an + bz / bn;
  double cr = ar / an + br / bn;
  double cn = std::hypot(cz, cr);
  cone = {
      zs, rs, sign * cz / cn, sign * cr / cn,
      0.5 * std::acos(std::clamp((az * bz + ar * br) / (an * bn), -1.0, 1.0))};
  return true;
}

void SeedAutomaton::seedCells(ConfIndex seed) {
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
    m_pool.azimuthWindow(m_hits.phi[seed], m_state.config.thetaRange, m_nb,
                         passes);
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

void SeedAutomaton::collectSubgraph() {
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

}  // namespace conftrack::detail

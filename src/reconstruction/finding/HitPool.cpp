#include "conftrack/reconstruction/finding/HitPool.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace conftrack {

namespace {
/// nanoflann dataset adaptor over the pool's conformal coordinates.
struct Cloud {
  // The member buffer, not the vector: it survives moving the HitPool.
  const ConformalHits* hits;
  const ConfIndex* members;
  std::size_t size;
  std::size_t kdtree_get_point_count() const { return size; }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    ConfIndex h = members[i];
    return dim == 0 ? hits->u[h] : hits->v[h];
  }
  template <class Box>
  bool kdtree_get_bbox(Box& /*unused*/) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 2, std::uint32_t>;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Appends the entries of a phi-sorted range within the window.
void collectWindow(const std::vector<double>& phis,
                   const std::vector<ConfIndex>& ids, std::size_t begin,
                   std::size_t end, double phi, double halfWidth,
                   std::vector<ConfIndex>& out) {
  auto scan = [&](double lo, double hi) {
    auto first = std::lower_bound(phis.begin() + begin, phis.begin() + end, lo);
    auto last = std::upper_bound(first, phis.begin() + end, hi);
    for (auto it = first; it != last; ++it) {
      out.push_back(ids[it - phis.begin()]);
    }
  };
  if (halfWidth >= std::numbers::pi) {
    scan(-kTwoPi, kTwoPi);
    return;
  }
  double lo = phi - halfWidth;
  double hi = phi + halfWidth;
  scan(std::max(lo, -std::numbers::pi), std::min(hi, std::numbers::pi));
  if (lo < -std::numbers::pi) {
    scan(lo + kTwoPi, std::numbers::pi);
  }
  if (hi > std::numbers::pi) {
    scan(-std::numbers::pi, hi - kTwoPi);
  }
}
}  // namespace

struct HitPool::Tree {
  Cloud cloud;
  KdTree index;
  Tree(const ConformalHits& hits, const std::vector<ConfIndex>& members)
      : cloud{&hits, members.data(), members.size()},
        index(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

HitPool::HitPool(const ConformalHits& hits, std::vector<ConfIndex> members)
    : m_hits(&hits), m_members(std::move(members)) {
  std::sort(m_members.begin(), m_members.end());
  m_members.erase(std::unique(m_members.begin(), m_members.end()),
                  m_members.end());
  m_tree = std::make_unique<Tree>(hits, m_members);
  auto byPhi = [&](ConfIndex a, ConfIndex b) {
    return hits.phi[a] != hits.phi[b] ? hits.phi[a] < hits.phi[b] : a < b;
  };
  m_byPhi = m_members;
  std::sort(m_byPhi.begin(), m_byPhi.end(), byPhi);
  m_phis.reserve(m_byPhi.size());
  for (ConfIndex i : m_byPhi) {
    m_phis.push_back(hits.phi[i]);
  }
  m_layerHits = m_members;
  std::sort(m_layerHits.begin(), m_layerHits.end(),
            [&](ConfIndex a, ConfIndex b) {
              if (hits.layer[a] != hits.layer[b]) {
                return hits.layer[a] < hits.layer[b];
              }
              return byPhi(a, b);
            });
  for (std::uint32_t k = 0; k < m_layerHits.size(); ++k) {
    std::uint32_t l = hits.layer[m_layerHits[k]];
    m_layerPhis.push_back(hits.phi[m_layerHits[k]]);
    if (m_layers.empty() || m_layers.back() != l) {
      m_layers.push_back(l);
      m_layerRange.emplace_back(k, k);
    }
    m_layerRange.back().second = k + 1;
  }
}

HitPool::~HitPool() = default;
HitPool::HitPool(HitPool&&) noexcept = default;
HitPool& HitPool::operator=(HitPool&&) noexcept = default;

void HitPool::disc(double u, double v, double radius,
                   std::vector<ConfIndex>& out) const {
  out.clear();
  if (m_members.empty()) {
    return;
  }
  std::vector<std::pair<std::uint32_t, double>> found;
  const double query[2] = {u, v};
  m_tree->index.radiusSearch(query, radius * radius, found,
                             nanoflann::SearchParams(32, 0.0F, false));
  std::sort(found.begin(), found.end(), [&](const auto& a, const auto& b) {
    return a.second != b.second ? a.second < b.second
                                : m_members[a.first] < m_members[b.first];
  });
  out.reserve(found.size());
  for (const auto& f : found) {
    out.push_back(m_members[f.first]);
  }
}

void HitPool::azimuthWindow(double phi, double halfWidth,
                            std::vector<ConfIndex>& out) const {
  out.clear();
  collectWindow(m_phis, m_byPhi, 0, m_byPhi.size(), phi, halfWidth, out);
  auto dphi = [&](ConfIndex i) {
    double d = std::abs(m_hits->phi[i] - phi);
    return d > std::numbers::pi ? kTwoPi - d : d;
  };
  std::sort(out.begin(), out.end(), [&](ConfIndex a, ConfIndex b) {
    double da = dphi(a);
    double db = dphi(b);
    return da != db ? da < db : a < b;
  });
}

void HitPool::layerWindow(std::uint32_t layer, double phi, double halfWidth,
                          std::vector<ConfIndex>& out) const {
  auto it = std::lower_bound(m_layers.begin(), m_layers.end(), layer);
  if (it == m_layers.end() || *it != layer) {
    return;
  }
  auto [begin, end] = m_layerRange[it - m_layers.begin()];
  std::size_t before = out.size();
  collectWindow(m_layerPhis, m_layerHits, begin, end, phi, halfWidth, out);
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(before), out.end());
}

}  // namespace conftrack

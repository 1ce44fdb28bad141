#include "conftrack/reconstruction/finding/HitPool.hpp"

#include "conftrack/reconstruction/finding/detail/PhiWindow.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <numeric>
#include <optional>

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

}  // namespace

/// The k-d tree of disc(), built on its first search: the shipped chains'
/// seeding bounds its windows in azimuth or z0 and never asks for the
/// whole disc, and the tree cost 1 % of CLICdet's reconstruction, built
/// for every step's pool.
struct HitPool::Tree {
  Cloud cloud;
  std::once_flag built;
  std::optional<KdTree> tree;
  Tree(const ConformalHits& hits, const std::vector<ConfIndex>& members)
      : cloud{&hits, members.data(), members.size()} {}
  const KdTree& index() {
    std::call_once(built, [this] {
      tree.emplace(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    });
    return *tree;
  }
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
  m_phiCells.add(m_phis, 0, static_cast<std::uint32_t>(m_phis.size()));
  // By layer, then as in m_byPhi: a counting sort of m_byPhi by layer,
  // which keeps its order within each layer (the order that sorting by
  // (layer, azimuth, index) gave, without a second sort per pool).
  {
    std::uint32_t nLayers = 0;
    for (ConfIndex i : m_byPhi) {
      nLayers = std::max<std::uint32_t>(nLayers, hits.layer[i] + 1U);
    }
    std::vector<std::uint32_t> slot(nLayers + 1, 0);
    for (ConfIndex i : m_byPhi) {
      ++slot[hits.layer[i] + 1U];
    }
    std::partial_sum(slot.begin(), slot.end(), slot.begin());
    m_layerHits.resize(m_byPhi.size());
    for (ConfIndex i : m_byPhi) {
      m_layerHits[slot[hits.layer[i]]++] = i;
    }
  }
  for (std::uint32_t k = 0; k < m_layerHits.size(); ++k) {
    std::uint32_t l = hits.layer[m_layerHits[k]];
    m_layerPhis.push_back(hits.phi[m_layerHits[k]]);
    double rc = hits.rc[m_layerHits[k]];
    if (m_layers.empty() || m_layers.back() != l) {
      m_layers.push_back(l);
      m_layerRange.emplace_back(k, k);
      m_layerRc.emplace_back(rc, rc);
    }
    m_layerRange.back().second = k + 1;
    m_layerRc.back().first = std::min(m_layerRc.back().first, rc);
    m_layerRc.back().second = std::max(m_layerRc.back().second, rc);
  }
  // Bins along each layer's long coordinate, about kHitsPerBin members
  // each, filled in azimuth order (a counting sort keeps it per bin).
  constexpr std::size_t kHitsPerBin = 32;
  constexpr std::size_t kMaxBins = 256;
  m_binHits.reserve(m_layerHits.size());
  m_binCells.reserve(m_layerHits.size() / kHitsPerBin + m_layers.size(),
                     m_layerHits.size());
  m_binPhis.reserve(m_layerHits.size());
  std::vector<std::uint32_t> binOfHit;
  for (std::size_t k = 0; k < m_layers.size(); ++k) {
    auto [begin, end] = m_layerRange[k];
    LayerBins b;
    b.zMin = b.rMin = std::numeric_limits<double>::infinity();
    b.zMax = b.rMax = -b.zMin;
    for (std::uint32_t i = begin; i < end; ++i) {
      ConfIndex h = m_layerHits[i];
      b.zMin = std::min(b.zMin, hits.z[h]);
      b.zMax = std::max(b.zMax, hits.z[h]);
      b.rMin = std::min(b.rMin, hits.radius[h]);
      b.rMax = std::max(b.rMax, hits.radius[h]);
    }
    // A barrel's hits along z, a disk's along R: the layer's own long
    // coordinate, which callers' boxes bound (a disk's z window lies about
    // its nominal z). Choosing by the hits' spread put the few hits left
    // on a disk along z, and a box about the nominal z then missed those
    // of sensors mounted a few millimetres off it (TrackML strip disks:
    // -5.5 to +3.5 mm).
    b.alongZ = !hits.isEndcap(m_layerHits[begin]);
    b.wMin = b.alongZ ? b.zMin : b.rMin;
    double wMax = b.alongZ ? b.zMax : b.rMax;
    b.nBins = static_cast<std::uint32_t>(
        std::clamp<std::size_t>((end - begin) / kHitsPerBin, 1, kMaxBins));
    b.binWidth = (wMax - b.wMin) / b.nBins;
    if (!(b.binWidth > 0.0)) {
      b.nBins = 1;
    }
    binOfHit.resize(end - begin);
    std::vector<std::uint32_t> count(b.nBins + 1, 0);
    for (std::uint32_t i = begin; i < end; ++i) {
      ConfIndex h = m_layerHits[i];
      binOfHit[i - begin] = b.binOf(b.alongZ ? hits.z[h] : hits.radius[h]);
      ++count[binOfHit[i - begin] + 1];
    }
    std::partial_sum(count.begin(), count.end(), count.begin());
    const std::vector<std::uint32_t> binStart = count;
    auto offset = static_cast<std::uint32_t>(m_binHits.size());
    m_binHits.resize(offset + (end - begin));
    m_binPhis.resize(offset + (end - begin));
    for (std::uint32_t i = begin; i < end; ++i) {
      std::uint32_t slot = offset + count[binOfHit[i - begin]]++;
      m_binHits[slot] = m_layerHits[i];
      m_binPhis[slot] = m_layerPhis[i];
    }
    // The bins' ranges live in their azimuth cells (ids from firstBin).
    for (std::uint32_t n = 0; n < b.nBins; ++n) {
      const std::uint32_t id = m_binCells.add(m_binPhis, offset + binStart[n],
                                              offset + binStart[n + 1]);
      if (n == 0) {
        b.firstBin = id;
      }
    }
    m_layerBins.push_back(b);
  }
  m_layerCells.reserve(m_layerRange.size(), m_layerPhis.size());
  for (auto [begin, end] : m_layerRange) {
    m_layerCells.add(m_layerPhis, begin, end);
  }
  m_layerWs.resize(m_layerHits.size());
  for (std::size_t k = 0; k < m_layers.size(); ++k) {
    const bool alongZ = m_layerBins[k].alongZ;
    for (std::uint32_t i = m_layerRange[k].first; i < m_layerRange[k].second;
         ++i) {
      m_layerWs[i] =
          alongZ ? hits.z[m_layerHits[i]] : hits.radius[m_layerHits[i]];
    }
  }
  m_box = {std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};
  for (const LayerBins& b : m_layerBins) {
    m_box = {std::min(m_box.zMin, b.zMin), std::max(m_box.zMax, b.zMax),
             std::min(m_box.rMin, b.rMin), std::max(m_box.rMax, b.rMax)};
  }
}

std::uint32_t HitPool::LayerBins::binOf(double w) const {
  if (nBins <= 1) {
    return 0;
  }
  double x = std::floor((w - wMin) / binWidth);
  if (!(x > 0.0)) {
    return 0;
  }
  return x >= nBins - 1 ? nBins - 1 : static_cast<std::uint32_t>(x);
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
  m_tree->index().radiusSearch(query, radius * radius, found,
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

void HitPool::discWindow(double u, double v, double radius, double phi,
                         double halfWidth, std::vector<ConfIndex>& out,
                         const std::function<bool(ConfIndex)>& keep,
                         const RzCone* rz) const {
  out.clear();
  if (halfWidth >= std::numbers::pi && rz == nullptr) {
    disc(u, v, radius, out);
    if (keep) {
      std::erase_if(out, [&](ConfIndex h) { return !keep(h); });
    }
    return;
  }
  // Squared distances as nanoflann computes them (query - point, strict
  // comparison), so that the set and its order are exactly disc()'s.
  const double r2 = radius * radius;
  const double rc = std::sqrt(u * u + v * v);
  const bool all = halfWidth >= std::numbers::pi;  // with a (z, R) cone
  std::vector<std::pair<ConfIndex, double>> found;
  std::vector<ConfIndex> window;
  std::optional<PreparedRz> prepared;
  RzBox rzBox{};
  const bool useReach = prepareReach(rz, prepared, rzBox);
  for (std::size_t k = 0; k < m_layers.size(); ++k) {
    // A member within the disc has |rc_h - rc| < radius (margin for
    // rounding).
    if (m_layerRc[k].second < rc - radius - 1e-12 ||
        m_layerRc[k].first > rc + radius + 1e-12) {
      continue;
    }
    if (useReach && !rzBox.overlaps(m_layerBins[k])) {
      continue;  // outside the (z, R) cone: rzRange() would refuse it
    }
    window.clear();
    const double half = all ? 2.0 * std::numbers::pi : halfWidth + 1e-9;
    if (rz == nullptr) {
      detail::collectPhiWindow(m_layerPhis, m_layerHits, m_layerCells,
                               static_cast<std::uint32_t>(k), phi, half,
                               window);
    } else {
      const LayerBins& bins = m_layerBins[k];
      double wLo = 0.0;
      double wHi = 0.0;
      if (!rzRange(*prepared, bins, wLo, wHi)) {
        continue;
      }
      collectLayer(k, wLo, wHi, phi, half, window);
    }
    for (ConfIndex h : window) {
      double du = u - m_hits->u[h];
      double dv = v - m_hits->v[h];
      double d2 = du * du + dv * dv;
      if (d2 < r2 && (!keep || keep(h))) {
        found.emplace_back(h, d2);
      }
    }
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second < b.second : a.first < b.first;
  });
  out.reserve(found.size());
  for (const auto& f : found) {
    out.push_back(f.first);
  }
}

void HitPool::azimuthWindow(double phi, double halfWidth,
                            std::vector<ConfIndex>& out,
                            const std::function<bool(ConfIndex)>& keep) const {
  out.clear();
  detail::collectPhiWindow(m_phis, m_byPhi, m_phiCells, 0, phi, halfWidth, out);
  if (keep) {
    // The order below is total (ties by index): sorting the survivors
    // gives the order that filtering the sorted window gave.
    std::erase_if(out, [&](ConfIndex h) { return !keep(h); });
  }
  auto dphi = [&](ConfIndex i) {
    double d = std::abs(m_hits->phi[i] - phi);
    return d > std::numbers::pi ? detail::kTwoPi - d : d;
  };
  std::sort(out.begin(), out.end(), [&](ConfIndex a, ConfIndex b) {
    double da = dphi(a);
    double db = dphi(b);
    return da != db ? da < db : a < b;
  });
}

void HitPool::layerWindow(std::uint32_t layer, double phi, double halfWidth,
                          std::vector<ConfIndex>& out, const RzCone* rz) const {
  auto it = std::lower_bound(m_layers.begin(), m_layers.end(), layer);
  if (it == m_layers.end() || *it != layer) {
    return;
  }
  const auto k = static_cast<std::size_t>(it - m_layers.begin());
  if (rz == nullptr) {
    detail::collectPhiWindow(m_layerPhis, m_layerHits, m_layerCells,
                             static_cast<std::uint32_t>(k), phi, halfWidth,
                             out);
    return;
  }
  const LayerBins& bins = m_layerBins[k];
  double wLo = 0.0;
  double wHi = 0.0;
  if (!rzRange(PreparedRz(*rz), bins, wLo, wHi)) {
    return;
  }
  collectLayer(k, wLo, wHi, phi, halfWidth, out);
}

void HitPool::layerBox(std::uint32_t layer, double phi, double halfWidth,
                       double zLo, double zHi, double rLo, double rHi,
                       std::vector<ConfIndex>& out) const {
  auto it = std::lower_bound(m_layers.begin(), m_layers.end(), layer);
  if (it == m_layers.end() || *it != layer) {
    return;
  }
  const auto k = static_cast<std::size_t>(it - m_layers.begin());
  const LayerBins& bins = m_layerBins[k];
  const double lo =
      bins.alongZ ? std::max(zLo, bins.zMin) : std::max(rLo, bins.rMin);
  const double hi =
      bins.alongZ ? std::min(zHi, bins.zMax) : std::min(rHi, bins.rMax);
  if (lo > hi) {
    return;
  }
  collectLayer(k, lo, hi, phi, halfWidth, out);
}

void HitPool::collectLayer(std::size_t k, double wLo, double wHi, double phi,
                           double halfWidth,
                           std::vector<ConfIndex>& out) const {
  const LayerBins& bins = m_layerBins[k];
  const std::uint32_t first = bins.binOf(wLo);
  const std::uint32_t last = bins.binOf(wHi);
  // Each bin costs two binary searches: over a wide range of w one search
  // in the whole layer, then a test of w per hit, is cheaper.
  constexpr std::uint32_t kMaxBinSearches = 4;
  if (last - first + 1 <= kMaxBinSearches) {
    for (std::uint32_t n = first; n <= last; ++n) {
      detail::collectPhiWindow(m_binPhis, m_binHits, m_binCells,
                               bins.firstBin + n, phi, halfWidth, out);
    }
    return;
  }
  // The long coordinates are stored in the layer's azimuth order, so the
  // test reads them in sequence (not scattered over the event's hits).
  const double* w = m_layerWs.data();
  detail::forEachInPhiWindow(m_layerPhis, m_layerCells,
                             static_cast<std::uint32_t>(k), phi, halfWidth,
                             [&](std::size_t i) {
                               if (w[i] >= wLo && w[i] <= wHi) {
                                 out.push_back(m_layerHits[i]);
                               }
                             });
}

}  // namespace conftrack

// The vertex-z pre-pass (VertexZPrepass.hpp, algorithm.md 3.16): triplets
// on the three innermost barrel layers, a z0 histogram with the background
// of phi-rotated triplets subtracted, active bins and their runs.

#include "conftrack/reconstruction/finding/VertexZPrepass.hpp"

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/PrepassLayers.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace conftrack {

ZWindows::ZWindows(const std::vector<std::pair<double, double>>& intervals,
                   double grow) {
  std::vector<std::pair<double, double>> v;
  v.reserve(intervals.size());
  for (const auto& [lo, hi] : intervals) {
    v.emplace_back(lo - grow, hi + grow);
  }
  std::sort(v.begin(), v.end());
  for (const auto& [lo, hi] : v) {
    if (!m_hi.empty() && lo <= m_hi.back()) {
      m_hi.back() = std::max(m_hi.back(), hi);
    } else {
      m_lo.push_back(lo);
      m_hi.push_back(hi);
    }
  }
}

bool ZWindows::near(double z, double margin) const {
  // The first interval ending at or after z - margin.
  auto it = std::lower_bound(m_hi.begin(), m_hi.end(), z - margin);
  return it != m_hi.end() &&
         m_lo[static_cast<std::size_t>(it - m_hi.begin())] <= z + margin;
}

double ZWindows::length() const {
  double l = 0.0;
  for (std::size_t i = 0; i < m_lo.size(); ++i) {
    l += m_hi[i] - m_lo[i];
  }
  return l;
}

namespace {

constexpr double kPi = std::numbers::pi;

using detail::wrapAzimuth;

/// The hits of one layer, sorted by azimuth.
struct LayerHits {
  std::vector<double> phi, z, r;
};

LayerHits layerHits(const ConformalHits& hits, std::uint32_t layer,
                    const std::vector<std::uint8_t>* excluded) {
  std::vector<ConfIndex> idx;
  for (ConfIndex h = 0; h < hits.size(); ++h) {
    if (hits.layer[h] == layer &&
        (excluded == nullptr || (*excluded)[h] == 0)) {
      idx.push_back(h);
    }
  }
  // (phi, index): a total order, ConformalHits being in a fixed order.
  std::sort(idx.begin(), idx.end(), [&](ConfIndex a, ConfIndex b) {
    return hits.phi[a] != hits.phi[b] ? hits.phi[a] < hits.phi[b] : a < b;
  });
  LayerHits out;
  for (ConfIndex h : idx) {
    out.phi.push_back(hits.phi[h]);
    out.z.push_back(hits.z[h]);
    out.r.push_back(hits.radius[h]);
  }
  return out;
}

/// Calls f(i) for the hits of `l` within `half` of azimuth `centre`, in
/// azimuth order (the window may wrap at +-pi); stops when f returns true.
template <typename F>
void forEachInPhi(const LayerHits& l, double centre, double half, F&& f) {
  const double c = wrapAzimuth(centre);
  auto range = [&](double lo, double hi) {
    auto it = std::lower_bound(l.phi.begin(), l.phi.end(), lo);
    for (; it != l.phi.end() && *it <= hi; ++it) {
      if (f(static_cast<std::size_t>(it - l.phi.begin()))) {
        return true;
      }
    }
    return false;
  };
  if (c - half < -kPi) {
    if (!range(-kPi, c + half)) {
      range(c - half + 2.0 * kPi, kPi);
    }
  } else if (c + half > kPi) {
    if (!range(c - half, kPi)) {
      range(-kPi, c + half - 2.0 * kPi);
    }
  } else {
    range(c - half, c + half);
  }
}

/// The hits of the confirmation layer in a grid of azimuth x z cells, so
/// that a confirmation looks at a few cells instead of a binary search
/// and a scan (the pre-pass makes millions of pairs per TrackML event).
class ConfirmGrid {
 public:
  ConfirmGrid(const LayerHits& l, double phiCell, double zCell) : m_l(l) {
    m_nPhi =
        std::max<std::size_t>(1, static_cast<std::size_t>(2.0 * kPi / phiCell));
    m_phiCell = 2.0 * kPi / static_cast<double>(m_nPhi);
    m_zMin = 0.0;
    double zMax = 0.0;
    if (!l.z.empty()) {
      m_zMin = *std::min_element(l.z.begin(), l.z.end());
      zMax = *std::max_element(l.z.begin(), l.z.end());
    }
    m_nZ = std::clamp<std::size_t>(
        static_cast<std::size_t>((zMax - m_zMin) / zCell) + 1, 1, 1024);
    m_zCell = std::max(zCell, (zMax - m_zMin) / static_cast<double>(m_nZ));
    // Counting sort of the hits (kept in azimuth order within a cell).
    std::vector<std::uint32_t> cellOf(l.phi.size());
    m_start.assign(m_nPhi * m_nZ + 1, 0);
    for (std::size_t i = 0; i < l.phi.size(); ++i) {
      cellOf[i] = static_cast<std::uint32_t>(phiIndex(l.phi[i]) * m_nZ +
                                             zIndex(l.z[i]));
      ++m_start[cellOf[i] + 1];
    }
    for (std::size_t c = 1; c < m_start.size(); ++c) {
      m_start[c] += m_start[c - 1];
    }
    m_items.resize(l.phi.size());
    std::vector<std::uint32_t> fill(m_start.begin(), m_start.end() - 1);
    for (std::size_t i = 0; i < l.phi.size(); ++i) {
      m_items[fill[cellOf[i]]++] = static_cast<std::uint32_t>(i);
    }
  }

  /// Calls f(i) for the hits in the cells overlapping [phi -+ halfPhi] x
  /// [z -+ halfZ] (a superset); stops when f returns true.
  template <typename F>
  void search(double phi, double halfPhi, double z, double halfZ, F&& f) const {
    const auto span = static_cast<std::ptrdiff_t>(halfPhi / m_phiCell) + 1;
    const auto centre = static_cast<std::ptrdiff_t>(phiIndex(wrapAzimuth(phi)));
    const auto n = static_cast<std::ptrdiff_t>(m_nPhi);
    const std::size_t z0 = zIndex(z - halfZ);
    const std::size_t z1 = zIndex(z + halfZ);
    for (std::ptrdiff_t d = -std::min(span, n / 2);
         d <= std::min(span, (n - 1) / 2); ++d) {
      const auto ip = static_cast<std::size_t>(((centre + d) % n + n) % n);
      for (std::uint32_t k = m_start[ip * m_nZ + z0];
           k < m_start[ip * m_nZ + z1 + 1]; ++k) {
        if (f(m_items[k])) {
          return;
        }
      }
    }
  }

 private:
  std::size_t phiIndex(double phi) const {
    return std::min(m_nPhi - 1,
                    static_cast<std::size_t>((phi + kPi) / m_phiCell));
  }
  std::size_t zIndex(double z) const {
    const double x = (z - m_zMin) / m_zCell;
    return x <= 0.0 ? 0 : std::min(m_nZ - 1, static_cast<std::size_t>(x));
  }

  const LayerHits& m_l;
  std::size_t m_nPhi = 1;
  std::size_t m_nZ = 1;
  double m_phiCell = 1.0;
  double m_zMin = 0.0;
  double m_zCell = 1.0;
  std::vector<std::uint32_t> m_start;
  std::vector<std::uint32_t> m_items;
};

}  // namespace

std::optional<std::pair<std::string, std::string>> VertexZPrepass::findProblem(
    const Config& c, const Detector& detector) {
  struct Q {
    const char* key;
    double value;
    Range range;
  };
  const double halfPi = kPi / 2.0;
  for (const Q& q : {
           Q{"max_z_mm", c.maxAbsZ, Range::positiveFinite()},
           Q{"bin_width_mm", c.binWidth, Range{0.0, c.maxAbsZ, false, true}},
           Q{"smooth_bins", static_cast<double>(c.smoothBins),
             Range::closed(0, 1000)},
           Q{"max_dphi", c.maxDeltaPhi, Range{0.0, halfPi, false, true}},
           Q{"confirm_dphi", c.confirmPhi, Range{0.0, halfPi, false, true}},
           Q{"confirm_dz_mm", c.confirmZ, Range::positiveFinite()},
           Q{"min_excess", c.minExcess, Range{1.0, 1e9, true, true}},
           Q{"min_significance", c.minSignificance, Range::closed(0.0, 1e3)},
       }) {
    std::string what = rangeViolation(q.value, q.range);
    if (!what.empty()) {
      return std::make_pair(std::string(q.key), what);
    }
  }
  if (c.collections.empty()) {
    return std::make_pair(std::string("collections"),
                          std::string("must not be empty"));
  }
  std::size_t barrelLayers = 0;
  for (std::size_t i = 0; i < c.collections.size(); ++i) {
    const std::uint16_t s = c.collections[i];
    if (s >= detector.subdetectors().size()) {
      return std::make_pair(std::string("collections"),
                            "subdetector index " + std::to_string(s) +
                                " is not one of detector '" + detector.name() +
                                "'");
    }
    if (std::find(c.collections.begin(), c.collections.begin() + i, s) !=
        c.collections.begin() + i) {
      return std::make_pair(
          std::string("collections"),
          "subdetector '" + detector.subdetectors()[s].name + "' listed twice");
    }
    for (std::uint32_t l : detector.subdetectors()[s].layers) {
      barrelLayers += detector.layers()[l].isDisk() ? 0 : 1;
    }
  }
  if (barrelLayers < 3) {
    return std::make_pair(std::string("collections"),
                          "need at least three barrel layers (have " +
                              std::to_string(barrelLayers) + ")");
  }
  return std::nullopt;
}

VertexZPrepass::VertexZPrepass(const Detector& detector, Config config)
    : m_detector(&detector), m_config(std::move(config)) {
  if (auto p = findProblem(m_config, detector)) {
    throw std::invalid_argument("VertexZPrepass: key '" + p->first +
                                "': " + p->second);
  }
  m_layers = detail::barrelLayersByRadius(detector, m_config.collections);
  m_layers.resize(3);
}

VertexZPrepass::Result VertexZPrepass::run(
    const ConformalHits& hits,
    const std::vector<std::uint8_t>* excluded) const {
  const auto t0 = std::chrono::steady_clock::now();
  const Config& c = m_config;
  const LayerHits l0 = layerHits(hits, m_layers[0], excluded);
  const LayerHits l1 = layerHits(hits, m_layers[1], excluded);
  const LayerHits l2 = layerHits(hits, m_layers[2], excluded);
  const double r2 = m_detector->layers()[m_layers[2]].r;
  // Largest distance of a confirmation hit from the layer's radius (flat
  // sensors, overlaps): the z window of the grid search allows for it.
  double r2Spread = 0.0;
  for (double r : l2.r) {
    r2Spread = std::max(r2Spread, std::abs(r - r2));
  }
  const ConfirmGrid grid(l2, 2.0 * c.confirmPhi, 2.0 * c.confirmZ);
  const auto nBins =
      static_cast<std::size_t>(std::ceil(2.0 * c.maxAbsZ / c.binWidth));
  // [0]: triplets, [1]: the outer two hits taken at phi + pi (background).
  std::vector<std::int64_t> counts[2] = {std::vector<std::int64_t>(nBins, 0),
                                         std::vector<std::int64_t>(nBins, 0)};
  Result result;
  for (int rot = 0; rot < 2; ++rot) {
    const double shift = rot == 0 ? 0.0 : kPi;
    std::vector<std::int64_t>& h = counts[rot];
    for (std::size_t a = 0; a < l0.phi.size(); ++a) {
      const double pa = l0.phi[a];
      const double za = l0.z[a];
      const double ra = l0.r[a];
      forEachInPhi(l1, pa + shift, c.maxDeltaPhi, [&](std::size_t b) {
        const double dr = l1.r[b] - ra;
        if (!(dr > 1.0)) {
          return false;
        }
        const double slope = (l1.z[b] - za) / dr;
        const double z0 = za - slope * ra;
        if (!(std::abs(z0) < c.maxAbsZ)) {
          return false;
        }
        // Azimuth of a circle through the origin grows about linearly
        // with R: phi(R) = phi_b + dphi (R - R_b) / dR.
        const double dphi = wrapAzimuth(l1.phi[b] - shift - pa);
        const double rate = dphi / dr;
        bool confirmed = false;
        grid.search(
            l1.phi[b] + rate * (r2 - l1.r[b]),
            c.confirmPhi + std::abs(rate) * r2Spread, za + slope * (r2 - ra),
            c.confirmZ + std::abs(slope) * r2Spread, [&](std::size_t k) {
              const double pred = l1.phi[b] + rate * (l2.r[k] - l1.r[b]);
              if (std::abs(wrapAzimuth(l2.phi[k] - pred)) <= c.confirmPhi &&
                  std::abs(l2.z[k] - (za + slope * (l2.r[k] - ra))) <=
                      c.confirmZ) {
                confirmed = true;
              }
              return confirmed;
            });
        if (confirmed) {
          const auto bin =
              std::min(nBins - 1,
                       static_cast<std::size_t>((z0 + c.maxAbsZ) / c.binWidth));
          ++h[bin];
        }
        return false;
      });
    }
  }
  for (std::size_t i = 0; i < nBins; ++i) {
    result.triplets += static_cast<std::uint64_t>(counts[0][i]);
    result.background += static_cast<std::uint64_t>(counts[1][i]);
  }
  // Sums over 2k + 1 bins of the excess and of the counts.
  const auto k = static_cast<std::ptrdiff_t>(c.smoothBins);
  const auto n = static_cast<std::ptrdiff_t>(nBins);
  std::vector<std::int64_t> excess(nBins, 0);
  std::vector<std::int64_t> total(nBins, 0);
  std::vector<std::uint8_t> active(nBins, 0);
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, i - k);
         j <= std::min(n - 1, i + k); ++j) {
      excess[i] += counts[0][j] - counts[1][j];
      total[i] += counts[0][j] + counts[1][j];
    }
    const auto e = static_cast<double>(excess[i]);
    active[i] =
        e >= c.minExcess &&
        e >= c.minSignificance * std::sqrt(static_cast<double>(total[i]));
  }
  auto edge = [&](std::ptrdiff_t i) {
    return -c.maxAbsZ + static_cast<double>(i) * c.binWidth;
  };
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (!active[i]) {
      continue;
    }
    if (i == 0 || !active[i - 1]) {
      result.regions.emplace_back(edge(i), edge(i + 1));
    } else {
      result.regions.back().second = edge(i + 1);
    }
    // A local maximum (the first bin of a plateau).
    const bool left = i == 0 || excess[i] > excess[i - 1];
    const bool right = i == n - 1 || excess[i] >= excess[i + 1];
    if (left && right) {
      double sw = 0.0;
      double swz = 0.0;
      for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, i - k);
           j <= std::min(n - 1, i + k); ++j) {
        const auto w = static_cast<double>(
            std::max<std::int64_t>(0, counts[0][j] - counts[1][j]));
        sw += w;
        swz += w * (edge(j) + 0.5 * c.binWidth);
      }
      result.vertices.push_back(sw > 0.0 ? swz / sw
                                         : edge(i) + 0.5 * c.binWidth);
      result.excess.push_back(static_cast<double>(excess[i]));
    }
  }
  result.milliseconds = std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - t0)
                            .count();
  return result;
}

namespace detail {

std::vector<std::pair<double, double>> findFreeHitVertexRegions(
    const FinderState& state) {
  return VertexZPrepass(state.detector, *state.config.vertexPrepass)
      .run(state.hits, &state.used)
      .regions;
}

StepStats findVertexRegions(FinderState& state) {
  const VertexZPrepass::Result r =
      VertexZPrepass(state.detector, *state.config.vertexPrepass)
          .run(state.hits);
  state.vertexRegions = r.regions;
  StepStats stats;
  stats.name = "VertexZ";
  stats.milliseconds = r.milliseconds;
  return stats;
}

}  // namespace detail

}  // namespace conftrack

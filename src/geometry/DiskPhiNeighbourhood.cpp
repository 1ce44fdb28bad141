#include "conftrack/geometry/DiskPhiNeighbourhood.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack {

DiskPhiNeighbourhood::DiskPhiNeighbourhood(const ModuleLayout& layout)
    : m_layers(layout.numLayers()), m_moduleBin(layout.modules().size(), 0) {
  const std::vector<PlanarModule>& modules = layout.modules();
  std::vector<double> radii;
  for (std::uint32_t l = 0; l < layout.numLayers(); ++l) {
    const auto [begin, end] = layout.layerRange(l);
    if (begin == end || !layout.layerIsDisk(l)) {
      continue;
    }
    // The ring with the fewest sensors sets the number of bins.
    radii.clear();
    double largestPhi = -std::numeric_limits<double>::infinity();
    for (std::uint32_t i = begin; i < end; ++i) {
      const Vector3& c = modules[i].center;
      radii.push_back(c.head<2>().norm());
      largestPhi = std::max(largestPhi, std::atan2(c.y(), c.x()));
    }
    std::sort(radii.begin(), radii.end());
    std::uint32_t fewest = std::numeric_limits<std::uint32_t>::max();
    std::uint32_t inRing = 1;
    for (std::size_t k = 1; k <= radii.size(); ++k) {
      if (k == radii.size() || radii[k] - radii[k - 1] >= kRingTolerance) {
        fewest = std::min(fewest, inRing);
        inRing = 1;
      } else {
        ++inRing;
      }
    }
    LayerBins& bins = m_layers[l];
    bins.bins = fewest;
    bins.firstCentre = largestPhi;
    for (std::uint32_t i = begin; i < end; ++i) {
      const Vector3& c = modules[i].center;
      m_moduleBin[i] = binOf(bins, std::atan2(c.y(), c.x()));
    }
  }
}

std::uint32_t DiskPhiNeighbourhood::binOf(const LayerBins& layer,
                                          double phi) const {
  const double step = 2.0 * std::numbers::pi / layer.bins;
  const double shifted = std::floor((phi - layer.firstCentre) / step + 0.5);
  const auto n = static_cast<long long>(layer.bins);
  long long bin = static_cast<long long>(shifted) % n;
  if (bin < 0) {
    bin += n;
  }
  return static_cast<std::uint32_t>(bin);
}

bool DiskPhiNeighbourhood::contains(std::uint32_t layerIndex,
                                    std::uint32_t moduleIndex,
                                    double phi) const {
  const LayerBins& layer = m_layers[layerIndex];
  if (layer.bins == 0) {
    return true;  // not binned (barrel)
  }
  const std::uint32_t point = binOf(layer, phi);
  const std::uint32_t module = m_moduleBin[moduleIndex];
  const std::uint32_t distance =
      point > module ? point - module : module - point;
  return std::min(distance, layer.bins - distance) <= 1;
}

}  // namespace conftrack

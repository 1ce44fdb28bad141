#include "conftrack/core/TrackmlLayerMap.hpp"

#include "conftrack/core/Hit.hpp"

#include <algorithm>

namespace conftrack {

namespace {
std::uint64_t idKey(const DetectorId& id) {
  return (static_cast<std::uint64_t>(id.subdetector) << 32) |
         (static_cast<std::uint64_t>(static_cast<std::uint8_t>(id.side))
          << 16) |
         id.layer;
}
std::uint64_t trackmlKey(std::uint32_t volume, std::uint32_t layer) {
  return (static_cast<std::uint64_t>(volume) << 32) | layer;
}
std::optional<std::uint32_t> lookup(
    const std::vector<std::pair<std::uint64_t, std::uint32_t>>& index,
    std::uint64_t key) {
  auto it = std::lower_bound(
      index.begin(), index.end(), key,
      [](const auto& entry, std::uint64_t k) { return entry.first < k; });
  if (it == index.end() || it->first != key) {
    return std::nullopt;
  }
  return it->second;
}
}  // namespace

void TrackmlLayer::localAxes(const Vector3& position, Vector3& uAxis,
                             Vector3& vAxis) const {
  localMeasurementAxes(position, disk, uAxis, vAxis);
}

TrackmlLayerMap::TrackmlLayerMap(std::string detectorName, double envelopeR,
                                 double envelopeZ,
                                 std::vector<TrackmlLayer> layers)
    : m_detectorName(std::move(detectorName)),
      m_envelopeR(envelopeR),
      m_envelopeZ(envelopeZ),
      m_layers(std::move(layers)) {
  for (std::uint32_t i = 0; i < m_layers.size(); ++i) {
    m_idIndex.emplace_back(idKey(m_layers[i].id), i);
    m_trackmlIndex.emplace_back(
        trackmlKey(m_layers[i].volume, m_layers[i].layer), i);
  }
  std::sort(m_idIndex.begin(), m_idIndex.end());
  std::sort(m_trackmlIndex.begin(), m_trackmlIndex.end());
}

std::optional<std::uint32_t> TrackmlLayerMap::findTrackml(
    std::uint32_t volume, std::uint32_t layer) const {
  return lookup(m_trackmlIndex, trackmlKey(volume, layer));
}

std::optional<std::uint32_t> TrackmlLayerMap::find(const DetectorId& id) const {
  return lookup(m_idIndex, idKey(id));
}

}  // namespace conftrack

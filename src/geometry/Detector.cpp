#include "conftrack/geometry/Detector.hpp"

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

Detector::Detector(std::string name, std::string model, double bz,
                   double envelopeR, double envelopeZ,
                   std::vector<Subdetector> subdetectors,
                   std::vector<SensitiveLayer> layers,
                   std::vector<PassiveSurface> passives)
    : m_name(std::move(name)),
      m_model(std::move(model)),
      m_bz(bz),
      m_envelopeR(envelopeR),
      m_envelopeZ(envelopeZ),
      m_subdetectors(std::move(subdetectors)),
      m_layers(std::move(layers)),
      m_passives(std::move(passives)) {
  for (std::uint32_t i = 0; i < m_layers.size(); ++i) {
    m_idIndex.emplace_back(idKey(m_layers[i].id), i);
    m_trackmlIndex.emplace_back(
        trackmlKey(m_layers[i].trackmlVolume, m_layers[i].trackmlLayer), i);
  }
  std::sort(m_idIndex.begin(), m_idIndex.end());
  std::sort(m_trackmlIndex.begin(), m_trackmlIndex.end());
}

std::optional<std::uint16_t> Detector::findSubdetector(
    std::string_view name) const {
  for (std::size_t i = 0; i < m_subdetectors.size(); ++i) {
    if (m_subdetectors[i].name == name) {
      return static_cast<std::uint16_t>(i);
    }
  }
  return std::nullopt;
}

std::optional<std::uint32_t> Detector::findLayer(const DetectorId& id) const {
  return lookup(m_idIndex, idKey(id));
}

std::optional<std::uint32_t> Detector::findTrackmlLayer(
    std::uint32_t volume, std::uint32_t layer) const {
  return lookup(m_trackmlIndex, trackmlKey(volume, layer));
}

}  // namespace conftrack

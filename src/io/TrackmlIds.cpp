#include "conftrack/io/TrackmlIds.hpp"

#include <limits>

namespace conftrack {

std::optional<TrackmlId> toTrackml(const DetectorId& id,
                                   const TrackmlLayerMap* layers) {
  if (layers == nullptr) {
    if (id.side != Side::eBarrel) {
      return std::nullopt;
    }
    return TrackmlId{id.subdetector, id.layer, id.module};
  }
  auto index = layers->find(id);
  if (!index) {
    return std::nullopt;
  }
  const TrackmlLayer& layer = layers->layers()[*index];
  return TrackmlId{layer.volume, layer.layer, id.module};
}

std::optional<DetectorId> fromTrackml(const TrackmlId& id,
                                      const TrackmlLayerMap* layers) {
  if (layers == nullptr) {
    constexpr std::uint32_t kMax = std::numeric_limits<std::uint16_t>::max();
    if (id.volume > kMax || id.layer > kMax) {
      return std::nullopt;
    }
    return DetectorId{static_cast<std::uint16_t>(id.volume), Side::eBarrel,
                      static_cast<std::uint16_t>(id.layer), id.module};
  }
  auto index = layers->findTrackml(id.volume, id.layer);
  if (!index) {
    return std::nullopt;
  }
  const TrackmlLayer& layer = layers->layers()[*index];
  if (static_cast<std::uint64_t>(id.module) >=
      static_cast<std::uint64_t>(layer.nPhiModules) * layer.nZModules) {
    return std::nullopt;
  }
  DetectorId result = layer.id;
  result.module = id.module;
  return result;
}

}  // namespace conftrack

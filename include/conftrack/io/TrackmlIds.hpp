#pragma once

/// @file TrackmlIds.hpp
/// Mapping between conftrack's DetectorId and TrackML's
/// (volume_id, layer_id, module_id).
///
/// With a detector's layer map (core/TrackmlLayerMap.hpp,
/// Detector::trackmlLayerMap), a layer's TrackML ids are its volume and
/// layer and module_id is DetectorId::module (no offset). Without one
/// (nullptr) the ids are carried raw, so that files of detectors conftrack
/// has no description of (e.g. the Kaggle TrackML events) can be read,
/// processed and written back unchanged: subdetector = volume_id,
/// side = barrel, layer = layer_id, module = module_id.

#include "conftrack/core/DetectorId.hpp"
#include "conftrack/core/TrackmlLayerMap.hpp"

#include <cstdint>
#include <optional>

namespace conftrack {

/// A TrackML module identifier.
struct TrackmlId {
  /// TrackML volume_id.
  std::uint32_t volume = 0;
  /// TrackML layer_id (within the volume).
  std::uint32_t layer = 0;
  /// TrackML module_id (within the layer).
  std::uint32_t module = 0;

  friend constexpr bool operator==(const TrackmlId&,
                                   const TrackmlId&) = default;
};

/// TrackML ids of a DetectorId. nullopt if `layers` has no such layer,
/// or, without a layer map, if the id is not on the barrel side (raw ids
/// cannot express a side).
std::optional<TrackmlId> toTrackml(const DetectorId& id,
                                   const TrackmlLayerMap* layers);

/// DetectorId of TrackML ids. nullopt if `layers` has no layer
/// (volume, layer), if the module number exceeds the layer's segmentation,
/// or, without a layer map, if volume or layer do not fit 16 bits.
std::optional<DetectorId> fromTrackml(const TrackmlId& id,
                                      const TrackmlLayerMap* layers);

}  // namespace conftrack

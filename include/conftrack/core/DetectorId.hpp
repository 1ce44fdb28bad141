#pragma once

/// @file DetectorId.hpp
/// Identifies the sensitive element a hit was measured on.

#include <compare>
#include <cstdint>

namespace conftrack {

/// Side of a detector element along z.
enum class Side : std::int8_t { eNegative = -1, eBarrel = 0, ePositive = 1 };

/// Detector identifier of a hit: subdetector, side (endcaps), layer, module.
///
/// `subdetector` indexes Detector::subdetectors(), `layer` is the layer number
/// inside that subdetector (both sides of an endcap share layer numbers), and
/// `module` numbers the sensor within the layer. The triple
/// (subdetector, side, layer) is a "layer" in the sense of the CLICdp
/// definitions (evaluation.md A1).
struct DetectorId {
  std::uint16_t subdetector = 0;
  Side side = Side::eBarrel;
  std::uint16_t layer = 0;
  std::uint32_t module = 0;

  /// True if both ids name the same layer (subdetector, side, layer).
  constexpr bool sameLayer(const DetectorId& other) const {
    return subdetector == other.subdetector && side == other.side &&
           layer == other.layer;
  }
  /// True if both ids name the same sensor.
  constexpr bool sameSensor(const DetectorId& other) const {
    return sameLayer(other) && module == other.module;
  }

  friend constexpr auto operator<=>(const DetectorId&,
                                    const DetectorId&) = default;
};

}  // namespace conftrack

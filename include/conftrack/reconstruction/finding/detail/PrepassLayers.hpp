#pragma once

/// @file PrepassLayers.hpp
/// Helpers shared by the pre-passes of the finder that combine hits of
/// inner barrel layers (VertexZPrepass, BeamSpotPrepass; internal).

#include "conftrack/geometry/Detector.hpp"

#include <algorithm>
#include <cstdint>
#include <numbers>
#include <vector>

namespace conftrack::detail {

/// Azimuth difference wrapped into (-pi, pi].
inline double wrapAzimuth(double d) {
  constexpr double kPi = std::numbers::pi;
  while (d > kPi) {
    d -= 2.0 * kPi;
  }
  while (d <= -kPi) {
    d += 2.0 * kPi;
  }
  return d;
}

/// The barrel layers of `collections` (valid subdetector indices) by
/// radius, ties by layer index.
inline std::vector<std::uint32_t> barrelLayersByRadius(
    const Detector& detector, const std::vector<std::uint16_t>& collections) {
  std::vector<std::uint32_t> layers;
  for (std::uint16_t s : collections) {
    for (std::uint32_t l : detector.subdetectors()[s].layers) {
      if (!detector.layers()[l].isDisk()) {
        layers.push_back(l);
      }
    }
  }
  std::sort(layers.begin(), layers.end(),
            [&](std::uint32_t a, std::uint32_t b) {
              const double ra = detector.layers()[a].r;
              const double rb = detector.layers()[b].r;
              return ra != rb ? ra < rb : a < b;
            });
  return layers;
}

}  // namespace conftrack::detail

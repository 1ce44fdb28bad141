#pragma once

/// @file EventOverlay.hpp
/// Overlay of whole events into one (a load test of the reconstruction:
/// the TrackML detector at ten times the pile-up of its real events). Each
/// input event is added `copies` times, copy k rotated about the beam axis
/// by k x `rotation`: the rotated hits stay on their layers' cylinders and
/// disks (the layers are symmetric in azimuth), and the copies' tracks do
/// not coincide with the originals'.

#include "conftrack/core/Event.hpp"

#include <cstdint>
#include <span>

namespace conftrack {

/// How overlayEvents combines events.
struct EventOverlayConfig {
  /// Times each input event is added (>= 1).
  std::uint32_t copies = 1;
  /// Azimuthal rotation of copy k is k x this [rad]. Should not be a
  /// multiple of 2 pi / copies (the copies would fall onto each other).
  double rotation = 1.0;
  /// Event number of the result.
  std::uint64_t number = 0;

  /// Throws InputError for copies == 0 or a non-finite rotation.
  void validate() const;
};

/// All hits of `events`, each event `copies` times (input order, copy 0
/// first), rotated as described above (positions and local axes; the
/// detector ids and resolutions are kept: a rotated hit keeps the module id
/// of its original, which only matters to the "one hit per sensor" rule of
/// tracks, for sensors an azimuth `rotation` apart). Hit ids are renumbered
/// 1..N in that order. The result has neither truth nor particles.
Event overlayEvents(std::span<const Event> events,
                    const EventOverlayConfig& config);

}  // namespace conftrack

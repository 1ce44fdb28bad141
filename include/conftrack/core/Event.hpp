#pragma once

/// @file Event.hpp
/// All data of one event: hits, optional truth, particles.

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Particle.hpp"

#include <cstdint>
#include <vector>

namespace conftrack {

/// One event. `truth` is either empty (real data) or parallel to `hits`.
struct Event {
  /// Event number (TrackML file number).
  std::uint64_t number = 0;
  /// Measured hits, indexed by HitIndex.
  std::vector<Hit> hits;
  /// Truth per hit; empty or hits.size() entries.
  std::vector<HitTruth> truth;
  /// Generated particles, sorted by id.
  std::vector<Particle> particles;

  /// True if the event carries hit truth.
  bool hasTruth() const { return !truth.empty(); }
  /// Index of the particle with this id, or kInvalidIndex. Requires
  /// `particles` sorted by id. O(log n).
  ParticleIndex findParticle(std::uint64_t particleId) const;
  /// Sorts particles by id (call after filling them out of order).
  void sortParticles();
};

}  // namespace conftrack

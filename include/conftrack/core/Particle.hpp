#pragma once

/// @file Particle.hpp
/// A generated (true) particle.

#include "conftrack/core/Types.hpp"

#include <cstdint>

namespace conftrack {

/// Where a particle comes from.
enum class ParticleOrigin : std::uint8_t {
  eSignal = 0,  ///< the physics event
  eBackground =
      1,  ///< an overlaid background event (e.g. gamma gamma -> hadrons)
};

/// A true particle as produced by a generator or read from a file.
struct Particle {
  /// Unique id within the event (TrackML `particle_id`); never 0.
  std::uint64_t id = 0;
  /// PDG Monte Carlo code.
  std::int32_t pdg = 0;
  /// Generator status as in HepMC: 1 = stable final state (simulated),
  /// 2 = decayed (kept for the record, e.g. a B hadron or a K0S).
  std::int32_t status = 1;
  /// Charge in units of e.
  double charge = 0.0;
  /// Production vertex [mm].
  Vector3 vertex = Vector3::Zero();
  /// Production time [ns], relative to the physics bunch crossing.
  double time = 0.0;
  /// Momentum at production [GeV].
  Vector3 momentum = Vector3::Zero();
  /// Id of the parent particle, 0 if primary.
  std::uint64_t parentId = 0;
  /// Physics event or background.
  ParticleOrigin origin = ParticleOrigin::eSignal;
  /// Number of hits the particle left (filled by the simulation or reader).
  std::uint32_t nHits = 0;

  /// Transverse momentum [GeV].
  double pt() const { return momentum.head<2>().norm(); }
  /// True if the generator left it undecayed.
  bool isStable() const { return status == 1; }
  /// True if it was generated as background.
  bool isBackground() const { return origin == ParticleOrigin::eBackground; }
};

}  // namespace conftrack

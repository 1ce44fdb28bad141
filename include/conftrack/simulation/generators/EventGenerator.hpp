#pragma once

/// @file EventGenerator.hpp
/// The interface of all event generators: the true particles of one event.

#include "conftrack/core/Particle.hpp"
#include "conftrack/core/Random.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace conftrack {

/// Produces the true particles of one event.
///
/// Reproducibility: an event is a pure function of (engine state, event
/// number). Random generators draw only from the engine passed in (made by
/// makeEngine(seed, event, stream)) and ignore the event number; generators
/// that replay stored events (HepMC3Generator) use only the event number.
/// One interface serves both so that the caller never needs to know which
/// kind it holds, and no generator keeps a cursor that would make the
/// result depend on the order in which threads ask for events.
///
/// Output contract: particle ids are 1..n in vector order (sorted), parents
/// come before their daughters and parentId is 0 or the id of a particle in
/// the same vector. composeEvent() merges signal and background lists.
///
/// Implementations are immutable after construction, so generate() is
/// const and may be called concurrently from several threads.
class EventGenerator {
 public:
  virtual ~EventGenerator() = default;

  /// Short human-readable name, e.g. "ParticleGun" or "HepMC3(file.hepmc)".
  virtual std::string name() const = 0;

  /// The particles of event `eventNumber`, drawing randomness from `rng`.
  /// Non-virtual so that `generate(rng)` and `generate(rng, n)` both work on
  /// any derived class without name hiding.
  std::vector<Particle> generate(RandomEngine& rng,
                                 std::uint64_t eventNumber = 0) const {
    return doGenerate(rng, eventNumber);
  }

 protected:
  /// The implementation of generate().
  virtual std::vector<Particle> doGenerate(RandomEngine& rng,
                                           std::uint64_t eventNumber) const = 0;
};

}  // namespace conftrack

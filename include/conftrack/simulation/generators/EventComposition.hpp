#pragma once

/// @file EventComposition.hpp
/// Merging the particles of the physics event and of the overlaid
/// background into one list with unique ids.

#include "conftrack/core/Particle.hpp"

#include <cstdint>
#include <vector>

namespace conftrack {

/// Background particle ids start above this offset.
///
/// Id scheme of a composed event: signal particles keep the ids their
/// generator gave them (1..n, so they must stay below the offset);
/// background particle k (generator id k) gets id kBackgroundIdOffset + k,
/// and a non-zero parentId is shifted the same way, so decay chains stay
/// consistent. The origin of a particle can thus be read from its id
/// (id > 1000000: background), and the signal ids do not change when the
/// overlay is switched on or off.
inline constexpr std::uint64_t kBackgroundIdOffset = 1'000'000;

/// Concatenates signal and background particles (in that order), shifts
/// the background ids and parentIds by kBackgroundIdOffset and marks them
/// eBackground. The result is sorted by id if both inputs are. Throws
/// InputError if a signal id is 0 or >= kBackgroundIdOffset, or a
/// background id is 0.
std::vector<Particle> composeEvent(std::vector<Particle> signal,
                                   const std::vector<Particle>& background);

}  // namespace conftrack

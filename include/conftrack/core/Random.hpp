#pragma once

/// @file Random.hpp
/// Reproducible random streams: one run seed, one independent stream per
/// (seed, event number, purpose), so results do not depend on thread count
/// or on which events a job runs.

#include <cstdint>
#include <random>

namespace conftrack {

/// The random engine used everywhere.
using RandomEngine = std::mt19937_64;

/// Purposes of separate streams inside one event, so that e.g. switching
/// the overlay on does not change the signal event.
enum class RandomStream : std::uint64_t {
  eSignalGenerator = 1,
  eBackgroundGenerator = 2,
  eSimulation = 3,
  eBackgroundSimulation = 4,
  /// New interaction points of real events (simulate-trackml
  /// --luminous-region).
  eLuminousRegion = 5,
};

/// SplitMix64 finaliser: a bijective 64-bit mixer.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Seed for the stream (runSeed, eventNumber, stream).
constexpr std::uint64_t deriveSeed(std::uint64_t runSeed,
                                   std::uint64_t eventNumber,
                                   RandomStream stream) {
  return mix64(mix64(mix64(runSeed) ^ eventNumber) ^
               static_cast<std::uint64_t>(stream));
}

/// A fresh engine for (runSeed, eventNumber, stream).
inline RandomEngine makeEngine(std::uint64_t runSeed, std::uint64_t eventNumber,
                               RandomStream stream) {
  std::seed_seq seq{deriveSeed(runSeed, eventNumber, stream)};
  return RandomEngine(seq);
}

}  // namespace conftrack

#pragma once

/// @file SharedHitResolution.hpp
/// The finder's shared-hit resolution (internal; FinderConfig::
/// finalMinUniqueHits): the selection's clone and ambiguity rules
/// (TrackSelector, docs/algorithm.md 10) applied to the found tracks
/// before the final hole filling, so that the hits of the tracks it drops
/// return to the pool while the kept tracks can still take them.

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <cstdint>

namespace conftrack::detail {

/// Drops (or trims) ambiguous tracks of a FinderState and releases their
/// hits.
class SharedHitResolution {
 public:
  struct Config {
    /// A track sharing this many hits with one better kept track is its
    /// clone (FinderConfig::cloneSharedHits; 0: no clone rule).
    std::uint32_t cloneSharedHits = 2;
    /// A track that shares hits with better kept tracks needs this many
    /// hits of its own (FinderConfig::finalMinUniqueHits; at least 1).
    std::uint32_t minUniqueHits = 6;
    /// A conformal track that breaks a rule keeps the hits no better kept
    /// track holds, refitted, if they are at least minUniqueHits
    /// (FinderConfig::finalTrimSharedHits); otherwise it is dropped.
    bool trimSharedHits = false;
  };

  /// Throws std::invalid_argument for minUniqueHits 0.
  explicit SharedHitResolution(Config config);

  /// Visits the live tracks best first (betterCandidate: more hits, then
  /// the lower fit chi2/ndf, then the hit lists: a total order, so the
  /// result does not depend on the input order) and drops those that
  /// break a rule of Config (or trims them, with trimSharedHits). Every
  /// used hit that no kept track holds (the dropped tracks' hits, those a
  /// trimmed track lost) is marked unused. Compacts the tracks; returns
  /// how many it dropped.
  std::uint32_t run(FinderState& state) const;

 private:
  Config m_config;
};

}  // namespace conftrack::detail

#pragma once

/// @file SharedHitRules.hpp
/// The clone and ambiguity rules for tracks that share hits, applied to
/// tracks visited best first: by the track selection after the fit
/// (TrackSelector) and by the finder's shared-hit resolution before its
/// final hole filling (detail::SharedHitResolution, finder key
/// final_min_unique_hits). One implementation, so that the finder drops
/// what the selection would.

#include <cstdint>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace conftrack {

/// Judges tracks in order, best first, against the tracks kept before them.
/// Hits are integer keys (hit ids, or any index unique per hit).
class SharedHitRules {
 public:
  /// What judge() decided.
  enum class Verdict { eKeep, eClone, eAmbiguous };

  /// cloneSharedHits: a track sharing this many hits with one kept track is
  /// its clone (0: no clone rule). minUniqueHits: a track sharing hits with
  /// kept tracks needs this many hits no kept track holds (0: no such
  /// rule); a track that shares none is no ambiguity.
  SharedHitRules(std::uint32_t cloneSharedHits, std::uint32_t minUniqueHits)
      : m_cloneSharedHits(cloneSharedHits), m_minUniqueHits(minUniqueHits) {}

  /// Judges the next track: `matched` are the hits the clone rule counts
  /// (the selection: those the fit used), `all` those the unique count
  /// sees (outliers included). A kept track is registered as `index`.
  Verdict judge(std::span<const std::uint64_t> matched,
                std::span<const std::uint64_t> all, std::uint32_t index);

  /// True if a kept track holds hit `id` (with minUniqueHits; always
  /// false without it).
  bool claimed(std::uint64_t id) const { return m_claimed.contains(id); }

 private:
  std::uint32_t m_cloneSharedHits;
  std::uint32_t m_minUniqueHits;
  /// Hit -> kept tracks whose matched hits hold it.
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> m_owners;
  /// All hits of the kept tracks (with minUniqueHits).
  std::unordered_set<std::uint64_t> m_claimed;
  /// Scratch: hits shared with each kept track.
  std::unordered_map<std::uint32_t, std::uint32_t> m_shared;
};

}  // namespace conftrack

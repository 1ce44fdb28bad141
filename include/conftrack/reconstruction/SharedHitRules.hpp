#pragma once

/// @file SharedHitRules.hpp
/// The clone and ambiguity rules for tracks that share hits, applied to
/// tracks visited best first: by the track selection after the fit
/// (TrackSelector) and by the finder's shared-hit resolution before its
/// final hole filling (detail::SharedHitResolution, finder key
/// final_min_unique_hits). One implementation, so that the finder drops
/// what the selection would.

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace conftrack {

/// Judges tracks in order, best first, against the tracks kept before them.
/// Hits are the event's hit indices (the finder's or the selection's),
/// below the hit count given to the constructor: each hit's kept owners and
/// whether a kept track holds it live in arrays indexed by hit, so that
/// judging allocates nothing per hit (the finder judges every track after
/// every step).
class SharedHitRules {
 public:
  /// What judge() decided.
  enum class Verdict { eKeep, eClone, eAmbiguous };

  /// cloneSharedHits: a track sharing this many hits with one kept track is
  /// its clone (0: no clone rule). minUniqueHits: a track sharing hits with
  /// kept tracks needs this many hits no kept track holds (0: no such
  /// rule); a track that shares none is no ambiguity. hitCount: every hit
  /// index is below it.
  SharedHitRules(std::uint32_t cloneSharedHits, std::uint32_t minUniqueHits,
                 std::size_t hitCount);

  /// Judges the next track: `matched` are the hits the clone rule counts
  /// (the selection: those the fit used), `all` those the unique count
  /// sees (outliers included). A kept track is registered as `index`.
  /// Throws std::out_of_range for a hit index at or above the hit count.
  Verdict judge(std::span<const std::uint32_t> matched,
                std::span<const std::uint32_t> all, std::uint32_t index);

  /// True if a kept track holds hit `hit` (with minUniqueHits; always
  /// false without it).
  bool claimed(std::uint32_t hit) const {
    return hit < m_claimed.size() && m_claimed[hit] != 0;
  }

 private:
  /// End of a hit's owner list.
  static constexpr std::uint32_t kNoLink = 0xffffffffu;
  /// One kept track holding a hit, and the next of that hit's list.
  struct OwnerLink {
    std::uint32_t owner;
    std::uint32_t next;
  };

  /// Throws std::out_of_range unless every hit is below the hit count.
  void checkHits(std::span<const std::uint32_t> hits) const;
  /// The clone rule: whether `matched` shares cloneSharedHits hits with
  /// one kept track.
  bool isClone(std::span<const std::uint32_t> matched);

  std::uint32_t m_cloneSharedHits;
  std::uint32_t m_minUniqueHits;
  /// Per hit the first link of its owner list in m_links (kNoLink: none).
  std::vector<std::uint32_t> m_firstOwner;
  std::vector<OwnerLink> m_links;
  /// Per hit: held by a kept track (with minUniqueHits).
  std::vector<std::uint8_t> m_claimed;
  /// Scratch: (kept track, hits shared with it); a track shares hits with
  /// few kept tracks, so a list searched linearly.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_sharedCounts;
};

}  // namespace conftrack

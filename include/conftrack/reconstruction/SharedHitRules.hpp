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
#include <unordered_map>
#include <unordered_set>
#include <utility>
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
  /// keyBound: if non-zero, every key is below it (the finder's hit
  /// indices), and the hits' owners and claims are kept in arrays indexed by
  /// key instead of hash tables, which allocated per hit (the finder judges
  /// every track after every step: 4 % of a real TrackML event's
  /// instructions); the verdicts are the same. judge() throws
  /// std::out_of_range for a key at or above it.
  SharedHitRules(std::uint32_t cloneSharedHits, std::uint32_t minUniqueHits,
                 std::size_t keyBound = 0);

  /// Judges the next track: `matched` are the hits the clone rule counts
  /// (the selection: those the fit used), `all` those the unique count
  /// sees (outliers included). A kept track is registered as `index`.
  Verdict judge(std::span<const std::uint64_t> matched,
                std::span<const std::uint64_t> all, std::uint32_t index);

  /// True if a kept track holds hit `id` (with minUniqueHits; always
  /// false without it).
  bool claimed(std::uint64_t id) const;

 private:
  /// No owner (end of an owner list of the array storage).
  static constexpr std::uint32_t kNoLink = 0xffffffffu;
  /// One kept track holding a hit, and the next of that hit's list.
  struct OwnerLink {
    std::uint32_t owner;
    std::uint32_t next;
  };

  /// Throws std::out_of_range unless key < keyBound (array storage).
  void checkKey(std::uint64_t key) const;
  /// The clone rule: whether `matched` shares cloneSharedHits hits with
  /// one kept track.
  bool isClone(std::span<const std::uint64_t> matched);

  std::uint32_t m_cloneSharedHits;
  std::uint32_t m_minUniqueHits;
  std::size_t m_keyBound;
  /// Array storage (keyBound > 0): per key the first link of its owner
  /// list in m_links (kNoLink: none), and whether a kept track holds it.
  std::vector<std::uint32_t> m_firstOwner;
  std::vector<OwnerLink> m_links;
  std::vector<std::uint8_t> m_claimedFlags;
  /// Scratch of the array storage: (kept track, hits shared with it).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_sharedCounts;
  /// Hash storage (keyBound 0):
  /// Hit -> kept tracks whose matched hits hold it.
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> m_owners;
  /// All hits of the kept tracks (with minUniqueHits).
  std::unordered_set<std::uint64_t> m_claimed;
  /// Scratch: hits shared with each kept track.
  std::unordered_map<std::uint32_t, std::uint32_t> m_shared;
};

}  // namespace conftrack

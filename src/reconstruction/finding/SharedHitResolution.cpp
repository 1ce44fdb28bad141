// The finder's shared-hit resolution (SharedHitResolution.hpp).
//
// The selection after the fit drops a track that holds hits of better
// tracks unless enough of its hits are its own (TrackSelector,
// min_unique_hits). On TrackML such tracks are short candidates through
// the dense pixel volume, and they often hold the second hit of a real
// track's overlap on a layer: the real track's overlap search found that
// hit used, and once the selection dropped the short track the hit was on
// no track at all. Applying the same rules at the end of finding, before
// the final hole filling and overlap search, gives those hits back to the
// tracks that cross them.

#include "conftrack/reconstruction/finding/detail/SharedHitResolution.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace conftrack::detail {

SharedHitResolution::SharedHitResolution(Config config) : m_config(config) {
  if (m_config.minUniqueHits == 0) {
    throw std::invalid_argument(
        "SharedHitResolution: minUniqueHits must be at least 1");
  }
}

std::uint32_t SharedHitResolution::run(FinderState& state) const {
  std::vector<TrackCandidate>& tracks = state.tracks;
  std::vector<std::uint32_t> order(tracks.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return betterCandidate(tracks[a], tracks[b]);
  });
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // The kept track that first claimed each hit.
  std::vector<std::uint32_t> owner(state.hits.size(), kNone);
  std::vector<std::uint32_t> sharedWith;
  std::uint32_t dropped = 0;
  for (std::uint32_t t : order) {
    TrackCandidate& track = tracks[t];
    if (!track.alive) {
      continue;
    }
    sharedWith.clear();
    for (ConfIndex h : track.hits) {
      if (owner[h] != kNone) {
        sharedWith.push_back(owner[h]);
      }
    }
    std::sort(sharedWith.begin(), sharedWith.end());
    bool clone = false;
    if (m_config.cloneSharedHits > 0) {
      for (auto it = sharedWith.begin(); it != sharedWith.end();) {
        const auto end = std::upper_bound(it, sharedWith.end(), *it);
        clone = clone || std::size_t(end - it) >= m_config.cloneSharedHits;
        it = end;
      }
    }
    const std::size_t own = track.hits.size() - sharedWith.size();
    // A track that shares nothing is no ambiguity.
    if (clone || (!sharedWith.empty() && own < m_config.minUniqueHits)) {
      track.alive = false;
      ++dropped;
      continue;
    }
    for (ConfIndex h : track.hits) {
      if (owner[h] == kNone) {
        owner[h] = t;
      }
    }
  }
  for (ConfIndex h = 0; h < state.hits.size(); ++h) {
    if (state.used[h] != 0 && owner[h] == kNone) {
      state.used[h] = 0;
    }
  }
  if (dropped > 0) {
    state.compact();
  }
  return dropped;
}

}  // namespace conftrack::detail

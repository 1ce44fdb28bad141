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

#include "conftrack/reconstruction/SharedHitRules.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace conftrack::detail {

namespace {

/// Removes from a conformal track the hits that kept tracks hold
/// (`rules`) and refits it as a candidate of its step (fitCandidate: the
/// step's chi2 cuts apply to what is left). False, with the track
/// unchanged, for a helix track, if fewer than minUnique hits remain or if
/// the refit fails or is cut.
bool trimTrack(const FinderState& state, const SharedHitRules& rules,
               std::uint32_t minUnique, TrackCandidate& track) {
  if (track.helix || track.step >= state.config.steps.size()) {
    return false;
  }
  std::vector<ConfIndex> own;
  for (ConfIndex h : track.hits) {
    if (!rules.claimed(h)) {
      own.push_back(h);
    }
  }
  if (own.size() < minUnique || own.size() == track.hits.size()) {
    return false;
  }
  TrackCandidate trimmed = track;
  if (!fitCandidate(state, state.config.steps[track.step], std::move(own),
                    trimmed)) {
    return false;
  }
  track = std::move(trimmed);
  return true;
}

}  // namespace

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
  // The finder has no outliers: both rules see all of a track's hits.
  SharedHitRules rules(m_config.cloneSharedHits, m_config.minUniqueHits,
                       state.hits.size());
  std::uint32_t dropped = 0;
  std::uint32_t trimmed = 0;
  for (std::uint32_t t : order) {
    TrackCandidate& track = tracks[t];
    if (!track.alive) {
      continue;
    }
    bool keep = rules.judge(track.hits, track.hits, t) ==
                SharedHitRules::Verdict::eKeep;
    if (!keep && m_config.trimSharedHits &&
        trimTrack(state, rules, m_config.minUniqueHits, track)) {
      // Trimmed, it shares no hit: the rules keep it.
      keep = rules.judge(track.hits, track.hits, t) ==
             SharedHitRules::Verdict::eKeep;
      ++trimmed;
    }
    if (!keep) {
      track.alive = false;
      ++dropped;
    }
  }
  if (dropped > 0 || trimmed > 0) {
    state.compact();  // also re-indexes the trimmed tracks' hits
  }
  // Every used hit that no kept track holds goes back to the pool (not
  // those an earlier pass's tracks hold).
  for (ConfIndex h = 0; h < state.hits.size(); ++h) {
    if (!rules.claimed(h) && state.used[h] != FinderState::kReserved) {
      state.used[h] = 0;
    }
  }
  return dropped;
}

}  // namespace conftrack::detail

#include "conftrack/reconstruction/selection/TrackSelector.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace conftrack {

namespace {

/// Sorted ids of the hits used in the fit (outliers excluded).
std::vector<std::uint64_t> usedHitIds(std::span<const Hit> hits,
                                      const Track& track) {
  if (track.outlier.size() != track.hits.size()) {
    throw std::invalid_argument(
        "TrackSelector: outlier flags not parallel to the hits");
  }
  std::vector<std::uint64_t> ids;
  ids.reserve(track.hits.size());
  for (std::size_t i = 0; i < track.hits.size(); ++i) {
    if (track.hits[i] >= hits.size()) {
      throw std::out_of_range("TrackSelector: hit index out of range");
    }
    if (track.outlier[i] == 0) {
      ids.push_back(hits[track.hits[i]].id);
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

double chi2PerNdf(const Track& track) {
  return track.ndf > 0 ? track.chi2 / track.ndf
                       : std::numeric_limits<double>::infinity();
}

}  // namespace

std::optional<TrackSelector::Problem> TrackSelector::findProblem(
    const Config& config) {
  if (config.minHits == 0) {
    return Problem{"min_hits", "must be at least 1"};
  }
  // Tracks have at most a few hundred hits; a larger value is a typo.
  constexpr std::uint32_t kMaxUniqueHits = 1000;
  if (config.minUniqueHits > kMaxUniqueHits) {
    return Problem{"min_unique_hits",
                   "must be at most " + std::to_string(kMaxUniqueHits)};
  }
  return std::nullopt;
}

TrackSelector::TrackSelector(const Config& config) : m_config(config) {
  if (std::optional<Problem> p = findProblem(m_config)) {
    throw std::invalid_argument("TrackSelector: " + p->key + " " + p->what);
  }
}

SelectionResult TrackSelector::run(std::span<const Hit> hits,
                                   std::vector<Track> tracks) const {
  SelectionResult result;
  // Candidates passing the per-track cuts, with their used hit ids.
  std::vector<std::size_t> candidates;
  std::vector<std::vector<std::uint64_t>> ids(tracks.size());
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    if (m_config.requireFitted && !tracks[i].fitted) {
      ++result.unfitted;
      continue;
    }
    ids[i] = usedHitIds(hits, tracks[i]);
    if (ids[i].size() < m_config.minHits) {
      ++result.tooFewHits;
      continue;
    }
    candidates.push_back(i);
  }
  std::vector<std::uint8_t> keep(tracks.size(), 0);
  if (m_config.cloneSharedHits == 0 && m_config.minUniqueHits == 0) {
    for (std::size_t i : candidates) {
      keep[i] = 1;
    }
  } else {
    // Best first: more hits, lower chi2/ndf, smaller hit-id list. The last
    // key makes the order total for distinct tracks (identical tracks are
    // clones of each other and either may stand for both).
    std::stable_sort(candidates.begin(), candidates.end(),
                     [&](std::size_t a, std::size_t b) {
                       if (ids[a].size() != ids[b].size()) {
                         return ids[a].size() > ids[b].size();
                       }
                       const double qa = chi2PerNdf(tracks[a]);
                       const double qb = chi2PerNdf(tracks[b]);
                       if (qa != qb) {
                         return qa < qb;
                       }
                       return ids[a] < ids[b];
                     });
    // Hit id -> kept tracks holding it; shared-hit counts per kept track.
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> owners;
    std::unordered_map<std::uint32_t, std::uint32_t> shared;
    // Ids of all hits (outliers included) of the kept tracks.
    std::unordered_set<std::uint64_t> claimed;
    for (std::size_t i : candidates) {
      shared.clear();
      bool clone = false;
      for (std::uint64_t id : ids[i]) {
        if (m_config.cloneSharedHits == 0) {
          break;
        }
        auto it = owners.find(id);
        if (it == owners.end()) {
          continue;
        }
        for (std::uint32_t owner : it->second) {
          if (++shared[owner] >= m_config.cloneSharedHits) {
            clone = true;
            break;
          }
        }
        if (clone) {
          break;
        }
      }
      if (clone) {
        ++result.clones;
        continue;
      }
      if (m_config.minUniqueHits > 0) {
        // All hits count here, outliers included: the finder put them on
        // the track, and an outlier-rich track is no fake for that (a fit
        // pulled off by one wrong hit flags many good ones).
        std::size_t unique = 0;
        for (HitIndex h : tracks[i].hits) {
          unique += claimed.contains(hits[h].id) ? 0 : 1;
        }
        // A track that shares no hit is no ambiguity (minHits judges it).
        if (unique < tracks[i].hits.size() && unique < m_config.minUniqueHits) {
          ++result.ambiguous;
          continue;
        }
        for (HitIndex h : tracks[i].hits) {
          claimed.insert(hits[h].id);
        }
      }
      keep[i] = 1;
      for (std::uint64_t id : ids[i]) {
        owners[id].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
  // Compacted in place: a second array of the kept tracks doubled the
  // memory of the largest events (hundreds of thousands of candidates).
  std::size_t kept = 0;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    if (keep[i] != 0) {
      if (kept != i) {
        tracks[kept] = std::move(tracks[i]);
      }
      ++kept;
    }
  }
  tracks.resize(kept);
  if (m_config.dropOutliers) {
    // The kept tracks' flags are parallel to their hits (usedHitIds).
    for (Track& t : tracks) {
      std::size_t n = 0;
      for (std::size_t k = 0; k < t.hits.size(); ++k) {
        if (t.outlier[k] == 0) {
          t.hits[n] = t.hits[k];
          t.outlier[n] = 0;
          ++n;
        }
      }
      t.hits.resize(n);
      t.outlier.resize(n);
    }
  }
  result.tracks = std::move(tracks);
  return result;
}

}  // namespace conftrack

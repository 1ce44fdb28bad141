#include "conftrack/reconstruction/selection/TrackSelector.hpp"

#include "conftrack/reconstruction/SharedHitRules.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace conftrack {

namespace {

/// Throws for a track that is not a valid list of the event's hits: flags
/// not parallel to the hits, an index outside the event, a hit held twice.
/// The last is a finder bug that the evaluation would otherwise count
/// twice, silently (the track files' reader refuses it; `conftrack run`
/// and the Python module never read files): every path stops here.
void checkTrackHits(std::span<const Hit> hits, const Track& track,
                    std::vector<HitIndex>& scratch) {
  if (track.outlier.size() != track.hits.size()) {
    throw std::invalid_argument(
        "TrackSelector: outlier flags not parallel to the hits");
  }
  for (const HitIndex h : track.hits) {
    if (h >= hits.size()) {
      throw std::out_of_range("TrackSelector: hit index out of range");
    }
  }
  scratch.assign(track.hits.begin(), track.hits.end());
  std::sort(scratch.begin(), scratch.end());
  const auto twice = std::adjacent_find(scratch.begin(), scratch.end());
  if (twice != scratch.end()) {
    throw std::invalid_argument("TrackSelector: a track holds hit id " +
                                std::to_string(hits[*twice].id) + " twice");
  }
}

/// Sorted ids of the hits used in the fit (outliers excluded); the track
/// passed checkTrackHits. `fitted`: scratch.
std::vector<std::uint64_t> usedHitIds(std::span<const Hit> hits,
                                      const Track& track,
                                      std::vector<HitIndex>& fitted) {
  track.fittedHits(fitted);
  std::vector<std::uint64_t> ids;
  ids.reserve(fitted.size());
  for (const HitIndex h : fitted) {
    ids.push_back(hits[h].id);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

double chi2PerNdf(const Track& track) {
  return track.ndf > 0 ? track.chi2 / track.ndf
                       : std::numeric_limits<double>::infinity();
}

/// True if two of the track's hits lie on one layer.
bool repeatsALayer(std::span<const Hit> hits, const Track& track) {
  for (std::size_t i = 1; i < track.hits.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (hits[track.hits[i]].detId.sameLayer(hits[track.hits[j]].detId)) {
        return true;
      }
    }
  }
  return false;
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
  if (config.shortTrackHits > kMaxUniqueHits) {
    return Problem{"short_track_hits",
                   "must be at most " + std::to_string(kMaxUniqueHits)};
  }
  if (config.shortTrackHits > 0 &&
      !(config.shortTrackMaxChi2Ndf > 0.0 &&
        std::isfinite(config.shortTrackMaxChi2Ndf))) {
    return Problem{"short_track_max_chi2_ndf",
                   "must be > 0 (and finite) when short_track_hits is set"};
  }
  return std::nullopt;
}

TrackSelector::TrackSelector(const Config& config) : m_config(config) {
  if (std::optional<Problem> p = findProblem(m_config)) {
    throw std::invalid_argument("TrackSelector: " + p->key + " " + p->what);
  }
}

bool TrackSelector::poorShortTrack(std::span<const Hit> hits,
                                   const Track& track) const {
  const Config& c = m_config;
  if (track.hits.size() >= c.shortTrackHits) {
    return false;
  }
  if (!c.shortTrackSteps.empty() &&
      std::find(c.shortTrackSteps.begin(), c.shortTrackSteps.end(),
                track.findingStep) == c.shortTrackSteps.end()) {
    return false;
  }
  return chi2PerNdf(track) > c.shortTrackMaxChi2Ndf ||
         repeatsALayer(hits, track);
}

SelectionResult TrackSelector::run(std::span<const Hit> hits,
                                   std::vector<Track> tracks) const {
  SelectionResult result;
  // Candidates passing the per-track cuts, with their used hit ids.
  std::vector<std::size_t> candidates;
  std::vector<std::vector<std::uint64_t>> ids(tracks.size());
  std::vector<HitIndex> scratch;
  for (const Track& track : tracks) {
    checkTrackHits(hits, track, scratch);
  }
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    if (m_config.requireFitted && !tracks[i].fitted) {
      ++result.unfitted;
      continue;
    }
    ids[i] = usedHitIds(hits, tracks[i], scratch);
    if (ids[i].size() < m_config.minHits) {
      ++result.tooFewHits;
      continue;
    }
    if (poorShortTrack(hits, tracks[i])) {
      ++result.poorShort;
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
    // The rules count hits by index (checkTrackHits: in range, none twice
    // on a track): the clone rule the fitted ones, the unique count all.
    SharedHitRules rules(m_config.cloneSharedHits, m_config.minUniqueHits,
                         hits.size());
    std::vector<HitIndex> fitted;
    for (std::size_t i : candidates) {
      tracks[i].fittedHits(fitted);
      switch (
          rules.judge(fitted, tracks[i].hits, static_cast<std::uint32_t>(i))) {
        case SharedHitRules::Verdict::eClone:
          ++result.clones;
          break;
        case SharedHitRules::Verdict::eAmbiguous:
          ++result.ambiguous;
          break;
        case SharedHitRules::Verdict::eKeep:
          keep[i] = 1;
          break;
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
        if (t.outlier[k] != kOutlierHit) {
          t.hits[n] = t.hits[k];
          t.outlier[n] = t.outlier[k];
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

#pragma once

/// @file TrackSelector.hpp
/// Selection of the fitted tracks (algorithm.md 11.2, 11.3): the clone
/// treatment with the Kalman chi2 (the paper repeats it on the fitted
/// collection; downstream ClonesAndSplitTracksFinder) and the minimum
/// number of hits after the fit.

#include "conftrack/core/Hit.hpp"
#include "conftrack/reconstruction/Track.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace conftrack {

/// Output and counters of TrackSelector::run.
struct SelectionResult {
  /// The kept tracks, in their input order.
  std::vector<Track> tracks;
  /// Dropped because the fit failed (Config::requireFitted).
  std::size_t unfitted = 0;
  /// Dropped for fewer than Config::minHits hits in the fit.
  std::size_t tooFewHits = 0;
  /// Dropped as clones of a better track.
  std::size_t clones = 0;
};

/// Track selection.
///
/// 1. Tracks whose fit failed and tracks with fewer than minHits hits used
///    in the fit (outliers do not count) are dropped.
/// 2. Clone treatment: two tracks sharing at least cloneSharedHits hits
///    (used hits, compared by Hit::id) are clones; of each clone pair the
///    better one is kept. "Better" is the total order: more used hits,
///    then lower chi2/ndf, then the lexicographically smaller sorted list of
///    hit ids. The tracks are visited best first and a track is kept if it
///    shares fewer than cloneSharedHits hits with every track kept before,
///    so the result is independent of the input order.
///
/// Thread-safe: run() is const.
class TrackSelector {
 public:
  /// Settings; defaults are the CLIC/CLD values.
  struct Config {
    /// Tracks sharing at least this many used hits are clones
    /// (ClonesAndSplitTracksFinder: 2). 0 disables the clone treatment.
    std::uint32_t cloneSharedHits = 2;
    /// Minimum number of hits used in the fit (upstream
    /// MinClustersOnTrackAfterFit: 3 for CLIC and CLD).
    std::uint32_t minHits = 3;
    /// Drop tracks whose fit failed.
    bool requireFitted = true;
  };

  /// A selector with the default Config.
  TrackSelector() = default;
  /// A selector with `config`.
  explicit TrackSelector(const Config& config) : m_config(config) {}

  /// The settings.
  const Config& config() const { return m_config; }

  /// Selects among `tracks`, whose hit indices point into `hits` (the
  /// event's hit array; only Hit::id is used). Throws std::out_of_range for
  /// a hit index outside `hits` and std::invalid_argument for a track
  /// whose outlier flags are not parallel to its hits.
  SelectionResult run(std::span<const Hit> hits,
                      std::vector<Track> tracks) const;

 private:
  Config m_config;
};

}  // namespace conftrack

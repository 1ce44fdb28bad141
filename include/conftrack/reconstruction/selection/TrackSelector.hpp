#pragma once

/// @file TrackSelector.hpp
/// Selection of the fitted tracks (docs/algorithm.md section 10): the
/// clone treatment with the Kalman chi2 (the paper repeats it on the fitted
/// collection; downstream ClonesAndSplitTracksFinder), the minimum number
/// of hits after the fit, the shared-hit resolution and the short-track
/// rule.

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Track.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
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
  /// Dropped for fewer than Config::minUniqueHits hits of their own.
  std::size_t ambiguous = 0;
  /// Dropped by the short-track rule (Config::shortTrackHits).
  std::size_t poorShort = 0;
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
/// 3. Shared-hit resolution (ambiguity resolution, off by default): in the
///    same best-first order, a track that shares hits with better kept
///    tracks is dropped if fewer than minUniqueHits of its hits (outliers
///    included) are its own; a track sharing none is left to minHits. The clone
///    treatment removes pairs sharing several hits; this removes the tracks
///    that share one hit with each of several better tracks, which in dense
///    events are mostly fakes built across neighbouring particles
///    (docs/algorithm.md section 10). A shared hit stays on both kept tracks.
/// 4. Short-track rule (off by default), applied with step 1: a track of
///    fewer than shortTrackHits hits, from one of shortTrackSteps, is kept
///    only if no two of its hits lie on one layer and its chi2/ndf is at
///    most shortTrackMaxChi2Ndf. A helix step's tracks of four or five
///    strip hits are made of noise and left-over hits as easily as of a
///    particle; an overlap partner adds a hit but no lever arm, and noise
///    supplies partners as readily as particles do (docs/algorithm.md
///    section 10).
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
    /// Shared-hit resolution: a track holding hits of better kept tracks
    /// needs at least this many hits (outliers included) of its own. 0 disables
    /// it (CLICdet, CLD: one hit per particle and layer, few shared hits);
    /// TrackML: 6.
    std::uint32_t minUniqueHits = 0;
    /// Remove the hits the fit rejected as outliers from the kept tracks
    /// (after the clone and shared-hit treatment, which count them): a
    /// track is then the measurements its parameters rest on, as an ACTS
    /// track's measurement states. Off by default (the outlier flags are
    /// written with the hits).
    bool dropOutliers = false;
    /// Short-track rule: tracks with fewer hits than this (outliers
    /// included; 0: no rule) must have one hit per layer and chi2/ndf at
    /// most shortTrackMaxChi2Ndf.
    std::uint32_t shortTrackHits = 0;
    /// The largest chi2/ndf of a short track.
    double shortTrackMaxChi2Ndf = 0.0;
    /// The finding steps (Track::findingStep) whose tracks the short-track
    /// rule judges; empty: all. Chain files name them ([selection]
    /// short_track_steps).
    std::vector<std::uint16_t> shortTrackSteps;
  };

  /// A selector with the default Config.
  TrackSelector() = default;
  /// A selector with `config`; throws std::invalid_argument with the
  /// problem findProblem reports.
  explicit TrackSelector(const Config& config);

  /// A nonsense setting: its chain-file key ([selection] table) and what is
  /// wrong with it.
  struct Problem {
    std::string key;
    std::string what;
  };
  /// The first nonsense setting of `config` (minHits = 0, minUniqueHits
  /// above 1000, a short-track rule without a positive chi2/ndf bound),
  /// none if it is valid.
  static std::optional<Problem> findProblem(const Config& config);

  /// The settings.
  const Config& config() const { return m_config; }

  /// Selects among `tracks`, whose hit indices point into `hits` (the
  /// event's hit array; only Hit::id is used). Throws std::out_of_range for
  /// a hit index outside `hits` and std::invalid_argument for a track
  /// whose outlier flags are not parallel to its hits or that holds a hit
  /// twice (any track, kept or not: such a track is a finder bug).
  SelectionResult run(std::span<const Hit> hits,
                      std::vector<Track> tracks) const;

 private:
  /// The short-track rule (Config::shortTrackHits) rejects the track.
  bool poorShortTrack(std::span<const Hit> hits, const Track& track) const;

  Config m_config;
};

}  // namespace conftrack

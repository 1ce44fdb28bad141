#pragma once

/// @file TrackmlScore.hpp
/// The TrackML score (evaluation.md A3, trackml-library score.py) of one
/// event, with efficiency and fake rate in the TrackML convention (strict
/// double 50 % matching). Needs truth; never used by reconstruction.
///
/// A submission labels every hit with a track id. As in score.py every
/// label is a track, 0 included: hits labelled 0 ("no track") form one more
/// track, which is good only if it happens to pass both 50 % criteria.

#include "conftrack/core/Event.hpp"
#include "conftrack/io/TrackmlSubmission.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace conftrack {

/// Selections of the efficiency and fake rate (not of the score).
struct TrackmlScoreConfig {
  /// Reconstructable particles: at least this many hits (the score gives
  /// particles with fewer than 4 hits no weight) ...
  std::uint32_t minParticleHits = 4;
  /// ... and at least this pT [GeV] (0: no cut; particles missing from
  /// event.particles then count by their hits alone).
  double minPt = 0.0;
  /// Tracks in the fake rate: label != 0 and at least this many hits.
  std::uint32_t minTrackHits = 4;
};

/// Score and rates of one event.
struct TrackmlScore {
  /// The official event score: summed weight of the majority hits of good
  /// tracks over the summed weight of all hits (1 for a perfect submission).
  double score = 0.0;
  /// Sum of the hit weights used for the normalisation.
  double totalWeight = 0.0;
  /// True if the truth had no weights (all 0) and they were computed
  /// (computeTrackmlWeights).
  bool weightsComputed = false;
  /// Distinct labels (tracks), 0 included, and the good ones among them.
  std::size_t nTracks = 0;
  std::size_t nGoodTracks = 0;
  /// Reconstructable particles and those with a good track (label != 0).
  std::size_t nReconstructable = 0;
  std::size_t nReconstructed = 0;
  /// nReconstructed / nReconstructable (0 if none).
  double efficiency = 0.0;
  /// Tracks of the fake-rate selection and those that are not good or
  /// whose majority is noise.
  std::size_t nSelectedTracks = 0;
  std::size_t nFakeTracks = 0;
  /// nFakeTracks / nSelectedTracks (0 if none).
  double fakeRate = 0.0;
};

/// The hit weights the score uses, parallel to event.hits: the truth's, or,
/// if they are all 0 (e.g. a truth file without a weight column), computed
/// from the truth and event.particles as trackml-library does
/// (computeTrackmlWeights; then `*computed` is set to true if given).
std::vector<double> trackmlHitWeights(const Event& event,
                                      bool* computed = nullptr);

/// Scores `labels` (one track id per hit, parallel to event.hits) against
/// the event's truth. Weights come from the truth; if they are all 0 (e.g.
/// a truth file without a weight column) they are computed from the truth
/// and event.particles as trackml-library does. Throws
/// std::invalid_argument if the event has no truth or the sizes differ.
TrackmlScore scoreTrackml(const Event& event,
                          std::span<const std::uint64_t> labels,
                          const TrackmlScoreConfig& config = {});

/// The same for tracks (lists of hit indices), labelled by trackmlLabels.
TrackmlScore scoreTrackml(const Event& event,
                          std::span<const std::vector<HitIndex>> tracks,
                          const TrackmlScoreConfig& config = {});

}  // namespace conftrack

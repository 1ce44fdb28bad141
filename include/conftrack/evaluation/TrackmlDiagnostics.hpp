#pragma once

/// @file TrackmlDiagnostics.hpp
/// TrackML truth diagnostics (docs/diagnostics.md): where the weight of an
/// event goes that the TrackML score (TrackmlScore.hpp) does not get, by
/// cause, in total and in bins of the particles' pT, |eta| and production
/// radius. Needs truth; never used by reconstruction.
///
/// Every hit's weight falls in exactly one category of WeightBreakdown, so
/// that found + the lost categories = 1 and found = the TrackML score. The
/// matching is the score's (strict double 50 %, hits labelled 0 forming one
/// more track): the matched track of a particle is the track that holds
/// more than half of the particle's hits and of whose hits the particle
/// holds more than half. There is at most one.

#include "conftrack/core/Event.hpp"

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace conftrack {

/// Where the weight goes, as fractions of the event's total hit weight.
/// The categories are mutually exclusive; total() is 1 (0 for an event
/// without weight).
struct WeightBreakdown {
  /// Hits of a particle on its matched track: what the score gets.
  double found = 0.0;
  /// Matched particle, hit on no track, on a layer where the matched track
  /// has a hit of the particle already (an overlap hit: a second module of
  /// the same layer).
  double leftOffSameLayer = 0.0;
  /// Matched particle, hit on no track, on a layer where the matched track
  /// has no hit of the particle.
  double leftOffNewLayer = 0.0;
  /// Matched particle, hit on another track.
  double otherTracks = 0.0;
  /// Not matched, not impure; no track holds more than maxStrayHits of its
  /// hits.
  double neverFound = 0.0;
  /// Not matched, not impure; two or more tracks hold more than
  /// maxStrayHits of its hits each (none more than half of them).
  double split = 0.0;
  /// Not matched, not impure; exactly one track holds more than
  /// maxStrayHits of its hits (no more than half of them); the rest is on no
  /// track or strays on others.
  double partial = 0.0;
  /// Not matched; a track (label other than 0) holds more than half of its
  /// hits, but the particle holds no more than half of that track's hits.
  double impure = 0.0;
  /// Noise hits (particle 0) not credited by the score (0 unless the truth
  /// gives noise hits weight).
  double noise = 0.0;

  /// Sum of all categories, found included.
  double total() const;
  /// Sum of the lost categories: total() - found.
  double lost() const;
  /// Adds `scale` times every category of `other`.
  void add(const WeightBreakdown& other, double scale = 1.0);
};

/// Where the lost hits of matched particles lie (fractions of the event's
/// total weight). A particle's hits are taken in the order of its
/// trajectory: their truth times, or, where the truth gives all of them
/// one time (the Kaggle files have none), their true positions' distance
/// from the production vertex (monotonic over the half turn that TrackML
/// particles make). A track's hits are taken by the distance of their
/// measured positions from the origin.
struct LostHitPlaces {
  /// Left off (leftOffSameLayer + leftOffNewLayer): before the particle's
  /// first hit on its matched track, between its first and last, after its
  /// last.
  double leftOffBefore = 0.0;
  double leftOffBetween = 0.0;
  double leftOffAfter = 0.0;
  /// On another track (otherTracks): that track's first or last hit, or
  /// one inside it.
  double otherAtHolderEnd = 0.0;
  double otherInsideHolder = 0.0;

  /// Adds `scale` times every field of `other`.
  void add(const LostHitPlaces& other, double scale = 1.0);
};

/// One bin [min, max) of a particle quantity.
struct DiagnosticsBin {
  double min = 0.0;
  double max = 0.0;
  /// Particles with weight in the bin (a mean over events in
  /// averageDiagnostics).
  double particles = 0.0;
  /// The weight of those particles' hits, as fractions of the event's
  /// total weight; weight.total() is the bin's share of the event.
  WeightBreakdown weight;
};

/// The breakdown in bins of one particle quantity.
struct DiagnosticsHistogram {
  /// "pt", "abs_eta" or "production_radius".
  std::string quantity;
  std::vector<DiagnosticsBin> bins;
  /// Weight of hits in no bin: noise, particles missing from
  /// event.particles and values outside the edges. Bins + outside add up to
  /// the event's breakdown.
  WeightBreakdown outside;
};

/// Bin edges (ascending; the last may be infinity) and categories.
struct TrackmlDiagnosticsConfig {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  /// Transverse momentum [GeV].
  std::vector<double> ptEdges = {0.0, 0.1, 0.3, 0.5, 1.0, 2.0, 5.0, kInf};
  /// |eta| of the momentum at production.
  std::vector<double> absEtaEdges = {0.0, 1.0, 2.0, 3.0, 4.0, kInf};
  /// Transverse distance of the production vertex from the beam line [mm].
  std::vector<double> radiusEdges = {0.0, 1.0, 10.0, 100.0, kInf};
  /// A track with at most this many hits of an unmatched particle is a
  /// stray pick-up, not a piece of it (neverFound, split, partial).
  std::uint32_t maxStrayHits = 1;
};

/// The diagnostics of one event (or their mean, averageDiagnostics).
struct TrackmlDiagnostics {
  /// Summed hit weight (before normalisation) and whether the weights were
  /// computed because the truth has none (as scoreTrackml does).
  double totalWeight = 0.0;
  bool weightsComputed = false;
  /// The whole event; weight.found is the TrackML score.
  WeightBreakdown weight;
  /// Where the left-off and other-track weight of weight lies.
  LostHitPlaces places;
  /// The same in bins of pT, |eta| and production radius.
  DiagnosticsHistogram pt;
  DiagnosticsHistogram absEta;
  DiagnosticsHistogram radius;
  /// Tracks (labels other than 0) ...
  double tracks = 0.0;
  /// ... and those of them with no particle (noise excluded) holding more
  /// than half of their hits; fakeFraction = fakeTracks / tracks.
  double fakeTracks = 0.0;
  double fakeFraction = 0.0;
  /// Particles with weight matched to a track (label other than 0), and
  /// the mean over them of the fraction of their hits on that track.
  double foundParticles = 0.0;
  double meanFoundHitFraction = 0.0;
  /// Hits of other particles or noise on the matched tracks of those
  /// particles, and their weight (fraction of the total). Not a loss of
  /// score: each such hit is counted as a loss of its own particle.
  double foreignHitsOnMatched = 0.0;
  double foreignWeightOnMatched = 0.0;
};

/// The diagnostics of `labels` (one track id per hit, parallel to
/// event.hits, 0: no track) against the event's truth. Weights as in
/// scoreTrackml (trackmlHitWeights). Layers are told apart by the hits'
/// DetectorId (subdetector, side, layer). Throws std::invalid_argument if
/// the event has no truth, the sizes differ or the bin edges are not
/// ascending.
TrackmlDiagnostics diagnoseTrackml(const Event& event,
                                   std::span<const std::uint64_t> labels,
                                   const TrackmlDiagnosticsConfig& config = {});

/// The mean over events of every field (fractions, counts and
/// totalWeight); weightsComputed if any event's were. The events must have
/// the same bins (std::invalid_argument otherwise); an empty span gives an
/// all-zero result.
TrackmlDiagnostics averageDiagnostics(
    std::span<const TrackmlDiagnostics> events);

}  // namespace conftrack

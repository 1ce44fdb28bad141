#pragma once

/// @file TruthMatching.hpp
/// Track-to-particle matching and the particle selection of the CLICdp
/// definitions (evaluation.md A1), with the ACTS double matching as an
/// option (evaluation.md A2). Needs truth; never used by reconstruction.

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Units.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace conftrack {

/// Which particles count as reconstructable (CLICdp "ILDLike").
struct ParticleSelection {
  double minPt = 0.1 * units::GeV;
  double maxAbsCosTheta = 0.99;
  /// Hits on distinct (subdetector, side, layer) triples.
  std::uint32_t minLayers = 4;
};

/// How tracks are matched to particles.
struct MatchingConfig {
  /// A track is pure if at least this fraction of its hits comes from its
  /// majority particle (CLICdp: 0.75).
  double purity = 0.75;
  /// ACTS style: additionally the track must hold at least `purity` of the
  /// particle's hits (use with purity 0.5).
  bool doubleMatching = false;
};

/// Matching result of one track.
struct TrackMatch {
  /// Majority particle (index into event.particles), kInvalidIndex if the
  /// majority of hits is noise.
  ParticleIndex particle = kInvalidIndex;
  std::uint32_t nHits = 0;
  std::uint32_t nMajority = 0;
  /// nMajority / nHits.
  double purity = 0.0;
  /// Passes the matching criteria: a true track of `particle`.
  bool matched = false;
};

/// Truth summary of one particle.
struct ParticleTruth {
  std::uint32_t nHits = 0;
  std::uint32_t nLayers = 0;  ///< distinct layers with hits
  bool reconstructable = false;
  std::uint32_t nMatchedTracks = 0;
  /// Smallest angular distance sqrt(dEta^2 + dPhi^2) to any other charged
  /// stable particle of the event with pT > 0.1 GeV (the paper's proximity).
  double proximity = 0.0;
};

/// Matching of all tracks and particles of one event.
struct EventMatching {
  std::vector<TrackMatch> tracks;
  std::vector<ParticleTruth> particles;  ///< parallel to event.particles
};

/// Matches tracks (lists of event hit indices) to the event's particles.
EventMatching matchTracks(const Event& event,
                          std::span<const std::vector<HitIndex>> tracks,
                          const ParticleSelection& selection = {},
                          const MatchingConfig& matching = {});

}  // namespace conftrack

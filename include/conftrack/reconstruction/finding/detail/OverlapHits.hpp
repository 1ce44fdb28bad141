#pragma once

/// @file OverlapHits.hpp
/// Overlap hits (internal): the second (third) hit a particle leaves on one
/// layer where neighbouring sensors overlap, added to the track that holds
/// the first (issue 15; the algorithm is described in OverlapHits.cpp).

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <cstdint>
#include <vector>

namespace conftrack::detail {

/// A compatible hit on another sensor of one of a track's layers: a
/// candidate second hit of an overlap (OverlapHitCollector, and the helix
/// step's HelixFollower), with its pair chi2 and arc length.
struct OverlapCandidate {
  std::uint32_t module;
  double chi2;
  ConfIndex hit;
  double s;
};

/// Keeps the best candidate of each sensor (lowest chi2, then hit) and
/// orders those best first (total order: chi2, hit).
void keepBestPerSensor(std::vector<OverlapCandidate>& candidates);

/// Variance [mm^2] of the displacement across the track of hit h's
/// crossing that a deflection theta0 [rad] (layerTheta0 of the layer at
/// the track's momentum) in the crossing of hit a, on another sensor of
/// the same layer, causes: theta0 times their distance in space. Not
/// negligible for steep low-momentum tracks: TrackML's barrel pixel
/// sensors overlap so that a track at |eta| = 2.5 crosses them 9 mm
/// apart, where 0.36 GeV scatters by 0.08 mm against hit errors of 0.015.
/// Across the track in the transverse plane as given; the z residual at
/// a given arc length moves by sqrt(1 + tanLambda^2) times as much.
double overlapScatteringVariance(const ConformalHits& hits, ConfIndex a,
                                 ConfIndex h, double theta0);

/// Adds overlap hits to the live tracks of a FinderState.
class OverlapHitCollector {
 public:
  /// Cuts of the overlap search (FinderConfig::overlapMaxChi2 and
  /// FinderConfig::overlapMaxArc, read from the chain's [finder] table).
  struct Config {
    /// Largest chi2 (2 degrees of freedom, uv and sz) of the difference
    /// between the candidate's residuals to the track's fits and those of
    /// the track's hit on the same layer.
    double maxChi2 = 20.0;
    /// Largest distance between two sensors of one layer along the layer's
    /// normal (radial on barrels, z on disks) [mm]: TrackML's barrel
    /// sensors lie within 3 mm in radius (plus the tilt of flat sensors on
    /// a cylinder), its disk sensors within 11 mm in z.
    double maxGap = 12.0;
    /// Largest transverse arc length between the two crossings of one
    /// layer [mm] (maxGap seen at a grazing angle is capped here).
    double maxArc = 25.0;
    /// Largest number of hits on one layer of a track (the corner where
    /// four sensors overlap gives four; more is a looper's second turn).
    std::uint32_t maxHitsPerLayer = 4;
  };

  /// Throws std::invalid_argument for a non-positive or non-finite cut.
  OverlapHitCollector(FinderState& state, const HitPool& pool, StepStats& stats,
                      Config config);

  /// Adds to track t the compatible unused pool hits on the layers of its
  /// hits in the pool (other sensors than the track's on that layer);
  /// refits it. Returns the number of hits added.
  std::uint32_t collect(std::uint32_t t);

 private:
  /// chi2 of hit h at arc length sh against the track's hit a at sa: the
  /// difference of their residuals to the fits, against both hits' errors
  /// and the scattering by theta0 in a's sensor (overlapScatteringVariance,
  /// computed once per layer by collect). The
  /// fits' local deviation, which scattering in all earlier layers makes
  /// far larger than the hit errors below a few GeV, cancels.
  double pairChi2(const TrackCandidate& track, ConfIndex a, double sa,
                  ConfIndex h, double sh, double theta0) const;

  FinderState& m_state;
  const ConformalHits& m_hits;
  const HitPool& m_pool;
  StepStats& m_stats;
  Config m_config;
  /// Scratch: pool layers as a lookup, the window, arc lengths.
  std::vector<std::uint8_t> m_inPool;
  std::vector<ConfIndex> m_window;
};

/// Merges pairs of live tracks that share hits into one, where the union
/// (no two hits on one sensor) passes the chi2 cuts of the step that built
/// the first: with two hits on many layers the automaton builds two
/// nearly disjoint candidates of one particle (one through each sensor of
/// an overlap), which the clone treatment cannot see as clones, and the
/// overlap search then gives each the other's hits. Pairs are taken in
/// (track, track) order. Returns the number of merges.
std::uint32_t mergeTracksSharingHits(FinderState& state, StepStats& stats);

/// Drops the live tracks of step `step` with fewer than `belowHits` hits
/// that hold no overlap pair (two hits on one layer) and frees the hits
/// that no live track holds (FindingStep::overlapPairBelowHits). Returns
/// the number dropped.
std::uint32_t dropUnpairedShortTracks(FinderState& state, std::uint16_t step,
                                      std::uint32_t belowHits);

/// Runs the collector over every live track (in track order; a hit may go
/// to two tracks of one particle built through different sensors), then
/// mergeTracksSharingHits.
void addOverlapHits(FinderState& state, const HitPool& pool, StepStats& stats);

}  // namespace conftrack::detail

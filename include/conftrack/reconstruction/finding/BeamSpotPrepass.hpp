#pragma once

/// @file BeamSpotPrepass.hpp
/// Transverse beam-line pre-pass of the conformal finder (algorithm.md
/// 3.24): measures where the beams of an event collide in (x, y) from
/// triplets of hits on three inner barrel layers, before any track is
/// built, so that the conformal map can be taken about the beam line
/// without the user giving it (FinderConfig::beamSpotX, beamSpotY). Truth
/// is never used.

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Types.hpp"
#include "conftrack/geometry/Detector.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace conftrack {

/// The beam-line pre-pass.
///
/// Three barrel layers of `collections` are used: the innermost, the first
/// at least `minLayerGap` further out and the first as far beyond that (a
/// lever arm per pair; CLICdet's double layers give 31, 44 and 58 mm,
/// TrackML's pixels 32, 72 and 116 mm). Every `stride`-th hit of the first
/// layer in azimuth order (at most `maxSeedHits` of them, spread over all
/// azimuths) is paired with the hits of the second layer within
/// `maxDeltaPhi` whose straight line in (R, z) meets R = 0 within
/// `maxAbsZ`; a hit of the third layer within `confirmPhi` of the azimuth
/// extrapolated linearly in R and within `confirmZ` of the (R, z) line
/// completes a triplet. The circle through a triplet of radius at least
/// that of a `minPt` track (the scattering of softer tracks blurs their
/// circles) and passing within `maxD0` of the detector axis is kept.
///
/// The beam line b is the point that the kept circles pass closest to.
/// Random triplets of other particles' hits outnumber the tracks' in jets
/// and with overlay, so it is first found by a vote: each circle marks the
/// cells of a grid it crosses (0.25 mm cells within `maxD0` of the
/// configured line, then 0.02 mm cells within 0.5 mm of the first result)
/// with the sector of its direction, and the 3 x 3 block marked from the
/// most directions wins (nearly parallel random circles of one jet cross
/// each other somewhere along it; only at the beam line do circles from
/// all directions meet). Then b is the least-squares solution of
/// |b - c_i| - R_i = 0 (centres c_i, radii R_i) over the circles within a
/// window about it that shrinks to three robust standard deviations of
/// their residuals (at least `minScale`). The estimate is used if at least
/// `minTriplets` circles remain, they measure both coordinates (weight
/// along the weaker axis of at least one circle) and the fit settles;
/// otherwise the configured beam line stays.
///
/// Hits are taken in (layer, azimuth, hit id) order and every sum runs in
/// that order, so the result depends neither on the input order nor on
/// threads.
class BeamSpotPrepass {
 public:
  struct Config {
    /// Subdetectors whose barrel layers may be used (three of them, spaced
    /// by minLayerGap, must exist).
    std::vector<std::uint16_t> collections;
    /// Least radial distance between the layers used [mm]; > 0.
    double minLayerGap = 10.0;
    /// Azimuth window of the second hit about the first [rad] (sets the
    /// softest track; with minPt); (0, pi/2].
    double maxDeltaPhi = 0.03;
    /// Azimuth window of the third hit about the linear extrapolation
    /// [rad]; (0, pi/2]. Both windows widen by the azimuth offsets of a
    /// straight track from a beam line maxD0 off the configured one.
    double confirmPhi = 0.005;
    /// z window of the third hit about the pair's (R, z) line [mm]; > 0.
    double confirmZ = 2.0;
    /// Largest |z| of a pair's (R, z) line at R = 0 [mm]; > 0.
    double maxAbsZ = 300.0;
    /// Softest track whose circle is used [GeV] (its radius in the
    /// detector's central field); > 0.
    double minPt = 0.5;
    /// Largest distance of a circle from the configured beam line, and
    /// half-width of the vote's grid [mm]; (0, 10]. A beam line found
    /// within 0.75 mm of the grid's edge is not used.
    double maxD0 = 2.0;
    /// Most first-layer hits used as seeds (every stride-th); >= 1.
    std::uint32_t maxSeedHits = 4000;
    /// Fewest circles for an estimate; >= 3.
    std::uint32_t minTriplets = 30;
    /// Floor of the window's scale [mm]: the spread of good circles'
    /// residuals (resolution and scattering); (0, 100].
    double minScale = 0.005;
  };

  /// What the pre-pass found in one event.
  struct Result {
    /// True if the estimate below is used (enough circles, spanning the
    /// plane); false: position is the configured beam line.
    bool valid = false;
    /// The beam line's transverse position [mm].
    Vector2 position = Vector2::Zero();
    /// Its standard uncertainty per coordinate [mm] (the larger of the
    /// two), from the trimmed circles' spread; 0 if not valid.
    double uncertainty = 0.0;
    /// Triplets whose circle passed the pT and distance cuts.
    std::uint64_t triplets = 0;
    /// Circles kept by the last trimming.
    std::uint64_t inliers = 0;
    /// Time of the pre-pass [ms].
    double milliseconds = 0.0;
  };

  /// The first problem of `config` for `detector` as (chain-file key, what),
  /// keys those of the chain's [beam_spot_prepass] table; nothing if valid.
  static std::optional<std::pair<std::string, std::string>> findProblem(
      const Config& config, const Detector& detector);

  /// Throws std::invalid_argument "BeamSpotPrepass: key 'k': what" for an
  /// invalid config (findProblem). `detector` must outlive this.
  BeamSpotPrepass(const Detector& detector, Config config);

  const Config& config() const { return m_config; }
  /// The three layers used (indices into Detector::layers()), innermost
  /// first.
  const std::vector<std::uint32_t>& layers() const { return m_layers; }

  /// Measures the beam line among `hits` (all hits of the event; those off
  /// the three layers are ignored); `start` is the configured beam line,
  /// the first iteration's point and the fallback [mm].
  Result run(std::span<const Hit> hits, const Vector2& start) const;

 private:
  const Detector* m_detector;
  Config m_config;
  std::vector<std::uint32_t> m_layers;
};

}  // namespace conftrack

#pragma once

/// @file ConformalTrackFinder.hpp
/// The conformal-tracking pattern recognition (paper 4.1): runs the chain
/// of steps on the hits of one event. Truth is never used.

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/PromptBending.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/TrackCandidate.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace conftrack {

/// A found track: event hit indices along the path plus the finder's fits.
struct FoundTrack {
  std::vector<HitIndex> hits;
  /// Hits of the particle's further half-turns (loopers), joined to the
  /// track but not fitted: the fit measures the first half-turn.
  std::vector<HitIndex> turnHits;
  ConformalFitResult uv;
  SzFitResult sz;
  double pt = 0.0;
  int charge = 0;
  std::uint16_t step = 0;
  bool fitBackward = false;
};

/// A Track with the finder's information (hits, estimates, fit quality);
/// not yet fitted. Its turnHits follow its hits, flagged kTurnHit.
Track toTrack(const FoundTrack& found);

/// Output of the finder for one event.
struct FindingResult {
  std::vector<FoundTrack> tracks;
  std::vector<StepStats> steps;
  /// The event's vertex regions from the vertex-z pre-pass ([lo, hi] in z
  /// [mm], ascending; empty without a pre-pass or where it found none),
  /// about which the steps with vertex_window_mm seed (algorithm.md 3.16).
  std::vector<std::pair<double, double>> vertexRegions;
  /// The beam line about which the hits were mapped [mm]: the beam-line
  /// pre-pass's where it measured one, else the chain's (algorithm.md
  /// 3.24).
  Vector2 beamSpot = Vector2::Zero();
  double milliseconds = 0.0;
};

/// Conformal track finder. Stateless after construction: `run` is const
/// and may be called from several threads at once.
class ConformalTrackFinder {
 public:
  struct Config {
    /// The chain and global settings (chains/clicdet.toml by default).
    FinderConfig chain;
  };

  /// Throws std::invalid_argument if the chain is not valid for `detector`
  /// (findChainProblem), naming the chain-file key of the problem.
  ConformalTrackFinder(const Detector& detector, Config config);

  /// A later pass over the hits that earlier tracks left
  /// (Reconstruction's second pass, algorithm.md 3.21).
  struct Pass {
    /// The steps that run: indices into the chain's steps, ascending.
    std::span<const std::uint16_t> steps;
    /// One flag per hit of `hits` (same order): non-zero where an earlier
    /// track holds it. No step takes such a hit.
    std::span<const std::uint8_t> taken;
    /// The event's vertex regions (FindingResult::vertexRegions of the
    /// first pass), in place of the pre-pass.
    std::span<const std::pair<double, double>> vertexRegions;
    /// The event's beam line (FindingResult::beamSpot of the first pass),
    /// in place of the beam-line pre-pass; unset: the chain's
    /// (FinderConfig::beamSpotX, beamSpotY).
    std::optional<Vector2> beamSpot;
  };

  /// Finds tracks among `hits`. The result does not depend on the order of
  /// the hits or on the number of threads.
  FindingResult run(std::span<const Hit> hits) const;
  /// The same with only the steps of `pass`, over the hits it leaves free;
  /// the stages after the steps (shared-hit resolution, hole filling,
  /// merging) see only the tracks of this pass. Throws
  /// std::invalid_argument if `taken` does not have one flag per hit or
  /// the steps are not ascending indices of the chain's steps.
  FindingResult run(std::span<const Hit> hits, const Pass& pass) const;

  const Config& config() const { return m_config; }

 private:
  FindingResult find(std::span<const Hit> hits, const Pass* pass) const;

  const Detector* m_detector;
  Config m_config;
  /// The field's bending factors (FinderConfig::fieldCorrection); null in
  /// a uniform field or without the correction. Shared by copies.
  std::shared_ptr<const PromptBending> m_bending;
  /// The beam-line pre-pass of the chain (FinderConfig::beamSpotPrepass),
  /// set up once.
  std::optional<BeamSpotPrepass> m_beamSpotPrepass;
};

}  // namespace conftrack

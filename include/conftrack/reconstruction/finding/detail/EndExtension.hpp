#pragma once

/// @file EndExtension.hpp
/// The final extension (a conftrack addition; FinderConfig::finalExtension,
/// docs/algorithm.md 3.23): after the last step, every conformal track is
/// followed outwards once more from its last hit over the hits no track
/// holds, in all the chain's collections, with its step's cell-angle cuts
/// multiplied, a wider azimuth window and the multiple-scattering
/// allowance. The steps' extensions stop where a track bends more than
/// their cuts allow: a low-momentum track scattered in a disk, or one that
/// the weakening field at a solenoid's end turns; this pass takes their
/// particles' further hits that are still free.

#include "conftrack/reconstruction/finding/detail/TrackFollower.hpp"

#include <cstdint>

namespace conftrack::detail {

/// Outward extension of one track with loosened cuts.
class EndExtension {
 public:
  /// The cuts of the extension.
  struct Config {
    /// The step's angle and chi2 cuts and the finder's window size and
    /// look-ahead; phiWindow is the final extension's own.
    ExtensionCuts cuts;
    /// Multiplier of the cell-angle cuts (at least 1).
    double angleFactor = 3.0;
    /// Tracks with fewer hits are left alone (at least 3): the direction
    /// of a short track is too uncertain for loosened cuts, and TrackML's
    /// three- and four-hit prompt tracks (PixelShort) are particles that
    /// ended, whose further hits are other particles' (event 1001: those
    /// found fell from 36 to 26 of 61 without this limit, the score the
    /// same within 0.0001).
    std::uint32_t minHits = 5;

    /// The configuration of `step` in `finder`: finder keys
    /// final_extension_angle_factor and final_extension_phi_window.
    static Config fromStep(const FindingStep& step, const FinderConfig& finder);
  };

  /// Throws std::invalid_argument naming the key of a bad value.
  explicit EndExtension(const Config& config);

  const Config& config() const { return m_config; }

  /// Extends track t of state.tracks outwards with unused hits of `pool`,
  /// claiming each at once (used flag, clone index,
  /// StepStats::extendedHits). Helix-step tracks and those with fewer
  /// than minHits hits are left alone.
  void run(FinderState& state, const HitPool& pool, StepStats& stats,
           std::uint32_t t) const;

 private:
  Config m_config;
  FollowRules m_rules;
  /// Scratch buffers, reused from track to track (not shared between
  /// threads: one unit per step and event).
  mutable FollowWorkspace m_work;
};

/// Runs EndExtension on every live track of `state`, each with the cuts of
/// the step that built it.
void extendTrackEnds(FinderState& state, const HitPool& pool, StepStats& stats);

}  // namespace conftrack::detail

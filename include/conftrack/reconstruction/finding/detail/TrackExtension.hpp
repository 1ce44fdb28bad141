#pragma once

/// @file TrackExtension.hpp
/// The per-layer extension of ExtendTracks (upstream.md 10, its first
/// pass): a track is followed outwards from its last hit along its
/// predicted helix, one layer crossing at a time, with the step's cuts and
/// a look-ahead among compatible hits (TrackFollower.cpp). The step runs it
/// on the tracks above FindingStep::highPtCut, before CatchAllExtension.

#include "conftrack/reconstruction/finding/detail/TrackFollower.hpp"

#include <cstdint>

namespace conftrack::detail {

/// Outward extension of one track along its helix.
///
/// Only the outgoing branch of the helix is searched (within half a turn),
/// new hits must lie further out than the track's last hit, and the cell
/// angles are cut at 1x the step's. The refits keep the track's conformal
/// model: with the quadratic term free, a vertex-detector track plus the
/// tracker hits of a neighbouring particle of the same jet fits as well as
/// the right combination, while the prompt (straight-line) model tells them
/// apart by a factor of ten in chi2 (upstream always refits with it).
class TrackExtension {
 public:
  /// The cuts of the extension.
  struct Config {
    /// The step's angle and chi2 cuts and the finder's window and
    /// look-ahead settings.
    ExtensionCuts cuts;
    /// Retry the nearest crossing with the allowance for multiple
    /// scattering when no hit passes without it (finder key
    /// scattering_allowance).
    bool scatteringAllowance = true;

    /// The configuration of `step` in `finder`.
    static Config fromStep(const FindingStep& step, const FinderConfig& finder);
  };

  /// Throws std::invalid_argument naming the key of a bad value.
  explicit TrackExtension(const Config& config);

  const Config& config() const { return m_config; }

  /// Extends track t of state.tracks with unused hits of `pool`, claiming
  /// each at once (used flag, clone index, StepStats::extendedHits).
  void run(FinderState& state, const HitPool& pool, StepStats& stats,
           std::uint32_t t) const;

 private:
  Config m_config;
  FollowRules m_rules;
  /// Scratch buffers, reused from track to track (not shared between
  /// threads: one unit per step and event).
  mutable FollowWorkspace m_work;
};

}  // namespace conftrack::detail

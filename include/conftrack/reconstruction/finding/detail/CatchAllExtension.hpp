#pragma once

/// @file CatchAllExtension.hpp
/// The catch-all extension of ExtendTracks (upstream.md 10, its second,
/// "low-pT" pass): every live track is followed again with loose cuts, so
/// that it picks up the compatible hits the per-layer pass (TrackExtension,
/// only above FindingStep::highPtCut) did not look for, including those of
/// a looper on its way back in.

#include "conftrack/reconstruction/finding/detail/TrackFollower.hpp"

#include <cstdint>

namespace conftrack::detail {

/// Loose extension of one track, loopers included.
///
/// Both crossings of a barrel layer within one turn of the last hit are
/// searched, so a hit may lie further in than the last one (a looper
/// curling back), but it must lie on the last hit's side of z = 0; the
/// cell angles are cut at 3x the step's (upstream's catch-all cuts). No
/// scattering allowance: with loose angles and both branches of the helix
/// it would let low-pT tracks take their neighbours' hits in dense jets.
class CatchAllExtension {
 public:
  /// The cuts of the extension.
  struct Config {
    /// The step's angle and chi2 cuts (the angles applied 3x) and the
    /// finder's window and look-ahead settings.
    ExtensionCuts cuts;

    /// The configuration of `step` in `finder`.
    static Config fromStep(const FindingStep& step, const FinderConfig& finder);
  };

  /// Throws std::invalid_argument naming the key of a bad value.
  explicit CatchAllExtension(const Config& config);

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

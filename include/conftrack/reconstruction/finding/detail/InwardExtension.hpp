#pragma once

/// @file InwardExtension.hpp
/// The inward part of the completion of a newly built track (a conftrack
/// addition; upstream has none): for inside-out steps, the track is
/// followed from its first hit back towards the IP through the step's
/// layers. It recovers hits lost when a short cell (e.g. between the two
/// sensors of a double layer, 2 mm apart) failed an angle cut and the
/// automaton started the track a layer further out.

#include "conftrack/reconstruction/finding/detail/TrackFollower.hpp"

#include <cstdint>

namespace conftrack::detail {

/// Inward extension of one track from its first hit.
///
/// The per-layer extension run backwards: only the branch of the helix
/// the particle came along is searched (within half a turn), new hits must
/// lie further in than the first hit and are put before it, and the cell
/// angles are cut at 3x the step's: inwards the chord to a 2 mm-distant
/// double-layer sensor is as noisy as the cell that failed in the first
/// place.
class InwardExtension {
 public:
  /// The cuts of the extension.
  struct Config {
    /// The step's angle and chi2 cuts (the angles applied 3x) and the
    /// finder's window and look-ahead settings.
    ExtensionCuts cuts;
    /// Retry the nearest crossing with the allowance for multiple
    /// scattering when no hit passes without it (finder key
    /// inward_scattering_allowance).
    bool scatteringAllowance = true;

    /// The configuration of `step` in `finder`.
    static Config fromStep(const FindingStep& step, const FinderConfig& finder);
  };

  /// Throws std::invalid_argument naming the key of a bad value.
  explicit InwardExtension(const Config& config);

  const Config& config() const { return m_config; }

  /// Extends track t of state.tracks inwards with unused hits of `pool`,
  /// claiming each at once (used flag, clone index,
  /// StepStats::extendedHits).
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

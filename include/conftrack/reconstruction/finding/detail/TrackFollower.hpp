#pragma once

/// @file TrackFollower.hpp
/// Following a track hit by hit along its predicted helix, with a
/// look-ahead among compatible hits (internal): the loop that the extension
/// units TrackExtension, CatchAllExtension and InwardExtension run, each
/// with its own FollowRules. The algorithm is described in
/// TrackFollower.cpp.

#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPredictionError.hpp"
#include "conftrack/reconstruction/finding/detail/LayerCrossingSearch.hpp"

#include <cstdint>
#include <string_view>
#include <vector>

namespace conftrack::detail {

/// The cuts of the extension units: those of the step that runs them and
/// of the finder. The defaults are FindingStep's and FinderConfig's.
struct ExtensionCuts {
  /// Largest angle in (u, v) between the track's direction at its end hit
  /// and the cell to a new hit [rad] (step key max_cell_angle; the rules'
  /// angleFactor multiplies it).
  double maxCellAngle = 0.005;
  /// Largest angle in (s, z) between the track's s-z line and the cell to
  /// a new hit [rad] (max_cell_angle_rz; times angleFactor).
  double maxCellAngleRZ = 0.005;
  /// Largest increase of chi2_uv/ndf and of chi2_sz/ndf when a hit is
  /// added (chi2_cut), scaled below chi2PtScale.
  double chi2Cut = 100.0;
  /// pT scale of chi2Cut [GeV] (chi2_cut_pt_scale_GeV; 0: off).
  double chi2PtScale = 0.0;
  /// Half-width of the azimuth window around a predicted crossing [rad]
  /// (finder key extension_phi_window).
  double phiWindow = 0.1;
  /// At most this many hits examined per predicted crossing (finder key
  /// max_window_hits; counted as Guard::eWindowHits).
  std::uint32_t maxWindowHits = 256;
  /// Layers of look-ahead when several hits of a layer are compatible
  /// (finder key extension_lookahead; 0: the greedy choice).
  int lookahead = 2;
  /// A candidate's chi2 (as ranked) must not exceed this many times the
  /// track's chi2/ndf, or hitChi2Floor if larger (finder keys
  /// extension_hit_chi2_ratio, 0: off, and extension_hit_chi2_floor).
  double hitChi2Ratio = 0.0;
  double hitChi2Floor = 100.0;
  /// Above this chi2 (as ranked) the nearest layer's best hit is compared
  /// with the best hit beyond that layer, which wins if lower by more than
  /// a missing hit's charge (finder key extension_skip_chi2; 0: off).
  double skipChi2 = 0.0;
  /// Candidates are ranked in z against the (s, z) filter of the track's
  /// hits rather than its straight-line fit (finder key
  /// extension_sz_filter).
  bool szFilter = false;
  /// Candidates are ranked in (u, v) with the transverse scattering of
  /// every layer the track crossed rather than the last one's (finder key
  /// extension_uv_scattering).
  bool uvScattering = false;

  /// The largest chi2 of a candidate hit (as ranked) on a track with these
  /// fits; infinite when the cut is off.
  double maxHitChi2(const ConformalFitResult& uv, const SzFitResult& sz) const;
  /// The chi2 cut for a track of transverse momentum `pt` [GeV].
  double chi2CutAt(double pt) const {
    return scaledChi2Cut(chi2Cut, chi2PtScale, pt);
  }
  /// The cuts of `step` in `finder`.
  static ExtensionCuts fromStep(const FindingStep& step,
                                const FinderConfig& finder);
  /// Throws std::invalid_argument naming the key of the first value out of
  /// range (the ranges of the chain validation); `unit` starts the message.
  /// `phiWindowKey` names the finder key phiWindow came from (the final
  /// extension has its own).
  void validate(std::string_view unit,
                std::string_view phiWindowKey = "extension_phi_window") const;
};

/// What distinguishes the ways of following a track.
struct FollowRules {
  /// From the last hit outwards (hits appended) or from the first hit
  /// back towards the IP (hits prepended).
  Direction direction = Direction::eOutward;
  /// Which crossings of a barrel layer are searched.
  Branches branches = Branches::eOutgoing;
  /// Multiplier of the cell-angle cuts (1 or 3, upstream's loose cuts).
  double angleFactor = 1.0;
  /// New hits must lie on the end hit's side of z = 0.
  bool sameZSide = false;
  /// New hits must lie further from the beam line than the end hit
  /// (further in when following inwards).
  bool radiusOrdered = true;
  /// When no hit of the nearest crossing passes, retry it with the
  /// allowance for multiple scattering (FinderConfig::scatteringAllowance).
  bool scatteringAllowance = false;
};

/// Scratch buffers of followTrack (one per unit, reused across tracks).
struct FollowWorkspace {
  CrossingScratch crossing;
  /// The track being followed.
  Chain chain;
  /// Compatible hits of the next crossing of the chain itself.
  std::vector<Candidate> candidates;
  /// Compatible hits beyond the nearest layer (ExtensionCuts::skipChi2).
  std::vector<Candidate> later;
  /// One level of the look-ahead: the chain with a tentative hit and the
  /// compatible hits beyond it.
  struct Level {
    Chain chain;
    std::vector<Candidate> candidates;
  };
  /// Indexed by the remaining depth (1 .. lookahead; 0 unused).
  std::vector<Level> levels;
  /// The chain's hits in the order of the search and their arc lengths
  /// (ExtensionCuts::szFilter, uvScattering).
  HelixPath filterPath;
  std::vector<double> filterArcs;
  /// The transverse prediction error of the chain's hits and their inputs
  /// (ExtensionCuts::uvScattering).
  HelixPredictionError uvError;
  std::vector<double> uvSigma;
  std::vector<double> uvKink;
};

/// Follows track t of state.tracks over `pool` with `cuts` and `rules`,
/// adding compatible hits one at a time (each claimed at once) until no
/// crossing has one; the track is rewritten only if it grew. Tracks with
/// fewer than three hits and helix-step tracks are left alone.
void followTrack(FinderState& state, const HitPool& pool, StepStats& stats,
                 std::uint32_t t, const ExtensionCuts& cuts,
                 const FollowRules& rules, FollowWorkspace& work);

}  // namespace conftrack::detail

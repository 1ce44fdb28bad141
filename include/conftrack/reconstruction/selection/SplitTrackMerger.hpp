#pragma once

/// @file SplitTrackMerger.hpp
/// Merging the pieces of one particle after the fit (issue 15, item 4).
/// The finder's own merging (TrackMerger) compares circles and lines of
/// the hits; a particle produced millimetres off the beam line fits no
/// circle through the origin, and its vertex-detector piece and its
/// tracker piece, built by different steps, stay apart. Their fitted
/// perigee parameters, with the covariances that the Kalman fit gives them,
/// agree nevertheless (docs/algorithm.md 10.1).

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace conftrack {

/// Pairs of fitted tracks whose perigee parameters agree within their
/// errors, whose hits follow each other along the helix and lie on
/// different layers (or on one layer within an overlap of neighbouring
/// sensors), are refitted as one track and replace the two pieces if the
/// merged fit is as good as theirs. Tracks with a looper's further-turn
/// hits (kTurnHit) are left alone, and so are pairs with a hit beyond the
/// first half-turn from the perigee of the piece with the better-measured
/// curvature (a looper's returning half), where the arc length along that
/// circle no longer orders the hits. Pairs are tried best parameter chi2 first,
/// each track at most once per round; rounds repeat (at most three) so that
/// three pieces become one. The result does not depend on the thread count or
/// the input hit order.
class SplitTrackMerger {
 public:
  struct Config {
    /// Merge at all (chain file [split_merging] enabled). Off: run()
    /// returns the tracks unchanged.
    bool enabled = false;
    /// Largest chi2 (5 degrees of freedom) of the difference of the two
    /// pieces' parameters at the IP with the sum of their covariances
    /// (max_parameter_chi2).
    double maxParameterChi2 = 30.0;
    /// Pair search: the pieces' tanLambda (max_tan_lambda_difference) and
    /// phi0 (max_phi0_difference [rad]) differ by at most these, a cheap
    /// preselection before the chi2.
    double maxTanLambdaDifference = 0.1;
    double maxPhi0Difference = 0.2;
    /// Two hits of the pieces on one layer further apart than this are two
    /// crossings of it, not an overlap of neighbouring sensors
    /// (max_same_layer_distance_mm).
    double maxSameLayerDistance = 15.0 * units::mm;
    /// The merged fit's chi2/ndf is at most this times the larger of the
    /// pieces' and 1 (max_chi2_ratio).
    double maxChi2Ratio = 2.0;
  };

  /// A nonsense setting: its chain-file key ([split_merging] table) and
  /// what is wrong with it.
  struct Problem {
    std::string key;
    std::string what;
  };
  /// The first nonsense setting of `config` (a bound that is not positive
  /// and finite, a chi2 ratio below 1, a phi0 window of pi or more), none if
  /// it is valid.
  static std::optional<Problem> findProblem(const Config& config);

  /// A merger refitting with `fitter`, which must outlive it; throws
  /// std::invalid_argument with the problem findProblem reports.
  SplitTrackMerger(const KalmanFitter& fitter, const Config& config);

  const Config& config() const { return m_config; }

  struct Result {
    std::vector<Track> tracks;
    /// Pairs merged (a track of three pieces counts two).
    std::size_t merges = 0;
  };

  /// Merges among `tracks` (fitted by the same fitter; hit indices into
  /// `hits`, the event's hit array). Tracks keep their order; a merged
  /// track takes the place of its first piece. Throws std::out_of_range
  /// for a hit index outside `hits`.
  Result run(std::span<const Hit> hits, std::vector<Track> tracks) const;

 private:
  struct Candidate;
  /// Whether tracks a and b can be one particle's pieces; their parameter
  /// chi2 if so.
  std::optional<double> compatible(std::span<const Hit> hits, const Track& a,
                                   const Track& b) const;
  /// The merged track of a and b, if its fit is as good as theirs.
  std::optional<Track> merge(std::span<const Hit> hits, const Track& a,
                             const Track& b) const;

  const KalmanFitter* m_fitter;
  Config m_config;
};

}  // namespace conftrack

#pragma once

/// @file HitReassigner.hpp
/// Giving a fitted track's rejected hits, and hits that no track holds, to
/// the track whose end they continue (issue 15). A track that runs on past
/// its particle's last hit (the particle ended, or left the layer through
/// a gap) takes a neighbour's hit in the finder's greedy extensions; its
/// Kalman fit then flags the hit as an outlier, while the neighbour's own
/// track, extended later, found the hit taken and ended one layer short.
/// After the fit both tracks' helices are known, and the hit goes to the
/// one whose refit takes it (docs/algorithm.md 10.2).

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

/// For each outlier hit of a fitted track (and, with Config::freeHits,
/// each hit that no track holds), in hit order: the fitted tracks one of
/// whose end hits lies within Config::maxEndDistance and whose helix at
/// that end passes the hit within the windows, beyond that end, are
/// refitted with the hit added there; the hit moves to the refit with the
/// smallest chi2 increase if that increase is at most
/// Config::maxChi2Increase, the refit keeps the hit and flags no more
/// outliers than before. The track the hit leaves used it in no fit, so its
/// fit stands. Tracks with a looper's further-turn hits are left alone.
/// The result does not depend on the thread count or the input hit order
/// of the tracks' hits (hits are visited by index, candidates by chi2 and
/// track order).
class HitReassigner {
 public:
  struct Config {
    /// Reassign at all (chain file [hit_reassignment] enabled). Off: run()
    /// returns the tracks unchanged.
    bool enabled = false;
    /// Also offer the hits that no track holds (free_hits).
    bool freeHits = false;
    /// Largest distance of the hit from the track's first or last fitted
    /// hit [mm] (max_end_distance_mm).
    double maxEndDistance = 500.0 * units::mm;
    /// Largest distance of the hit from the circle of the track's state at
    /// that end, transverse [mm] (max_transverse_mm), and from its z
    /// there (max_longitudinal_mm): a preselection before the refit.
    double maxTransverse = 5.0 * units::mm;
    double maxLongitudinal = 10.0 * units::mm;
    /// Largest chi2 of the hit against the prediction of the track's
    /// state at that end (max_predicted_chi2; 2 degrees of freedom, the
    /// state's covariance, the hit's errors and the scattering allowance
    /// below).
    double maxPredictedChi2 = 12.0;
    /// Position error from multiple scattering per metre of path at 1 GeV
    /// [mm] (scattering_mm_per_m_gev): about 2 mrad per layer crossed.
    double scatteringPerMetre = 1.5 * units::mm;
    /// Refits tried per hit, best prediction first (refits_per_hit, at
    /// least 1): the hit goes to the first refit that takes it with a chi2
    /// increase of at most maxChi2Increase.
    int refitsPerHit = 1;
    /// Largest increase of the track's chi2 in such a refit
    /// (max_chi2_increase; the hit is a 2-D measurement).
    double maxChi2Increase = 12.0;
  };

  /// A nonsense setting: its chain-file key ([hit_reassignment] table) and
  /// what is wrong with it.
  struct Problem {
    std::string key;
    std::string what;
  };
  /// The first nonsense setting of `config` (a bound that is not positive
  /// and finite, no refit per hit), none if it is valid.
  static std::optional<Problem> findProblem(const Config& config);

  /// A reassigner refitting with `fitter`, which must outlive it; throws
  /// std::invalid_argument with the problem findProblem reports.
  HitReassigner(const KalmanFitter& fitter, const Config& config);

  const Config& config() const { return m_config; }

  struct Result {
    std::vector<Track> tracks;
    /// Outlier hits moved to another track.
    std::size_t outliersMoved = 0;
    /// Hits of no track added to one (Config::freeHits).
    std::size_t freeHitsAdded = 0;
    /// Refits tried.
    std::size_t refits = 0;
  };

  /// Reassigns among `tracks` (fitted by the same fitter; hit indices into
  /// `hits`, the event's hit array). Tracks keep their order. Throws
  /// std::out_of_range for a hit index outside `hits`.
  Result run(std::span<const Hit> hits, std::vector<Track> tracks) const;

 private:
  const KalmanFitter* m_fitter;
  Config m_config;
};

}  // namespace conftrack

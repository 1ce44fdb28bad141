#pragma once

/// @file Track.hpp
/// A reconstructed track: its hits, the finder's estimates and, once
/// fitted, LCIO perigee parameters with covariance (physics.md 3).

#include "conftrack/core/Types.hpp"

#include <cstdint>
#include <vector>

namespace conftrack {

/// Five LCIO track parameters (d0, phi0, omega, z0, tanLambda).
using TrackVector = Eigen::Matrix<double, 5, 1>;
/// Their 5x5 covariance.
using TrackCovariance = Eigen::Matrix<double, 5, 5>;

/// Indices into TrackVector.
enum TrackParameter : int {
  eD0 = 0,         ///< signed transverse impact parameter [mm]
  ePhi0 = 1,       ///< azimuth of the momentum at the PCA [rad]
  eOmega = 2,      ///< signed curvature q/rho [1/mm]
  eZ0 = 3,         ///< z at the PCA [mm]
  eTanLambda = 4,  ///< pz / pT
};

/// Parameters at a reference point (PCA in the x-y plane to it).
struct TrackState {
  Vector3 reference = Vector3::Zero();
  TrackVector parameters = TrackVector::Zero();
  TrackCovariance covariance = TrackCovariance::Zero();
};

/// What a track does with one of its hits (Track::outlier).
enum HitUse : std::uint8_t {
  kFittedHit = 0,   ///< a measurement of the fit
  kOutlierHit = 1,  ///< rejected by the fit
  /// On a looper's further half-turn, joined to the track but not fitted:
  /// the fit measures the first half-turn (docs/algorithm.md 3.17).
  kTurnHit = 2,
};

/// A track of one event.
struct Track {
  /// Hits along the path (event hit indices), including outliers; a
  /// looper's further-turn hits follow those of its first half-turn.
  std::vector<HitIndex> hits;
  /// Per hit: a HitUse (0: fitted; non-zero: an outlier in the ACTS sense,
  /// on the track but not in its fit).
  std::vector<std::uint8_t> outlier;
  /// Finding: step that created the track, pT and charge estimates from
  /// the conformal fit, and its two chi2/ndf values.
  std::uint16_t findingStep = 0;
  double ptEstimate = 0.0;
  int chargeEstimate = 0;
  double chi2Uv = 0.0;
  int ndfUv = 0;
  double chi2Sz = 0.0;
  int ndfSz = 0;
  /// Fitting: true once a Kalman fit succeeded.
  bool fitted = false;
  /// Fitted states: at the IP (the perigee about the beam line; reference
  /// = its point at z = 0, the origin unless the beams are off the axis),
  /// first and last hit.
  TrackState atIp;
  TrackState atFirstHit;
  TrackState atLastHit;
  double chi2 = 0.0;
  int ndf = 0;

  /// Number of hits used in the fit (kFittedHit).
  std::uint32_t numMeasurements() const;
  /// Number of hits that the fit rejected (kOutlierHit).
  std::uint32_t numOutliers() const;
  /// Number of a looper's further-turn hits (kTurnHit).
  std::uint32_t numTurnHits() const;
  /// The hits of the fit (kFittedHit), in track order, into `out`
  /// (cleared first; a buffer the caller reuses).
  void fittedHits(std::vector<HitIndex>& out) const;
  /// Takes the result of `fitted`, a fit of this track's leading hits (in
  /// the same order): its outlier flags for those hits, its states, chi2,
  /// ndf and status. Hits beyond (a looper's further turns) keep theirs;
  /// the finder's fields stay.
  void takeFit(const Track& fitted);
};

}  // namespace conftrack

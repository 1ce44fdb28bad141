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

/// A track of one event.
struct Track {
  /// Hits along the path (event hit indices), including outliers.
  std::vector<HitIndex> hits;
  /// Per hit: true if the fit rejected it as an outlier.
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
  /// Fitted states: at the IP (reference = origin), first and last hit.
  TrackState atIp;
  TrackState atFirstHit;
  TrackState atLastHit;
  double chi2 = 0.0;
  int ndf = 0;

  /// Number of hits used in the fit (not outliers).
  std::uint32_t numMeasurements() const;
  std::uint32_t numOutliers() const;
};

}  // namespace conftrack

#pragma once

/// @file TrackResiduals.hpp
/// Residuals (reconstructed - true) and pulls (residual / fitted
/// uncertainty) of the track parameters at the IP, and the kinematics of a
/// reconstructed track used to bin fake and duplicate rates.

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Track.hpp"

#include <array>
#include <cstddef>
#include <string_view>

namespace conftrack {

/// Transverse momentum, polar angle and azimuth of a reconstructed track.
struct TrackKinematics {
  double pt = 0.0;     ///< [GeV]
  double theta = 0.0;  ///< [rad], in [0, pi]
  double phi = 0.0;    ///< [rad], in (-pi, pi]
  /// True if taken from the fitted state at the IP; false if from the
  /// finder's pT estimate and the hit positions.
  bool fromFit = false;
};

/// Kinematics of `track`: from the fitted IP state if `track.fitted`
/// (pT = kPtPerTeslaMm |bz| / |Omega|, theta = atan2(1, tanLambda)),
/// otherwise pT from the finder's estimate and theta, phi from the
/// direction origin -> outermost hit (an approximation for prompt tracks,
/// good to the chord-versus-arc difference).
TrackKinematics trackKinematics(const Track& track, const Event& event,
                                double bz);

/// The LCIO parameters of a true particle (physics.md 3 "From a true
/// particle"): the production vertex and momentum moved to the PCA to the
/// line parallel to z through `reference` along the ideal helix (by
/// default the origin; a track's residuals use its perigee's reference,
/// the beam line it was fitted about).
TrackVector trueTrackParameters(const Particle& particle, double bz,
                                const Vector3& reference = Vector3::Zero());

/// Quantities whose resolution is measured.
enum ResidualQuantity : int {
  eResidualD0 = 0,     ///< d0 [mm]
  eResidualZ0,         ///< z0 [mm]
  eResidualPhi0,       ///< phi0 [rad], wrapped into (-pi, pi]
  eResidualTheta,      ///< theta [rad]
  eResidualPt,         ///< pT [GeV]
  eResidualPtOverPt2,  ///< (pT_reco - pT_true) / pT_true^2 [1/GeV]
  eNumResidualQuantities
};

/// Quantities whose pull is measured: the five LCIO parameters, then pT
/// (sigma from Omega: sigma(pT) = pT sigma(Omega) / |Omega|) and theta
/// (sigma from tanLambda: sigma(theta) = sigma(tanLambda) / (1 + tan^2)).
enum PullQuantity : int {
  ePullD0 = 0,
  ePullZ0,
  ePullPhi0,
  ePullOmega,
  ePullTanLambda,
  ePullPt,
  ePullTheta,
  eNumPullQuantities
};

/// Name used in files ("d0", "z0", "phi0", "theta", "pt", "pt_over_pt2").
std::string_view residualName(ResidualQuantity quantity);
/// Unit of the reported resolutions ("um", "mrad", "GeV", "1/GeV").
std::string_view residualUnit(ResidualQuantity quantity);
/// Factor from native units to residualUnit() (e.g. 1000 for mm -> um).
double residualScale(ResidualQuantity quantity);
/// Name used in files ("d0", "z0", "phi0", "omega", "tanlambda", "pt",
/// "theta").
std::string_view pullName(PullQuantity quantity);

/// Residuals and pulls of one fitted track against its true particle.
struct TrackResidual {
  /// Generated pT [GeV] and polar angle [rad] of the particle.
  double truePt = 0.0;
  double trueTheta = 0.0;
  /// Indexed by ResidualQuantity, native units.
  std::array<double, eNumResidualQuantities> residuals{};
  /// Indexed by PullQuantity; NaN where the variance is not positive.
  std::array<double, eNumPullQuantities> pulls{};
};

/// Residuals and pulls of `track.atIp` (reference: origin) against
/// `particle` in the field `bz`. Requires a fitted track.
TrackResidual computeTrackResidual(const Track& track, const Particle& particle,
                                   double bz);

}  // namespace conftrack

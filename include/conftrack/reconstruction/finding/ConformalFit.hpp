#pragma once

/// @file ConformalFit.hpp
/// The two regressions of conformal tracking (upstream.md 7): a weighted
/// fit of y' = c + m x' (+ q x'^2) in a rotated conformal frame, and a
/// weighted straight-line fit of z versus the arc length s.
///
/// Improvements over upstream (upstream.md 14.1): ndf = n - (number of
/// parameters); the covariance is the inverse normal matrix; residual
/// variances use the full 2-D conformal hit covariance projected on the
/// fitted curve (effective variance); degenerate systems are reported as
/// invalid instead of silently passing. Both fits expose the exact chi2
/// increment of adding one point, e^2 / (sigma_e^2 + h^T C h), so that
/// extensions test a hit in O(1) without refitting.

#include "conftrack/core/Types.hpp"
#include "conftrack/reconstruction/finding/ConformalHits.hpp"

#include <span>

namespace conftrack {

/// Result of the fit in the conformal plane, and the circle it implies.
struct ConformalFitResult {
  bool valid = false;
  bool quadratic = false;
  /// Frame: x' along (cosA, sinA), y' along (-sinA, cosA).
  double cosA = 1.0;
  double sinA = 0.0;
  /// (c, m, q): y' = c + m x' + q x'^2 (q = 0 for the straight line).
  Eigen::Vector3d params = Eigen::Vector3d::Zero();
  /// Covariance of the parameters (inverse normal matrix).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double chi2 = 0.0;
  int ndf = 0;
  /// Circle through the origin implied by (c, m): centre [mm], radius [mm].
  double centreX = 0.0;
  double centreY = 0.0;
  double radius = 0.0;
  /// Direction of motion around the centre: +1 counter-clockwise (negative
  /// charge for Bz > 0), -1 clockwise (positive charge).
  int orientation = 1;

  double chi2PerNdf() const { return ndf > 0 ? chi2 / ndf : 0.0; }
  /// Charge sign for a field along +z.
  int charge() const { return -orientation; }
  /// Transverse momentum [GeV] in a field bz [T].
  double pt(double bz) const;
  /// Exact chi2 increment of adding hit i. `extraVariance` is added to the
  /// hit's variance perpendicular to the curve (conformal units squared),
  /// e.g. an allowance for multiple scattering, which the fit ignores.
  double deltaChi2(const ConformalHits& hits, ConfIndex i,
                   double extraVariance = 0.0) const;
  /// Residual of hit i (y' minus the curve at its x'), and in `variance`
  /// its variance from the hit's own errors.
  double residual(const ConformalHits& hits, ConfIndex i,
                  double& variance) const;
};

/// Fits the hits (in track order: along the particle's path). With
/// `frameFrom` the rotation of an earlier fit is reused, so that
/// parameters stay comparable while a track grows.
ConformalFitResult fitConformal(const ConformalHits& hits,
                                std::span<const ConfIndex> track,
                                bool quadratic,
                                const ConformalFitResult* frameFrom = nullptr);

/// Arc-length bookkeeping on the fitted circle: s = radius * turning angle
/// from the track's first hit, in the direction of motion.
struct ArcFrame {
  double centreX = 0.0;
  double centreY = 0.0;
  double radius = 0.0;
  int orientation = 1;
  double beta0 = 0.0;  ///< angle of the first hit around the centre

  /// Arc length of the point (x, y), taking the turn closest to `near`.
  double arcLength(double x, double y, double near) const;
  /// Arc length of hit h: that of its position in the conformal map (at
  /// radius g r, on the circle of a track from the beam line) divided by
  /// g, which is the transverse path of such a track in the field the map
  /// corrects for (PromptBending; g = 1, the hit's own position, in a
  /// uniform field). Near the apex of a low-momentum track the hit's own
  /// position lies off the mapped circle and its angle there is no
  /// measure of the path.
  double hitArcLength(const ConformalHits& hits, ConfIndex h,
                      double near) const;
  /// Arc length of hit h on a track whose z follows the line through
  /// (sRef, zRef) with slope tanLambda: of the turn closest to `near` and
  /// the turns either side of it, the one whose z lies nearest the line,
  /// unless that improves the z distance by less than
  /// kTurnChoiceMargin (then the turn closest to `near`). A track that
  /// runs more than half a turn between two hits (a forward low-momentum
  /// track from the vertex barrel to a disk) would otherwise get a hit
  /// put a whole turn back, and its s-z line a z error of tanLambda times
  /// the circumference. With `follows` the hit comes after `near` along
  /// the track: only the next turn is tried, and only if the nearest one
  /// lies behind `near`.
  double helixArcLength(const ConformalHits& hits, ConfIndex h, double near,
                        double sRef, double zRef, double tanLambda,
                        bool follows = false) const;
  /// Point on the circle at arc length s.
  Vector2 pointAt(double s) const;
};

/// The least z improvement for which helixArcLength takes another turn
/// than the one nearest the expected arc length [mm]: the wrong turn puts
/// a hit tanLambda times the circumference (hundreds of millimetres for a
/// forward low-momentum track) off, while a central looper's turns differ
/// in z by less than this and stay with the nearest one.
inline constexpr double kTurnChoiceMargin = 10.0;

/// Builds the arc frame of a circle fit with the first hit as origin.
ArcFrame makeArcFrame(const ConformalFitResult& circle,
                      const ConformalHits& hits, ConfIndex first);

/// Result of the fit z = z0 + tanLambda * s.
struct SzFitResult {
  bool valid = false;
  double z0 = 0.0;
  double tanLambda = 0.0;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  double chi2 = 0.0;
  int ndf = 0;
  /// Arc length of the last hit of the track.
  double lastS = 0.0;

  double chi2PerNdf() const { return ndf > 0 ? chi2 / ndf : 0.0; }
  /// Exact chi2 increment of adding a point (s, z) with variances.
  double deltaChi2(double s, double z, double varZ, double varS) const;
  /// Residual z - z(s) of a point, and in `variance` its variance from the
  /// point's own errors.
  double residual(double s, double z, double varZ, double varS,
                  double& variance) const;
};

/// Fits z versus s for the hits (track order), s from the arc frame.
SzFitResult fitSz(const ConformalHits& hits, std::span<const ConfIndex> track,
                  const ArcFrame& arc);

}  // namespace conftrack

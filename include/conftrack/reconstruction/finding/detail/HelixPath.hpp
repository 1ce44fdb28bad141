#pragma once

/// @file HelixPath.hpp
/// Real-space pieces of the helix step for displaced tracks, shared by its
/// seeding (HelixTracks.cpp) and its following (HelixFollower.hpp): a
/// track's circle in the transverse plane, a candidate's hits with their
/// arc lengths, and its fits in the (s, z) plane.

#include "conftrack/geometry/Surfaces.hpp"
#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace conftrack::detail {

/// A crossing this far inside a layer's edges without a hit is a miss [mm].
inline constexpr double kHelixEdgeMargin = 10.0;

/// A circle in the transverse plane with a direction of motion.
struct TransverseCircle {
  double cx = 0.0;
  double cy = 0.0;
  double rho = 0.0;
  int orientation = 1;  ///< +1 counter-clockwise

  /// Arc length from point a to point b along the motion, in [0, 2 pi rho).
  double arc(double ax, double ay, double bx, double by) const {
    const double pax = ax - cx;
    const double pay = ay - cy;
    const double pbx = bx - cx;
    const double pby = by - cy;
    double angle =
        orientation * std::atan2(pax * pby - pay * pbx, pax * pbx + pay * pby);
    if (angle < 0.0) {
      angle += 2.0 * std::numbers::pi;
    }
    return rho * angle;
  }
  /// Distance of closest approach to the beam line.
  double d0() const { return std::abs(norm2(cx, cy) - rho); }
};

/// The circle through three points, oriented from the first to the last;
/// false if they are (numerically) on a line.
bool circleThrough(double x1, double y1, double x2, double y2, double x3,
                   double y3, TransverseCircle& out);

/// Least-squares circle through points (algebraic distance, Kasa): exact
/// for three points; false if degenerate or (numerically) straight.
/// `orientation` comes from the first, middle and last points.
bool fitCircle(const ConformalHits& hits, std::span<const ConfIndex> idx,
               TransverseCircle& out);

/// Smallest distance between two layers' extents [mm].
double layerDistance(const SensitiveLayer& a, const SensitiveLayer& b);

/// A candidate being followed: hits with their arc lengths along the
/// track, and the straight-line fit z = z0 + t s.
struct HelixPath {
  std::vector<ConfIndex> hits;
  std::vector<double> s;
  double chi2 = 0.0;
  double z0 = 0.0;
  double t = 0.0;
};

/// Weighted straight-line fit z = z0 + t s over the path's hits (sets
/// p.z0 and p.t); the error of s on disks (from the radial resolution)
/// enters through the previous slope.
void fitPathSz(const ConformalHits& hits, HelixPath& p);

/// The track's z and slope dz/ds after its last hit, filtered hit by hit
/// along s with the multiple scattering of each layer crossed (a Kalman
/// filter in the (s, z) plane): unlike one straight line through all hits,
/// it follows the slope changes that scattering makes at low momentum.
struct SzState {
  double z = 0.0;
  double t = 0.0;
  double varZ = 0.0;
  double covZt = 0.0;
  double varT = 0.0;

  /// Predicted z a distance ds further along, and its variance.
  double zAt(double ds) const { return z + t * ds; }
  double varAt(double ds) const {
    return varZ + 2.0 * ds * covZt + ds * ds * varT;
  }
};

/// Filters the path's hits along s (SzState): starts at the first hit
/// with the slope of the straight-line fit (p.t), then at each further hit
/// propagates, adds the scattering of the layer just left
/// (helixTheta0 at transverse momentum pt) to the slope's variance and
/// updates with the hit's z (on a disk its radial error, moved along the
/// track, enters as t^2 varRxy).
SzState filterPathSz(const ConformalHits& hits, const HelixPath& p,
                     const std::vector<SensitiveLayer>& layers, double minPt,
                     double pt);

/// Highland width of the deflection in `layer` for a track of transverse
/// momentum pt (at least minPt) and slope t = tan(lambda).
double helixTheta0(const SensitiveLayer& layer, double minPt, double pt,
                   double t);

/// A hit's transverse resolution [mm]: its conformal tangential error
/// scaled back by R^2.
double transverseSigma(const ConformalHits& hits, ConfIndex h);

/// HelixPredictionError's inputs for the hits `path` (in the order of the
/// search): each hit's transverseSigma in `sigma` and, in `kink`, the
/// transverse scattering angle in its layer (helixTheta0 at pt, floor
/// minPt, slope t, over cos(lambda)), once per layer crossing (the second
/// hit of an overlap adds none).
void predictionErrorInputs(const ConformalHits& hits,
                           const std::vector<SensitiveLayer>& layers,
                           std::span<const ConfIndex> path, double minPt,
                           double pt, double t, std::vector<double>& sigma,
                           std::vector<double>& kink);

/// Transverse momentum [GeV] of a circle of radius c.rho in the field bz.
double circlePt(const TransverseCircle& c, double bz);

}  // namespace conftrack::detail

#pragma once

/// @file FitterState.hpp
/// Internals of KalmanFitter shared by its source files (the filter and
/// smoother, the propagation, the measurement update): the states between
/// and at nodes, where a hit is measured, and numerical constants. Not part
/// of the public API.

#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace conftrack {

namespace detail {

using Matrix25 = Eigen::Matrix<double, 2, 5>;
using Matrix52 = Eigen::Matrix<double, 5, 2>;

inline constexpr double kInf = std::numeric_limits<double>::infinity();
/// Smallest arc between two crossings, as the simulation (a surface just
/// crossed is not found again within it) [mm].
inline constexpr double kMinStep = 1e-4 * units::mm;
/// Largest distance along the track between a node's PCA and the crossing
/// of its own surface that is still taken as "the same crossing" [mm]:
/// after an update the PCA moves by about the residual, divided by the
/// cosine of the crossing angle along the track.
inline constexpr double kOwnCrossingTolerance = 1.0 * units::m;
/// Longest transverse arc searched for the next node [mm].
inline constexpr double kMaxArc = 100.0 * units::m;
/// A point closer than this to a surface is on it [mm].
inline constexpr double kOnSurface = 1e-9 * units::mm;

/// Crossing of the surface extended to infinity (cylinder in z, disk in
/// r): a hit is on its layer even where the predicted track just misses
/// the layer's edge.
double crossExtended(const Helix& helix, const NavigationSurface& surface,
                     double sMin, double sMax);

/// Makes `c` exactly symmetric (rounding in the products breaks it).
inline void symmetrize(TrackCovariance& c) {
  c = 0.5 * (c + c.transpose()).eval();
}

}  // namespace detail

/// A state on its way between nodes: parameters and covariance relative
/// to `pivot`, and the accumulated transport Jacobian since the last node
/// (without process noise: the RTS smoother needs F, and the predicted
/// covariance F C F^T + Q).
struct KalmanFitter::Propagation {
  Vector3 pivot = Vector3::Zero();
  TrackVector params = TrackVector::Zero();
  TrackCovariance cov = TrackCovariance::Zero();
  TrackJacobian jacobian = TrackJacobian::Identity();
};

/// Where one hit is measured: the layer whose crossing carries the
/// navigation and the material, and the measurement plane through the hit
/// (its sensor's orientation) with the local axes of the residual.
struct KalmanFitter::Measurement {
  /// Index of the layer's surface in the navigator (sensitive layers
  /// first, so it is also the layer index).
  std::uint32_t surface = 0;
  /// The hit: a point of the plane [mm].
  Vector3 origin = Vector3::Zero();
  /// Unit axes of the residual (u, v), matching Hit::sigmaU / sigmaV.
  Vector3 uAxis = Vector3::UnitX();
  Vector3 vAxis = Vector3::UnitZ();
  /// Unit normal of the plane, uAxis x vAxis.
  Vector3 normal = Vector3::UnitY();
};

/// A hit node of a filter pass.
struct KalmanFitter::Node {
  /// Index of the hit in FitInput::hits.
  std::uint32_t hit = 0;
  /// Predicted crossing of the hit's measurement surface: the reference
  /// point.
  Vector3 pivot = Vector3::Zero();
  TrackVector predicted = TrackVector::Zero();
  TrackCovariance predictedCov = TrackCovariance::Zero();
  TrackVector filtered = TrackVector::Zero();
  TrackCovariance filteredCov = TrackCovariance::Zero();
  /// Transport from the previous node of the pass.
  TrackJacobian jacobian = TrackJacobian::Identity();
  /// True once its hit is used (an outlier's node is removed).
  bool used = false;
};

/// The nodes and chi2 of one filter pass.
struct KalmanFitter::Pass {
  std::vector<Node> nodes;
  double chi2 = 0.0;
  std::uint32_t used = 0;
};

}  // namespace conftrack

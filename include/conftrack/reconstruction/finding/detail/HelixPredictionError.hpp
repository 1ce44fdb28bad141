#pragma once

/// @file HelixPredictionError.hpp
/// The transverse error of a helix-step prediction (HelixFollower): how far
/// the circle fitted to a path's hits may miss the particle an arc length
/// ds beyond its last hit, from the hits' resolution and from the multiple
/// scattering in every layer the path crossed.

#include <Eigen/Dense>

#include <span>
#include <vector>

namespace conftrack::detail {

/// Variances of a path's transverse prediction [mm^2], in the linear
/// approximation where the circle is a parabola y(s) = a + b s + c s^2 in
/// the transverse arc length s (the fitted circle is exact for three hits
/// and close to a least-squares fit for more).
///
/// - Resolution: the weighted least-squares parabola through the hits
///   (weights 1 / sigma_k^2) predicts at s with the variance
///   f(s)^T (sum_k f_k f_k^T / sigma_k^2)^-1 f(s), f = (1, s, s^2). For
///   three hits this is their Lagrange extrapolation: three pixel-disk
///   hits 13 mm apart miss the next disk, 16.5 mm on, by 5.7 sigma_hit,
///   where the former estimate (the last hit's error grown by 1 +
///   (ds / lever)^2) gave 1.4.
/// - Scattering: a kink theta_k at hit k moves the particle by theta_k
///   (s - s_k) beyond it; the fit follows part of that through the later
///   hits, and the prediction misses by theta_k g_k(s) with g_k(s) = (s -
///   s_k) - sum_{j > k} a_j(s) (s_j - s_k), a_j(s) the fit's weights of
///   the hits in its prediction at s. The variance sums theta_k^2 g_k^2
///   over every kink of the path, not only the last layer's.
///
/// Reused from path to path (scratch buffers; no allocation once they
/// have grown).
class HelixPredictionError {
 public:
  /// Sets up for a path: `s` the arc lengths of its hits (ascending, the
  /// last hit's the largest) [mm], `sigma` their transverse errors [mm],
  /// `kink` the transverse scattering angle in each hit's layer [rad] (0
  /// where the particle crossed no new material, e.g. the second hit of an
  /// overlap). False if the hits do not fix a parabola (fewer than three
  /// distinct arc lengths, a non-positive error): then both variances are
  /// 0 and the caller keeps its own estimate.
  bool reset(std::span<const double> s, std::span<const double> sigma,
             std::span<const double> kink);

  /// Variance from the hits' resolution at ds beyond the last hit [mm^2].
  double resolutionVariance(double ds) const;
  /// Variance from the scattering of the path's kinks at ds beyond the
  /// last hit [mm^2]; includes the kink in the last hit's layer (theta (ds)
  /// for it alone).
  double scatteringVariance(double ds) const;

 private:
  /// f(s) for the scaled arc length u = (s - s_last) / lever.
  static Eigen::Vector3d basis(double u) { return {1.0, u, u * u}; }

  bool m_valid = false;
  /// The path's length (s_last - s_first, at least 1 mm): the arc lengths
  /// are scaled by it so that the normal matrix is well conditioned.
  double m_lever = 1.0;
  std::vector<double> m_u;      ///< scaled arc lengths, last hit at 0
  std::vector<double> m_kink2;  ///< kink variances [rad^2]
  std::vector<Eigen::Vector3d> m_weighted;  ///< f_k / sigma_k^2
  Eigen::Matrix3d m_covariance = Eigen::Matrix3d::Zero();
};

}  // namespace conftrack::detail

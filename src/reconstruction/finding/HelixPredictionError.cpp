// The transverse prediction error of a helix path
// (detail/HelixPredictionError.hpp).

#include "conftrack/reconstruction/finding/detail/HelixPredictionError.hpp"

#include <algorithm>
#include <cstddef>

namespace conftrack::detail {

bool HelixPredictionError::reset(std::span<const double> s,
                                 std::span<const double> sigma,
                                 std::span<const double> kink) {
  m_valid = false;
  const std::size_t n = s.size();
  m_u.resize(n);
  m_kink2.resize(n);
  m_weighted.resize(n);
  if (n < 3 || sigma.size() != n || kink.size() != n) {
    return false;
  }
  m_lever = std::max(s[n - 1] - s[0], 1.0);
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    if (!(sigma[k] > 0.0)) {
      return false;
    }
    m_u[k] = (s[k] - s[n - 1]) / m_lever;
    const Eigen::Vector3d f = basis(m_u[k]);
    m_weighted[k] = f / (sigma[k] * sigma[k]);
    normal += f * m_weighted[k].transpose();
    m_kink2[k] = kink[k] * kink[k];
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(normal);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
    return false;
  }
  m_covariance = ldlt.solve(Eigen::Matrix3d::Identity());
  // Collinear bases (fewer than three distinct arc lengths) leave a
  // singular normal matrix that LDLT may still factorise.
  if (!m_covariance.allFinite() ||
      !(m_covariance.diagonal().minCoeff() > 0.0)) {
    return false;
  }
  m_valid = true;
  return true;
}

double HelixPredictionError::resolutionVariance(double ds) const {
  if (!m_valid) {
    return 0.0;
  }
  const Eigen::Vector3d f = basis(ds / m_lever);
  return std::max(0.0, f.dot(m_covariance * f));
}

double HelixPredictionError::scatteringVariance(double ds) const {
  if (!m_valid) {
    return 0.0;
  }
  const double u = ds / m_lever;
  // a_j(u) = f(u)^T C f_j / sigma_j^2; g_k needs the sums of a_j and
  // a_j u_j over the hits after k, taken from the last hit backwards.
  const Eigen::Vector3d cf = m_covariance * basis(u);
  double sumA = 0.0;
  double sumAU = 0.0;
  double variance = 0.0;
  for (std::size_t k = m_u.size(); k-- > 0;) {
    const double g = m_lever * ((u - m_u[k]) - (sumAU - m_u[k] * sumA));
    variance += m_kink2[k] * g * g;
    const double a = cf.dot(m_weighted[k]);
    sumA += a;
    sumAU += a * m_u[k];
  }
  return variance;
}

}  // namespace conftrack::detail

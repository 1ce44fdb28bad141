#include "conftrack/geometry/MagneticField.hpp"

#include <cmath>
#include <stdexcept>

namespace conftrack {

MagneticField::MagneticField(const Config& config) : m_config(config) {
  if (!(m_config.centralBz >= 0.0)) {
    throw std::invalid_argument("MagneticField: centralBz must be >= 0");
  }
  if (!(m_config.solenoidRadius >= 0.0)) {
    throw std::invalid_argument("MagneticField: solenoidRadius must be >= 0");
  }
  if (m_config.solenoidRadius > 0.0 &&
      !(m_config.solenoidHalfLength > 0.0 && m_config.centralBz > 0.0)) {
    throw std::invalid_argument(
        "MagneticField: a solenoid needs a positive solenoidHalfLength and "
        "centralBz");
  }
  if (!isUniform()) {
    double g = 0.0;
    double g1 = 0.0;
    double g2 = 0.0;
    double g3 = 0.0;
    profile(0.0, g, g1, g2, g3);
    m_scale = m_config.centralBz / g;
  }
}

void MagneticField::profile(double z, double& g, double& g1, double& g2,
                            double& g3) const {
  // f(u) = u / sqrt(u^2 + a^2): the on-axis field of the sheet from its end
  // at distance u; f' = a^2 / q^(3/2), f'' = -3 a^2 u / q^(5/2), f''' =
  // 3 a^2 (4 u^2 - a^2) / q^(7/2), q = u^2 + a^2.
  const double a2 = m_config.solenoidRadius * m_config.solenoidRadius;
  const double half = m_config.solenoidHalfLength;
  g = g1 = g2 = g3 = 0.0;
  for (const double sign : {-1.0, 1.0}) {
    // u = L - z (sign -1) and L + z (sign +1); du/dz = sign.
    const double u = half + sign * z;
    const double q = u * u + a2;
    const double root = std::sqrt(q);
    g += u / root;
    g1 += sign * a2 / (q * root);
    g2 += -3.0 * a2 * u / (q * q * root);
    g3 += sign * 3.0 * a2 * (4.0 * u * u - a2) / (q * q * q * root);
  }
}

Vector3 MagneticField::at(const Vector3& position) const {
  if (isUniform()) {
    return {0.0, 0.0, m_config.centralBz};
  }
  double g = 0.0;
  double g1 = 0.0;
  double g2 = 0.0;
  double g3 = 0.0;
  profile(position.z(), g, g1, g2, g3);
  const double r2 = position.x() * position.x() + position.y() * position.y();
  const double bz = m_scale * (g - 0.25 * r2 * g2);
  // B_r = r (-g'/2 + r^2 g'''/16) and (x, y) = r (cos, sin); with this
  // B_z, div B = 0 exactly and curl B = O(r^3 g'''').
  const double radial = m_scale * (-0.5 * g1 + r2 * g3 / 16.0);
  return {radial * position.x(), radial * position.y(), bz};
}

double MagneticField::bendingComponent(const Vector3& field,
                                       const Vector3& direction) {
  const double transverse =
      std::sqrt(direction.x() * direction.x() + direction.y() * direction.y());
  const double alongT =
      (field.x() * direction.x() + field.y() * direction.y()) / transverse;
  return field.z() - direction.z() / transverse * alongT;
}

}  // namespace conftrack

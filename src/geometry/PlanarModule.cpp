#include "conftrack/geometry/PlanarModule.hpp"

#include <algorithm>
#include <cmath>

namespace conftrack {

double PlanarModule::halfUAt(double v) const {
  const double f = std::clamp((v + halfV) / (2.0 * halfV), 0.0, 1.0);
  return minHalfU + f * (maxHalfU - minHalfU);
}

bool PlanarModule::contains(double u, double v) const {
  return std::abs(v) <= halfV && std::abs(u) <= halfUAt(v);
}

std::array<Vector3, 4> PlanarModule::corners() const {
  const Vector3 u = uAxis();
  const Vector3 v = vAxis();
  return {center - minHalfU * u - halfV * v, center + minHalfU * u - halfV * v,
          center + maxHalfU * u + halfV * v, center - maxHalfU * u + halfV * v};
}

}  // namespace conftrack

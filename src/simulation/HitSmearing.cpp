#include "conftrack/simulation/HitSmearing.hpp"

#include <cmath>

namespace conftrack {

bool smearHitPosition(const SensitiveLayer& layer, const Vector3& truePosition,
                      RandomEngine& rng,
                      std::normal_distribution<double>& normal,
                      unsigned maxAttempts, Vector3& measured) {
  if (layer.isDisk()) {
    Vector3 uAxis;
    Vector3 vAxis;
    layer.localAxes(truePosition, uAxis, vAxis);
    const double r2Min = layer.rMin * layer.rMin;
    const double r2Max = layer.rMax * layer.rMax;
    for (unsigned attempt = 0; attempt < maxAttempts; ++attempt) {
      const double du = layer.sigmaU * normal(rng);
      const double dv = layer.sigmaV * normal(rng);
      Vector3 p = truePosition + du * uAxis + dv * vAxis;
      p.z() = layer.z();
      const double r2 = p.head<2>().squaredNorm();
      if (r2 >= r2Min && r2 <= r2Max) {
        measured = p;
        return true;
      }
    }
    return false;
  }
  const double phi = std::atan2(truePosition.y(), truePosition.x());
  for (unsigned attempt = 0; attempt < maxAttempts; ++attempt) {
    const double du = layer.sigmaU * normal(rng);
    const double dv = layer.sigmaV * normal(rng);
    const double z = truePosition.z() + dv;
    if (z >= layer.zMin && z <= layer.zMax) {
      const double phiNew = phi + du / layer.r;
      measured = {layer.r * std::cos(phiNew), layer.r * std::sin(phiNew), z};
      return true;
    }
  }
  return false;
}

}  // namespace conftrack

#include "conftrack/geometry/Surfaces.hpp"

#include "conftrack/core/Hit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace conftrack {

namespace {
std::uint32_t binOf(double x, double lo, double hi, std::uint32_t n) {
  if (n <= 1 || !(hi > lo)) {
    return 0;
  }
  double f = (x - lo) / (hi - lo);
  auto i = static_cast<std::int64_t>(std::floor(f * n));
  return static_cast<std::uint32_t>(
      std::clamp<std::int64_t>(i, 0, static_cast<std::int64_t>(n) - 1));
}
}  // namespace

std::uint32_t SensitiveLayer::moduleAt(const Vector3& position) const {
  double phi = std::atan2(position.y(), position.x());
  std::uint32_t iPhi =
      binOf(phi, -std::numbers::pi, std::numbers::pi, nPhiModules);
  std::uint32_t iSlow =
      isDisk() ? binOf(position.head<2>().norm(), rMin, rMax, nZModules)
               : binOf(position.z(), zMin, zMax, nZModules);
  return iSlow * nPhiModules + iPhi;
}

void SensitiveLayer::localAxes(const Vector3& position, Vector3& uAxis,
                               Vector3& vAxis) const {
  localMeasurementAxes(position, isDisk(), uAxis, vAxis);
}

}  // namespace conftrack

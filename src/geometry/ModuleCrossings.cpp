#include "conftrack/geometry/ModuleCrossings.hpp"

#include <algorithm>
#include <cmath>

namespace conftrack {

namespace {

/// Largest distance between the layer crossing and a sensor crossing that
/// is searched [mm]: at grazing incidence the bound shell / |cos alpha|
/// grows without limit, but a track that grazes a layer over more than
/// this is a looper turning in it, which leaves a hit on the sensors it
/// crosses nearest to the layer crossing anyway.
constexpr double kMaxShift = 200.0;
/// Newton iterations and convergence in s [mm].
constexpr int kMaxIterations = 12;
constexpr double kTolerance = 1e-7;

}  // namespace

void findModuleCrossings(const Helix& helix, double sLayer, double sMin,
                         std::uint32_t layer, const ModuleLayout& layout,
                         std::vector<std::uint32_t>& scratch,
                         std::vector<ModuleCrossing>& crossings) {
  Vector3 point;
  Vector3 momentum;
  helix.positionAndMomentum(sLayer, point, momentum);
  const Vector3 direction = momentum.normalized();
  const double r = point.head<2>().norm();
  // Cosine of the incidence on the layer surface (radial or along z).
  double cosLayer = 0.0;
  if (layout.layerIsDisk(layer)) {
    cosLayer = std::abs(direction.z());
  } else if (r > 0.0) {
    cosLayer = std::abs(direction.head<2>().dot(point.head<2>()) / r);
  }
  const double shell = layout.shellHalfThickness(layer);
  const double sine = std::sqrt(std::max(0.0, 1.0 - cosLayer * cosLayer));
  const double shift = cosLayer > 0.0
                           ? std::min(kMaxShift, shell * sine / cosLayer + 1.0)
                           : kMaxShift;
  const double v = layout.layerIsDisk(layer) ? r : point.z();
  scratch.clear();
  layout.candidates(layer, std::atan2(point.y(), point.x()), v,
                    r > shift ? std::asin(shift / r) : 3.2, shift, scratch);

  // The window in s: the 3-D distance bounds the transverse arc.
  const double window = shift + shell;
  const std::size_t first = crossings.size();
  for (std::uint32_t index : scratch) {
    const PlanarModule& m = layout.modules()[index];
    const double s = helix.planeCrossing(m.center, m.normal(), sLayer, window,
                                         kMaxIterations, kTolerance);
    if (s == Helix::kNoCrossing || !(s > sMin)) {
      continue;
    }
    const Vector3 local = m.toLocal(helix.position(s));
    if (m.contains(local.x(), local.y())) {
      crossings.push_back({s, index, local.x(), local.y()});
    }
  }
  std::sort(crossings.begin() + static_cast<std::ptrdiff_t>(first),
            crossings.end(),
            [](const ModuleCrossing& a, const ModuleCrossing& b) {
              return a.s < b.s || (a.s == b.s && a.module < b.module);
            });
}

}  // namespace conftrack

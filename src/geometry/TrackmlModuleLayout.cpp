#include "conftrack/geometry/TrackmlModuleLayout.hpp"

#include "conftrack/core/Error.hpp"

#include <cmath>
#include <string>

namespace conftrack {

ModuleLayout buildTrackmlModuleLayout(const std::vector<TrackmlModule>& modules,
                                      const Detector& detector,
                                      const TrackmlDetectorOptions& options) {
  const double sqrt12 = std::sqrt(12.0);
  std::vector<PlanarModule> sensors;
  sensors.reserve(modules.size());
  for (const TrackmlModule& m : modules) {
    const auto layer = detector.findTrackmlLayer(m.volume, m.layer);
    if (!layer) {
      throw InputError(options.source,
                       "module (volume_id, layer_id, module_id) = (" +
                           std::to_string(m.volume) + ", " +
                           std::to_string(m.layer) + ", " +
                           std::to_string(m.module) +
                           ") is on no layer of detector " + detector.name());
    }
    PlanarModule& s = sensors.emplace_back();
    s.layer = *layer;
    s.module = m.module;
    s.center = m.center;
    s.rotation = m.rotation;
    s.minHalfU = m.minHalfU;
    s.maxHalfU = m.maxHalfU;
    s.halfV = m.halfV;
    s.thickness = m.thickness;
    s.thicknessX0 = m.thickness / options.moduleX0;
    s.sigmaU = m.pitchU / sqrt12;
    s.sigmaV = m.pitchV / sqrt12;
  }
  const double support = options.supportThickness > 0.0
                             ? options.supportThickness / options.supportX0
                             : 0.0;
  return ModuleLayout(detector, std::move(sensors),
                      std::vector<double>(detector.layers().size(), support));
}

}  // namespace conftrack

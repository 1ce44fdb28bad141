#include "conftrack/geometry/Detector.hpp"

#include <utility>

namespace conftrack {

namespace {
/// The TrackML view of `layers` (the fields the io functions use).
std::vector<TrackmlLayer> trackmlLayers(
    const std::vector<SensitiveLayer>& layers) {
  std::vector<TrackmlLayer> out;
  out.reserve(layers.size());
  for (const SensitiveLayer& l : layers) {
    TrackmlLayer t;
    t.name = l.name;
    t.id = l.id;
    t.volume = l.trackmlVolume;
    t.layer = l.trackmlLayer;
    t.disk = l.isDisk();
    t.r = l.r;
    t.zMin = l.zMin;
    t.zMax = l.zMax;
    t.rMin = l.rMin;
    t.rMax = l.rMax;
    t.sigmaU = l.sigmaU;
    t.sigmaV = l.sigmaV;
    t.nPhiModules = l.nPhiModules;
    t.nZModules = l.nZModules;
    out.push_back(std::move(t));
  }
  return out;
}
}  // namespace

Detector::Detector(std::string name, std::string model, MagneticField field,
                   double envelopeR, double envelopeZ,
                   std::vector<Subdetector> subdetectors,
                   std::vector<SensitiveLayer> layers,
                   std::vector<PassiveSurface> passives)
    : m_name(std::move(name)),
      m_model(std::move(model)),
      m_field(std::move(field)),
      m_envelopeR(envelopeR),
      m_envelopeZ(envelopeZ),
      m_subdetectors(std::move(subdetectors)),
      m_layers(std::move(layers)),
      m_passives(std::move(passives)),
      m_trackml(m_name, m_envelopeR, m_envelopeZ, trackmlLayers(m_layers)) {}

std::optional<std::uint16_t> Detector::findSubdetector(
    std::string_view name) const {
  for (std::size_t i = 0; i < m_subdetectors.size(); ++i) {
    if (m_subdetectors[i].name == name) {
      return static_cast<std::uint16_t>(i);
    }
  }
  return std::nullopt;
}

std::optional<std::uint32_t> Detector::findLayer(const DetectorId& id) const {
  return m_trackml.find(id);
}

std::optional<std::uint32_t> Detector::findTrackmlLayer(
    std::uint32_t volume, std::uint32_t layer) const {
  return m_trackml.findTrackml(volume, layer);
}

}  // namespace conftrack

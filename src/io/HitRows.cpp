#include "conftrack/io/HitRows.hpp"

#include "conftrack/core/Units.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace conftrack {

namespace {

/// Hits closer to the beam line than this are refused: no tracking layer is
/// there, and the conformal mapping u = x / (x^2 + y^2) would overflow.
constexpr double kMinHitRadius = 1.0 * units::um;

/// How far a hit may lie from the nominal surface of the layer it claims
/// (normal to it and beyond its edges). Real modules are staggered and
/// tilted around the nominal layer: the real TrackML hits lie up to 6.1 mm
/// from the layers of detectors/trackml.toml, and the module-level
/// simulation of CLICdet puts the vertex-endcap spiral petals up to 20.7 mm
/// from their layer's mean z (geometry/LayoutModules.hpp). 25 mm admits
/// both with a margin and still refuses a hit that names the wrong layer or
/// none.
constexpr double kLayerTolerance = 25.0 * units::mm;

std::string millimetres(double value) {
  std::ostringstream os;
  os << std::setprecision(6) << value / units::mm << " mm";
  return os.str();
}

/// Refuses a hit that lies outside the tracker or away from the layer its
/// (volume_id, layer_id) names: such a file is corrupt or belongs to
/// another detector, and reconstruction would silently produce nonsense.
void checkOnLayer(const HitRowErrors& errors, const Hit& hit,
                  const TrackmlLayer& layer, const TrackmlLayerMap& detector) {
  // hypot: x^2 + y^2 overflows for the 1e308 of a corrupt file.
  const double r = std::hypot(hit.position.x(), hit.position.y());
  const double z = hit.position.z();
  // The message is built only for a hit that fails (most pass).
  auto at = [&] {
    return "hit_id " + std::to_string(hit.id) + " at r = " + millimetres(r) +
           ", z = " + millimetres(z);
  };
  if (!(r <= detector.envelopeR() && std::abs(z) <= detector.envelopeZ())) {
    errors.fail(at() + " lies outside the tracker of detector '" +
                detector.detectorName() +
                "' (r <= " + millimetres(detector.envelopeR()) +
                ", |z| <= " + millimetres(detector.envelopeZ()) + ")");
  }
  const bool on = layer.disk ? std::abs(z - layer.z()) <= kLayerTolerance &&
                                   r >= layer.rMin - kLayerTolerance &&
                                   r <= layer.rMax + kLayerTolerance
                             : std::abs(r - layer.r) <= kLayerTolerance &&
                                   z >= layer.zMin - kLayerTolerance &&
                                   z <= layer.zMax + kLayerTolerance;
  if (!on) {
    const std::string surface = layer.disk
                                    ? "z = " + millimetres(layer.z()) + ", " +
                                          millimetres(layer.rMin) +
                                          " <= r <= " + millimetres(layer.rMax)
                                    : "r = " + millimetres(layer.r) +
                                          ", |z| <= " + millimetres(layer.zMax);
    errors.fail(at() + " is not on the layer its volume_id/layer_id name (" +
                layer.name + ": " + surface + ", tolerance " +
                millimetres(kLayerTolerance) + ")");
  }
}

}  // namespace

HitRowBuilder::HitRowBuilder(const TrackmlLayerMap* layers)
    : m_layers(layers) {}

const TrackmlLayer* HitRowBuilder::findLayer(std::uint32_t volume,
                                             std::uint32_t layer) {
  if (m_layer == nullptr || volume != m_volume || layer != m_layerId) {
    auto index = m_layers->findTrackml(volume, layer);
    if (!index) {
      return nullptr;
    }
    m_layer = &m_layers->layers()[*index];
    m_volume = volume;
    m_layerId = layer;
  }
  return m_layer;
}

Hit HitRowBuilder::build(const HitRow& row, const HitRowErrors& errors) {
  Hit hit;
  hit.id = row.id;
  ++m_rows;
  if (m_contiguous && hit.id != m_rows) {
    m_contiguous = false;
    for (std::uint64_t id = 1; id < m_rows; ++id) {
      m_seen.insert(id);
    }
  }
  if (!m_contiguous && !m_seen.insert(hit.id).second) {
    errors.fail("duplicate hit_id " + std::to_string(hit.id));
  }
  hit.position = row.position * units::mm;
  if (!(std::hypot(hit.position.x(), hit.position.y()) >= kMinHitRadius)) {
    errors.fail("hit_id " + std::to_string(hit.id) +
                " lies on the beam line (sqrt(x^2 + y^2) < 1 um): no tracking "
                "layer is there and conformal coordinates are undefined");
  }
  const TrackmlId& tid = row.trackml;
  if (m_layers != nullptr) {
    const TrackmlLayer* layer = findLayer(tid.volume, tid.layer);
    if (layer == nullptr) {
      errors.fail("(volume_id, layer_id) = (" + std::to_string(tid.volume) +
                  ", " + std::to_string(tid.layer) +
                  ") is not a layer of detector '" + m_layers->detectorName() +
                  "'");
    }
    if (static_cast<std::uint64_t>(tid.module) >=
        static_cast<std::uint64_t>(layer->nPhiModules) * layer->nZModules) {
      errors.failField("module_id", "exceeds the " +
                                        std::to_string(layer->nPhiModules *
                                                       layer->nZModules) +
                                        " modules of layer " + layer->name);
    }
    checkOnLayer(errors, hit, *layer, *m_layers);
    hit.detId = layer->id;
    hit.detId.module = tid.module;
    layer->localAxes(hit.position, hit.uAxis, hit.vAxis);
    hit.sigmaU = layer->sigmaU;
    hit.sigmaV = layer->sigmaV;
  } else {
    auto id = fromTrackml(tid, nullptr);
    if (!id) {
      errors.fail(
          "volume_id/layer_id do not fit 16 bits (needed without a "
          "detector)");
    }
    hit.detId = *id;
  }
  if (row.sigmaU) {
    hit.sigmaU = *row.sigmaU * units::mm;
  }
  if (row.sigmaV) {
    hit.sigmaV = *row.sigmaV * units::mm;
  }
  return hit;
}

}  // namespace conftrack

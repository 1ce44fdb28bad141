#pragma once

/// @file Detector.hpp
/// A tracker made of barrel layers and endcap disks in a uniform solenoid
/// field, with passive material. Read from TOML (DetectorReader.hpp).

#include "conftrack/core/DetectorId.hpp"
#include "conftrack/core/TrackmlLayerMap.hpp"
#include "conftrack/geometry/MagneticField.hpp"
#include "conftrack/geometry/Surfaces.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack {

/// Barrel or endcap.
enum class SubdetectorKind : std::uint8_t { eBarrel, eEndcap };

/// A named group of layers ("VertexBarrel", "InnerTrackerEndcap", ...).
/// Track-finding steps refer to subdetectors by name.
struct Subdetector {
  std::string name;
  SubdetectorKind kind = SubdetectorKind::eBarrel;
  /// Indices into Detector::layers(), sorted by (side, layer).
  std::vector<std::uint32_t> layers;
  /// Number of distinct layer numbers (an endcap counts each disk once).
  std::uint16_t nLayers = 0;
};

/// The whole tracker. Immutable once built; cheap lookups by DetectorId.
class Detector {
 public:
  /// Builds and indexes a detector. Layer ids must be consistent with the
  /// subdetector list (DetectorReader guarantees it).
  Detector(std::string name, std::string model, MagneticField field,
           double envelopeR, double envelopeZ,
           std::vector<Subdetector> subdetectors,
           std::vector<SensitiveLayer> layers,
           std::vector<PassiveSurface> passives);

  /// Short name, e.g. "CLICdet".
  const std::string& name() const { return m_name; }
  /// Detector model, e.g. "CLIC_o3_v14".
  const std::string& model() const { return m_model; }
  /// The field along +z at the centre [T]: the field of the reconstruction,
  /// which assumes it uniform.
  double bz() const { return m_field.centralBz(); }
  /// The field everywhere (uniform, or a solenoid's; the simulation).
  const MagneticField& field() const { return m_field; }
  /// Tracker volume: r < envelopeR(), |z| < envelopeZ() [mm].
  double envelopeR() const { return m_envelopeR; }
  double envelopeZ() const { return m_envelopeZ; }

  const std::vector<Subdetector>& subdetectors() const {
    return m_subdetectors;
  }
  const std::vector<SensitiveLayer>& layers() const { return m_layers; }
  const std::vector<PassiveSurface>& passives() const { return m_passives; }

  /// Index of the subdetector with this name.
  std::optional<std::uint16_t> findSubdetector(std::string_view name) const;
  /// Index into layers() of the layer of this id (module ignored).
  std::optional<std::uint32_t> findLayer(const DetectorId& id) const;
  /// Layer index for TrackML (volume_id, layer_id).
  std::optional<std::uint32_t> findTrackmlLayer(std::uint32_t volume,
                                                std::uint32_t layer) const;
  /// Number of distinct (subdetector, side, layer) triples.
  std::size_t numLayers() const { return m_layers.size(); }
  /// The layers as the TrackML files see them, indexed as layers(): what the
  /// io readers and writers take instead of the detector.
  const TrackmlLayerMap& trackmlLayerMap() const { return m_trackml; }

 private:
  std::string m_name;
  std::string m_model;
  MagneticField m_field;
  double m_envelopeR;
  double m_envelopeZ;
  std::vector<Subdetector> m_subdetectors;
  std::vector<SensitiveLayer> m_layers;
  std::vector<PassiveSurface> m_passives;
  /// The layers' TrackML view; also the index of findLayer and
  /// findTrackmlLayer.
  TrackmlLayerMap m_trackml;
};

/// The TrackML layer map of `detector`, or nullptr without one (the io
/// functions then take ids raw, io/TrackmlIds.hpp).
inline const TrackmlLayerMap* trackmlLayerMapOf(const Detector* detector) {
  return detector != nullptr ? &detector->trackmlLayerMap() : nullptr;
}

}  // namespace conftrack

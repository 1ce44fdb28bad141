#pragma once

/// @file TrackmlLayerMap.hpp
/// The TrackML view of a detector's sensitive layers: which layer a TrackML
/// (volume_id, layer_id) names and back, with what the TrackML readers and
/// writers check and fill per layer (module count, surface, resolutions).
///
/// A Detector builds its map (geometry: Detector::trackmlLayerMap); the io
/// functions take the map instead of the Detector, so that io depends on
/// core only. Layer indices are those of Detector::layers().

#include "conftrack/core/DetectorId.hpp"
#include "conftrack/core/Types.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace conftrack {

/// One sensitive layer as the TrackML files see it (a copy of the fields of
/// the detector's SensitiveLayer that the readers and writers use).
struct TrackmlLayer {
  /// Layer name, unique in the detector (for messages).
  std::string name;
  /// conftrack identifier of the layer; its module field is 0.
  DetectorId id;
  /// TrackML volume_id and layer_id of the layer.
  std::uint32_t volume = 0;
  std::uint32_t layer = 0;
  /// True for an endcap disk (at z = zMin = zMax), false for a barrel
  /// cylinder (at radius r).
  bool disk = false;
  /// Cylinder radius [mm] (barrel).
  double r = 0.0;
  /// z extent [mm]: barrel [zMin, zMax]; disk zMin = zMax = z.
  double zMin = 0.0;
  double zMax = 0.0;
  /// Radial extent [mm]: barrel rMin = rMax = r.
  double rMin = 0.0;
  double rMax = 0.0;
  /// Resolutions along u (r-phi) and v (z on barrels, radial on disks) [mm].
  double sigmaU = 0.0;
  double sigmaV = 0.0;
  /// Segmentation into modules: module ids run from 0 to
  /// nPhiModules * nZModules - 1.
  std::uint32_t nPhiModules = 1;
  std::uint32_t nZModules = 1;

  /// Disk plane position (signed) [mm]; only for disks.
  double z() const { return zMin; }
  /// Local measurement axes (u, v) at a point on this layer
  /// (localMeasurementAxes, core/Hit.hpp).
  void localAxes(const Vector3& position, Vector3& uAxis, Vector3& vAxis) const;
};

/// The layers of a detector with lookups by TrackML (volume_id, layer_id)
/// and by DetectorId. Plain data, immutable once built; the layers are
/// stored contiguously, in the detector's order.
class TrackmlLayerMap {
 public:
  /// An empty map (no layers).
  TrackmlLayerMap() = default;
  /// Indexes `layers` (in the order of Detector::layers()) of the detector
  /// `detectorName`, whose tracker volume is r <= envelopeR, |z| <=
  /// envelopeZ [mm]. Where two layers share a key, lookups find the one
  /// with the smaller index.
  TrackmlLayerMap(std::string detectorName, double envelopeR, double envelopeZ,
                  std::vector<TrackmlLayer> layers);

  /// Name of the detector, for messages ("CLICdet").
  const std::string& detectorName() const { return m_detectorName; }
  /// Tracker volume of the detector [mm].
  double envelopeR() const { return m_envelopeR; }
  double envelopeZ() const { return m_envelopeZ; }
  /// The layers, indexed as Detector::layers().
  const std::vector<TrackmlLayer>& layers() const { return m_layers; }

  /// Index into layers() of the layer with TrackML (volume_id, layer_id).
  std::optional<std::uint32_t> findTrackml(std::uint32_t volume,
                                           std::uint32_t layer) const;
  /// Index into layers() of the layer of this id (module ignored).
  std::optional<std::uint32_t> find(const DetectorId& id) const;

 private:
  std::string m_detectorName;
  double m_envelopeR = 0.0;
  double m_envelopeZ = 0.0;
  std::vector<TrackmlLayer> m_layers;
  /// Sorted (key, layer index) pairs for find / findTrackml.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> m_idIndex;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> m_trackmlIndex;
};

}  // namespace conftrack

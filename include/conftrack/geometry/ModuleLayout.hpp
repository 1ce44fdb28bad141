#pragma once

/// @file ModuleLayout.hpp
/// The flat sensors of a detector's sensitive layers, with a per-layer
/// (phi, z) or (phi, r) grid so that a crossing is tested against a handful
/// of sensors, never all of them.

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/PlanarModule.hpp"

#include <cstdint>
#include <vector>

namespace conftrack {

/// All sensors of a detector, grouped by layer and indexed for lookup.
///
/// A layer of the Detector stays the surface that navigation crosses (a
/// cylinder or disk through the sensors); where it has sensors here, the
/// simulation looks for the sensors that the particle crosses near that
/// crossing (simulation/ModuleCrossings.hpp), so that overlapping sensors
/// give two hits. The layer's own material is then replaced by the
/// sensors' material plus `supportX0` (the mechanics that are not
/// sensors). Layers without sensors keep the ideal surface.
class ModuleLayout {
 public:
  /// Indexes `modules` for `detector`. `supportX0` holds, per layer of the
  /// detector, the material besides the sensors at normal incidence
  /// [fraction of X0] (empty: 0 everywhere). Throws std::invalid_argument
  /// for a module whose layer index is out of range, a non-positive size,
  /// a non-orthonormal rotation, duplicate module numbers on a layer, or a
  /// supportX0 of the wrong length or with a negative value. Rotations
  /// within 1e-3 of orthonormal are accepted and made exactly orthonormal
  /// (Gram-Schmidt from the u axis).
  ModuleLayout(const Detector& detector, std::vector<PlanarModule> modules,
               std::vector<double> supportX0 = {});

  /// All sensors, grouped by layer (layer order, then as given).
  const std::vector<PlanarModule>& modules() const { return m_modules; }
  /// Number of layers of the detector it was built for.
  std::size_t numLayers() const { return m_layers.size(); }
  /// True if layer `layer` has sensors.
  bool hasModules(std::uint32_t layer) const {
    return m_layers[layer].end > m_layers[layer].begin;
  }
  /// Indices into modules() of the sensors of a layer: [first, second).
  std::pair<std::uint32_t, std::uint32_t> layerRange(
      std::uint32_t layer) const {
    return {m_layers[layer].begin, m_layers[layer].end};
  }
  /// True if layer `layer` is a disk (its sensors face along z).
  bool layerIsDisk(std::uint32_t layer) const { return m_layers[layer].disk; }
  /// Material of a layer besides its sensors [X0].
  double supportX0(std::uint32_t layer) const {
    return m_layers[layer].supportX0;
  }
  /// Largest distance of a sensor point from the layer surface, along its
  /// normal (radially on barrels, in z on disks) [mm].
  double shellHalfThickness(std::uint32_t layer) const {
    return m_layers[layer].shell;
  }

  /// Appends to `out` the sensors of `layer` whose extent in phi and in
  /// z (barrel) or r (disk), grown by `marginPhi` [rad] and `marginV` [mm],
  /// contains the point (phi, v). Each sensor once; `out` is not cleared.
  /// Bins of the grid, so the cost is that of the sensors nearby.
  void candidates(std::uint32_t layer, double phi, double v, double marginPhi,
                  double marginV, std::vector<std::uint32_t>& out) const;

  /// Sensor of a layer with module number `module`, or nullptr.
  const PlanarModule* find(std::uint32_t layer, std::uint32_t module) const;

 private:
  /// Extent of a sensor as seen from the z axis.
  struct Extent {
    double phi = 0.0;      ///< azimuth of the centre
    double halfPhi = 0.0;  ///< largest |phi - centre phi| of the sensor
    double vMin = 0.0;     ///< z (barrel) or r (disk) range
    double vMax = 0.0;
  };
  struct Layer {
    std::uint32_t begin = 0;
    std::uint32_t end = 0;
    bool disk = false;
    double supportX0 = 0.0;
    double shell = 0.0;
    /// The grid: nPhi x nV bins over [-pi, pi) x [vLow, vHigh).
    std::uint32_t nPhi = 1;
    std::uint32_t nV = 1;
    double vLow = 0.0;
    double vHigh = 0.0;
    /// Bin b holds binModules[binStart[b] .. binStart[b + 1]).
    std::vector<std::uint32_t> binStart;
    std::vector<std::uint32_t> binModules;
  };

  void buildGrid(Layer& layer);
  std::uint32_t vBin(const Layer& layer, double v) const;

  std::vector<PlanarModule> m_modules;
  std::vector<Extent> m_extents;
  std::vector<Layer> m_layers;
};

}  // namespace conftrack

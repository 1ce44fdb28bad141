#pragma once

/// @file DiskPhiNeighbourhood.hpp
/// The sensors of a disk that a binned surface lookup returns around a
/// point: those in the point's azimuthal bin and its two neighbours, as
/// the surface arrays of the ACTS navigation that simulated the TrackML
/// files (docs/validation.md, item 6).

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"

#include <cstdint>
#include <vector>

namespace conftrack {

/// Azimuthal bins of every disk layer of a ModuleLayout and the bin of
/// each of its sensors, built as ACTS (2018) builds the surface array of a
/// disk with several rings: one equidistant phi axis for all rings, with
/// as many bins as the ring with the fewest sensors has sensors, rotated
/// so that the sensor with the largest azimuth sits at a bin centre; each
/// sensor in the bin of its centre. A lookup at a point returns the
/// sensors of its bin and of the bins on either side; where more sensors
/// than that overlap (the innermost TrackML pixel ring: 40 sensors of
/// 16.8 mm on a 30 mm inner radius, three to four deep), the others are
/// never tested and give no hit. Rings are sensors whose centres lie
/// within kRingTolerance of each other in radius. Barrel layers are not
/// binned (contains() is true): their sensors overlap at most two deep,
/// which a neighbourhood of three bins always covers.
class DiskPhiNeighbourhood {
 public:
  /// Sensors whose centre radii differ by less than this are one ring.
  static constexpr double kRingTolerance = 1.0 * units::mm;

  /// Bins the disk layers of `layout`.
  explicit DiskPhiNeighbourhood(const ModuleLayout& layout);

  /// Whether sensor `moduleIndex` (an index into layout.modules()) of
  /// layer `layer` is in the neighbourhood of azimuth `phi` [rad].
  bool contains(std::uint32_t layer, std::uint32_t moduleIndex,
                double phi) const;

  /// The number of phi bins of layer `layer` (0: not binned).
  std::uint32_t bins(std::uint32_t layer) const { return m_layers[layer].bins; }

 private:
  struct LayerBins {
    std::uint32_t bins = 0;
    /// Azimuth of the centre of bin 0 [rad].
    double firstCentre = 0.0;
  };
  std::uint32_t binOf(const LayerBins& layer, double phi) const;

  std::vector<LayerBins> m_layers;
  /// Phi bin of every sensor.
  std::vector<std::uint32_t> m_moduleBin;
};

}  // namespace conftrack

#pragma once

/// @file SimulationValidation.hpp
/// Checks a simulation against real data without truth: the particles of a
/// real event are simulated, and the simulation's hit counts are compared
/// with the real files they came from — the mean hits per particle (the
/// real `nhits` column) in bins of pT, |eta| and production radius, and the
/// hits per (volume, layer) of the real hits file (docs/validation.md).

#include "conftrack/core/Particle.hpp"
#include "conftrack/core/Units.hpp"

#include <compare>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace conftrack {

/// A TrackML (volume_id, layer_id) pair.
struct VolumeLayer {
  std::uint32_t volume = 0;
  std::uint32_t layer = 0;
  friend auto operator<=>(const VolumeLayer&, const VolumeLayer&) = default;
};

/// One event to compare.
struct SimulationValidationEvent {
  /// The real particles, Particle::nHits from the real `nhits` column.
  std::span<const Particle> real;
  /// The same particles after the simulation (matched by id, any order),
  /// Particle::nHits the simulated hit count.
  std::span<const Particle> simulated;
  /// The (volume, layer) of every hit of the real hits file.
  std::span<const VolumeLayer> realHits;
  /// The (volume, layer) of every simulated hit, noise included.
  std::span<const VolumeLayer> simulatedHits;
};

/// One bin of the hit-count table: sums over the real particles in it.
struct HitCountBin {
  double ptMin = 0.0;  ///< [GeV]
  double ptMax = 0.0;  ///< [GeV]
  double absEtaMin = 0.0;
  double absEtaMax = 0.0;
  /// Produced at least SimulationValidation::Config::displacedRadius from
  /// the beam line.
  bool displaced = false;
  std::size_t particles = 0;
  double realHits = 0.0;       ///< sum of the real hit counts
  double simulatedHits = 0.0;  ///< sum of the simulated hit counts

  double realMean() const;
  double simulatedMean() const;
  /// simulatedMean / realMean - 1; NaN without real hits.
  double deviation() const;
};

/// Hits of one (volume, layer) in the real and the simulated files.
struct LayerHitCount {
  VolumeLayer id;
  std::size_t real = 0;
  std::size_t simulated = 0;

  /// simulated / real - 1; NaN without real hits.
  double deviation() const;
};

/// The two tables, summed over events.
struct SimulationValidationTables {
  /// pT bins outermost, then |eta|, then prompt before displaced.
  std::vector<HitCountBin> bins;
  /// Every (volume, layer) with a real or simulated hit, in order.
  std::vector<LayerHitCount> layers;
  std::size_t events = 0;
  /// Real particles in the table's pT and |eta| range.
  std::size_t particles = 0;
  /// Real particles outside it (|eta| beyond the table, pT = 0).
  std::size_t outsideBins = 0;
  /// Real particles the simulation did not return (not in any bin).
  std::size_t unmatched = 0;

  /// Adds the tables of other events with the same binning. Throws
  /// std::invalid_argument if the binnings differ.
  void merge(const SimulationValidationTables& other);

  /// The tables of several simulations of the same real events (other
  /// seeds): the real columns of the first, the simulated ones averaged
  /// (hit-count sums divided by the number of repeats; layer counts
  /// rounded to the nearest hit). Averaging takes the simulation's own
  /// random spread out of the comparison. Throws std::invalid_argument for
  /// no tables, or tables whose binning or real columns differ.
  static SimulationValidationTables averageRepeats(
      std::span<const SimulationValidationTables> repeats);
};

/// How many well-populated bins agree.
struct BinAgreement {
  /// Bins with at least the minimum number of particles.
  std::size_t bins = 0;
  /// Of those, bins whose |deviation| is within the tolerance.
  std::size_t within = 0;
  /// The largest |deviation| among them (signed), 0 if none.
  double worst = 0.0;
};

/// Counts the bins with at least `minParticles` particles and those of
/// them within `tolerance` (relative, e.g. 0.05) of the real mean.
BinAgreement binAgreement(const SimulationValidationTables& tables,
                          std::size_t minParticles, double tolerance);

/// Builds the comparison tables of one event (no I/O: the caller reads the
/// real files and runs the simulation).
class SimulationValidation {
 public:
  struct Config {
    /// pT bin edges [GeV], strictly increasing from >= 0; the last may be
    /// infinite. The default is the binning.
    std::vector<double> ptEdges{0.0, 0.3 * units::GeV, 0.6 * units::GeV,
                                1.0 * units::GeV,
                                std::numeric_limits<double>::infinity()};
    /// Width of the |eta| bins (> 0).
    double etaBinWidth = 0.5;
    /// The table covers |eta| in [0, maxAbsEta) (a multiple of the width,
    /// at most 100 bins).
    double maxAbsEta = 4.0;
    /// Particles produced at least this far from the beam line
    /// (transverse distance of the production vertex) are "displaced"
    /// [mm] (> 0).
    double displacedRadius = 1.0 * units::mm;
  };

  /// Throws std::invalid_argument for a bad Config.
  explicit SimulationValidation(Config config);

  const Config& config() const { return m_config; }

  /// Empty tables with this binning.
  SimulationValidationTables empty() const;

  /// The tables of one event.
  SimulationValidationTables run(const SimulationValidationEvent& event) const;

 private:
  Config m_config;
  std::size_t m_etaBins = 0;
};

}  // namespace conftrack

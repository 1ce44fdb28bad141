#pragma once

/// @file EventSimulation.hpp
/// One configured sample: signal generator, optional gamma gamma -> hadrons
/// overlay, fast simulation and the readout time window. Each event is a
/// pure function of (seed, event number), whatever thread runs it.

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Detector.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/Simulator.hpp"
#include "conftrack/simulation/generators/EventGenerator.hpp"
#include "conftrack/simulation/generators/GammaGammaOverlay.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace conftrack {

class EventSimulation {
 public:
  struct Config {
    /// Sample name: "muons"/"gun", "ttbar3tev", "bb500", "hepmc:<path>".
    std::string sample = "ttbar3tev";
    /// Generator settings as TOML text (keys of GeneratorFactory.hpp, in
    /// a [generator] table, overlay keys in [overlay]); may be empty.
    std::string generatorToml;
    /// Name of the source of generatorToml, for error messages.
    std::string generatorTomlSource = "generator settings";
    /// Luminous region of the signal and of every overlay interaction
    /// (e.g. from --luminous-region); unset: a [luminous_region] table of
    /// generatorToml, else each generator's default. Setting both is an
    /// InputError.
    std::optional<LuminousRegion::Config> luminousRegion = std::nullopt;
    /// Bunch crossings of gamma gamma -> hadrons overlaid (0: none). The
    /// physics BX sits at position N/3 of the train (10 of 30, as CLIC)
    /// unless the [overlay] table sets physics_bx.
    std::size_t overlayBx = 0;
    /// Run seed; every event's streams derive from (seed, event number).
    std::uint64_t seed = 1;
    Simulator::Config simulator;
    /// Module-level simulation: the flat sensors of the detector (e.g.
    /// geometry/LayoutFile.hpp for CLICdet and CLD), crossed sensor by sensor
    /// so that overlapping sensors give two hits (Simulator.hpp). Null (the
    /// default): the ideal cylinders and disks of the detector file.
    std::shared_ptr<const ModuleLayout> modules;
    /// Readout window of the hit time (detectors.md 1.8: 10 ns from
    /// -0.25 ns for all CLICdet tracker collections); hits outside are
    /// dropped. Matters for the overlay's early and late bunch crossings.
    bool applyTimeWindow = true;
    double windowStart = -0.25 * units::ns;
    double windowEnd = 10.0 * units::ns;
  };

  /// Builds the generators; throws InputError for bad settings.
  EventSimulation(const Detector& detector, Config config);
  ~EventSimulation();

  /// Simulates event `eventNumber`: signal particles, then background
  /// particles (their own random streams, so the signal does not change
  /// when the overlay is switched on), then the time window.
  Event simulate(std::uint64_t eventNumber) const;

  const Config& config() const { return m_config; }
  /// Sample description, e.g. "ttbar3tev + 30 BX gg->hadrons".
  std::string description() const;

 private:
  const Detector* m_detector;
  Config m_config;
  std::unique_ptr<EventGenerator> m_signal;
  std::unique_ptr<GammaGammaOverlay> m_overlay;
  Simulator m_simulator;
};

}  // namespace conftrack

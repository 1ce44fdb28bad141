#pragma once

// Shared by the simulation tests: a simulator without material effects and
// without smearing, whose hits are the exact crossings.

#include "conftrack/simulation/Simulator.hpp"

namespace conftrack::test {

/// No multiple scattering, no energy loss, no smearing.
inline Simulator::Config idealSimulatorConfig() {
  Simulator::Config config;
  config.multipleScattering = false;
  config.energyLoss = false;
  config.smearHits = false;
  return config;
}

}  // namespace conftrack::test

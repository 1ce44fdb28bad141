#include "conftrack/simulation/generators/EventComposition.hpp"

#include "conftrack/core/Error.hpp"

#include <string>

namespace conftrack {

std::vector<Particle> composeEvent(std::vector<Particle> signal,
                                   const std::vector<Particle>& background) {
  for (const Particle& p : signal) {
    if (p.id == 0 || p.id >= kBackgroundIdOffset) {
      throw InputError("composeEvent: signal particle id " +
                       std::to_string(p.id) + " outside 1.." +
                       std::to_string(kBackgroundIdOffset - 1));
    }
  }
  signal.reserve(signal.size() + background.size());
  for (Particle p : background) {
    if (p.id == 0) {
      throw InputError("composeEvent: background particle with id 0");
    }
    p.id += kBackgroundIdOffset;
    if (p.parentId != 0) {
      p.parentId += kBackgroundIdOffset;
    }
    p.origin = ParticleOrigin::eBackground;
    signal.push_back(p);
  }
  return signal;
}

}  // namespace conftrack

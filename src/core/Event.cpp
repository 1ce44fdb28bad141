#include "conftrack/core/Event.hpp"

#include <algorithm>

namespace conftrack {

ParticleIndex Event::findParticle(std::uint64_t particleId) const {
  auto it = std::lower_bound(
      particles.begin(), particles.end(), particleId,
      [](const Particle& p, std::uint64_t id) { return p.id < id; });
  if (it == particles.end() || it->id != particleId) {
    return kInvalidIndex;
  }
  return static_cast<ParticleIndex>(it - particles.begin());
}

void Event::sortParticles() {
  std::sort(particles.begin(), particles.end(),
            [](const Particle& a, const Particle& b) { return a.id < b.id; });
}

}  // namespace conftrack

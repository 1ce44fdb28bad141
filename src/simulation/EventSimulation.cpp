#include "conftrack/simulation/EventSimulation.hpp"

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/simulation/generators/EventComposition.hpp"
#include "conftrack/simulation/generators/GeneratorFactory.hpp"

#include <algorithm>

namespace conftrack {

EventSimulation::EventSimulation(const Detector& detector, Config config)
    : m_detector(&detector),
      m_config(std::move(config)),
      m_simulator(detector, m_config.simulator, m_config.modules) {
  std::shared_ptr<toml::table> table =
      ConfigTable::parse(m_config.generatorToml, m_config.generatorTomlSource);
  ConfigTable root(*table, m_config.generatorTomlSource, "");
  std::optional<LuminousRegion::Config> region = m_config.luminousRegion;
  if (std::optional<ConfigTable> lr = root.findTable("luminous_region")) {
    if (region) {
      lr->fail("",
               "the luminous region is also set on the command line "
               "(--luminous-region/--beam-sigma-z): give it in one "
               "place");
    }
    region = readLuminousRegionConfig(*lr);
  }
  std::optional<ConfigTable> gen = root.findTable("generator");
  if (gen) {
    if (gen->has("sample")) {
      m_config.sample = gen->getString("sample");
    } else {
      // The sample comes from the command line; tell the factory.
      (*table)["generator"].as_table()->insert("sample", m_config.sample);
      gen = root.findTable("generator");
    }
    m_signal = makeGenerator(*gen, region);
  } else {
    m_signal = makeGenerator(m_config.sample, region);
  }
  std::optional<ConfigTable> over = root.findTable("overlay");
  if (m_config.overlayBx > 0 || over) {
    GammaGammaOverlay::Config oc;
    oc.luminousRegion = region.value_or(oc.luminousRegion);
    if (over) {
      rejectRegionAlias(*over, "beam_sigma_z_mm", "sigma_z_mm",
                        region.has_value());
      oc = readGammaGammaOverlayConfig(*over, oc);
      over->rejectUnknownKeys();
    }
    if (m_config.overlayBx > 0) {
      oc.numBunchCrossings = m_config.overlayBx;
      // CLIC puts the physics BX at position 10 of 30; keep that third for
      // other train lengths unless the [overlay] table sets it.
      if (!(over && over->has("physics_bx"))) {
        oc.physicsBunchCrossing =
            std::max<std::size_t>(1, (m_config.overlayBx + 1) / 3);
      }
    }
    m_config.overlayBx = oc.numBunchCrossings;
    m_overlay = std::make_unique<GammaGammaOverlay>(oc);
  }
  root.rejectUnknownKeys();
}

EventSimulation::~EventSimulation() = default;

std::string EventSimulation::description() const {
  std::string d = m_config.sample;
  if (m_overlay) {
    d += " + " + std::to_string(m_config.overlayBx) + " BX gg->hadrons";
  }
  if (m_config.modules) {
    d += ", module level";
  }
  return d;
}

Event EventSimulation::simulate(std::uint64_t eventNumber) const {
  Event event;
  event.number = eventNumber;
  RandomEngine genRng =
      makeEngine(m_config.seed, eventNumber, RandomStream::eSignalGenerator);
  std::vector<Particle> signal = m_signal->generate(genRng, eventNumber);
  std::vector<Particle> background;
  if (m_overlay) {
    RandomEngine bgRng = makeEngine(m_config.seed, eventNumber,
                                    RandomStream::eBackgroundGenerator);
    background = m_overlay->generate(bgRng, eventNumber);
  }
  std::vector<Particle> all = composeEvent(std::move(signal), background);
  auto firstBackground =
      std::partition_point(all.begin(), all.end(),
                           [](const Particle& p) { return !p.isBackground(); });
  std::vector<Particle> signalPart(all.begin(), firstBackground);
  std::vector<Particle> backgroundPart(firstBackground, all.end());
  RandomEngine simRng =
      makeEngine(m_config.seed, eventNumber, RandomStream::eSimulation);
  m_simulator.simulate(signalPart, simRng, event);
  if (!backgroundPart.empty()) {
    RandomEngine bgSimRng = makeEngine(m_config.seed, eventNumber,
                                       RandomStream::eBackgroundSimulation);
    m_simulator.simulate(backgroundPart, bgSimRng, event);
  }
  if (m_config.applyTimeWindow) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < event.hits.size(); ++i) {
      double t = event.truth[i].time;
      if (t > m_config.windowStart && t < m_config.windowEnd) {
        event.hits[kept] = event.hits[i];
        event.truth[kept] = event.truth[i];
        ++kept;
      }
    }
    event.hits.resize(kept);
    event.truth.resize(kept);
    for (Particle& p : event.particles) {
      p.nHits = 0;
    }
    for (const HitTruth& t : event.truth) {
      ParticleIndex p = event.findParticle(t.particleId);
      if (p != kInvalidIndex) {
        ++event.particles[p].nHits;
      }
    }
  }
  return event;
}

}  // namespace conftrack

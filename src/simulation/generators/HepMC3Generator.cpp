#include "conftrack/simulation/generators/HepMC3Generator.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/PdgTable.hpp"
#include "conftrack/core/Units.hpp"

#include <HepMC3/GenEvent.h>
#include <HepMC3/GenParticle.h>
#include <HepMC3/GenVertex.h>
#include <HepMC3/ReaderAscii.h>
#include <HepMC3/ReaderAsciiHepMC2.h>
#include <HepMC3/Units.h>

#include <cmath>
#include <exception>
#include <memory>
#include <sstream>

namespace conftrack {

namespace {

/// Production position of a particle: its production vertex's position, or
/// (if unset) the nearest ancestor vertex's, as GenVertex::position() does
/// but iteratively and with a step limit, so that no record can make it
/// recurse forever.
HepMC3::FourVector productionPosition(const HepMC3::ConstGenParticlePtr& p,
                                      std::size_t maxSteps) {
  HepMC3::ConstGenVertexPtr v = p->production_vertex();
  for (std::size_t step = 0; v && step <= maxSteps; ++step) {
    if (v->has_set_position()) {
      return v->position();
    }
    HepMC3::ConstGenVertexPtr next;
    for (const auto& in : v->particles_in()) {
      if (auto pv = in->production_vertex()) {
        next = pv;
        break;
      }
    }
    v = next;
  }
  return HepMC3::FourVector::ZERO_VECTOR();
}

std::vector<Particle> convert(const HepMC3::GenEvent& evt,
                              double maxProductionRadius) {
  const double momentumUnit =
      evt.momentum_unit() == HepMC3::Units::MEV ? units::MeV : units::GeV;
  const double lengthUnit =
      evt.length_unit() == HepMC3::Units::CM ? units::cm : units::mm;
  const std::size_t maxSteps = evt.vertices().size() + 1;
  std::vector<Particle> out;
  for (const auto& gp : evt.particles()) {
    if (gp->status() != 1) {
      continue;
    }
    const HepMC3::FourVector pos = productionPosition(gp, maxSteps);
    Particle p;
    p.vertex = lengthUnit * Vector3(pos.x(), pos.y(), pos.z());
    if (std::hypot(p.vertex.x(), p.vertex.y()) > maxProductionRadius) {
      continue;
    }
    p.id = out.size() + 1;
    p.pdg = gp->pid();
    p.status = 1;
    p.charge = pdg::charge(p.pdg);
    // HepMC stores c*t in length units.
    p.time = pos.t() * lengthUnit / constants::c;
    const HepMC3::FourVector& mom = gp->momentum();
    p.momentum = momentumUnit * Vector3(mom.px(), mom.py(), mom.pz());
    p.parentId = 0;
    p.origin = ParticleOrigin::eSignal;
    out.push_back(p);
  }
  return out;
}

}  // namespace

std::vector<std::vector<Particle>> readHepMCEvents(std::string_view text,
                                                   const std::string& source,
                                                   double maxProductionRadius) {
  // Everything that could crash the library is rejected here first, and
  // the reader is given the validated records as the validator re-printed
  // them (TextSummary::canonical), never the file's own text.
  hepmc::TextSummary summary = hepmc::validate(text, source);

  std::istringstream in{std::move(summary.canonical)};
  std::unique_ptr<HepMC3::Reader> reader;
  if (summary.format == hepmc::Format::eAsciiV3) {
    reader = std::make_unique<HepMC3::ReaderAscii>(in);
  } else {
    reader = std::make_unique<HepMC3::ReaderAsciiHepMC2>(in);
  }
  std::vector<std::vector<Particle>> events;
  events.reserve(summary.numEvents);
  for (std::size_t i = 0; i < summary.numEvents; ++i) {
    HepMC3::GenEvent evt;
    bool ok = false;
    try {
      ok = reader->read_event(evt);
    } catch (const std::exception& e) {
      throw InputError(source, "HepMC3 reader failed on event " +
                                   std::to_string(i + 1) + ": " + e.what());
    }
    // Exactly one read per validated event: the last event of a file
    // without END_EVENT_LISTING comes back complete although the reader
    // then reports end of input, so failed() is not consulted.
    if (!ok || evt.particles().size() != summary.particlesPerEvent[i]) {
      throw InputError(source, "HepMC3 reader failed on event " +
                                   std::to_string(i + 1) + " of " +
                                   std::to_string(summary.numEvents));
    }
    events.push_back(convert(evt, maxProductionRadius));
  }
  return events;
}

HepMC3Generator::HepMC3Generator(const Config& config) : m_cfg(config) {
  if (m_cfg.path.empty()) {
    throw InputError("HepMC3Generator: config field 'path': empty");
  }
  if (std::isnan(m_cfg.maxProductionRadius) ||
      !(m_cfg.maxProductionRadius > 0.0)) {
    throw InputError(
        "HepMC3Generator: config field 'maxProductionRadius': must be > 0");
  }
  if (m_cfg.luminousRegion) {
    m_region.emplace(requireValidRegion("HepMC3Generator", "luminousRegion",
                                        *m_cfg.luminousRegion));
  }
  const std::string text = hepmc::loadFile(m_cfg.path);
  m_format = hepmc::detectFormat(text);
  m_events = readHepMCEvents(text, m_cfg.path, m_cfg.maxProductionRadius);
}

std::string HepMC3Generator::name() const {
  return "HepMC3(" + m_cfg.path + ")";
}

std::vector<Particle> HepMC3Generator::doGenerate(
    RandomEngine& rng, std::uint64_t eventNumber) const {
  std::vector<Particle> particles = m_events[eventNumber % m_events.size()];
  if (m_region) {
    const LuminousRegion::Vertex shift = m_region->sample(rng);
    for (Particle& p : particles) {
      p.vertex += shift.position;
      p.time += shift.time;
    }
  }
  return particles;
}

}  // namespace conftrack

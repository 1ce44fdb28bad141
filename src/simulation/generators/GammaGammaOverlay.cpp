#include "conftrack/simulation/generators/GammaGammaOverlay.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/PdgTable.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace conftrack {

namespace {

[[noreturn]] void fail(const std::string& field, const std::string& problem) {
  throw InputError("GammaGammaOverlay: config field '" + field +
                   "': " + problem);
}

void requireRange(const std::string& field, double v, double lo, double hi,
                  bool loInclusive = true) {
  const bool aboveLo = loInclusive ? v >= lo : v > lo;
  if (!(std::isfinite(v) && aboveLo && v <= hi)) {
    std::ostringstream os;
    os << "must lie in " << (loInclusive ? "[" : "(") << lo << ", " << hi
       << "] (got " << v << ")";
    fail(field, os.str());
  }
}

}  // namespace

GammaGammaOverlay::GammaGammaOverlay(const Config& config)
    : m_cfg(config),
      m_region(requireValidRegion("GammaGammaOverlay", "luminousRegion",
                                  config.luminousRegion)) {
  const Config& c = m_cfg;
  if (c.numBunchCrossings < 1 || c.numBunchCrossings > 100000) {
    fail("numBunchCrossings", "must lie in [1, 100000]");
  }
  if (c.physicsBunchCrossing < 1 ||
      c.physicsBunchCrossing > c.numBunchCrossings) {
    fail("physicsBunchCrossing", "must lie in [1, numBunchCrossings]");
  }
  requireRange("bunchSpacing", c.bunchSpacing, 0.0, 1e9);
  requireRange("eventsPerBunchCrossing", c.eventsPerBunchCrossing, 0.0, 1e4);
  requireRange("meanCharged", c.meanCharged, 0.0, 1e4);
  requireRange("ptMean", c.ptMean, 0.0, 1e3, false);
  requireRange("ptMin", c.ptMin, 0.0, 1e3, false);
  requireRange("ptMax", c.ptMax, c.ptMin, 1e4, false);
  requireRange("etaMax", c.etaMax, 0.0, 20.0);
  requireRange("kaonFraction", c.kaonFraction, 0.0, 1.0);
  requireRange("protonFraction", c.protonFraction, 0.0, 1.0 - c.kaonFraction);
}

std::vector<Particle> GammaGammaOverlay::doGenerate(
    RandomEngine& rng, std::uint64_t /*eventNumber*/) const {
  const Config& c = m_cfg;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  auto poisson = [&](double mean) {
    if (!(mean > 0.0)) {
      return 0;
    }
    std::poisson_distribution<int> dist(mean);
    return dist(rng);
  };
  // Truncated exponential by inversion: pT = ptMin - slope ln(1 - u F),
  // F the probability of the untruncated tail below ptMax.
  const double tailMass = -std::expm1(-(c.ptMax - c.ptMin) / c.ptMean);

  std::vector<Particle> out;
  out.reserve(
      static_cast<std::size_t>(c.numBunchCrossings * c.eventsPerBunchCrossing *
                               (c.meanCharged + 1.0) * 1.2));
  for (std::size_t bx = 0; bx < c.numBunchCrossings; ++bx) {
    const double time =
        static_cast<double>(bunchCrossingOffset(bx)) * c.bunchSpacing;
    const int nEvents = poisson(c.eventsPerBunchCrossing);
    for (int ev = 0; ev < nEvents; ++ev) {
      // Each gamma gamma event has its own interaction point. One normal
      // distribution for the whole train: consecutive vertices share the
      // pairs of numbers it draws, as before the luminous region existed.
      const LuminousRegion::Vertex vertex = m_region.sample(rng, gauss);
      const int nCharged = poisson(c.meanCharged);
      // Charges in +- pairs keep each gamma gamma event (nearly) neutral.
      const int firstSign = uniform(rng) < 0.5 ? 1 : -1;
      for (int i = 0; i < nCharged; ++i) {
        int q = (i % 2 == 0) ? firstSign : -firstSign;
        if (i == nCharged - 1 && nCharged % 2 == 1) {
          q = uniform(rng) < 0.5 ? 1 : -1;
        }
        const double r = uniform(rng);
        std::int32_t species = pdg::kPiPlus;
        if (r < c.kaonFraction) {
          species = pdg::kKPlus;
        } else if (r < c.kaonFraction + c.protonFraction) {
          species = pdg::kProton;
        }
        const double pt =
            c.ptMin - c.ptMean * std::log1p(-uniform(rng) * tailMass);
        const double eta = c.etaMax * (2.0 * uniform(rng) - 1.0);
        const double phi = std::numbers::pi * (2.0 * uniform(rng) - 1.0);
        Particle p;
        p.id = out.size() + 1;
        p.pdg = q * species;
        p.status = 1;
        p.charge = q;
        p.vertex = vertex.position;
        p.time = time + vertex.time;
        p.momentum = Vector3(pt * std::cos(phi), pt * std::sin(phi),
                             pt * std::sinh(eta));
        p.origin = ParticleOrigin::eBackground;
        out.push_back(p);
      }
    }
  }
  return out;
}

}  // namespace conftrack

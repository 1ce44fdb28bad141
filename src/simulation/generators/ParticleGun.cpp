#include "conftrack/simulation/generators/ParticleGun.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/PdgTable.hpp"

#include <array>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string_view>

namespace conftrack {

namespace {

[[noreturn]] void fail(const std::string& field, const std::string& problem) {
  throw InputError("ParticleGun: config field '" + field + "': " + problem);
}

std::string str(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

bool isSupportedSpecies(std::int32_t pdgCode) {
  switch (std::abs(pdgCode)) {
    case 11:
    case 13:
    case 211:
    case 321:
    case 2212:
      return true;
    default:
      return false;
  }
}

}  // namespace

std::optional<std::int32_t> particleGunPdgFromName(const std::string& name) {
  static const std::array<std::pair<std::string_view, std::int32_t>, 10>
      kNames = {{{"e-", 11},
                 {"e+", -11},
                 {"mu-", 13},
                 {"mu+", -13},
                 {"pi+", 211},
                 {"pi-", -211},
                 {"K+", 321},
                 {"K-", -321},
                 {"p", 2212},
                 {"pbar", -2212}}};
  for (const auto& [n, code] : kNames) {
    if (n == name) {
      return code;
    }
  }
  return std::nullopt;
}

ParticleGun::ParticleGun(const Config& config)
    : m_cfg(config),
      m_region(requireValidRegion("ParticleGun", "luminousRegion",
                                  config.luminousRegion)) {
  const Config& c = m_cfg;
  if (!isSupportedSpecies(c.pdg)) {
    fail("pdg", "unsupported PDG code " + std::to_string(c.pdg) +
                    " (use +-11, +-13, +-211, +-321, +-2212)");
  }
  if (c.multiplicity < 1) {
    fail("multiplicity", "must be >= 1");
  }
  if (!(std::isfinite(c.momentumMin) && c.momentumMin > 0.0)) {
    fail("momentumMin",
         "must be finite and > 0 (got " + str(c.momentumMin) + ")");
  }
  if (!(std::isfinite(c.momentumMax) && c.momentumMax >= c.momentumMin)) {
    fail("momentumMax",
         "must be finite and >= momentumMin (got " + str(c.momentumMax) + ")");
  }
  if (c.angleSampling == AngleSampling::eUniformEta) {
    if (!(std::isfinite(c.etaMin) && std::isfinite(c.etaMax))) {
      fail("etaMin", "eta range must be finite");
    }
    if (!(c.etaMax >= c.etaMin)) {
      fail("etaMax", "must be >= etaMin");
    }
  } else {
    // theta = 0 or pi would give a particle along the beam with pT = 0.
    if (!(c.thetaMin > 0.0 && c.thetaMin < std::numbers::pi)) {
      fail("thetaMin", "must lie in (0, 180) deg (got " +
                           str(c.thetaMin / units::degree) + " deg)");
    }
    if (!(c.thetaMax >= c.thetaMin && c.thetaMax < std::numbers::pi)) {
      fail("thetaMax", "must lie in [thetaMin, 180) deg (got " +
                           str(c.thetaMax / units::degree) + " deg)");
    }
  }
  if (!(std::isfinite(c.phiMin) && std::isfinite(c.phiMax) &&
        c.phiMax >= c.phiMin)) {
    fail("phiMax", "phi range must be finite with phiMax >= phiMin");
  }
  if (c.phiMax - c.phiMin > 2.0 * std::numbers::pi + 1e-12) {
    fail("phiMax", "phi range wider than 360 deg");
  }
  if (!(std::isfinite(c.rMin) && c.rMin >= 0.0)) {
    fail("rMin", "must be finite and >= 0 (got " + str(c.rMin) + ")");
  }
  if (!(std::isfinite(c.rMax) && c.rMax >= c.rMin)) {
    fail("rMax", "must be finite and >= rMin (got " + str(c.rMax) + ")");
  }
}

std::vector<Particle> ParticleGun::doGenerate(
    RandomEngine& rng, std::uint64_t /*eventNumber*/) const {
  const Config& c = m_cfg;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto flat = [&](double lo, double hi) {
    // Fixed values must not consume randomness differently from ranges, so
    // always draw (keeps streams aligned when only a range changes).
    const double u = uniform(rng);
    return lo + (hi - lo) * u;
  };

  // One interaction point for all particles (no draw for a point).
  const LuminousRegion::Vertex vertex = m_region.sample(rng);
  std::vector<Particle> particles;
  particles.reserve(c.multiplicity);
  for (std::size_t i = 0; i < c.multiplicity; ++i) {
    Particle p;
    p.id = i + 1;
    p.pdg = c.pdg;
    if (c.randomCharge && uniform(rng) < 0.5) {
      p.pdg = -p.pdg;
    }
    p.charge = pdg::charge(p.pdg);
    p.status = 1;
    p.origin = ParticleOrigin::eSignal;

    double theta = 0.0;
    switch (c.angleSampling) {
      case AngleSampling::eUniformTheta:
        theta = flat(c.thetaMin, c.thetaMax);
        break;
      case AngleSampling::eUniformCosTheta:
        theta = std::acos(flat(std::cos(c.thetaMin), std::cos(c.thetaMax)));
        break;
      case AngleSampling::eUniformEta:
        theta = 2.0 * std::atan(std::exp(-flat(c.etaMin, c.etaMax)));
        break;
    }
    const double phi = flat(c.phiMin, c.phiMax);
    double momentum = 0.0;
    if (c.logMomentum) {
      momentum =
          std::exp(flat(std::log(c.momentumMin), std::log(c.momentumMax)));
    } else {
      momentum = flat(c.momentumMin, c.momentumMax);
    }
    const double sinTheta = std::sin(theta);
    const double pAbs = c.usePt ? momentum / sinTheta : momentum;
    const Vector3 dir(sinTheta * std::cos(phi), sinTheta * std::sin(phi),
                      std::cos(theta));
    p.momentum = pAbs * dir;

    p.vertex = vertex.position;
    p.time = vertex.time;
    if (c.rMax > 0.0) {
      // Transverse radius R along the direction: z follows as R cot(theta).
      const double r = flat(c.rMin, c.rMax);
      p.vertex +=
          r * Vector3(std::cos(phi), std::sin(phi), std::cos(theta) / sinTheta);
    }
    particles.push_back(p);
  }
  return particles;
}

}  // namespace conftrack

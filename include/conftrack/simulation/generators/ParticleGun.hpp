#pragma once

/// @file ParticleGun.hpp
/// Single-species particles with flat kinematic distributions, optionally
/// displaced (the single-particle and displaced-muon samples).

#include "conftrack/core/Types.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/generators/EventGenerator.hpp"

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>

namespace conftrack {

/// A particle gun: `multiplicity` independent particles per event.
///
/// Kinematics per particle: |p| (or pT) flat (or flat in log) in a range,
/// polar angle flat in theta, cos(theta) or eta, phi flat. One interaction
/// point per event, drawn from the luminous region (by default a point at
/// the origin) before the particles; every particle starts there, or
/// displaced along its direction: for a production radius R drawn flat in
/// [rMin, rMax] the vertex is point + R * (cos phi, sin phi, cot theta), so
/// the particle starts on the straight line from the interaction point
/// along its own direction and points away from it (as the CLICdp
/// displaced-muon samples). Time: that of the interaction point (0 by
/// default).
class ParticleGun final : public EventGenerator {
 public:
  /// How the polar angle is drawn.
  enum class AngleSampling {
    eUniformTheta,     ///< flat in theta over [thetaMin, thetaMax]
    eUniformCosTheta,  ///< flat in cos(theta) over [thetaMin, thetaMax]
    eUniformEta,       ///< flat in pseudorapidity over [etaMin, etaMax]
  };

  /// Configuration; defaults give the "muons" sample: one 10 GeV mu- per
  /// event, isotropic in 10 deg < theta < 170 deg, from the origin
  /// (luminous region "point").
  struct Config {
    /// PDG code: +-11, +-13, +-211, +-321, +-2212 (e, mu, pi, K, p).
    std::int32_t pdg = 13;
    /// If true the sign of `pdg` is flipped with probability 1/2 per
    /// particle (particle or antiparticle: random charge).
    bool randomCharge = false;
    /// Particles per event (>= 1).
    std::size_t multiplicity = 1;
    /// If true the momentum range is in pT, otherwise in |p|.
    bool usePt = false;
    /// Momentum (|p| or pT) range [GeV]; equal bounds give a fixed value.
    double momentumMin = 10.0 * units::GeV;
    /// Upper bound of the momentum range [GeV].
    double momentumMax = 10.0 * units::GeV;
    /// If true the momentum is flat in log(p) instead of flat in p.
    bool logMomentum = false;
    /// Polar-angle sampling.
    AngleSampling angleSampling = AngleSampling::eUniformCosTheta;
    /// Polar-angle range [rad], inside (0, pi); equal bounds: fixed theta.
    double thetaMin = 10.0 * units::degree;
    /// Upper bound of the polar angle [rad].
    double thetaMax = 170.0 * units::degree;
    /// Pseudorapidity range for eUniformEta.
    double etaMin = -2.5;
    /// Upper bound of the pseudorapidity range.
    double etaMax = 2.5;
    /// Azimuth range [rad], width at most 2 pi.
    double phiMin = -std::numbers::pi;
    /// Upper bound of the azimuth range [rad].
    double phiMax = std::numbers::pi;
    /// Where the interaction takes place (the origin of the
    /// displacement); default: a point at the origin.
    LuminousRegion::Config luminousRegion = LuminousRegion::point();
    /// Production-radius range [mm] of the displacement along the
    /// direction; rMax = 0 means no displacement (vertex fixed).
    double rMin = 0.0;
    /// Upper bound of the production radius [mm] (up to 600 mm for the
    /// displaced-track study).
    double rMax = 0.0;
  };

  /// Validates the configuration; throws InputError naming the bad field.
  explicit ParticleGun(const Config& config);

  /// "ParticleGun".
  std::string name() const override { return "ParticleGun"; }
  /// The configuration.
  const Config& config() const { return m_cfg; }

 private:
  std::vector<Particle> doGenerate(RandomEngine& rng,
                                   std::uint64_t eventNumber) const override;

  Config m_cfg;
  LuminousRegion m_region;
};

/// Parses a particle name ("mu-", "mu+", "e-", "e+", "pi-", "pi+", "K-",
/// "K+", "p", "pbar") into a PDG code; nullopt if unknown.
std::optional<std::int32_t> particleGunPdgFromName(const std::string& name);

}  // namespace conftrack

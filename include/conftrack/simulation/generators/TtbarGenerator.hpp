#pragma once

/// @file TtbarGenerator.hpp
/// A parametric multi-jet model of e+e- -> t tbar (3 TeV) and e+e- -> b bbar
/// (500 GeV): the jet topology of the reference events, not a physics
/// generator.

#include "conftrack/core/Units.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/generators/EventGenerator.hpp"
#include "conftrack/simulation/generators/Kinematics.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace conftrack {

/// e+e- -> t tbar or b bbar with a toy hadronisation.
///
/// Parton level (exact kinematics, four-momentum conserved to rounding):
/// - ttbar: tops back to back in the centre-of-mass frame, polar angle
///   from 1 + cos^2(theta), phi flat; t -> b W+ isotropic in the top rest
///   frame; W -> q qbar' (u dbar or c sbar, 50/50) or l nu (e, mu, tau) with
///   the configured branching ratios, isotropic in the W rest frame.
/// - bbar: b and bbar back to back, 1 + cos^2(theta). No ISR, no
///   beamstrahlung, no gluon radiation.
///
/// Hadronisation (independent fragmentation of each quark into a jet):
/// - the number of charged primaries is Poisson with mean
///   n(E) = nchA + nchB ln(E/GeV) + nchC ln^2(E/GeV), E the jet momentum
///   (for b jets the part not taken by the B hadron), then
///   made odd or even so that the jet carries its integer charge (below);
///   neutral primaries (pi0, K0S/K0L, Lambda) are Poisson with means
///   proportional to n(E);
/// - charged species: K+- (kaonFraction), p/pbar (protonFraction), else
///   pi+-; charges come in +- pairs plus |Q| particles of the jet's charge
///   Q: b jets have Q = 0 (the B hadron's charge is compensated), the two
///   quark jets of a W+- carry Q = +-1 and 0 (chosen at random), so the
///   event charge is exactly 0;
/// - longitudinal momentum fractions z_i drawn from (1 - z)^a / z on
///   [pMin/E, 1], then rescaled so that sum(p_L) equals the jet momentum;
///   transverse momenta k_T Gaussian (sigma per component), shifted so that
///   they sum to zero. Each jet's three-momentum is therefore conserved
///   exactly; its energy is not (hadron masses and k_T add ~0.3 % of
///   sqrt(s) per event);
/// - b jets: a B hadron (B0/B+-/Bs/Lambda_b 40/40/10/10 %) takes a
///   fraction x, flat in [bFragmentationMin, bFragmentationMax], of the b
///   quark momentum along its direction; the rest of the jet fragments as
///   above. The B flies exp(c tau beta gamma) and decays isotropically in
///   its rest frame (RAMBO phase space, four-momentum conserved) into
///   ~bDecayChargedMean charged pi/K, Poisson(bDecayPi0Mean) pi0 and, with
///   probability bSemileptonicFraction, a lepton and a neutrino.
///
/// Decays in flight: pi0 -> gamma gamma (at once), K0S -> pi+ pi- (69.2 %)
/// or pi0 pi0, Lambda -> p pi- (63.9 %) or n pi0, with exponential decay
/// lengths (c tau 26.84 mm, 78.9 mm); tau -> e/mu nu nu, pi nu, pi pi0 nu,
/// pi 2pi0 nu, 3pi nu. Decayed particles are kept with status 2, their
/// daughters have parentId, the decay vertex and the flight time.
/// Partons (t, W, quarks) are not stored; leptons and neutrinos from W
/// decays are. All primaries share one interaction point (position and
/// time) drawn from the luminous region after the partons.
///
/// Multiplicity tuning (defaults): n(E) = 1.30 ln(E/GeV) + 0.30 ln^2(E/GeV),
/// i.e. 9.3 charged primaries for a 45.6 GeV jet (LEP Z: about 10 per jet),
/// 12.4 at 100 GeV, 19.9 at 455 GeV. A 3 TeV ttbar event then has on
/// average 92 status-1 charged particles, 90.6 of them with pT > 0.1 GeV
/// and |cos theta| < 0.99 (the paper's "about 90 tracks"; fine tuning
/// against the simulation is to follow); a 500 GeV b bbar event has 34.
class TtbarGenerator final : public EventGenerator {
 public:
  /// Which process.
  enum class Process {
    eTtbar,  ///< e+e- -> t tbar
    eBbbar,  ///< e+e- -> b bbar
  };

  /// W decay channels.
  enum class WDecay {
    eHadrons = 0,   ///< W -> q qbar'
    eElectron = 1,  ///< W -> e nu
    eMuon = 2,      ///< W -> mu nu
    eTau = 3,       ///< W -> tau nu
  };

  /// Configuration; the defaults are the 3 TeV ttbar sample.
  struct Config {
    /// The process.
    Process process = Process::eTtbar;
    /// Centre-of-mass energy [GeV].
    double sqrtS = 3.0 * units::TeV;
    /// Top mass [GeV].
    double topMass = 172.5 * units::GeV;
    /// W mass [GeV].
    double wMass = 80.4 * units::GeV;
    /// b-quark mass [GeV] (parton kinematics).
    double bMass = 4.8 * units::GeV;
    /// W branching ratios (PDG); normalised to their sum when used.
    double brWToHadrons = 0.6741;
    /// BR(W -> e nu).
    double brWToENu = 0.1071;
    /// BR(W -> mu nu).
    double brWToMuNu = 0.1063;
    /// BR(W -> tau nu).
    double brWToTauNu = 0.1138;
    /// Constant term of the jet's mean charged multiplicity.
    double nchA = 0.0;
    /// Coefficient of ln(E/GeV).
    double nchB = 1.30;
    /// Coefficient of ln^2(E/GeV).
    double nchC = 0.30;
    /// Mean number of pi0 per mean charged primary.
    double pi0PerCharged = 0.45;
    /// Mean number of neutral kaons (half K0S, half K0L) per charged.
    double k0PerCharged = 0.10;
    /// Mean number of Lambda/anti-Lambda per charged.
    double lambdaPerCharged = 0.02;
    /// Fraction of charged primaries that are K+-.
    double kaonFraction = 0.11;
    /// Fraction of charged primaries that are p/pbar.
    double protonFraction = 0.05;
    /// Exponent a of the fragmentation function (1 - z)^a / z.
    double fragmentationExponent = 2.0;
    /// Lower cut of the fragmentation function: z >= pMin / E_jet [GeV].
    double fragmentationPMin = 0.3 * units::GeV;
    /// Gaussian sigma of each transverse component of k_T [GeV] (mean
    /// |k_T| = 1.25 sigma = 0.44 GeV).
    double ktSigma = 0.35 * units::GeV;
    /// B-hadron momentum fraction range (flat).
    double bFragmentationMin = 0.70;
    /// Upper bound of the B-hadron momentum fraction.
    double bFragmentationMax = 0.85;
    /// B-hadron c tau [mm].
    double bHadronCTau = 0.455 * units::mm;
    /// Mean number of charged particles in a B decay.
    double bDecayChargedMean = 5.0;
    /// Mean number of pi0 in a B decay.
    double bDecayPi0Mean = 1.5;
    /// Fraction of B decays with a lepton (e or mu, half each) + neutrino.
    double bSemileptonicFraction = 0.21;
    /// Fraction of charged hadrons from B decays that are kaons.
    double bDecayKaonFraction = 0.25;
    /// Where the interaction takes place (default: preset clic3tev, a
    /// Gaussian in z with sigma 0.044 mm).
    LuminousRegion::Config luminousRegion = LuminousRegion::clic3TeV();

    /// The 3 TeV ttbar sample ("ttbar3tev"): the defaults.
    static Config ttbar3TeV() { return Config{}; }
    /// The 500 GeV b bbar sample ("bb500").
    static Config bb500() {
      Config c;
      c.process = Process::eBbbar;
      c.sqrtS = 500.0 * units::GeV;
      return c;
    }
  };

  /// A final-state parton or lepton of the hard process.
  struct Parton {
    /// PDG code (quarks 1..5, leptons, neutrinos; sign as usual).
    std::int32_t pdg = 0;
    /// Four-momentum [GeV].
    FourMomentum p;
    /// Integer charge of the jet a quark turns into (0 for leptons).
    int jetCharge = 0;
  };

  /// One top decay chain t -> b W, W -> f f'.
  struct TopDecay {
    /// PDG code of the top (6 or -6).
    std::int32_t topPdg = 6;
    /// Four-momenta of the top, its b and its W [GeV].
    FourMomentum top, b, w;
    /// The W's decay products.
    std::array<Parton, 2> wDaughters;
    /// The W decay channel.
    WDecay wDecay = WDecay::eHadrons;
  };

  /// The parton-level event.
  struct PartonEvent {
    /// The two top decay chains (empty for b bbar).
    std::vector<TopDecay> tops;
    /// Final-state partons and leptons; their four-momenta sum to
    /// (sqrt(s), 0, 0, 0).
    std::vector<Parton> finalState;
  };

  /// Validates the configuration; throws InputError naming the bad field.
  explicit TtbarGenerator(const Config& config);

  /// "TtbarGenerator(ttbar, 3000 GeV)" or "TtbarGenerator(bbbar, 500 GeV)".
  std::string name() const override;
  /// The configuration.
  const Config& config() const { return m_cfg; }

  /// The parton level of one event (the first draws of generate()).
  PartonEvent generatePartons(RandomEngine& rng) const;

  /// Mean charged multiplicity n(E) of a jet of energy E [GeV].
  double meanChargedMultiplicity(double jetEnergy) const;

 private:
  std::vector<Particle> doGenerate(RandomEngine& rng,
                                   std::uint64_t eventNumber) const override;

  Config m_cfg;
  LuminousRegion m_region;
};

}  // namespace conftrack

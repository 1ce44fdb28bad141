#pragma once

/// @file PdgTable.hpp
/// Charges and masses of particles by PDG Monte Carlo code, for the
/// generators, the HepMC reader and the fit's mass hypotheses: the one
/// particle table of conftrack.

#include <cstdint>
#include <optional>

namespace conftrack::pdg {

/// PDG codes used by the generators (particle; the antiparticle is -code).
enum Code : std::int32_t {
  kDown = 1,               ///< d quark
  kUp = 2,                 ///< u quark
  kStrange = 3,            ///< s quark
  kCharm = 4,              ///< c quark
  kBottom = 5,             ///< b quark
  kTop = 6,                ///< t quark
  kElectron = 11,          ///< e-
  kElectronNeutrino = 12,  ///< nu_e
  kMuon = 13,              ///< mu-
  kMuonNeutrino = 14,      ///< nu_mu
  kTau = 15,               ///< tau-
  kTauNeutrino = 16,       ///< nu_tau
  kGluon = 21,             ///< gluon
  kPhoton = 22,            ///< photon
  kWPlus = 24,             ///< W+
  kPi0 = 111,              ///< pi0
  kPiPlus = 211,           ///< pi+
  kK0L = 130,              ///< K0L
  kK0S = 310,              ///< K0S
  kKPlus = 321,            ///< K+
  kB0 = 511,               ///< B0 (d bbar)
  kBPlus = 521,            ///< B+ (u bbar)
  kBs = 531,               ///< B0s (s bbar)
  kNeutron = 2112,         ///< neutron
  kProton = 2212,          ///< proton
  kLambda = 3122,          ///< Lambda (uds)
  kLambdaB = 5122,         ///< Lambda_b (udb)
};

/// Charge in units of e, three times (integer, exact). Known particles come
/// from a table; other hadrons, diquarks and nuclei are computed from the
/// quark content encoded in the PDG number (the HepPDT rule); unknown or
/// generator-internal codes give 0.
int threeCharge(std::int32_t pdgCode);

/// Charge in units of e.
double charge(std::int32_t pdgCode);

/// Mass [GeV] of the particles the generators produce (leptons, light and
/// b hadrons, gauge bosons, quarks as used for kinematics); nullopt if the
/// code is not in the table.
std::optional<double> mass(std::int32_t pdgCode);

/// Mass [GeV] as mass(), but throws std::invalid_argument for an unknown
/// code: for internal use with codes the generators chose themselves.
double massOf(std::int32_t pdgCode);

}  // namespace conftrack::pdg

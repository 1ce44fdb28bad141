#pragma once

/// @file PdgTable.hpp
/// Charges and masses of particles by PDG Monte Carlo code, for the
/// generators and the HepMC reader.

#include <cstdint>
#include <optional>

namespace conftrack::pdg {

/// PDG codes used by the generators (particle; the antiparticle is -code).
enum Code : std::int32_t {
  kDown = 1,
  kUp = 2,
  kStrange = 3,
  kCharm = 4,
  kBottom = 5,
  kTop = 6,
  kElectron = 11,
  kElectronNeutrino = 12,
  kMuon = 13,
  kMuonNeutrino = 14,
  kTau = 15,
  kTauNeutrino = 16,
  kGluon = 21,
  kPhoton = 22,
  kWPlus = 24,
  kPi0 = 111,
  kPiPlus = 211,
  kK0L = 130,
  kK0S = 310,
  kKPlus = 321,
  kB0 = 511,
  kBPlus = 521,
  kBs = 531,
  kNeutron = 2112,
  kProton = 2212,
  kLambda = 3122,
  kLambdaB = 5122,
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

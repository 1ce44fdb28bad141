#include "conftrack/core/PdgTable.hpp"

#include "conftrack/core/Units.hpp"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace conftrack::pdg {

namespace {

using namespace conftrack::units;

/// Three times the charge of quark 1..8 (d u s c b t b' t').
constexpr int kQuarkThreeCharge[8] = {-1, 2, -1, 2, -1, 2, -1, 2};

/// Table entries for codes whose charge cannot be read from the digits
/// (leptons, bosons) or that are common enough to look up directly.
std::optional<int> tabulatedThreeCharge(int absCode) {
  switch (absCode) {
    case 11:
    case 13:
    case 15:
    case 17:
      return -3;
    case 12:
    case 14:
    case 16:
    case 18:
    case 21:
    case 22:
    case 23:
    case 25:
    case 111:
    case 130:
    case 310:
    case 311:
    case 2112:
    case 3122:
      return 0;
    case 24:
    case 37:
    case 211:
    case 321:
    case 2212:
    case 3222:
      return 3;
    case 3112:
    case 3312:
    case 3334:
      return -3;
    default:
      return std::nullopt;
  }
}

/// The HepPDT rule on the digits n_q1 n_q2 n_q3 of a hadron code.
int quarkContentThreeCharge(int absCode) {
  // Nuclei 10LZZZAAAI: the charge is Z.
  if (absCode >= 1000000000) {
    return 3 * ((absCode / 10000) % 1000);
  }
  // Quarks themselves.
  if (absCode >= 1 && absCode <= 8) {
    return kQuarkThreeCharge[absCode - 1];
  }
  // Generator-internal and special ranges (81-100, 9900000 ...).
  if (absCode < 100 || absCode >= 9000000) {
    return 0;
  }
  const int nq3 = (absCode / 10) % 10;
  const int nq2 = (absCode / 100) % 10;
  const int nq1 = (absCode / 1000) % 10;
  const int nJ = absCode % 10;
  auto q = [](int n) {
    return (n >= 1 && n <= 8) ? kQuarkThreeCharge[n - 1] : 0;
  };
  if (nJ == 0) {
    // Special codes such as K0L (130) or glueballs: not quark content.
    return 0;
  }
  if (nq1 == 0) {
    if (nq2 == 0) {
      return 0;
    }
    // Meson q2 qbar3; for down-type q2 (s, b) the quark is q3 (K+ = u sbar).
    if (nq2 == 3 || nq2 == 5 || nq2 == 7) {
      return q(nq3) - q(nq2);
    }
    return q(nq2) - q(nq3);
  }
  if (nq3 == 0) {
    // Diquark q1 q2 (e.g. 2101).
    return q(nq1) + q(nq2);
  }
  return q(nq1) + q(nq2) + q(nq3);
}

}  // namespace

int threeCharge(std::int32_t pdgCode) {
  if (pdgCode == 0) {
    return 0;
  }
  // Avoid overflow of abs(INT_MIN).
  const long long code = pdgCode;
  const int absCode = static_cast<int>(code < 0 ? -code : code);
  const int sign = pdgCode < 0 ? -1 : 1;
  if (auto c = tabulatedThreeCharge(absCode)) {
    return sign * *c;
  }
  return sign * quarkContentThreeCharge(absCode);
}

double charge(std::int32_t pdgCode) { return threeCharge(pdgCode) / 3.0; }

std::optional<double> mass(std::int32_t pdgCode) {
  const long long code = pdgCode;
  switch (code < 0 ? -code : code) {
    // Quarks: light quarks are massless partons in the kinematics; c and b
    // carry their pole masses (the ttbar model overrides m_b from config).
    case 1:
    case 2:
    case 3:
      return 0.0;
    case 4:
      return 1.27 * GeV;
    case 5:
      return 4.8 * GeV;
    case 6:
      return 172.5 * GeV;
    case 11:
      return constants::kElectronMass;
    case 13:
      return constants::kMuonMass;
    case 15:
      return 1776.86 * MeV;
    case 12:
    case 14:
    case 16:
    case 21:
    case 22:
      return 0.0;
    case 23:
      return 91.1876 * GeV;
    case 24:
      return 80.377 * GeV;
    case 111:
      return 134.9768 * MeV;
    case 211:
      return constants::kPionMass;
    case 130:
    case 310:
    case 311:
      return 497.611 * MeV;
    case 321:
      return constants::kKaonMass;
    case 511:
      return 5279.65 * MeV;
    case 521:
      return 5279.34 * MeV;
    case 531:
      return 5366.88 * MeV;
    case 2112:
      return 939.56542052 * MeV;
    case 2212:
      return constants::kProtonMass;
    case 3122:
      return 1115.683 * MeV;
    case 5122:
      return 5619.60 * MeV;
    default:
      return std::nullopt;
  }
}

double massOf(std::int32_t pdgCode) {
  if (auto m = mass(pdgCode)) {
    return *m;
  }
  throw std::invalid_argument("pdg::massOf: no mass for PDG code " +
                              std::to_string(pdgCode));
}

}  // namespace conftrack::pdg

#include "conftrack/simulation/generators/TtbarGenerator.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/PdgTable.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>

namespace conftrack {

namespace {

using namespace conftrack::units;

// Lifetimes (PDG): c tau of the particles decayed in flight.
constexpr double kK0SCTau = 26.844 * mm;
constexpr double kLambdaCTau = 78.9 * mm;
constexpr double kTauCTau = 87.03 * um;
// Branching ratios of the two-body decays (PDG), the rest goes to neutrals.
constexpr double kK0SToPiPi = 0.692;
constexpr double kLambdaToPPi = 0.639;

[[noreturn]] void fail(const std::string& field, const std::string& problem) {
  throw InputError("TtbarGenerator: config field '" + field + "': " + problem);
}

std::string str(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

void requireRange(const std::string& field, double v, double lo, double hi) {
  if (!(std::isfinite(v) && v >= lo && v <= hi)) {
    fail(field,
         "must lie in [" + str(lo) + ", " + str(hi) + "] (got " + str(v) + ")");
  }
}

void requirePositive(const std::string& field, double v) {
  if (!(std::isfinite(v) && v > 0.0)) {
    fail(field, "must be finite and > 0 (got " + str(v) + ")");
  }
}

bool isBHadron(int absCode) {
  return absCode == pdg::kB0 || absCode == pdg::kBPlus || absCode == pdg::kBs ||
         absCode == pdg::kLambdaB;
}

/// Per-event state of the hadronisation: the output list, the engine and
/// the configuration. Lives only inside one generate() call.
class EventBuilder {
 public:
  EventBuilder(const TtbarGenerator& gen, RandomEngine& rng,
               std::vector<Particle>& out)
      : m_gen(gen), m_cfg(gen.config()), m_rng(rng), m_out(out) {}

  double uniform() { return m_uniform(m_rng); }

  int poisson(double mean) {
    if (!(mean > 0.0)) {
      return 0;
    }
    std::poisson_distribution<int> dist(mean);
    return dist(m_rng);
  }

  /// Stores a particle (status 1) and decays it if it is unstable in this
  /// model; returns its id.
  std::uint64_t add(std::int32_t code, const FourMomentum& p4,
                    const Vector3& vertex, double time,
                    std::uint64_t parentId) {
    Particle p;
    p.id = m_out.size() + 1;
    p.pdg = code;
    p.status = 1;
    p.charge = pdg::charge(code);
    p.vertex = vertex;
    p.time = time;
    p.momentum = p4.p;
    p.parentId = parentId;
    p.origin = ParticleOrigin::eSignal;
    m_out.push_back(p);
    const std::uint64_t id = p.id;
    const int absCode = std::abs(code);
    if (absCode == pdg::kPi0) {
      // c tau = 25 nm: decays at its production point.
      decayInto(id, p4, vertex, time, {pdg::kPhoton, pdg::kPhoton});
    } else if (absCode == pdg::kK0S) {
      auto [v, t] = flight(p4, kK0SCTau, vertex, time);
      if (uniform() < kK0SToPiPi) {
        decayInto(id, p4, v, t, {pdg::kPiPlus, -pdg::kPiPlus});
      } else {
        decayInto(id, p4, v, t, {pdg::kPi0, pdg::kPi0});
      }
    } else if (absCode == pdg::kLambda) {
      auto [v, t] = flight(p4, kLambdaCTau, vertex, time);
      const int s = code > 0 ? 1 : -1;
      if (uniform() < kLambdaToPPi) {
        decayInto(id, p4, v, t, {s * pdg::kProton, -s * pdg::kPiPlus});
      } else {
        decayInto(id, p4, v, t, {s * pdg::kNeutron, pdg::kPi0});
      }
    } else if (absCode == pdg::kTau) {
      auto [v, t] = flight(p4, kTauCTau, vertex, time);
      decayInto(id, p4, v, t, tauDecayProducts(code));
    } else if (isBHadron(absCode)) {
      auto [v, t] = flight(p4, m_cfg.bHadronCTau, vertex, time);
      decayInto(id, p4, v, t, bDecayProducts(code));
    }
    return id;
  }

  /// A jet from a quark of momentum pJet with integer charge jetCharge,
  /// starting at the interaction point `vertex`.
  void fragment(const Vector3& pJet, int jetCharge,
                const LuminousRegion::Vertex& vertex) {
    const double pAbs = pJet.norm();
    const double lambda = m_gen.meanChargedMultiplicity(pAbs);
    const int absQ = std::abs(jetCharge);
    int nCharged = poisson(lambda);
    if (nCharged < absQ) {
      nCharged = absQ;
    }
    // Parity: |Q| particles of the jet's charge plus +- pairs.
    if ((nCharged - absQ) % 2 != 0) {
      ++nCharged;
    }
    std::vector<std::int32_t> codes;
    const std::vector<int> charges = pairedCharges(nCharged, jetCharge);
    for (int q : charges) {
      const double r = uniform();
      std::int32_t species = pdg::kPiPlus;
      if (r < m_cfg.kaonFraction) {
        species = pdg::kKPlus;
      } else if (r < m_cfg.kaonFraction + m_cfg.protonFraction) {
        species = pdg::kProton;
      }
      codes.push_back(q * species);
    }
    const int nPi0 = poisson(m_cfg.pi0PerCharged * lambda);
    for (int i = 0; i < nPi0; ++i) {
      codes.push_back(pdg::kPi0);
    }
    const int nK0 = poisson(m_cfg.k0PerCharged * lambda);
    for (int i = 0; i < nK0; ++i) {
      codes.push_back(uniform() < 0.5 ? pdg::kK0S : pdg::kK0L);
    }
    const int nLambda = poisson(m_cfg.lambdaPerCharged * lambda);
    for (int i = 0; i < nLambda; ++i) {
      codes.push_back(uniform() < 0.5 ? pdg::kLambda : -pdg::kLambda);
    }
    if (codes.empty()) {
      // Keep the jet's momentum in the event.
      codes.push_back(pdg::kPi0);
    }

    // Longitudinal fractions from (1 - z)^a / z on [zMin, 1]: ln z flat,
    // accepted with probability (1 - z)^a.
    const std::size_t n = codes.size();
    const double zMin =
        std::clamp(m_cfg.fragmentationPMin / std::max(pAbs, 1e-9), 1e-9, 0.5);
    const double logZMin = std::log(zMin);
    std::vector<double> z(n);
    double zSum = 0.0;
    for (auto& zi : z) {
      while (true) {
        zi = std::exp(logZMin * uniform());
        if (uniform() < std::pow(1.0 - zi, m_cfg.fragmentationExponent)) {
          break;
        }
      }
      zSum += zi;
    }
    // Transverse momenta, balanced so that they add up to zero.
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::vector<Vector2> kt(n, Vector2::Zero());
    if (n > 1 && m_cfg.ktSigma > 0.0) {
      Vector2 mean = Vector2::Zero();
      for (auto& k : kt) {
        k = m_cfg.ktSigma * Vector2(gauss(m_rng), gauss(m_rng));
        mean += k;
      }
      mean /= static_cast<double>(n);
      for (auto& k : kt) {
        k -= mean;
      }
    }
    const Vector3 axis = pJet / pAbs;
    Vector3 e1, e2;
    orthonormalBasis(axis, e1, e2);
    for (std::size_t i = 0; i < n; ++i) {
      const Vector3 p =
          (pAbs * z[i] / zSum) * axis + kt[i].x() * e1 + kt[i].y() * e2;
      add(codes[i], FourMomentum::fromMass(p, pdg::massOf(codes[i])),
          vertex.position, vertex.time, 0);
    }
  }

  /// A b jet: B hadron with a fraction x of the quark momentum plus the
  /// fragments of the rest, which compensate the B hadron's charge.
  void bJet(const TtbarGenerator::Parton& quark,
            const LuminousRegion::Vertex& vertex) {
    const double x =
        m_cfg.bFragmentationMin +
        (m_cfg.bFragmentationMax - m_cfg.bFragmentationMin) * uniform();
    // Species of the hadron containing the b (quark) or bbar (antiquark).
    const double r = uniform();
    std::int32_t code = pdg::kLambdaB;
    if (r < 0.4) {
      code = -pdg::kB0;
    } else if (r < 0.8) {
      code = -pdg::kBPlus;
    } else if (r < 0.9) {
      code = -pdg::kBs;
    }
    if (quark.pdg < 0) {
      code = -code;
    }
    const Vector3 pB = x * quark.p.p;
    add(code, FourMomentum::fromMass(pB, pdg::massOf(code)), vertex.position,
        vertex.time, 0);
    const int qB = pdg::threeCharge(code) / 3;
    fragment(quark.p.p - pB, quark.jetCharge - qB, vertex);
  }

 private:
  /// Decay vertex and time after an exponential flight with c tau.
  std::pair<Vector3, double> flight(const FourMomentum& p4, double cTau,
                                    const Vector3& vertex, double time) {
    const double m = p4.mass();
    const double pAbs = p4.p.norm();
    if (!(pAbs > 0.0) || !(m > 0.0)) {
      return {vertex, time};
    }
    const double length = -std::log(1.0 - uniform()) * cTau * pAbs / m;
    return {vertex + length * p4.p / pAbs,
            time + length * p4.e / (pAbs * constants::c)};
  }

  /// Marks `parentId` as decayed and stores the daughters of a
  /// phase-space decay of p4 at (vertex, time).
  void decayInto(std::uint64_t parentId, const FourMomentum& p4,
                 const Vector3& vertex, double time,
                 const std::vector<std::int32_t>& codes) {
    m_out[parentId - 1].status = 2;
    std::vector<double> masses;
    masses.reserve(codes.size());
    for (auto c : codes) {
      masses.push_back(pdg::massOf(c));
    }
    const auto momenta = nBodyDecay(p4, masses, m_rng);
    for (std::size_t i = 0; i < codes.size(); ++i) {
      add(codes[i], momenta[i], vertex, time, parentId);
    }
  }

  /// n charges +-1 summing to q (n >= |q|, n - |q| even): |q| of sign q
  /// then +- pairs.
  static std::vector<int> pairedCharges(int n, int q) {
    std::vector<int> charges;
    const int s = q >= 0 ? 1 : -1;
    for (int i = 0; i < std::abs(q); ++i) {
      charges.push_back(s);
    }
    while (static_cast<int>(charges.size()) < n) {
      charges.push_back(1);
      charges.push_back(-1);
    }
    return charges;
  }

  /// tau- modes (PDG, simplified): e nu nu 17.8 %, mu nu nu 17.4 %,
  /// pi nu 10.9 %, pi pi0 nu 25.7 %, pi 2pi0 nu 9.3 %, 3 pi nu 18.9 %.
  std::vector<std::int32_t> tauDecayProducts(std::int32_t tauCode) {
    const double r = uniform();
    std::vector<std::int32_t> c;
    if (r < 0.178) {
      c = {pdg::kElectron, -pdg::kElectronNeutrino, pdg::kTauNeutrino};
    } else if (r < 0.352) {
      c = {pdg::kMuon, -pdg::kMuonNeutrino, pdg::kTauNeutrino};
    } else if (r < 0.461) {
      c = {-pdg::kPiPlus, pdg::kTauNeutrino};
    } else if (r < 0.718) {
      c = {-pdg::kPiPlus, pdg::kPi0, pdg::kTauNeutrino};
    } else if (r < 0.811) {
      c = {-pdg::kPiPlus, pdg::kPi0, pdg::kPi0, pdg::kTauNeutrino};
    } else {
      c = {-pdg::kPiPlus, -pdg::kPiPlus, pdg::kPiPlus, pdg::kTauNeutrino};
    }
    if (tauCode < 0) {
      for (auto& code : c) {
        code = code == pdg::kPi0 ? code : -code;
      }
    }
    return c;
  }

  /// Products of a B-hadron decay: optional lepton + neutrino, a proton
  /// for Lambda_b, charged pi/K with the remaining charge, pi0s; trimmed
  /// until they fit into the B mass.
  std::vector<std::int32_t> bDecayProducts(std::int32_t code) {
    const int absCode = std::abs(code);
    // b quark (not antiquark) inside: B mesons with negative code, Lambda_b
    // with positive code. b -> c l- nu~ gives a negative lepton.
    const bool hasBQuark = absCode == pdg::kLambdaB ? code > 0 : code < 0;
    const int sign = hasBQuark ? 1 : -1;
    std::vector<std::int32_t> fixed;
    int fixedCharge = 0;
    if (uniform() < m_cfg.bSemileptonicFraction) {
      const bool electron = uniform() < 0.5;
      const std::int32_t lepton = electron ? pdg::kElectron : pdg::kMuon;
      fixed.push_back(sign * lepton);
      fixed.push_back(-sign * (lepton + 1));
      fixedCharge -= sign;
    }
    if (absCode == pdg::kLambdaB) {
      // Baryon number ends up in a proton (via Lambda_c).
      fixed.push_back(sign * pdg::kProton);
      fixedCharge += sign;
    }
    const int qB = pdg::threeCharge(code) / 3;
    const int qRest = qB - fixedCharge;
    int nFixedCharged = 0;
    for (auto c : fixed) {
      nFixedCharged += pdg::threeCharge(c) != 0 ? 1 : 0;
    }
    int nCharged = poisson(m_cfg.bDecayChargedMean - nFixedCharged);
    if (nCharged < std::abs(qRest)) {
      nCharged = std::abs(qRest);
    }
    if ((nCharged - std::abs(qRest)) % 2 != 0) {
      // Move to the nearer allowed value, up or down with equal odds, so
      // the mean stays at bDecayChargedMean.
      nCharged += (nCharged > std::abs(qRest) && uniform() < 0.5) ? -1 : 1;
    }
    std::vector<std::int32_t> hadrons;
    for (int q : pairedCharges(nCharged, qRest)) {
      const bool kaon = uniform() < m_cfg.bDecayKaonFraction;
      hadrons.push_back(q * (kaon ? pdg::kKPlus : pdg::kPiPlus));
    }
    int nPi0 = poisson(m_cfg.bDecayPi0Mean);
    const double mB = pdg::massOf(code);
    // Trim until the products fit (rare): kaons -> pions, drop pi0s, then
    // drop +- pion pairs.
    auto total = [&]() {
      double m = nPi0 * pdg::massOf(pdg::kPi0);
      for (auto c : fixed) {
        m += pdg::massOf(c);
      }
      for (auto c : hadrons) {
        m += pdg::massOf(c);
      }
      return m;
    };
    while (total() > mB - 0.1 * GeV) {
      auto kaon = std::find_if(hadrons.begin(), hadrons.end(), [](auto c) {
        return std::abs(c) == pdg::kKPlus;
      });
      if (kaon != hadrons.end()) {
        *kaon = (*kaon > 0 ? 1 : -1) * pdg::kPiPlus;
      } else if (nPi0 > 0) {
        --nPi0;
      } else if (static_cast<int>(hadrons.size()) >= std::abs(qRest) + 2) {
        hadrons.resize(hadrons.size() - 2);
      } else {
        break;
      }
    }
    std::vector<std::int32_t> products = fixed;
    products.insert(products.end(), hadrons.begin(), hadrons.end());
    for (int i = 0; i < nPi0; ++i) {
      products.push_back(pdg::kPi0);
    }
    while (products.size() < 2) {
      products.push_back(pdg::kPi0);
    }
    return products;
  }

  const TtbarGenerator& m_gen;
  const TtbarGenerator::Config& m_cfg;
  RandomEngine& m_rng;
  std::vector<Particle>& m_out;
  std::uniform_real_distribution<double> m_uniform{0.0, 1.0};
};

}  // namespace

TtbarGenerator::TtbarGenerator(const Config& config)
    : m_cfg(config),
      m_region(requireValidRegion("TtbarGenerator", "luminousRegion",
                                  config.luminousRegion)) {
  const Config& c = m_cfg;
  requirePositive("sqrtS", c.sqrtS);
  requirePositive("topMass", c.topMass);
  requirePositive("wMass", c.wMass);
  requirePositive("bMass", c.bMass);
  const double bHadronMass = pdg::massOf(pdg::kLambdaB);
  if (c.process == Process::eTtbar) {
    if (!(c.sqrtS > 2.0 * c.topMass)) {
      fail("sqrtS", "below the ttbar threshold 2 * topMass (got " +
                        str(c.sqrtS) + " GeV)");
    }
    if (!(c.topMass > c.wMass + c.bMass)) {
      fail("topMass", "must exceed wMass + bMass");
    }
    // W -> c sbar and tau nu need room for the c and tau masses.
    if (!(c.wMass > 2.0 * pdg::massOf(pdg::kTau))) {
      fail("wMass", "too small for the W decay products");
    }
  } else if (!(c.sqrtS > 2.0 * c.bMass)) {
    fail("sqrtS", "below the b bbar threshold 2 * bMass");
  }
  for (auto [field, v] :
       {std::pair{"brWToHadrons", c.brWToHadrons},
        std::pair{"brWToENu", c.brWToENu}, std::pair{"brWToMuNu", c.brWToMuNu},
        std::pair{"brWToTauNu", c.brWToTauNu}}) {
    requireRange(field, v, 0.0, 1.0);
  }
  if (!(c.brWToHadrons + c.brWToENu + c.brWToMuNu + c.brWToTauNu > 0.0)) {
    fail("brWToHadrons", "the W branching ratios sum to zero");
  }
  for (auto [field, v] : {std::pair{"nchA", c.nchA}, std::pair{"nchB", c.nchB},
                          std::pair{"nchC", c.nchC}}) {
    requireRange(field, v, -1e3, 1e3);
  }
  requireRange("pi0PerCharged", c.pi0PerCharged, 0.0, 10.0);
  requireRange("k0PerCharged", c.k0PerCharged, 0.0, 10.0);
  requireRange("lambdaPerCharged", c.lambdaPerCharged, 0.0, 10.0);
  requireRange("kaonFraction", c.kaonFraction, 0.0, 1.0);
  requireRange("protonFraction", c.protonFraction, 0.0, 1.0 - c.kaonFraction);
  requireRange("fragmentationExponent", c.fragmentationExponent, 0.0, 100.0);
  requirePositive("fragmentationPMin", c.fragmentationPMin);
  requireRange("ktSigma", c.ktSigma, 0.0, 100.0);
  requireRange("bFragmentationMin", c.bFragmentationMin, 1e-3, 0.999);
  requireRange("bFragmentationMax", c.bFragmentationMax, c.bFragmentationMin,
               0.999);
  // The B hadron must be lighter than the part of the b momentum it takes.
  if (c.process == Process::eBbbar &&
      c.sqrtS / 2.0 * c.bFragmentationMin < 2.0 * bHadronMass) {
    fail("sqrtS", "too low for the b-jet model (B hadron mass)");
  }
  requireRange("bHadronCTau", c.bHadronCTau, 0.0, 1e6);
  requireRange("bDecayChargedMean", c.bDecayChargedMean, 0.0, 10.0);
  requireRange("bDecayPi0Mean", c.bDecayPi0Mean, 0.0, 10.0);
  requireRange("bSemileptonicFraction", c.bSemileptonicFraction, 0.0, 1.0);
  requireRange("bDecayKaonFraction", c.bDecayKaonFraction, 0.0, 1.0);
}

std::string TtbarGenerator::name() const {
  std::ostringstream os;
  os << "TtbarGenerator("
     << (m_cfg.process == Process::eTtbar ? "ttbar" : "bbbar") << ", "
     << m_cfg.sqrtS / units::GeV << " GeV)";
  return os.str();
}

double TtbarGenerator::meanChargedMultiplicity(double jetEnergy) const {
  const double l = std::log(std::max(jetEnergy, 1e-3) / units::GeV);
  return std::max(0.0, m_cfg.nchA + m_cfg.nchB * l + m_cfg.nchC * l * l);
}

TtbarGenerator::PartonEvent TtbarGenerator::generatePartons(
    RandomEngine& rng) const {
  const Config& c = m_cfg;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  // Production angle: 1 + cos^2(theta) by acceptance-rejection.
  double cosTheta = 0.0;
  do {
    cosTheta = 2.0 * uniform(rng) - 1.0;
  } while (2.0 * uniform(rng) > 1.0 + cosTheta * cosTheta);
  const double phi = 2.0 * std::numbers::pi * uniform(rng);
  const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
  const Vector3 dir(sinTheta * std::cos(phi), sinTheta * std::sin(phi),
                    cosTheta);
  const double beamEnergy = c.sqrtS / 2.0;

  PartonEvent event;
  if (c.process == Process::eBbbar) {
    const double p = std::sqrt(beamEnergy * beamEnergy - c.bMass * c.bMass);
    event.finalState.push_back({pdg::kBottom, {beamEnergy, p * dir}, 0});
    event.finalState.push_back({-pdg::kBottom, {beamEnergy, -p * dir}, 0});
    return event;
  }

  const double brSum = c.brWToHadrons + c.brWToENu + c.brWToMuNu + c.brWToTauNu;
  const double pTop =
      std::sqrt(beamEnergy * beamEnergy - c.topMass * c.topMass);
  for (int sign : {1, -1}) {
    TopDecay t;
    t.topPdg = sign * pdg::kTop;
    t.top = {beamEnergy, sign * pTop * dir};
    std::tie(t.b, t.w) = twoBodyDecay(t.top, c.bMass, c.wMass, rng);

    // W+ daughters (for the W- all codes flip sign).
    const double r = uniform(rng) * brSum;
    std::int32_t d1 = 0;
    std::int32_t d2 = 0;
    if (r < c.brWToHadrons) {
      t.wDecay = WDecay::eHadrons;
      const bool cs = uniform(rng) < 0.5;
      d1 = cs ? pdg::kCharm : pdg::kUp;
      d2 = cs ? -pdg::kStrange : -pdg::kDown;
    } else if (r < c.brWToHadrons + c.brWToENu) {
      t.wDecay = WDecay::eElectron;
      d1 = -pdg::kElectron;
      d2 = pdg::kElectronNeutrino;
    } else if (r < c.brWToHadrons + c.brWToENu + c.brWToMuNu) {
      t.wDecay = WDecay::eMuon;
      d1 = -pdg::kMuon;
      d2 = pdg::kMuonNeutrino;
    } else {
      t.wDecay = WDecay::eTau;
      d1 = -pdg::kTau;
      d2 = pdg::kTauNeutrino;
    }
    d1 *= sign;
    d2 *= sign;
    auto [p1, p2] = twoBodyDecay(t.w, pdg::massOf(d1), pdg::massOf(d2), rng);
    int q1 = 0;
    int q2 = 0;
    if (t.wDecay == WDecay::eHadrons) {
      // The W's charge goes to one of the two jets at random.
      (uniform(rng) < 0.5 ? q1 : q2) = sign;
    }
    t.wDaughters = {Parton{d1, p1, q1}, Parton{d2, p2, q2}};
    event.finalState.push_back({sign * pdg::kBottom, t.b, 0});
    event.finalState.push_back(t.wDaughters[0]);
    event.finalState.push_back(t.wDaughters[1]);
    event.tops.push_back(t);
  }
  return event;
}

std::vector<Particle> TtbarGenerator::doGenerate(
    RandomEngine& rng, std::uint64_t /*eventNumber*/) const {
  const PartonEvent partons = generatePartons(rng);
  // One interaction point for the whole event, drawn after the partons.
  const LuminousRegion::Vertex vertex = m_region.sample(rng);

  std::vector<Particle> out;
  out.reserve(m_cfg.process == Process::eTtbar ? 512 : 192);
  EventBuilder builder(*this, rng, out);
  for (const Parton& parton : partons.finalState) {
    const int absCode = std::abs(parton.pdg);
    if (absCode == pdg::kBottom) {
      builder.bJet(parton, vertex);
    } else if (absCode < pdg::kBottom) {
      builder.fragment(parton.p.p, parton.jetCharge, vertex);
    } else {
      // Leptons and neutrinos (tau decays inside add()).
      builder.add(parton.pdg, parton.p, vertex.position, vertex.time, 0);
    }
  }
  return out;
}

}  // namespace conftrack

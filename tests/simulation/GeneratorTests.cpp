// Tests of the event generators: particle gun, gamma gamma overlay,
// kinematics helpers, event composition and configuration (the ttbar/bbbar
// model: TtbarGeneratorTests.cpp).

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/PdgTable.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/simulation/generators/EventComposition.hpp"
#include "conftrack/simulation/generators/GammaGammaOverlay.hpp"
#include "conftrack/simulation/generators/GeneratorFactory.hpp"
#include "conftrack/simulation/generators/Kinematics.hpp"
#include "conftrack/simulation/generators/ParticleGun.hpp"
#include "conftrack/simulation/generators/TtbarGenerator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "GeneratorTestUtils.hpp"

using namespace conftrack;
using namespace conftrack::units;
using namespace conftrack::test;

// ---------------------------------------------------------------- kinematics

TEST(GeneratorKinematics, TwoBodyDecayConservesFourMomentum) {
  auto rng = engine(1);
  const FourMomentum parent =
      FourMomentum::fromMass(Vector3(300.0, -200.0, 900.0), 172.5);
  for (int i = 0; i < 100; ++i) {
    auto [a, b] = twoBodyDecay(parent, 4.8, 80.4, rng);
    EXPECT_NEAR(a.mass(), 4.8, 1e-9);
    EXPECT_NEAR(b.mass(), 80.4, 1e-9);
    const FourMomentum sum = a + b;
    EXPECT_NEAR(sum.e, parent.e, 1e-9);
    EXPECT_NEAR((sum.p - parent.p).norm(), 0.0, 1e-9);
  }
  EXPECT_THROW(twoBodyDecay(parent, 100.0, 80.4, rng), std::invalid_argument);
}

TEST(GeneratorKinematics, NBodyDecayConservesFourMomentum) {
  auto rng = engine(2);
  const FourMomentum parent =
      FourMomentum::fromMass(Vector3(10.0, 5.0, -40.0), 5.279);
  const std::vector<double> masses = {0.1396, 0.1396, 0.4937,
                                      0.135,  0.0,    0.000511};
  for (int i = 0; i < 100; ++i) {
    const auto d = nBodyDecay(parent, masses, rng);
    ASSERT_EQ(d.size(), masses.size());
    FourMomentum sum;
    for (std::size_t k = 0; k < d.size(); ++k) {
      EXPECT_NEAR(d[k].mass(), masses[k], 1e-6);
      sum += d[k];
    }
    EXPECT_NEAR(sum.e, parent.e, 1e-9);
    EXPECT_NEAR((sum.p - parent.p).norm(), 0.0, 1e-9);
  }
}

// -------------------------------------------------------------- particle gun

TEST(GeneratorParticleGun, KinematicsWithinRanges) {
  ParticleGun::Config cfg;
  cfg.pdg = 211;
  cfg.randomCharge = true;
  cfg.multiplicity = 5;
  cfg.usePt = true;
  cfg.momentumMin = 1.0 * GeV;
  cfg.momentumMax = 10.0 * GeV;
  cfg.thetaMin = 30.0 * degree;
  cfg.thetaMax = 150.0 * degree;
  cfg.phiMin = 0.0;
  cfg.phiMax = 90.0 * degree;
  const ParticleGun gun(cfg);
  std::set<int> pdgs;
  for (std::uint64_t ev = 0; ev < 200; ++ev) {
    auto rng = engine(ev);
    const auto particles = gun.generate(rng);
    ASSERT_EQ(particles.size(), 5u);
    expectWellFormed(particles);
    for (const Particle& p : particles) {
      pdgs.insert(p.pdg);
      EXPECT_EQ(std::abs(p.pdg), 211);
      EXPECT_EQ(p.charge, p.pdg > 0 ? 1.0 : -1.0);
      EXPECT_EQ(p.status, 1);
      EXPECT_FALSE(p.isBackground());
      EXPECT_GE(p.pt(), 1.0 - 1e-12);
      EXPECT_LE(p.pt(), 10.0 + 1e-12);
      const double theta = std::acos(cosTheta(p));
      EXPECT_GE(theta, 30.0 * degree - 1e-9);
      EXPECT_LE(theta, 150.0 * degree + 1e-9);
      const double phi = std::atan2(p.momentum.y(), p.momentum.x());
      EXPECT_GE(phi, -1e-12);
      EXPECT_LE(phi, 90.0 * degree + 1e-12);
      EXPECT_EQ(p.vertex, Vector3::Zero());
      EXPECT_EQ(p.time, 0.0);
    }
  }
  EXPECT_EQ(pdgs, (std::set<int>{-211, 211}));
}

TEST(GeneratorParticleGun, SpeciesFixedMomentumAndEta) {
  const std::map<std::string, std::pair<int, double>> species = {
      {"e-", {11, -1}},     {"e+", {-11, 1}},   {"mu-", {13, -1}},
      {"mu+", {-13, 1}},    {"pi+", {211, 1}},  {"pi-", {-211, -1}},
      {"K+", {321, 1}},     {"K-", {-321, -1}}, {"p", {2212, 1}},
      {"pbar", {-2212, -1}}};
  for (const auto& [name, expected] : species) {
    const auto code = particleGunPdgFromName(name);
    ASSERT_TRUE(code.has_value()) << name;
    ParticleGun::Config cfg;
    cfg.pdg = *code;
    cfg.angleSampling = ParticleGun::AngleSampling::eUniformEta;
    cfg.etaMin = -1.0;
    cfg.etaMax = 2.0;
    const ParticleGun gun(cfg);
    auto rng = engine(7);
    for (int i = 0; i < 20; ++i) {
      for (const Particle& p : gun.generate(rng)) {
        EXPECT_EQ(p.pdg, expected.first);
        EXPECT_EQ(p.charge, expected.second);
        EXPECT_NEAR(p.momentum.norm(), 10.0, 1e-12);
        const double eta = std::atanh(cosTheta(p));
        EXPECT_GE(eta, -1.0 - 1e-9);
        EXPECT_LE(eta, 2.0 + 1e-9);
      }
    }
  }
  EXPECT_FALSE(particleGunPdgFromName("photon").has_value());
}

TEST(GeneratorParticleGun, DisplacedVertexPointsAwayFromOrigin) {
  ParticleGun::Config cfg;
  cfg.rMin = 0.0;
  cfg.rMax = 600.0 * mm;
  cfg.logMomentum = true;
  cfg.momentumMin = 1.0;
  cfg.momentumMax = 100.0;
  const ParticleGun gun(cfg);
  auto rng = engine(3);
  for (int i = 0; i < 500; ++i) {
    const Particle p = gun.generate(rng).at(0);
    const double r = p.vertex.head<2>().norm();
    EXPECT_LE(r, 600.0 + 1e-9);
    EXPECT_GE(p.momentum.norm(), 1.0 - 1e-9);
    EXPECT_LE(p.momentum.norm(), 100.0 + 1e-9);
    if (r > 1e-6) {
      // On the line from the origin along the momentum, pointing away.
      const Vector3 dir = p.momentum.normalized();
      EXPECT_NEAR((p.vertex.normalized() - dir).norm(), 0.0, 1e-9);
      EXPECT_NEAR(p.vertex.z(),
                  r * cosTheta(p) / std::sqrt(1.0 - std::pow(cosTheta(p), 2)),
                  1e-6);
    }
  }
}

TEST(GeneratorParticleGun, InvalidConfigIsRejected) {
  ParticleGun::Config cfg;
  cfg.pdg = 22;
  expectInputError<ParticleGun>(cfg, "pdg");
  cfg = {};
  cfg.momentumMin = 0.0;
  expectInputError<ParticleGun>(cfg, "momentumMin");
  cfg = {};
  cfg.momentumMax = 1.0;
  expectInputError<ParticleGun>(cfg, "momentumMax");
  cfg = {};
  cfg.thetaMax = 180.0 * degree;
  expectInputError<ParticleGun>(cfg, "thetaMax");
  cfg = {};
  cfg.rMin = 10.0;
  cfg.rMax = 5.0;
  expectInputError<ParticleGun>(cfg, "rMax");
  cfg = {};
  cfg.multiplicity = 0;
  expectInputError<ParticleGun>(cfg, "multiplicity");
}

// --------------------------------------------------------------- overlay

TEST(GeneratorOverlay, EventsPerBunchCrossingAndFlags) {
  GammaGammaOverlay::Config cfg;
  cfg.meanCharged = 20.0;  // P(empty event) = 2e-9: every event is seen
  const GammaGammaOverlay overlay(cfg);
  EXPECT_EQ(overlay.bunchCrossingOffset(0), -9);
  EXPECT_EQ(overlay.bunchCrossingOffset(29), 20);
  const int nTrains = 200;
  std::size_t nEvents = 0;
  for (int train = 0; train < nTrains; ++train) {
    auto rng = makeEngine(5, train, RandomStream::eBackgroundGenerator);
    const auto particles = overlay.generate(rng);
    expectWellFormed(particles);
    std::set<std::pair<double, double>> events;  // (time, vertex z)
    for (const Particle& p : particles) {
      events.insert({p.time, p.vertex.z()});
      EXPECT_TRUE(p.isBackground());
      EXPECT_EQ(std::abs(p.pdg), 211);
      EXPECT_EQ(std::abs(p.charge), 1.0);
      const double bx = p.time / (0.5 * ns);
      EXPECT_EQ(bx, std::round(bx));
      EXPECT_GE(bx, -9.0);
      EXPECT_LE(bx, 20.0);
      EXPECT_GE(p.pt(), cfg.ptMin - 1e-12);
      EXPECT_LE(p.pt(), cfg.ptMax + 1e-12);
      EXPECT_LE(std::abs(std::atanh(cosTheta(p))), 3.0 + 1e-9);
      EXPECT_EQ(p.vertex.head<2>().norm(), 0.0);
    }
    nEvents += events.size();
  }
  const double nBx = 30.0 * nTrains;
  const double mean = nEvents / nBx;
  // 5 sigma of the Poisson mean over 6000 BX: 5 * sqrt(3.2 / 6000) = 0.115.
  EXPECT_NEAR(mean, 3.2, 5.0 * std::sqrt(3.2 / nBx));
}

TEST(GeneratorOverlay, ReconstructableCountNearTuningTarget) {
  const GammaGammaOverlay overlay(GammaGammaOverlay::Config{});
  double nReco = 0.0;
  const int nTrains = 100;
  for (int train = 0; train < nTrains; ++train) {
    auto rng = makeEngine(6, train, RandomStream::eBackgroundGenerator);
    const auto particles = overlay.generate(rng);
    nReco += std::count_if(particles.begin(), particles.end(),
                           reconstructableAtGeneratorLevel);
  }
  // Generator level (pT and angle only): 30 * 3.2 * 7.7 * 0.702 = 519.
  EXPECT_NEAR(nReco / nTrains, 519.0, 20.0);
}

TEST(GeneratorOverlay, InvalidConfigIsRejected) {
  GammaGammaOverlay::Config cfg;
  cfg.physicsBunchCrossing = 31;
  expectInputError<GammaGammaOverlay>(cfg, "physicsBunchCrossing");
  cfg = {};
  cfg.ptMax = 0.01;
  expectInputError<GammaGammaOverlay>(cfg, "ptMax");
  cfg = {};
  cfg.meanCharged = -1.0;
  expectInputError<GammaGammaOverlay>(cfg, "meanCharged");
}

// ----------------------------------------------------------- determinism

TEST(GeneratorDeterminism, SameSeedSameEventDifferentSeedDifferentEvent) {
  std::vector<std::unique_ptr<EventGenerator>> generators;
  generators.push_back(makeGenerator("muons"));
  generators.push_back(makeGenerator("ttbar3tev"));
  generators.push_back(makeGenerator("bb500"));
  generators.push_back(
      std::make_unique<GammaGammaOverlay>(GammaGammaOverlay::Config{}));
  for (const auto& gen : generators) {
    auto a = makeEngine(1, 17, RandomStream::eSignalGenerator);
    auto b = makeEngine(1, 17, RandomStream::eSignalGenerator);
    auto c = makeEngine(1, 18, RandomStream::eSignalGenerator);
    const auto first = gen->generate(a, 17);
    EXPECT_TRUE(identical(first, gen->generate(b, 17))) << gen->name();
    EXPECT_FALSE(identical(first, gen->generate(c, 18))) << gen->name();
  }
}

// ----------------------------------------------------------- composition

TEST(GeneratorComposition, BackgroundIdsAreOffset) {
  const TtbarGenerator signalGen(TtbarGenerator::Config::ttbar3TeV());
  const GammaGammaOverlay overlay(GammaGammaOverlay::Config{});
  auto rs = makeEngine(3, 1, RandomStream::eSignalGenerator);
  auto rb = makeEngine(3, 1, RandomStream::eBackgroundGenerator);
  auto signal = signalGen.generate(rs);
  auto background = overlay.generate(rb);
  // A fake decay in the background checks the parentId shift.
  background[1].parentId = background[0].id;
  const auto merged = composeEvent(signal, background);
  ASSERT_EQ(merged.size(), signal.size() + background.size());
  EXPECT_TRUE(std::is_sorted(
      merged.begin(), merged.end(),
      [](const Particle& x, const Particle& y) { return x.id < y.id; }));
  for (std::size_t i = 0; i < signal.size(); ++i) {
    EXPECT_TRUE(identical(merged[i], signal[i]));
  }
  for (std::size_t i = 0; i < background.size(); ++i) {
    const Particle& m = merged[signal.size() + i];
    EXPECT_EQ(m.id, kBackgroundIdOffset + background[i].id);
    EXPECT_EQ(m.parentId, background[i].parentId == 0
                              ? 0
                              : kBackgroundIdOffset + background[i].parentId);
    EXPECT_TRUE(m.isBackground());
  }
  std::set<std::uint64_t> ids;
  for (const Particle& p : merged) {
    ids.insert(p.id);
  }
  EXPECT_EQ(ids.size(), merged.size());

  signal.back().id = kBackgroundIdOffset;
  EXPECT_THROW(composeEvent(signal, background), InputError);
}

// ----------------------------------------------------- TOML configuration

namespace {

ConfigTable tableOf(const std::shared_ptr<toml::table>& root) {
  return ConfigTable(*root, "gen.toml", "");
}

}  // namespace

TEST(GeneratorConfig, ParticleGunFromToml) {
  const auto root = ConfigTable::parse(R"(
sample = "gun"
particle = "mu+"
multiplicity = 2
pt_min_GeV = 1.0
pt_max_GeV = 2.0
theta_min_deg = 20
theta_max_deg = 160
theta_sampling = "theta"
r_min_mm = 10
r_max_mm = 600
)",
                                       "gen.toml");
  const auto gen = makeGenerator(tableOf(root));
  const auto* gun = dynamic_cast<const ParticleGun*>(gen.get());
  ASSERT_NE(gun, nullptr);
  const auto& c = gun->config();
  EXPECT_EQ(c.pdg, -13);
  EXPECT_EQ(c.multiplicity, 2u);
  EXPECT_TRUE(c.usePt);
  EXPECT_DOUBLE_EQ(c.momentumMin, 1.0 * GeV);
  EXPECT_DOUBLE_EQ(c.thetaMin, 20.0 * degree);
  EXPECT_EQ(c.angleSampling, ParticleGun::AngleSampling::eUniformTheta);
  EXPECT_DOUBLE_EQ(c.rMax, 600.0 * mm);
}

TEST(GeneratorConfig, TomlErrorsAreLocated) {
  auto expectError = [](const std::string& text, const std::string& part) {
    const auto root = ConfigTable::parse(text, "gen.toml");
    try {
      makeGenerator(tableOf(root));
      FAIL() << "expected InputError for: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << e.what();
    }
  };
  expectError("sample = \"gun\"\npt_GeV = 1\nbogus = 3\n",
              "gen.toml:3: key 'bogus': unknown key");
  expectError("sample = \"gun\"\nparticle = \"photon\"\n",
              "gen.toml:2: key 'particle'");
  expectError("sample = \"gun\"\np_GeV = -1\n", "gen.toml:2: key 'p_GeV'");
  expectError("sample = \"gun\"\np_GeV = 1\npt_GeV = 1\n", "give one of");
  expectError("sample = \"gun\"\npdg = 22\n", "unsupported PDG code 22");
  expectError("sample = \"ttbar3tev\"\nsqrt_s_GeV = 200\n", "sqrtS");
  expectError("sample = \"zz\"\n", "gen.toml:1: key 'sample'");
  expectError("sample = \"hepmc\"\npath = \"does-not-exist.hepmc\"\n",
              "no such file");
}

TEST(GeneratorConfig, TtbarAndOverlayFromToml) {
  const auto root = ConfigTable::parse(R"(
[signal]
sample = "bb500"
nch_a = 1.0
beam_sigma_z_mm = 0.05
[overlay]
bunch_crossings = 20
physics_bx = 5
mean_charged = 5.0
pt_mean_GeV = 0.4
)",
                                       "gen.toml");
  const ConfigTable top = tableOf(root);
  const auto gen = makeGenerator(top.getTable("signal"));
  const auto* tt = dynamic_cast<const TtbarGenerator*>(gen.get());
  ASSERT_NE(tt, nullptr);
  EXPECT_EQ(tt->config().process, TtbarGenerator::Process::eBbbar);
  EXPECT_DOUBLE_EQ(tt->config().sqrtS, 500.0 * GeV);
  EXPECT_DOUBLE_EQ(tt->config().nchA, 1.0);
  EXPECT_DOUBLE_EQ(tt->config().luminousRegion.sigmaZ, 0.05 * mm);
  const auto overlay = makeOverlay(top.getTable("overlay"));
  EXPECT_EQ(overlay->config().numBunchCrossings, 20u);
  EXPECT_EQ(overlay->bunchCrossingOffset(0), -4);
  EXPECT_DOUBLE_EQ(overlay->config().ptMean, 0.4 * GeV);
  EXPECT_THROW(makeGenerator("nonsense"), InputError);
}

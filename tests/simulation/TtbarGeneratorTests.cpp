// Tests of the ttbar/bbbar event model (TtbarGenerator): top and W decay
// masses, four-momentum conservation at parton and hadron level, W
// branching ratios, decays in flight, multiplicity and beam spot, bbbar at
// 500 GeV and bad configurations.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/PdgTable.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/simulation/generators/Kinematics.hpp"
#include "conftrack/simulation/generators/TtbarGenerator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "GeneratorTestUtils.hpp"

using namespace conftrack;
using namespace conftrack::units;
using namespace conftrack::test;

TEST(GeneratorTtbar, TopAndWDecayMasses) {
  const TtbarGenerator gen(TtbarGenerator::Config::ttbar3TeV());
  const auto& c = gen.config();
  auto rng = engine(11);
  for (int ev = 0; ev < 500; ++ev) {
    const auto partons = gen.generatePartons(rng);
    ASSERT_EQ(partons.tops.size(), 2u);
    ASSERT_EQ(partons.finalState.size(), 6u);
    for (const auto& t : partons.tops) {
      EXPECT_NEAR(t.top.mass() / c.topMass, 1.0, 1e-6);
      EXPECT_NEAR((t.b + t.w).mass() / c.topMass, 1.0, 1e-6);
      EXPECT_NEAR(t.w.mass() / c.wMass, 1.0, 1e-6);
      EXPECT_NEAR(t.b.mass() / c.bMass, 1.0, 1e-6);
      const FourMomentum w = t.wDaughters[0].p + t.wDaughters[1].p;
      EXPECT_NEAR(w.mass() / c.wMass, 1.0, 1e-6);
      // W+ from t, W- from tbar: daughter charges add up to the W charge.
      const int wCharge = t.topPdg > 0 ? 3 : -3;
      EXPECT_EQ(pdg::threeCharge(t.wDaughters[0].pdg) +
                    pdg::threeCharge(t.wDaughters[1].pdg),
                wCharge);
      EXPECT_EQ(t.wDaughters[0].jetCharge + t.wDaughters[1].jetCharge,
                t.wDecay == TtbarGenerator::WDecay::eHadrons ? wCharge / 3 : 0);
    }
  }
}

TEST(GeneratorTtbar, PartonFinalStateConservesFourMomentum) {
  for (const auto& cfg :
       {TtbarGenerator::Config::ttbar3TeV(), TtbarGenerator::Config::bb500()}) {
    const TtbarGenerator gen(cfg);
    auto rng = engine(12);
    for (int ev = 0; ev < 200; ++ev) {
      FourMomentum sum;
      for (const auto& parton : gen.generatePartons(rng).finalState) {
        sum += parton.p;
      }
      EXPECT_NEAR(sum.e / cfg.sqrtS, 1.0, 1e-12);
      EXPECT_LT(sum.p.norm() / cfg.sqrtS, 1e-12);
    }
  }
}

TEST(GeneratorTtbar, WBranchingRatios) {
  const TtbarGenerator gen(TtbarGenerator::Config::ttbar3TeV());
  const auto& c = gen.config();
  const double sum = c.brWToHadrons + c.brWToENu + c.brWToMuNu + c.brWToTauNu;
  const std::array<double, 4> expected = {c.brWToHadrons / sum,
                                          c.brWToENu / sum, c.brWToMuNu / sum,
                                          c.brWToTauNu / sum};
  std::array<int, 4> counts = {0, 0, 0, 0};
  auto rng = engine(13);
  const int nEvents = 10000;  // 20k W decays
  for (int ev = 0; ev < nEvents; ++ev) {
    for (const auto& t : gen.generatePartons(rng).tops) {
      ++counts[static_cast<int>(t.wDecay)];
    }
  }
  const double n = 2.0 * nEvents;
  for (int k = 0; k < 4; ++k) {
    const double sigma = std::sqrt(n * expected[k] * (1.0 - expected[k]));
    EXPECT_NEAR(counts[k], n * expected[k], 5.0 * sigma) << "channel " << k;
  }
}

TEST(GeneratorTtbar, HadronLevelConservation) {
  const TtbarGenerator gen(TtbarGenerator::Config::ttbar3TeV());
  for (std::uint64_t ev = 0; ev < 100; ++ev) {
    auto rng = engine(ev);
    const auto particles = gen.generate(rng);
    expectWellFormed(particles);
    FourMomentum sum;
    double charge = 0.0;
    for (const Particle& p : particles) {
      if (p.isStable()) {
        sum += fourMomentum(p);
        charge += p.charge;
      }
    }
    // Three-momentum is conserved jet by jet; energy only approximately
    // (hadron masses and k_T are added on top of the partons).
    EXPECT_LT(sum.p.norm(), 1e-6 * 3000.0);
    EXPECT_NEAR(sum.e / 3000.0, 1.0, 0.02);
    // Jet charges are assigned so that the event is neutral.
    EXPECT_EQ(charge, 0.0);
  }
}

TEST(GeneratorTtbar, DecaysInFlightReconstructParentMass) {
  const TtbarGenerator gen(TtbarGenerator::Config::ttbar3TeV());
  int nK0S = 0;
  int nLambda = 0;
  int nB = 0;
  double bCharged = 0.0;
  for (std::uint64_t ev = 0; ev < 100; ++ev) {
    auto rng = engine(ev, 7);
    const auto particles = gen.generate(rng);
    std::map<std::uint64_t, std::vector<const Particle*>> daughters;
    for (const Particle& p : particles) {
      if (p.parentId != 0) {
        daughters[p.parentId].push_back(&p);
      }
    }
    for (const Particle& p : particles) {
      if (p.status != 2) {
        continue;
      }
      const auto& d = daughters[p.id];
      ASSERT_GE(d.size(), 2u);
      FourMomentum sum;
      for (const Particle* k : d) {
        sum += fourMomentum(*k);
        // Daughters start at the decay vertex, after the parent.
        EXPECT_EQ(k->vertex, d.front()->vertex);
        EXPECT_GE(k->time, p.time);
      }
      const double m = pdg::massOf(p.pdg);
      EXPECT_NEAR(sum.mass() / m, 1.0, 1e-6) << "pdg " << p.pdg;
      // The flight is along the parent's direction.
      const Vector3 flight = d.front()->vertex - p.vertex;
      if (flight.norm() > 1e-9) {
        EXPECT_NEAR(flight.normalized().dot(p.momentum.normalized()), 1.0,
                    1e-9);
      }
      const int absPdg = std::abs(p.pdg);
      if (absPdg == pdg::kK0S && d.size() == 2 && d[0]->charge != 0.0) {
        ++nK0S;
        EXPECT_EQ(d[0]->charge + d[1]->charge, 0.0);
        EXPECT_EQ(std::abs(d[0]->pdg), pdg::kPiPlus);
      }
      if (absPdg == pdg::kLambda && d[0]->charge != 0.0) {
        ++nLambda;
      }
      if (absPdg == pdg::kB0 || absPdg == pdg::kBPlus || absPdg == pdg::kBs ||
          absPdg == pdg::kLambdaB) {
        ++nB;
        double q = 0.0;
        for (const Particle* k : d) {
          q += k->charge;
          bCharged += k->charge != 0.0 ? 1.0 : 0.0;
        }
        EXPECT_EQ(q, p.charge);
      }
    }
  }
  EXPECT_GT(nK0S, 50);
  EXPECT_GT(nLambda, 5);
  EXPECT_EQ(nB, 200);  // two b jets per event
  EXPECT_NEAR(bCharged / nB, 5.0, 0.6);
}

TEST(GeneratorTtbar, ReconstructableMultiplicityAndBeamSpot) {
  const TtbarGenerator gen(TtbarGenerator::Config::ttbar3TeV());
  double nReco = 0.0;
  double sumZ2 = 0.0;
  const int nEvents = 400;
  for (int ev = 0; ev < nEvents; ++ev) {
    auto rng = engine(ev, 99);
    const auto particles = gen.generate(rng);
    nReco += std::count_if(particles.begin(), particles.end(),
                           reconstructableAtGeneratorLevel);
    // The first particle is a primary: the beam-spot vertex.
    ASSERT_EQ(particles.front().parentId, 0u);
    EXPECT_EQ(particles.front().vertex.head<2>().norm(), 0.0);
    sumZ2 += std::pow(particles.front().vertex.z(), 2);
  }
  // Tuned to the paper's "about 90 tracks" (generator level).
  EXPECT_NEAR(nReco / nEvents, 90.0, 3.0);
  EXPECT_NEAR(std::sqrt(sumZ2 / nEvents), 0.044, 0.005);
}

TEST(GeneratorTtbar, BbbarAt500GeV) {
  const TtbarGenerator gen(TtbarGenerator::Config::bb500());
  EXPECT_EQ(gen.name(), "TtbarGenerator(bbbar, 500 GeV)");
  double nReco = 0.0;
  for (std::uint64_t ev = 0; ev < 50; ++ev) {
    auto rng = engine(ev);
    const auto particles = gen.generate(rng);
    expectWellFormed(particles);
    double charge = 0.0;
    int nB = 0;
    for (const Particle& p : particles) {
      charge += p.isStable() ? p.charge : 0.0;
      const int a = std::abs(p.pdg);
      nB += (a == pdg::kB0 || a == pdg::kBPlus || a == pdg::kBs ||
             a == pdg::kLambdaB)
                ? 1
                : 0;
      nReco += reconstructableAtGeneratorLevel(p) ? 1.0 : 0.0;
    }
    EXPECT_EQ(charge, 0.0);
    EXPECT_EQ(nB, 2);
  }
  EXPECT_GT(nReco / 50, 20.0);
  EXPECT_LT(nReco / 50, 50.0);
}

TEST(GeneratorTtbar, InvalidConfigIsRejected) {
  auto cfg = TtbarGenerator::Config::ttbar3TeV();
  cfg.sqrtS = 300.0;
  expectInputError<TtbarGenerator>(cfg, "sqrtS");
  cfg = TtbarGenerator::Config::ttbar3TeV();
  cfg.wMass = 170.0;
  expectInputError<TtbarGenerator>(cfg, "topMass");
  cfg = TtbarGenerator::Config::ttbar3TeV();
  cfg.bFragmentationMax = 0.5;
  expectInputError<TtbarGenerator>(cfg, "bFragmentationMax");
  cfg = TtbarGenerator::Config::ttbar3TeV();
  cfg.kaonFraction = -0.1;
  expectInputError<TtbarGenerator>(cfg, "kaonFraction");
}

// The comparison of a simulation with real files (SimulationValidation):
// binning, sums, matching by id, layer counts, merging, and the agreement
// count.

#include "conftrack/evaluation/SimulationValidation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace conftrack {
namespace {

Particle particle(std::uint64_t id, double pt, double eta, double r,
                  std::uint32_t nHits) {
  Particle p;
  p.id = id;
  p.momentum = Vector3(pt, 0.0, pt * std::sinh(eta));
  p.vertex = Vector3(r, 0.0, 0.0);
  p.nHits = nHits;
  return p;
}

const HitCountBin& binOf(const SimulationValidationTables& t, double pt,
                         double absEta, bool displaced) {
  for (const HitCountBin& b : t.bins) {
    if (pt >= b.ptMin && pt < b.ptMax && absEta >= b.absEtaMin &&
        absEta < b.absEtaMax && b.displaced == displaced) {
      return b;
    }
  }
  throw std::logic_error("no bin");
}

TEST(SimulationValidation, DefaultBinningIsTheIssues) {
  const SimulationValidation v(SimulationValidation::Config{});
  // 4 pT bins x 8 |eta| bins x prompt/displaced.
  EXPECT_EQ(v.empty().bins.size(), 64u);
}

TEST(SimulationValidation, SumsRealAndSimulatedHitsPerBin) {
  const SimulationValidation v(SimulationValidation::Config{});
  const std::vector<Particle> real = {
      particle(1, 0.2, 0.3, 0.0, 9),     // prompt, pT < 0.3, |eta| < 0.5
      particle(2, 0.25, -0.4, 0.5, 11),  // same bin (|eta|, r < 1 mm)
      particle(3, 0.2, 0.3, 5.0, 4),     // displaced
      particle(4, 2.0, 3.7, 0.0, 12),    // pT > 1, 3.5 <= |eta| < 4
      particle(5, 2.0, 4.2, 0.0, 3),     // |eta| beyond the table
      particle(6, 1.0, 0.1, 0.0, 8),     // not simulated: unmatched
  };
  // Simulated in another order, with other counts.
  const std::vector<Particle> simulated = {
      particle(4, 2.0, 3.7, 0.0, 6),  particle(3, 0.2, 0.3, 5.0, 18),
      particle(1, 0.2, 0.3, 0.0, 26), particle(2, 0.25, -0.4, 0.5, 27),
      particle(5, 2.0, 4.2, 0.0, 1),
  };
  const SimulationValidationTables t =
      v.run({real, simulated, std::span<const VolumeLayer>(),
             std::span<const VolumeLayer>()});
  EXPECT_EQ(t.events, 1u);
  EXPECT_EQ(t.particles, 4u);
  EXPECT_EQ(t.outsideBins, 1u);
  EXPECT_EQ(t.unmatched, 1u);
  const HitCountBin& low = binOf(t, 0.2, 0.3, false);
  EXPECT_EQ(low.particles, 2u);
  EXPECT_DOUBLE_EQ(low.realMean(), 10.0);
  EXPECT_DOUBLE_EQ(low.simulatedMean(), 26.5);
  EXPECT_NEAR(low.deviation(), 1.65, 1e-12);
  EXPECT_EQ(binOf(t, 0.2, 0.3, true).particles, 1u);
  EXPECT_DOUBLE_EQ(binOf(t, 0.2, 0.3, true).simulatedHits, 18.0);
  const HitCountBin& forward = binOf(t, 2.0, 3.7, false);
  EXPECT_DOUBLE_EQ(forward.realMean(), 12.0);
  EXPECT_DOUBLE_EQ(forward.simulatedMean(), 6.0);
  EXPECT_DOUBLE_EQ(forward.deviation(), -0.5);
}

TEST(SimulationValidation, CountsHitsPerVolumeAndLayer) {
  const SimulationValidation v(SimulationValidation::Config{});
  const std::vector<VolumeLayer> real = {{8, 2}, {7, 4}, {8, 2}, {8, 4}};
  const std::vector<VolumeLayer> simulated = {{8, 4}, {8, 2}, {9, 2}};
  const SimulationValidationTables t =
      v.run({std::span<const Particle>(), std::span<const Particle>(), real,
             simulated});
  ASSERT_EQ(t.layers.size(), 4u);
  EXPECT_EQ(t.layers[0].id, (VolumeLayer{7, 4}));
  EXPECT_EQ(t.layers[0].real, 1u);
  EXPECT_EQ(t.layers[0].simulated, 0u);
  EXPECT_EQ(t.layers[1].id, (VolumeLayer{8, 2}));
  EXPECT_EQ(t.layers[1].real, 2u);
  EXPECT_EQ(t.layers[1].simulated, 1u);
  EXPECT_EQ(t.layers[2].id, (VolumeLayer{8, 4}));
  EXPECT_EQ(t.layers[3].id, (VolumeLayer{9, 2}));
  EXPECT_EQ(t.layers[3].real, 0u);
  EXPECT_EQ(t.layers[3].simulated, 1u);
}

TEST(SimulationValidation, MergeSumsEventsAndLayers) {
  const SimulationValidation v(SimulationValidation::Config{});
  const std::vector<Particle> a = {particle(1, 0.5, 1.2, 0.0, 10)};
  const std::vector<Particle> aSim = {particle(1, 0.5, 1.2, 0.0, 11)};
  const std::vector<Particle> b = {particle(7, 0.5, -1.3, 0.0, 14)};
  const std::vector<Particle> bSim = {particle(7, 0.5, -1.3, 0.0, 12)};
  const std::vector<VolumeLayer> hitsA = {{8, 2}};
  const std::vector<VolumeLayer> hitsB = {{8, 2}, {13, 6}};
  SimulationValidationTables total = v.empty();
  total.merge(v.run({a, aSim, hitsA, hitsA}));
  total.merge(v.run({b, bSim, hitsB, hitsA}));
  EXPECT_EQ(total.events, 2u);
  const HitCountBin& bin = binOf(total, 0.5, 1.25, false);
  EXPECT_EQ(bin.particles, 2u);
  EXPECT_DOUBLE_EQ(bin.realMean(), 12.0);
  EXPECT_DOUBLE_EQ(bin.simulatedMean(), 11.5);
  ASSERT_EQ(total.layers.size(), 2u);
  EXPECT_EQ(total.layers[0].real, 2u);
  EXPECT_EQ(total.layers[0].simulated, 2u);
  EXPECT_EQ(total.layers[1].real, 1u);
  EXPECT_EQ(total.layers[1].simulated, 0u);

  SimulationValidation::Config coarse;
  coarse.etaBinWidth = 1.0;
  EXPECT_THROW(total.merge(SimulationValidation(coarse).empty()),
               std::invalid_argument);
}

TEST(SimulationValidation, RepeatsAverageTheSimulatedColumnsOnly) {
  const SimulationValidation v(SimulationValidation::Config{});
  const std::vector<Particle> real = {particle(1, 0.5, 1.2, 0.0, 10),
                                      particle(2, 0.5, 1.3, 0.0, 12)};
  const std::vector<Particle> first = {particle(1, 0.5, 1.2, 0.0, 11),
                                       particle(2, 0.5, 1.3, 0.0, 12)};
  const std::vector<Particle> second = {particle(1, 0.5, 1.2, 0.0, 8),
                                        particle(2, 0.5, 1.3, 0.0, 14)};
  const std::vector<VolumeLayer> realHits = {{8, 2}, {8, 2}, {8, 4}};
  const std::vector<VolumeLayer> oneHit = {{8, 2}};
  const std::vector<VolumeLayer> fourHits = {{8, 2}, {8, 2}, {8, 2}, {13, 2}};
  const std::vector<SimulationValidationTables> repeats = {
      v.run({real, first, realHits, oneHit}),
      v.run({real, second, realHits, fourHits})};
  const SimulationValidationTables mean =
      SimulationValidationTables::averageRepeats(repeats);
  EXPECT_EQ(mean.events, 1u);
  EXPECT_EQ(mean.particles, 2u);
  const HitCountBin& bin = binOf(mean, 0.5, 1.25, false);
  EXPECT_EQ(bin.particles, 2u);
  EXPECT_DOUBLE_EQ(bin.realMean(), 11.0);
  EXPECT_DOUBLE_EQ(bin.simulatedMean(), (23.0 + 22.0) / 2.0 / 2.0);
  ASSERT_EQ(mean.layers.size(), 3u);
  EXPECT_EQ(mean.layers[0].real, 2u);  // (8, 2): 1 and 3 simulated
  EXPECT_EQ(mean.layers[0].simulated, 2u);
  EXPECT_EQ(mean.layers[1].real, 1u);  // (8, 4): never simulated
  EXPECT_EQ(mean.layers[1].simulated, 0u);
  EXPECT_EQ(mean.layers[2].real, 0u);       // (13, 2): 1 of 2 repeats
  EXPECT_EQ(mean.layers[2].simulated, 1u);  // 0.5 rounds away from 0

  EXPECT_THROW(SimulationValidationTables::averageRepeats({}),
               std::invalid_argument);
  const std::vector<Particle> otherReal = {particle(1, 0.5, 1.2, 0.0, 9),
                                           particle(2, 0.5, 1.3, 0.0, 12)};
  const std::vector<SimulationValidationTables> mixed = {
      repeats[0], v.run({otherReal, first, realHits, oneHit})};
  EXPECT_THROW(SimulationValidationTables::averageRepeats(mixed),
               std::invalid_argument);
}

TEST(SimulationValidation, AgreementCountsOnlyPopulatedBins) {
  SimulationValidationTables t;
  HitCountBin good;
  good.particles = 200;
  good.realHits = 2000.0;
  good.simulatedHits = 2080.0;  // +4 %
  HitCountBin bad = good;
  bad.simulatedHits = 5000.0;  // +150 %
  HitCountBin few = good;
  few.particles = 10;
  few.simulatedHits = 100000.0;  // ignored: too few particles
  t.bins = {good, bad, few};
  const BinAgreement a = binAgreement(t, 100, 0.05);
  EXPECT_EQ(a.bins, 2u);
  EXPECT_EQ(a.within, 1u);
  EXPECT_DOUBLE_EQ(a.worst, 1.5);
}

TEST(SimulationValidation, BadConfigIsRejected) {
  auto rejects = [](auto change) {
    SimulationValidation::Config c;
    change(c);
    EXPECT_THROW(SimulationValidation{c}, std::invalid_argument);
  };
  rejects([](auto& c) { c.ptEdges = {0.3}; });
  rejects([](auto& c) { c.ptEdges = {0.0, 1.0, 0.5}; });
  rejects([](auto& c) {
    c.ptEdges = {0.0, std::numeric_limits<double>::infinity(), 5.0};
  });
  rejects([](auto& c) { c.ptEdges = {-1.0, 1.0}; });
  rejects([](auto& c) { c.etaBinWidth = 0.0; });
  rejects([](auto& c) { c.maxAbsEta = 3.7; });
  rejects([](auto& c) { c.etaBinWidth = 0.01; });
  rejects([](auto& c) {
    c.displacedRadius = std::numeric_limits<double>::quiet_NaN();
  });
}

}  // namespace
}  // namespace conftrack

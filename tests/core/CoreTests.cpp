#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Event.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/Track.hpp"
#include "conftrack/core/Units.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

namespace conftrack {
namespace {

TEST(Units, ConversionsAndConstants) {
  EXPECT_DOUBLE_EQ(1.0 * units::m, 1000.0 * units::mm);
  EXPECT_DOUBLE_EQ(3.0 * units::um, 0.003);
  EXPECT_DOUBLE_EQ(1.0 * units::MeV, 1e-3 * units::GeV);
  EXPECT_DOUBLE_EQ(180.0 * units::degree, std::numbers::pi);
  // pT = 0.3 B R: 1 GeV in 4 T has R = 834 mm (physics.md section 1).
  double radius = 1.0 * units::GeV / (constants::kPtPerTeslaMm * 4.0);
  EXPECT_NEAR(radius, 834.0 * units::mm, 0.5);
  EXPECT_DOUBLE_EQ(constants::c, 299.792458);
}

TEST(Random, StreamsAreIndependentAndReproducible) {
  std::set<std::uint64_t> seeds;
  for (std::uint64_t ev = 0; ev < 1000; ++ev) {
    seeds.insert(deriveSeed(1, ev, RandomStream::eSimulation));
    seeds.insert(deriveSeed(1, ev, RandomStream::eSignalGenerator));
    seeds.insert(deriveSeed(2, ev, RandomStream::eSimulation));
  }
  EXPECT_EQ(seeds.size(), 3000u);
  RandomEngine a = makeEngine(7, 3, RandomStream::eSimulation);
  RandomEngine b = makeEngine(7, 3, RandomStream::eSimulation);
  EXPECT_EQ(a(), b());
}

TEST(Event, FindParticle) {
  Event ev;
  for (std::uint64_t id : {5u, 2u, 9u}) {
    Particle p;
    p.id = id;
    ev.particles.push_back(p);
  }
  ev.sortParticles();
  EXPECT_EQ(ev.findParticle(2), 0u);
  EXPECT_EQ(ev.findParticle(9), 2u);
  EXPECT_EQ(ev.findParticle(4), kInvalidIndex);
}

TEST(Track, FittedHitsLeaveOutliersAndTurnHits) {
  Track t;
  t.hits = {7, 3, 9, 4, 12};
  t.outlier = {kFittedHit, kOutlierHit, kFittedHit, kTurnHit, kFittedHit};
  std::vector<HitIndex> fitted = {99};  // cleared first
  t.fittedHits(fitted);
  EXPECT_EQ(fitted, (std::vector<HitIndex>{7, 9, 12}));
  EXPECT_EQ(fitted.size(), t.numMeasurements());
}

TEST(ConfigTable, TypedGettersAndErrors) {
  auto table = ConfigTable::parse("a = 1.5\nb = 3\nc = \"x\"\n[t]\nd = true\n",
                                  "cfg.toml");
  ConfigTable root(*table, "cfg.toml", "");
  EXPECT_DOUBLE_EQ(root.getDouble("a", Range::positive()), 1.5);
  EXPECT_EQ(root.getInt("b"), 3);
  EXPECT_DOUBLE_EQ(root.getDouble("b"), 3.0);  // integers are numbers too
  EXPECT_EQ(root.getString("c"), "x");
  EXPECT_DOUBLE_EQ(root.getDouble("e", 7.0, Range{}), 7.0);
  EXPECT_TRUE(root.getTable("t").getBool("d"));
  EXPECT_NO_THROW(root.rejectUnknownKeys());
  try {
    root.getDouble("a", Range::closed(2.0, 3.0));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "cfg.toml:1: key 'a': value 1.5 out of range [2, 3]");
  }
  try {
    root.getTable("t").getString("missing");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cfg.toml:4: key 't.missing': missing");
  }
}

TEST(ConfigTable, UnknownKeyIsReported) {
  auto table = ConfigTable::parse("a = 1\nzzz = 2\n", "cfg.toml");
  ConfigTable root(*table, "cfg.toml", "");
  root.getInt("a");
  try {
    root.rejectUnknownKeys();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cfg.toml:2: key 'zzz': unknown key");
  }
}

}  // namespace
}  // namespace conftrack

// The simulator as a whole: hit smearing pulls, hit counts in CLICdet,
// bookkeeping (ids, nHits, skipped particles) and determinism.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/simulation/HitSmearing.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

namespace conftrack {
namespace {

using namespace units;

/// `n` charged pions from near the origin with a soft spectrum (exponential
/// pT, mean 0.4 GeV, above 0.1 GeV) and |eta| < 2.5.
std::vector<Particle> softPions(std::size_t n, std::uint64_t seed) {
  RandomEngine rng(seed);
  std::exponential_distribution<double> pt(1.0 / 0.4);
  std::uniform_real_distribution<double> eta(-2.5, 2.5);
  std::uniform_real_distribution<double> phi(-std::numbers::pi,
                                             std::numbers::pi);
  std::normal_distribution<double> vertex(0.0, 0.01);
  std::vector<Particle> out;
  for (std::size_t i = 0; i < n; ++i) {
    Particle p;
    p.id = i + 1;
    p.charge = i % 2 == 0 ? 1.0 : -1.0;
    p.pdg = 211 * static_cast<int>(p.charge);
    const double t = 0.1 + pt(rng);
    const double f = phi(rng);
    p.momentum = {t * std::cos(f), t * std::sin(f), t * std::sinh(eta(rng))};
    p.vertex = {vertex(rng), vertex(rng), 100.0 * vertex(rng)};
    out.push_back(p);
  }
  return out;
}

TEST(SimulatorSmearing, PullsInLocalFrame) {
  // (measured - true)/sigma in local u (r-phi arc / tangential) and v (z /
  // radial) for all hits of 3000 soft pions in CLICdet: mean 0 +- 0.02,
  // width 1 +- 0.02 per layer kind.
  const Detector detector = loadDetector("clicdet");
  const Simulator simulator(detector);
  Event event;
  RandomEngine rng(7);
  simulator.simulate(softPions(3000, 1), rng, event);
  struct Sums {
    double n = 0, u = 0, uu = 0, v = 0, vv = 0;
  };
  Sums barrel;
  Sums disk;
  for (std::size_t i = 0; i < event.hits.size(); ++i) {
    const Hit& hit = event.hits[i];
    const Vector3& truth = event.truth[i].position;
    const SensitiveLayer& layer =
        detector.layers()[*detector.findLayer(hit.detId)];
    double du = 0;
    double dv = 0;
    if (layer.isDisk()) {
      Vector3 uAxis;
      Vector3 vAxis;
      layer.localAxes(truth, uAxis, vAxis);
      EXPECT_DOUBLE_EQ(hit.position.z(), layer.z());
      du = (hit.position - truth).dot(uAxis);
      dv = (hit.position - truth).dot(vAxis);
    } else {
      // Stays on the cylinder; u is the arc length.
      EXPECT_NEAR(hit.position.head<2>().norm(), layer.r, 1e-9);
      double dphi = std::atan2(hit.position.y(), hit.position.x()) -
                    std::atan2(truth.y(), truth.x());
      dphi = std::remainder(dphi, 2 * std::numbers::pi);
      du = layer.r * dphi;
      dv = hit.position.z() - truth.z();
    }
    EXPECT_EQ(hit.sigmaU, layer.sigmaU);
    EXPECT_EQ(hit.sigmaV, layer.sigmaV);
    Sums& s = layer.isDisk() ? disk : barrel;
    const double pu = du / hit.sigmaU;
    const double pv = dv / hit.sigmaV;
    s.n += 1;
    s.u += pu;
    s.uu += pu * pu;
    s.v += pv;
    s.vv += pv * pv;
  }
  for (const Sums* s : {&barrel, &disk}) {
    ASSERT_GT(s->n, 10000) << (s == &barrel ? "barrel" : "disk");
    const double mu = s->u / s->n;
    const double mv = s->v / s->n;
    EXPECT_NEAR(mu, 0.0, 0.02);
    EXPECT_NEAR(mv, 0.0, 0.02);
    EXPECT_NEAR(std::sqrt(s->uu / s->n - mu * mu), 1.0, 0.02);
    EXPECT_NEAR(std::sqrt(s->vv / s->n - mv * mv), 1.0, 0.02);
  }
}

TEST(SimulatorSmearing, RedrawsAndDropsAtTheEdge) {
  // A barrel layer with a 1 mm z resolution: hits at the edge are redrawn
  // until inside; with one attempt half of them are dropped.
  SensitiveLayer layer;
  layer.shape = SurfaceShape::eCylinder;
  layer.r = layer.rMin = layer.rMax = 100.0;
  layer.zMin = -50.0;
  layer.zMax = 50.0;
  layer.sigmaU = 0.01;
  layer.sigmaV = 1.0;
  std::normal_distribution<double> normal;
  RandomEngine rng(3);
  const Vector3 edge(100.0, 0.0, 50.0);
  int kept1 = 0;
  int kept10 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Vector3 measured;
    kept1 += smearHitPosition(layer, edge, rng, normal, 1, measured);
    if (smearHitPosition(layer, edge, rng, normal, 10, measured)) {
      ++kept10;
      EXPECT_LE(measured.z(), 50.0);
      EXPECT_NEAR(measured.head<2>().norm(), 100.0, 1e-12);
    }
  }
  EXPECT_NEAR(kept1 / double(n), 0.5, 0.02);
  EXPECT_NEAR(kept10 / double(n), 1.0 - std::pow(0.5, 10), 0.002);
  // A disk: the ring r in [rMin, rMax] is respected, z stays on the disk.
  SensitiveLayer disk;
  disk.shape = SurfaceShape::eDisk;
  disk.zMin = disk.zMax = 800.0;
  disk.rMin = 100.0;
  disk.rMax = 500.0;
  disk.sigmaU = 0.007;
  disk.sigmaV = 2.0;
  for (int i = 0; i < 1000; ++i) {
    Vector3 measured;
    if (smearHitPosition(disk, Vector3(0.0, 100.0, 800.0), rng, normal, 10,
                         measured)) {
      EXPECT_GE(measured.head<2>().norm(), 100.0);
      EXPECT_EQ(measured.z(), 800.0);
    }
  }
}

TEST(SimulatorClicdet, CentralMuonHitCounts) {
  // 10 GeV muon at theta = 89 deg: 6 vertex-barrel, 3 inner-tracker and 3
  // outer-tracker barrel hits, nothing else, with all effects on.
  const Detector detector = loadDetector("clicdet");
  const Simulator simulator(detector);
  for (int k = 0; k < 8; ++k) {
    const double theta = 89.0 * degree;
    const double phi = -3.0 + 0.8 * k;
    Particle mu;
    mu.id = 1;
    mu.pdg = k % 2 == 0 ? 13 : -13;
    mu.charge = k % 2 == 0 ? -1.0 : 1.0;
    mu.momentum =
        10.0 * Vector3(std::sin(theta) * std::cos(phi),
                       std::sin(theta) * std::sin(phi), std::cos(theta));
    Event event;
    RandomEngine rng(100 + k);
    simulator.simulate({mu}, rng, event);
    std::map<std::string, int> counts;
    for (const Hit& hit : event.hits) {
      ++counts[detector.subdetectors()[hit.detId.subdetector].name];
    }
    EXPECT_EQ(counts.size(), 3u);
    EXPECT_EQ(counts["VertexBarrel"], 6);
    EXPECT_EQ(counts["InnerTrackerBarrel"], 3);
    EXPECT_EQ(counts["OuterTrackerBarrel"], 3);
    EXPECT_EQ(event.particles.at(0).nHits, 12u);
    // Layers are hit in order, with modules and axes filled.
    for (std::size_t i = 0; i < event.hits.size(); ++i) {
      const Hit& hit = event.hits[i];
      const SensitiveLayer& layer =
          detector.layers()[*detector.findLayer(hit.detId)];
      EXPECT_EQ(hit.detId.module, layer.moduleAt(event.truth[i].position));
      EXPECT_NEAR(hit.uAxis.dot(hit.vAxis), 0.0, 1e-12);
      EXPECT_NEAR(hit.vAxis.z(), 1.0, 1e-12);
      if (i > 0) {
        EXPECT_GT(event.truth[i].time, event.truth[i - 1].time);
        EXPECT_GT(event.truth[i].position.head<2>().norm(),
                  event.truth[i - 1].position.head<2>().norm());
      }
    }
    // Time ~ path / c for a relativistic muon.
    const Vector3& last = event.truth.back().position;
    EXPECT_NEAR(event.truth.back().time, last.norm() / constants::c, 0.01);
  }
}

TEST(SimulatorBookkeeping, IdsParticlesAndSkips) {
  const Detector detector = loadDetector("clicdet");
  const Simulator simulator(detector);
  std::vector<Particle> particles = softPions(20, 9);
  particles[3].charge = 0.0;  // neutral
  particles[3].pdg = 111;
  particles[5].status = 2;                   // decayed
  particles[7].momentum *= 1e-3;             // below minMomentum
  particles[9].vertex = {0.0, 0.0, 3000.0};  // outside the envelope
  // Out of order: the output is sorted by id.
  std::swap(particles[0], particles[1]);
  Event event;
  RandomEngine rng(1);
  simulator.simulate(particles, rng, event);
  ASSERT_EQ(event.hits.size(), event.truth.size());
  ASSERT_EQ(event.particles.size(), particles.size());
  for (std::size_t i = 0; i < event.particles.size(); ++i) {
    EXPECT_EQ(event.particles[i].id, i + 1);
  }
  for (std::size_t i : {3, 5, 7, 9}) {
    EXPECT_EQ(event.particles[i].nHits, 0u) << i;
  }
  std::size_t total = 0;
  for (const Particle& p : event.particles) {
    total += p.nHits;
  }
  EXPECT_EQ(total, event.hits.size());
  for (std::size_t i = 0; i < event.hits.size(); ++i) {
    EXPECT_EQ(event.hits[i].id, i + 1);
    const ParticleIndex index = event.findParticle(event.truth[i].particleId);
    ASSERT_NE(index, kInvalidIndex);
  }
  // A second call appends, with ids continuing.
  const std::size_t before = event.hits.size();
  std::vector<Particle> more = softPions(5, 10);
  for (Particle& p : more) {
    p.id += 100;
  }
  simulator.simulate(more, rng, event);
  std::set<std::uint64_t> ids;
  for (const Hit& h : event.hits) {
    ids.insert(h.id);
  }
  EXPECT_EQ(ids.size(), event.hits.size());
  EXPECT_GT(event.hits.size(), before);
  EXPECT_EQ(event.particles.size(), 25u);
}

TEST(SimulatorBookkeeping, RejectsInvalidConfig) {
  const Detector detector = loadDetector("clicdet");
  Simulator::Config config;
  config.maxTurns = 0.0;
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
  config = {};
  config.maxSmearAttempts = 0;
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
  config = {};
  config.minCosIncidence = 0.0;
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
}

TEST(SimulatorDeterminism, SameSeedSameOutput) {
  const Detector detector = loadDetector("clicdet");
  const Simulator simulator(detector);
  const std::vector<Particle> particles = softPions(500, 4);
  auto run = [&](std::uint64_t seed) {
    Event event;
    RandomEngine rng = makeEngine(seed, 17, RandomStream::eSimulation);
    simulator.simulate(particles, rng, event);
    return event;
  };
  const Event a = run(1);
  const Event b = run(1);
  const Event c = run(2);
  ASSERT_EQ(a.hits.size(), b.hits.size());
  ASSERT_GT(a.hits.size(), 1000u);
  for (std::size_t i = 0; i < a.hits.size(); ++i) {
    EXPECT_EQ(a.hits[i].id, b.hits[i].id);
    EXPECT_EQ(a.hits[i].position, b.hits[i].position);
    EXPECT_EQ(a.hits[i].detId, b.hits[i].detId);
    EXPECT_EQ(a.truth[i].momentum, b.truth[i].momentum);
    EXPECT_EQ(a.truth[i].time, b.truth[i].time);
  }
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    EXPECT_EQ(a.particles[i].nHits, b.particles[i].nHits);
  }
  // A different seed gives different smearing.
  bool differs = a.hits.size() != c.hits.size();
  for (std::size_t i = 0; !differs && i < a.hits.size(); ++i) {
    differs = a.hits[i].position != c.hits[i].position;
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace conftrack

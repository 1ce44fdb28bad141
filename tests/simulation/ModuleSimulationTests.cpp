// The simulation with flat sensors (Simulator + ModuleLayout): overlaps
// give two hits and gaps none, hits are measured in the sensor frame; the
// half-turn looper stop, the blind turning band, hadronic interactions and
// the grazing cut of the TrackML-like simulation.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/MaterialInteractions.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "IdealSimulatorConfig.hpp"

namespace conftrack {
namespace {

constexpr double kPi = std::numbers::pi;

/// Barrel layers at the given radii (|z| < halfZ), 2 T.
Detector barrels(const std::vector<double>& radii, double halfZ,
                 double xOverX0) {
  std::string text =
      "[detector]\nname = \"Toy\"\nmodel = \"toy\"\nbz_T = 2.0\n"
      "envelope_r_mm = 900.0\nenvelope_z_mm = 4000.0\n\n"
      "[[subdetector]]\nname = \"Barrel\"\nkind = \"barrel\"\n";
  for (std::size_t i = 0; i < radii.size(); ++i) {
    text += "  [[subdetector.layer]]\n  name = \"L" + std::to_string(i) +
            "\"\n  r_mm = " + std::to_string(radii[i]) +
            "\n  half_z_mm = " + std::to_string(halfZ) +
            "\n  x_over_x0 = " + std::to_string(xOverX0) +
            "\n  sigma_rphi_um = 10.0\n  sigma_z_um = 20.0\n";
  }
  return parseDetector(text, "toy.toml");
}

/// A ring of `n` flat sensors around the first layer of `detector`, each
/// `widthFactor` times as wide as the ring's phi sector (> 1: overlaps,
/// < 1: gaps), alternately 1 mm inside and outside the layer radius, of
/// `sensorX0` [X0]; each layer's support `supportX0` [X0].
std::shared_ptr<const ModuleLayout> ring(const Detector& detector, int n,
                                         double widthFactor,
                                         double supportX0 = 0.001,
                                         double sensorX0 = 0.002) {
  const SensitiveLayer& layer = detector.layers()[0];
  std::vector<PlanarModule> modules;
  for (int k = 0; k < n; ++k) {
    const double phi = 2.0 * kPi * k / n;
    const double r = layer.r + (k % 2 == 0 ? -1.0 : 1.0);
    PlanarModule m;
    m.layer = 0;
    m.module = static_cast<std::uint32_t>(k + 1);
    m.center = Vector3(r * std::cos(phi), r * std::sin(phi), 0.0);
    m.rotation.col(0) = Vector3(-std::sin(phi), std::cos(phi), 0.0);
    m.rotation.col(1) = Vector3::UnitZ();
    m.rotation.col(2) = Vector3(std::cos(phi), std::sin(phi), 0.0);
    m.minHalfU = m.maxHalfU = widthFactor * layer.r * std::tan(kPi / n);
    m.halfV = layer.zMax;
    m.thickness = 0.2;
    m.thicknessX0 = sensorX0;
    m.sigmaU = 0.01;
    m.sigmaV = 0.05;
    modules.push_back(m);
  }
  return std::make_shared<const ModuleLayout>(
      detector, modules,
      std::vector<double>(detector.layers().size(), supportX0));
}

Particle particle(std::uint64_t id, double pt, double phi, double eta,
                  const Vector3& vertex = Vector3::Zero(), int pdg = 211) {
  Particle p;
  p.id = id;
  p.pdg = pdg;
  p.charge = pdg > 0 ? 1.0 : -1.0;
  p.vertex = vertex;
  p.momentum =
      Vector3(pt * std::cos(phi), pt * std::sin(phi), pt * std::sinh(eta));
  return p;
}

/// Binomial: `measured` within 5 standard deviations of `expected` for
/// `n` trials.
void expectFraction(double measured, double expected, int n) {
  EXPECT_NEAR(measured, expected,
              5.0 * std::sqrt(expected * (1.0 - expected) / n));
}

TEST(ModuleSimulation, OverlapGivesTwoHitsAndGapNone) {
  const Detector detector = barrels({100.0}, 200.0, 0.01);
  const Simulator overlapping(detector, test::idealSimulatorConfig(),
                              ring(detector, 16, 1.1));
  const Simulator gapped(detector, test::idealSimulatorConfig(),
                         ring(detector, 16, 0.9));
  // phi = 0: the centre of sensor 1; phi = pi/16: the border of sensors 1
  // and 2 (the overlap, or the gap).
  const std::vector<Particle> particles = {particle(1, 100.0, 0.0, 0.3),
                                           particle(2, 100.0, kPi / 16, -0.2)};
  Event a;
  RandomEngine rng(1);
  overlapping.simulate(particles, rng, a);
  ASSERT_EQ(a.particles[0].nHits, 1u);
  ASSERT_EQ(a.particles[1].nHits, 2u);
  std::set<std::uint32_t> modules;
  for (std::size_t i = 0; i < a.hits.size(); ++i) {
    const Hit& hit = a.hits[i];
    const PlanarModule* m = overlapping.modules()->find(0, hit.detId.module);
    ASSERT_NE(m, nullptr);
    // The (unsmeared) hit is the crossing of the sensor's mid-plane, with
    // the sensor's frame and resolution.
    EXPECT_NEAR(m->toLocal(hit.position).z(), 0.0, 1e-9);
    EXPECT_TRUE(hit.position.isApprox(a.truth[i].position, 1e-12));
    EXPECT_TRUE(hit.uAxis.isApprox(m->uAxis()));
    EXPECT_DOUBLE_EQ(hit.sigmaU, 0.01);
    if (a.truth[i].particleId == 2) {
      modules.insert(hit.detId.module);
    }
  }
  EXPECT_EQ(modules, (std::set<std::uint32_t>{1, 2}));
  Event b;
  gapped.simulate(particles, rng, b);
  EXPECT_EQ(b.particles[0].nHits, 1u);
  EXPECT_EQ(b.particles[1].nHits, 0u);
}

TEST(ModuleSimulation, BelowThePtFloorAParticleEndsInItsFirstSensor) {
  const Detector detector = barrels({100.0, 200.0}, 200.0, 0.01);
  Simulator::Config config = test::idealSimulatorConfig();
  // At the border of sensors 1 and 2 of an overlapping ring: two hits on
  // the first layer, one on the second.
  const std::vector<Particle> particles = {particle(1, 2.0, kPi / 16, -0.2),
                                           particle(2, 20.0, kPi / 16, -0.2)};
  const auto hitsWith = [&](double floor) {
    config.minTransverseMomentum = floor;
    Event event;
    RandomEngine rng(5);
    Simulator(detector, config, ring(detector, 16, 1.1))
        .simulate(particles, rng, event);
    return std::vector<std::uint32_t>{event.particles[0].nHits,
                                      event.particles[1].nHits};
  };
  using Counts = std::vector<std::uint32_t>;
  EXPECT_EQ(hitsWith(0.0), (Counts{3, 3}));
  // Below the floor: the first sensor's hit only, not the overlapping one.
  EXPECT_EQ(hitsWith(10.0), (Counts{1, 3}));
  config.minTransverseMomentum = -1.0;
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
}

TEST(ModuleSimulation, SmearedInTheSensorFrameAndKeptInside) {
  const Detector detector = barrels({100.0}, 200.0, 0.01);
  Simulator::Config config = test::idealSimulatorConfig();
  config.smearHits = true;
  const Simulator simulator(detector, config, ring(detector, 16, 1.1));
  std::vector<Particle> particles;
  for (int k = 0; k < 4000; ++k) {
    particles.push_back(particle(k + 1, 50.0, 2.0 * kPi * k / 4000.0,
                                 std::remainder(0.37 * k, 1.5)));
  }
  Event event;
  RandomEngine rng(3);
  simulator.simulate(particles, rng, event);
  double sum = 0.0;
  double sum2 = 0.0;
  double sumV2 = 0.0;
  for (std::size_t i = 0; i < event.hits.size(); ++i) {
    const PlanarModule* m =
        simulator.modules()->find(0, event.hits[i].detId.module);
    const Vector3 local = m->toLocal(event.hits[i].position);
    EXPECT_NEAR(local.z(), 0.0, 1e-9);
    EXPECT_TRUE(m->contains(local.x(), local.y()));
    const Vector3 d = event.hits[i].position - event.truth[i].position;
    const double pullU = d.dot(m->uAxis()) / m->sigmaU;
    sum += pullU;
    sum2 += pullU * pullU;
    sumV2 += std::pow(d.dot(m->vAxis()) / m->sigmaV, 2);
  }
  const double n = static_cast<double>(event.hits.size());
  ASSERT_GT(n, 4000.0);  // overlaps add to one hit per particle
  // Pulls: mean 0 +- 0.05, width 1 +- 0.05 (about 4500 hits).
  EXPECT_NEAR(sum / n, 0.0, 0.05);
  EXPECT_NEAR(std::sqrt(sum2 / n), 1.0, 0.05);
  EXPECT_NEAR(std::sqrt(sumV2 / n), 1.0, 0.05);
}

TEST(ModuleSimulation, TrackmlLoopersStopAfterHalfATurn) {
  const Detector detector = barrels({100.0, 200.0, 300.0, 400.0}, 2000.0, 0.0);
  Simulator::Config config = test::idealSimulatorConfig();
  const Simulator follow(detector, config);
  config.maxTurns = 0.5;  // as trackmlSimulatorConfig (ACTS loop protection)
  const Simulator half(detector, config);
  // pT 0.085 GeV in 2 T: radius 141.7 mm. From the origin the particle
  // reaches r = 283 mm after half a turn: it crosses 100 and 200 outward.
  // From (250, 0) heading inward: the circle centre is at (250, -141.7) or
  // (250, 141.7); the particle passes its smallest radius, 145.6 mm, and
  // after half a turn is at (250, +-283.4), r = 377.9 mm: in through 200,
  // out through 200 and 300.
  const std::vector<Particle> particles = {
      particle(1, 0.085, 0.4, 0.01),
      particle(2, 0.085, kPi, 0.01, Vector3(250.0, 0.0, 0.0))};
  Event stopped;
  RandomEngine rng(1);
  half.simulate(particles, rng, stopped);
  EXPECT_EQ(stopped.particles[0].nHits, 2u);
  EXPECT_EQ(stopped.particles[1].nHits, 3u);
  double lastR = 0.0;
  for (std::size_t i = 0; i < stopped.hits.size(); ++i) {
    if (stopped.truth[i].particleId == 1) {
      const double r = stopped.hits[i].position.head<2>().norm();
      EXPECT_GT(r, lastR);  // outward only
      lastR = r;
    }
  }
  Event followed;
  follow.simulate(particles, rng, followed);
  EXPECT_GT(followed.particles[0].nHits, 20u);  // 10 turns of 4 crossings
  EXPECT_GT(followed.particles[1].nHits, 20u);
}

TEST(ModuleSimulation, InwardStartIsBlindInItsTurningBandAfterTheTurn) {
  const Detector detector = barrels({100.0, 200.0, 300.0, 400.0}, 2000.0, 0.0);
  Simulator::Config config = test::idealSimulatorConfig();
  config.maxTurns = 0.5;
  // The inward particle of TrackmlLoopersStopAfterHalfATurn: in through
  // 200, smallest radius 145.6 mm, out through 200 and 300. The outward
  // one from the same place crosses 300 and 400 out and 400 back in.
  const std::vector<Particle> particles = {
      particle(1, 0.085, kPi, 0.01, Vector3(250.0, 0.0, 0.0)),
      particle(2, 0.085, 0.0, 0.01, Vector3(250.0, 0.0, 0.0))};
  const auto hitsWith = [&](std::vector<double> edges, double minRadius) {
    config.turnBandEdges = std::move(edges);
    config.turnBandMinProductionRadius = minRadius;
    Event event;
    RandomEngine rng(3);
    Simulator(detector, config).simulate(particles, rng, event);
    return std::vector<std::uint32_t>{event.particles[0].nHits,
                                      event.particles[1].nHits};
  };
  using Counts = std::vector<std::uint32_t>;
  EXPECT_EQ(hitsWith({}, 0.0), (Counts{3, 3}));
  // Turned below 250 mm: the way out through 200 is blind, not 300.
  EXPECT_EQ(hitsWith({250.0}, 0.0), (Counts{2, 3}));
  // Turned between 100 and 350 mm: 200 and 300 on the way out are blind;
  // the way in (200) is not.
  EXPECT_EQ(hitsWith({100.0, 350.0}, 0.0), (Counts{1, 3}));
  // Turned in another band than the layers it crosses afterwards.
  EXPECT_EQ(hitsWith({140.0, 150.0}, 0.0), (Counts{3, 3}));
  // Produced inside the minimum production radius: not affected.
  EXPECT_EQ(hitsWith({250.0}, 260.0), (Counts{3, 3}));
  config.turnBandEdges = {300.0, 200.0};
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
  config.turnBandEdges = {-1.0};
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
}

TEST(ModuleSimulation, HadronicInteractionsEndHadronsOnly) {
  // Two layers of 0.5 X0: a pion ends in the first with probability
  // 1 - exp(-0.5 / (lambda_I / X0)) = 0.0958 (silicon); muons never do.
  const Detector detector = barrels({100.0, 200.0}, 2000.0, 0.5);
  Simulator::Config config = test::idealSimulatorConfig();
  config.hadronicInteractions = true;
  const Simulator simulator(detector, config);
  std::vector<Particle> particles;
  constexpr int kCount = 20000;
  for (int k = 0; k < kCount; ++k) {
    particles.push_back(particle(k + 1, 10.0, 0.001 * k, 0.0, Vector3::Zero(),
                                 k % 2 == 0 ? 211 : -13));
  }
  Event event;
  RandomEngine rng(9);
  simulator.simulate(particles, rng, event);
  int pionsWithOneHit = 0;
  for (const Particle& p : event.particles) {
    if (p.pdg == 211) {
      pionsWithOneHit += p.nHits == 1 ? 1 : 0;
      EXPECT_GE(p.nHits, 1u);
    } else {
      EXPECT_EQ(p.nHits, 2u);
    }
  }
  const double expected =
      -std::expm1(-0.5 / kSiliconInteractionOverRadiationLength);
  // Binomial: 5 standard deviations (0.0021).
  expectFraction(pionsWithOneHit / (kCount / 2.0), expected, kCount / 2);
}

/// Fractions of `particles` with 0, 1, 2 and 3 or more hits.
std::vector<double> hitCountFractions(const Simulator& simulator,
                                      const std::vector<Particle>& particles) {
  Event event;
  RandomEngine rng(21);
  simulator.simulate(particles, rng, event);
  std::vector<int> counts(4, 0);
  for (const Particle& p : event.particles) {
    ++counts[std::min<std::uint32_t>(p.nHits, 3)];
  }
  std::vector<double> fraction;
  for (int n : counts) {
    fraction.push_back(double(n) / double(particles.size()));
  }
  return fraction;
}

TEST(ModuleSimulation, PlacedSupportOfABarrelLayerLiesOnItsSide) {
  // 10 GeV pions through the overlap (or gap) of sensors 1 and 2 of a ring
  // at r = 100 mm (0.05 X0 each) with 0.3 X0 of support, interaction
  // length 1 X0; the
  // second layer (r = 200 mm) has no sensors: one ideal surface, one hit.
  // Drawn once per layer (the default), an interaction ends a pion after
  // both hits of the overlap. Placed, each sensor ends it after its own
  // hit, and the support on the inner side before them (no hit), also
  // through a gap, on the outer side after them.
  const Detector detector = barrels({100.0, 200.0}, 2000.0, 0.01);
  Simulator::Config config = test::idealSimulatorConfig();
  config.hadronicInteractions = true;
  config.interactionLengthX0 = 1.0;
  constexpr int kCount = 4000;
  constexpr int kHalfCount = kCount / 2;
  // The overlap (or gap) at phi = pi/16 reaches 0.1 x 100 tan(pi/16) = 2
  // mm to either side: +-0.01 rad keeps every particle inside it.
  std::vector<Particle> particles;
  for (int k = 0; k < kCount; ++k) {
    particles.push_back(
        particle(k + 1, 10.0, kPi / 16 + 5e-6 * (k - kHalfCount), 0.0));
  }
  const auto fractions = [&](bool placed, double innerMinRadius,
                             double widthFactor) {
    config.placedSupport = placed;
    config.innerSupportMinRadius = innerMinRadius;
    return hitCountFractions(
        Simulator(detector, config, ring(detector, 16, widthFactor, 0.3, 0.05)),
        particles);
  };
  // The sensors are tilted by pi/16 against the radial pions; the
  // support has the layer surface's geometry (radial crossing).
  const double sensor = -std::expm1(-0.05 / std::cos(kPi / 16));
  const double support = -std::expm1(-0.3);
  const double layer = -std::expm1(-(0.3 + 2 * 0.05 / std::cos(kPi / 16)));

  const std::vector<double> once = fractions(false, 0.0, 1.1);
  EXPECT_EQ(once[0], 0.0);
  EXPECT_EQ(once[1], 0.0);  // never between the two sensors
  expectFraction(once[2], layer, kCount);
  const std::vector<double> inner = fractions(true, 50.0, 1.1);
  expectFraction(inner[0], support, kCount);
  expectFraction(inner[1], (1.0 - support) * sensor, kCount);
  expectFraction(inner[2], (1.0 - support) * (1.0 - sensor) * sensor, kCount);
  const std::vector<double> outer = fractions(true, 150.0, 1.1);
  EXPECT_EQ(outer[0], 0.0);
  expectFraction(outer[1], sensor, kCount);
  expectFraction(outer[2], (1.0 - sensor) * (sensor + (1.0 - sensor) * support),
                 kCount);
  // Through the gap the support is crossed all the same.
  expectFraction(fractions(true, 50.0, 0.9)[0], support, kCount);
  config.innerSupportMinRadius = -1.0;
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
}

TEST(ModuleSimulation, PlacedSupportOfADiskLiesBetweenItsSensorPlanes) {
  // A disk at z = 300 mm with 0.3 X0 of support and two overlapping
  // sensors, one 2 mm in front of the disk surface, one 2 mm behind;
  // 10 GeV pions through their overlap. Placed, the support ends a pion
  // between its two hits; drawn once per layer, never.
  const std::string text =
      "[detector]\nname = \"Toy\"\nmodel = \"toy\"\nbz_T = 2.0\n"
      "envelope_r_mm = 900.0\nenvelope_z_mm = 4000.0\n\n"
      "[[subdetector]]\nname = \"Disk\"\nkind = \"endcap\"\n"
      "  [[subdetector.layer]]\n  name = \"D0\"\n  z_mm = 300.0\n"
      "  r_min_mm = 20.0\n  r_max_mm = 150.0\n  x_over_x0 = 0.01\n"
      "  sigma_rphi_um = 10.0\n  sigma_r_um = 20.0\n";
  const Detector detector = parseDetector(text, "toy.toml");
  std::uint32_t disk = 0;
  while (detector.layers()[disk].z() < 0.0) {
    ++disk;
  }
  std::vector<PlanarModule> modules;
  for (int k = 0; k < 2; ++k) {
    // Sensors 40 mm wide in y, overlapping over |y| < 2 mm at x = 60 mm.
    PlanarModule m;
    m.layer = disk;
    m.module = static_cast<std::uint32_t>(k + 1);
    m.center = Vector3(60.0, k == 0 ? -18.0 : 18.0, k == 0 ? 298.0 : 302.0);
    m.rotation.col(0) = Vector3::UnitY();
    m.rotation.col(1) = Vector3::UnitX();
    m.rotation.col(2) = Vector3::UnitZ();
    m.minHalfU = m.maxHalfU = 20.0;
    m.halfV = 40.0;
    m.thickness = 0.2;
    m.thicknessX0 = 0.002;
    m.sigmaU = 0.01;
    m.sigmaV = 0.05;
    modules.push_back(m);
  }
  std::vector<double> support(detector.layers().size(), 0.0);
  support[disk] = 0.3;
  const auto layout =
      std::make_shared<const ModuleLayout>(detector, modules, support);
  Simulator::Config config = test::idealSimulatorConfig();
  config.hadronicInteractions = true;
  config.interactionLengthX0 = 1.0;
  constexpr int kCount = 4000;
  constexpr int kHalfCount = kCount / 2;
  // Towards (60, 0, 300) mm: eta = asinh(5); +-0.01 rad in phi is +-0.6
  // mm in y.
  const double eta = std::asinh(5.0);
  std::vector<Particle> particles;
  for (int k = 0; k < kCount; ++k) {
    particles.push_back(particle(k + 1, 10.0, 5e-6 * (k - kHalfCount), eta));
  }
  // Normal to the disk, the path is 1 / cos(theta) = sqrt(26) / 5 longer.
  const double secant = std::sqrt(26.0) / 5.0;
  const double sensor = -std::expm1(-0.002 * secant);
  const double layer = -std::expm1(-0.3 * secant);
  config.placedSupport = false;
  const std::vector<double> once =
      hitCountFractions(Simulator(detector, config, layout), particles);
  EXPECT_EQ(once[0], 0.0);
  EXPECT_EQ(once[1], 0.0);
  EXPECT_EQ(once[2], 1.0);
  config.placedSupport = true;
  const std::vector<double> placed =
      hitCountFractions(Simulator(detector, config, layout), particles);
  EXPECT_EQ(placed[0], 0.0);
  expectFraction(placed[1], sensor + (1.0 - sensor) * layer, kCount);
}

TEST(ModuleSimulation, DiskInnerRingLoadsTheFirstFrontSensorOnly) {
  // A disk at z = 300 mm whose sensors carry no support: two overlapping
  // sensors in front of its surface (z = 297.5 and 298 mm) and one behind
  // (302 mm) about x = 60 mm, one behind alone about x = 130 mm; a second
  // disk at 400 mm with one large sensor, which every pion that goes on
  // crosses. The inner ring's material (0.3 X0 here) loads the first
  // sensor crossed in front of the surface below its radius, after that
  // sensor's hit: pions through the overlap end with exactly one hit that
  // often, those through the lone sensor behind it never.
  const std::string text =
      "[detector]\nname = \"Toy\"\nmodel = \"toy\"\nbz_T = 2.0\n"
      "envelope_r_mm = 900.0\nenvelope_z_mm = 4000.0\n\n"
      "[[subdetector]]\nname = \"Disk\"\nkind = \"endcap\"\n"
      "  [[subdetector.layer]]\n  name = \"D0\"\n  z_mm = 300.0\n"
      "  r_min_mm = 20.0\n  r_max_mm = 200.0\n  x_over_x0 = 0.01\n"
      "  sigma_rphi_um = 10.0\n  sigma_r_um = 20.0\n"
      "  [[subdetector.layer]]\n  name = \"D1\"\n  z_mm = 400.0\n"
      "  r_min_mm = 20.0\n  r_max_mm = 250.0\n  x_over_x0 = 0.01\n"
      "  sigma_rphi_um = 10.0\n  sigma_r_um = 20.0\n";
  const Detector detector = parseDetector(text, "toy.toml");
  auto layerAt = [&](double z) {
    std::uint32_t l = 0;
    while (std::abs(detector.layers()[l].z() - z) > 1.0) {
      ++l;
    }
    return l;
  };
  auto sensor = [](std::uint32_t layer, std::uint32_t id, Vector3 centre,
                   double halfY, double halfX) {
    PlanarModule m;
    m.layer = layer;
    m.module = id;
    m.center = centre;
    m.rotation.col(0) = Vector3::UnitY();
    m.rotation.col(1) = Vector3::UnitX();
    m.rotation.col(2) = Vector3::UnitZ();
    m.minHalfU = m.maxHalfU = halfY;
    m.halfV = halfX;
    m.thickness = 0.2;
    m.thicknessX0 = 0.002;
    m.sigmaU = 0.01;
    m.sigmaV = 0.05;
    return m;
  };
  const std::uint32_t d0 = layerAt(300.0);
  const std::uint32_t d1 = layerAt(400.0);
  const std::vector<PlanarModule> modules = {
      sensor(d0, 1, Vector3(60.0, -18.0, 297.5), 20.0, 30.0),
      sensor(d0, 2, Vector3(60.0, 18.0, 298.0), 20.0, 30.0),
      sensor(d0, 3, Vector3(60.0, 0.0, 302.0), 20.0, 30.0),
      sensor(d0, 4, Vector3(130.0, 0.0, 302.0), 20.0, 30.0),
      sensor(d1, 1, Vector3(110.0, 0.0, 400.0), 80.0, 80.0)};
  const std::vector<double> support(detector.layers().size(), 0.0);
  const auto layout =
      std::make_shared<const ModuleLayout>(detector, modules, support);
  Simulator::Config config = test::idealSimulatorConfig();
  config.hadronicInteractions = true;
  config.interactionLengthX0 = 1.0;
  config.placedSupport = true;
  config.diskInnerRingX0 = 0.3;
  config.diskInnerRingRadius = 150.0;
  constexpr int kCount = 4000;
  // Through the overlap at (60, 0, 300) mm (r / z = 0.2) and through the
  // lone back sensor at (130, 0, 300) mm; +-0.01 rad in phi.
  std::vector<Particle> overlap;
  std::vector<Particle> lone;
  for (int k = 0; k < kCount; ++k) {
    const double phi = 5e-6 * (k - kCount / 2);
    overlap.push_back(particle(k + 1, 10.0, phi, std::asinh(5.0)));
    lone.push_back(particle(k + 1, 10.0, phi, std::asinh(300.0 / 130.0)));
  }
  // Fractions of pions with 1, 2, ... hits.
  auto hitCounts = [&](const Simulator::Config& c,
                       const std::vector<Particle>& particles) {
    Event event;
    RandomEngine rng(5);
    Simulator(detector, c, layout).simulate(particles, rng, event);
    std::vector<double> fraction(6, 0.0);
    for (const Particle& p : event.particles) {
      fraction[std::min<std::uint32_t>(p.nHits, 5)] += 1.0 / kCount;
    }
    return fraction;
  };
  const double secant = std::sqrt(26.0) / 5.0;
  const double silicon = -std::expm1(-0.002 * secant);
  const double loaded = -std::expm1(-0.302 * secant);
  const std::vector<double> ring = hitCounts(config, overlap);
  EXPECT_EQ(ring[0], 0.0);
  expectFraction(ring[1], loaded, kCount);
  // The second front sensor carries its silicon only.
  expectFraction(ring[2], (1.0 - loaded) * silicon, kCount);
  const std::vector<double> behind = hitCounts(config, lone);
  EXPECT_EQ(behind[0], 0.0);
  EXPECT_LT(behind[1], 0.01);  // its silicon only: 0.2 %
  // Beyond the ring's radius, none.
  config.diskInnerRingRadius = 50.0;
  EXPECT_LT(hitCounts(config, overlap)[1], 0.01);
  config.diskInnerRingX0 = -0.1;
  EXPECT_THROW(Simulator(detector, config, layout), std::invalid_argument);
}

TEST(ModuleSimulation, NoHitAtGrazingIncidenceBelowTheCut) {
  // eta = 3.7 through a barrel sensor at r = 100 mm: cos(alpha) = 0.049.
  const Detector detector = barrels({100.0}, 3000.0, 0.01);
  std::shared_ptr<const ModuleLayout> sensors = ring(detector, 16, 1.1);
  Simulator::Config config = test::idealSimulatorConfig();
  const std::vector<Particle> particles = {particle(1, 5.0, 0.0, 3.7),
                                           particle(2, 5.0, 0.0, 2.0)};
  Event all;
  RandomEngine rng(1);
  Simulator(detector, config, sensors).simulate(particles, rng, all);
  EXPECT_EQ(all.particles[0].nHits, 1u);
  EXPECT_EQ(all.particles[1].nHits, 1u);
  config.minHitCosIncidence = 0.1;
  Event cut;
  Simulator(detector, config, sensors).simulate(particles, rng, cut);
  EXPECT_EQ(cut.particles[0].nHits, 0u);
  EXPECT_EQ(cut.particles[1].nHits, 1u);  // cos(alpha) = 0.27
  config.minHitCosIncidence = 1.0;
  EXPECT_THROW(Simulator(detector, config, sensors), std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

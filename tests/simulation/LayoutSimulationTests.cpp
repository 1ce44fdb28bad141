// The module-level simulation of CLICdet and CLD (Simulator with the
// sensors of data/layouts/, buildLayoutModules): every layer a straight
// track crosses away from its edges gets a hit, also the spiral vertex
// endcap of CLICdet whose petals lie behind the neighbouring layer.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/LayoutModules.hpp"
#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "Gunzip.hpp"
#include "IdealSimulatorConfig.hpp"

namespace conftrack {
namespace {

constexpr double kPi = std::numbers::pi;

struct Sensors {
  Detector detector;
  std::shared_ptr<const ModuleLayout> layout;
};

const Sensors& setup(const std::string& name) {
  static std::map<std::string, Sensors> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const auto file = std::filesystem::path(CONFTRACK_TEST_DATA_DIR) /
                      "layouts" / (name + "_layout.json.gz");
    Detector detector = loadDetector(name);
    auto layout = std::make_shared<const ModuleLayout>(
        buildLayoutModules(test::gunzip(file), detector, file.string()));
    it = cache.emplace(name, Sensors{std::move(detector), std::move(layout)})
             .first;
  }
  return it->second;
}

TEST(LayoutSimulation, EveryCrossedLayerHasAHit) {
  // 100 GeV muons from the origin, |eta| < 2.8, no scattering: on every
  // layer whose surface the straight line crosses away from its edges
  // (10 % in z on barrels, 25 % / 15 % of rMin / rMax on disks), the
  // particle has a hit, except in the azimuthal gaps of the outer sensors
  // of the vertex double layers (LayoutModulesTests): below 5 % there.
  for (const std::string name : {"clicdet", "cld"}) {
    const Sensors& s = setup(name);
    const Simulator simulator(s.detector, test::idealSimulatorConfig(),
                              s.layout);
    RandomEngine rng(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<Particle> particles;
    for (std::uint64_t i = 0; i < 3000; ++i) {
      const double phi = kPi * (2.0 * uniform(rng) - 1.0);
      const double eta = 2.8 * (2.0 * uniform(rng) - 1.0);
      Particle p;
      p.id = i + 1;
      p.pdg = 13;
      p.charge = -1.0;
      p.momentum = 100.0 * units::GeV *
                   Vector3(std::cos(phi), std::sin(phi), std::sinh(eta));
      particles.push_back(p);
    }
    Event event;
    simulator.simulate(particles, rng, event);
    std::map<std::pair<std::uint64_t, std::uint32_t>, int> hits;
    for (std::size_t i = 0; i < event.hits.size(); ++i) {
      const auto layer = s.detector.findLayer(event.hits[i].detId);
      ASSERT_TRUE(layer.has_value());
      ++hits[std::make_pair(event.truth[i].particleId, *layer)];
    }
    std::map<std::string, std::pair<int, int>> missed;  // (crossed, missed)
    for (const Particle& p : particles) {
      const Vector3 d = p.momentum.normalized();
      const double tanTheta = d.head<2>().norm() / std::abs(d.z());
      for (std::uint32_t l = 0; l < s.detector.layers().size(); ++l) {
        const SensitiveLayer& layer = s.detector.layers()[l];
        bool crossed = false;
        if (layer.isDisk()) {
          const double r = std::abs(layer.z()) * tanTheta;
          crossed = layer.z() * d.z() > 0.0 && r > 1.25 * layer.rMin &&
                    r < 0.85 * layer.rMax;
        } else {
          crossed = std::abs(layer.r / tanTheta) < 0.9 * layer.zMax;
        }
        if (crossed) {
          auto& m = missed[layer.name];
          ++m.first;
          m.second += hits.count(std::make_pair(p.id, l)) == 0 ? 1 : 0;
        }
      }
    }
    for (const auto& [layer, m] : missed) {
      const bool outerVertex =
          layer == "VXD_B_L1" || layer == "VXD_B_L3" || layer == "VXD_B_L5";
      if (outerVertex) {
        EXPECT_LT(m.second, 0.05 * m.first) << name << " " << layer;
      } else {
        // Ring-boundary corners of the tracker disks: below 1 %.
        EXPECT_LE(m.second, 0.01 * m.first) << name << " " << layer;
      }
      if (layer.starts_with("VXD_E_")) {
        EXPECT_EQ(m.second, 0) << name << " " << layer;
      }
    }
    EXPECT_GT(missed["VXD_E_L5_pos"].first, 50) << name;
  }
}

TEST(LayoutSimulation, EventSimulationUsesTheSensorsOnlyWhenGiven) {
  const Sensors& s = setup("clicdet");
  EventSimulation::Config config;
  config.sample = "ttbar3tev";
  EventSimulation ideal(s.detector, config);
  config.modules = s.layout;
  EventSimulation modular(s.detector, config);
  EXPECT_EQ(modular.description(), "ttbar3tev, module level");
  EXPECT_EQ(ideal.description(), "ttbar3tev");
  const Event a = ideal.simulate(1);
  const Event b = modular.simulate(1);
  // Same particles; the hits differ (sensor positions, overlaps).
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    EXPECT_EQ(a.particles[i].id, b.particles[i].id);
  }
  std::size_t onSensor = 0;
  for (const Hit& hit : b.hits) {
    const auto layer = s.detector.findLayer(hit.detId);
    ASSERT_TRUE(layer.has_value());
    const PlanarModule* sensor = s.layout->find(*layer, hit.detId.module);
    ASSERT_NE(sensor, nullptr);
    const Vector3 local = sensor->toLocal(hit.position);
    EXPECT_NEAR(local.z(), 0.0, 1e-9);
    onSensor += sensor->contains(local.x(), local.y()) ? 1 : 0;
  }
  EXPECT_EQ(onSensor, b.hits.size());
  EXPECT_GT(b.hits.size(), 500u);
}

}  // namespace
}  // namespace conftrack

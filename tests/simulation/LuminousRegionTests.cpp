// Tests of the luminous region: sampled widths against the configuration,
// the presets, validation, the generators drawing their interaction points
// from it, and its keys in generator files.

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/generators/GammaGammaOverlay.hpp"
#include "conftrack/simulation/generators/GeneratorFactory.hpp"
#include "conftrack/simulation/generators/HepMC3Generator.hpp"
#include "conftrack/simulation/generators/ParticleGun.hpp"
#include "conftrack/simulation/generators/TtbarGenerator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "InputErrorOf.hpp"

using namespace conftrack;
using namespace conftrack::units;

namespace {

/// Mean and standard deviation of a sample.
struct Moments {
  double mean = 0.0;
  double sigma = 0.0;
};

Moments momentsOf(const std::vector<double>& x) {
  double sum = 0.0;
  for (double v : x) {
    sum += v;
  }
  Moments m;
  m.mean = sum / static_cast<double>(x.size());
  double sum2 = 0.0;
  for (double v : x) {
    sum2 += (v - m.mean) * (v - m.mean);
  }
  m.sigma = std::sqrt(sum2 / static_cast<double>(x.size() - 1));
  return m;
}

/// Checks a sample against a Gaussian of `mean` and `sigma` within five
/// standard errors: sigma / sqrt(n) for the mean, sigma / sqrt(2 n) for the
/// width.
void expectGaussian(const std::vector<double>& x, double mean, double sigma,
                    const std::string& what) {
  const double n = static_cast<double>(x.size());
  const Moments m = momentsOf(x);
  EXPECT_NEAR(m.mean, mean, 5.0 * sigma / std::sqrt(n)) << what;
  EXPECT_NEAR(m.sigma, sigma, 5.0 * sigma / std::sqrt(2.0 * n)) << what;
}

ConfigTable tableOf(const std::shared_ptr<toml::table>& root) {
  return ConfigTable(*root, "gen.toml", "");
}

/// The message of reading `text` as a [luminous_region] table.
std::string regionError(const std::string& text) {
  return test::inputErrorOf([&] {
    const auto root =
        ConfigTable::parse("[luminous_region]\n" + text, "gen.toml");
    readLuminousRegionConfig(tableOf(root).getTable("luminous_region"));
  });
}

}  // namespace

// ------------------------------------------------------------ the region

// 20000 vertices: the widths are checked to 5 / sqrt(40000) = 2.5 %, the
// means to 5 / sqrt(20000) = 3.5 % of the width.
TEST(LuminousRegion, SampledWidthsMatchTheConfiguredSigmas) {
  LuminousRegion::Config c;
  c.position = Vector3(0.5 * mm, -0.2 * mm, 3.0 * mm);
  c.time = 0.25 * ns;
  c.sigmaX = 10.0 * um;
  c.sigmaY = 30.0 * nm;
  c.sigmaZ = 50.0 * mm;
  c.sigmaT = 0.2 * ns;
  const LuminousRegion region(c);
  auto rng = makeEngine(7, 1, RandomStream::eSignalGenerator);
  std::array<std::vector<double>, 4> draws;
  for (int i = 0; i < 20000; ++i) {
    const LuminousRegion::Vertex v = region.sample(rng);
    draws[0].push_back(v.position.x());
    draws[1].push_back(v.position.y());
    draws[2].push_back(v.position.z());
    draws[3].push_back(v.time);
  }
  expectGaussian(draws[0], c.position.x(), c.sigmaX, "x");
  expectGaussian(draws[1], c.position.y(), c.sigmaY, "y");
  expectGaussian(draws[2], c.position.z(), c.sigmaZ, "z");
  expectGaussian(draws[3], c.time, c.sigmaT, "t");
  // Independent axes: the x-z correlation of 20000 pairs is 0 within
  // 5 / sqrt(20000) = 0.035.
  const Moments mx = momentsOf(draws[0]);
  const Moments mz = momentsOf(draws[2]);
  double cov = 0.0;
  for (std::size_t i = 0; i < draws[0].size(); ++i) {
    cov += (draws[0][i] - mx.mean) * (draws[2][i] - mz.mean);
  }
  cov /= static_cast<double>(draws[0].size() - 1);
  EXPECT_NEAR(cov / (mx.sigma * mz.sigma), 0.0, 0.035);
}

// A region with only a length takes one standard normal per vertex, z =
// sigmaZ * N: the draws of the generators before the region existed. A
// point takes none.
TEST(LuminousRegion, OnlyNonZeroWidthsDrawRandomNumbers) {
  LuminousRegion::Config c;
  c.sigmaZ = 44.0 * um;
  const LuminousRegion length(c);
  auto rng = makeEngine(3, 9, RandomStream::eSignalGenerator);
  auto reference = rng;
  for (int i = 0; i < 10; ++i) {
    std::normal_distribution<double> fresh(0.0, 1.0);
    EXPECT_EQ(length.sample(rng).position,
              Vector3(0.0, 0.0, 44.0 * um * fresh(reference)));
  }
  EXPECT_EQ(rng, reference);
  // With a shared distribution, consecutive vertices use both numbers of
  // each pair it draws.
  std::normal_distribution<double> shared(0.0, 1.0);
  std::normal_distribution<double> expected(0.0, 1.0);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(length.sample(rng, shared).position.z(),
              44.0 * um * expected(reference));
  }
  EXPECT_EQ(rng, reference);
  const LuminousRegion point(LuminousRegion::point());
  EXPECT_EQ(point.sample(rng).position, Vector3::Zero());
  EXPECT_EQ(point.sample(rng).time, 0.0);
  EXPECT_EQ(rng, reference);
}

TEST(LuminousRegion, PresetsExistAndValidate) {
  const std::vector<std::string> names = {
      "clic3tev", "fccee-z", "fccee-ttbar", "hllhc", "trackml-kaggle", "point"};
  ASSERT_EQ(LuminousRegion::presets().size(), names.size());
  for (const std::string& name : names) {
    const LuminousRegion::Preset* p = LuminousRegion::findPreset(name);
    ASSERT_NE(p, nullptr) << name;
    EXPECT_EQ(p->name, name);
    EXPECT_FALSE(p->machine.empty()) << name;
    EXPECT_FALSE(p->source.empty()) << name;
    EXPECT_NO_THROW(LuminousRegion{p->config}) << name;
    EXPECT_NE(LuminousRegion::presetNames().find(name), std::string::npos);
  }
  EXPECT_EQ(LuminousRegion::findPreset("clic"), nullptr);
  // The numbers of docs/luminous-region.md.
  const auto sigmas = [](std::string_view name) {
    const auto& c = LuminousRegion::findPreset(name)->config;
    return std::array<double, 4>{c.sigmaX, c.sigmaY, c.sigmaZ, c.sigmaT};
  };
  using A = std::array<double, 4>;
  EXPECT_EQ(sigmas("clic3tev"), (A{0.0, 0.0, 44.0 * um, 0.0}));
  EXPECT_EQ(sigmas("fccee-z"), (A{4.5 * um, 20.0 * nm, 0.30 * mm, 28.6 * ps}));
  EXPECT_EQ(sigmas("fccee-ttbar"),
            (A{27.0 * um, 48.2 * nm, 1.27 * mm, 6.0 * ps}));
  EXPECT_EQ(sigmas("hllhc"), (A{12.5 * um, 12.5 * um, 50.0 * mm, 0.0}));
  EXPECT_EQ(sigmas("trackml-kaggle"), (A{15.0 * um, 15.0 * um, 5.5 * mm, 0.0}));
  EXPECT_EQ(sigmas("point"), (A{0.0, 0.0, 0.0, 0.0}));
  for (const LuminousRegion::Preset& p : LuminousRegion::presets()) {
    EXPECT_EQ(p.config.position, Vector3::Zero()) << p.name;
    EXPECT_EQ(p.config.time, 0.0) << p.name;
  }
  // The CLIC generators' default is the clic3tev preset: 0.044 mm, the
  // value of conftrack's generators before the region existed.
  EXPECT_EQ(LuminousRegion::clic3TeV().sigmaZ, 0.044 * mm);
  EXPECT_EQ(TtbarGenerator::Config::bb500().luminousRegion.sigmaZ, 0.044 * mm);
  EXPECT_EQ(GammaGammaOverlay::Config{}.luminousRegion.sigmaZ, 0.044 * mm);
  EXPECT_EQ(ParticleGun::Config{}.luminousRegion.sigmaZ, 0.0);
}

TEST(LuminousRegion, InvalidConfigIsRejectedNamingTheField) {
  const auto messageOf = [](const LuminousRegion::Config& c) {
    return test::inputErrorOf([&] { LuminousRegion{c}; });
  };
  LuminousRegion::Config c;
  c.sigmaZ = -1.0 * mm;
  EXPECT_EQ(messageOf(c),
            "LuminousRegion: config field 'sigmaZ': must lie in [0, 1000] mm "
            "(got -1)");
  c = {};
  c.position.x() = std::nan("");
  EXPECT_EQ(messageOf(c),
            "LuminousRegion: config field 'position.x': must be finite (got "
            "nan)");
  c = {};
  c.sigmaT = INFINITY;
  EXPECT_EQ(messageOf(c),
            "LuminousRegion: config field 'sigmaT': must be finite (got inf)");
  c = {};
  c.position.z() = 2000.0 * mm;
  EXPECT_EQ(messageOf(c),
            "LuminousRegion: config field 'position.z': must lie in [-1000, "
            "1000] mm (got 2000)");
  // In a generator's configuration the field is the generator's.
  TtbarGenerator::Config tt;
  tt.luminousRegion.sigmaX = -1.0;
  EXPECT_EQ(test::inputErrorOf([&] { TtbarGenerator{tt}; }),
            "TtbarGenerator: config field 'luminousRegion.sigmaX': must lie "
            "in [0, 1000] mm (got -1)");
  ParticleGun::Config gun;
  gun.luminousRegion.sigmaY = std::nan("");
  EXPECT_EQ(test::inputErrorOf([&] { ParticleGun{gun}; }),
            "ParticleGun: config field 'luminousRegion.sigmaY': must be "
            "finite (got nan)");
}

// ---------------------------------------------------------- generators

// tt: all primaries of an event share one interaction point; over 400
// events its z follows the region: width within 5 / sqrt(800) = 18 %, mean
// within 5 / sqrt(400) = 25 % of the width.
TEST(LuminousRegionGenerators, TtbarPrimariesShareOnePointFromTheRegion) {
  TtbarGenerator::Config cfg = TtbarGenerator::Config::ttbar3TeV();
  cfg.luminousRegion = LuminousRegion::findPreset("hllhc")->config;
  cfg.luminousRegion.position = Vector3(1.0 * mm, 2.0 * mm, -5.0 * mm);
  const TtbarGenerator gen(cfg);
  std::vector<double> zs;
  for (std::uint64_t ev = 0; ev < 400; ++ev) {
    auto rng = makeEngine(11, ev, RandomStream::eSignalGenerator);
    const auto particles = gen.generate(rng);
    std::set<std::array<double, 4>> points;
    for (const Particle& p : particles) {
      if (p.parentId == 0) {
        points.insert({p.vertex.x(), p.vertex.y(), p.vertex.z(), p.time});
      }
    }
    ASSERT_EQ(points.size(), 1u) << "event " << ev;
    const auto& v = *points.begin();
    EXPECT_NEAR(v[0], 1.0 * mm, 5.0 * 12.5 * um);
    EXPECT_NEAR(v[1], 2.0 * mm, 5.0 * 12.5 * um);
    zs.push_back(v[2]);
  }
  expectGaussian(zs, -5.0 * mm, 50.0 * mm, "ttbar z");
}

// Overlay: every gamma gamma event draws its own point. 200 trains of 30
// BX x 3.2 events: about 19000 points, width within 2.6 %.
TEST(LuminousRegionGenerators, EveryOverlayInteractionDrawsItsOwnPoint) {
  GammaGammaOverlay::Config cfg;
  cfg.meanCharged = 20.0;  // no empty events: every point is seen
  cfg.luminousRegion.sigmaZ = 10.0 * mm;
  cfg.luminousRegion.sigmaX = 5.0 * um;
  const GammaGammaOverlay overlay(cfg);
  std::vector<double> zs;
  std::vector<double> xs;
  for (int train = 0; train < 200; ++train) {
    auto rng = makeEngine(5, train, RandomStream::eBackgroundGenerator);
    // Points in first-seen order; particles of one event are consecutive.
    std::vector<Vector3> points;
    for (const Particle& p : overlay.generate(rng)) {
      if (points.empty() || p.vertex != points.back()) {
        points.push_back(p.vertex);
      }
    }
    for (const Vector3& v : points) {
      zs.push_back(v.z());
      xs.push_back(v.x());
    }
  }
  ASSERT_GT(zs.size(), 15000u);
  expectGaussian(zs, 0.0, 10.0 * mm, "overlay z");
  expectGaussian(xs, 0.0, 5.0 * um, "overlay x");
}

// Gun: one point per event for all its particles; displaced particles
// start on the line from that point along their direction.
TEST(LuminousRegionGenerators, GunParticlesShareThePointAndDisplaceFromIt) {
  ParticleGun::Config cfg;
  cfg.multiplicity = 4;
  cfg.rMin = 10.0 * mm;
  cfg.rMax = 300.0 * mm;
  cfg.luminousRegion.position = Vector3(0.0, 0.0, 20.0 * mm);
  cfg.luminousRegion.sigmaZ = 30.0 * mm;
  const ParticleGun gun(cfg);
  std::vector<double> zs;
  for (std::uint64_t ev = 0; ev < 2000; ++ev) {
    auto rng = makeEngine(2, ev, RandomStream::eSignalGenerator);
    const auto particles = gun.generate(rng);
    ASSERT_EQ(particles.size(), 4u);
    // The interaction point: the vertex minus the displacement R (cos phi,
    // sin phi, cot theta), R the transverse radius (x = y = 0 here).
    std::vector<double> origins;
    for (const Particle& p : particles) {
      const double r = p.vertex.head<2>().norm();
      EXPECT_GE(r, 10.0 * mm - 1e-9);
      const double cotTheta = p.momentum.z() / p.momentum.head<2>().norm();
      origins.push_back(p.vertex.z() - r * cotTheta);
      EXPECT_NEAR(std::atan2(p.vertex.y(), p.vertex.x()),
                  std::atan2(p.momentum.y(), p.momentum.x()), 1e-9);
    }
    const auto [lo, hi] = std::minmax_element(origins.begin(), origins.end());
    ASSERT_NEAR(*lo, *hi, 1e-9) << "event " << ev;
    zs.push_back(origins.front());
  }
  expectGaussian(zs, 20.0 * mm, 30.0 * mm, "gun z");
}

// HepMC: without a region the file's vertices; with one, every particle
// of an event moves by the same drawn point.
TEST(LuminousRegionGenerators, HepMCEventsMoveAsAWhole) {
  HepMC3Generator::Config cfg;
  cfg.path = (std::filesystem::path(CONFTRACK_TEST_DATA_DIR) / "hepmc" /
              "g4pythia.hepmc.gz")
                 .string();
  const HepMC3Generator plain(cfg);
  cfg.luminousRegion = LuminousRegion::findPreset("fccee-ttbar")->config;
  const HepMC3Generator moved(cfg);
  std::vector<double> zs;
  for (std::uint64_t ev = 0; ev < 400; ++ev) {
    auto rng = makeEngine(8, ev, RandomStream::eSignalGenerator);
    auto unused = rng;
    const auto a = plain.generate(unused, ev);
    const auto b = moved.generate(rng, ev);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_FALSE(a.empty());
    const Vector3 shift = b.front().vertex - a.front().vertex;
    const double dt = b.front().time - a.front().time;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_NEAR((b[i].vertex - a[i].vertex - shift).norm(), 0.0, 1e-9);
      EXPECT_NEAR(b[i].time - a[i].time, dt, 1e-12);
      EXPECT_EQ(b[i].momentum, a[i].momentum);
    }
    zs.push_back(shift.z());
  }
  expectGaussian(zs, 0.0, 1.27 * mm, "HepMC shift z");
}

// Same seed, same event: the same interaction points; another seed gives
// others.
TEST(LuminousRegionGenerators, PointsDependOnlyOnSeedAndEvent) {
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = 5;
  cfg.luminousRegion = LuminousRegion::findPreset("fccee-z")->config;
  cfg.simulator.multipleScattering = false;
  const Detector det = loadDetector("clicdet");
  const auto pointsOf = [&](std::uint64_t seed, std::uint64_t event) {
    cfg.seed = seed;
    std::vector<Vector3> points;
    for (const Particle& p :
         EventSimulation(det, cfg).simulate(event).particles) {
      if (p.parentId == 0) {
        points.push_back(p.vertex);
      }
    }
    return points;
  };
  const auto a = pointsOf(1, 3);
  EXPECT_GT(a.size(), 10u);
  EXPECT_EQ(a, pointsOf(1, 3));
  EXPECT_NE(a, pointsOf(2, 3));
  EXPECT_NE(a, pointsOf(1, 4));
}

// ------------------------------------------------------------ TOML keys

TEST(LuminousRegionConfig, PresetKeysAndUnits) {
  const auto root = ConfigTable::parse(R"(
[luminous_region]
preset = "hllhc"
z_mm = 3
sigma_z_mm = 40
t_ns = 0.5
sigma_t_ns = 0.18
)",
                                       "gen.toml");
  const LuminousRegion::Config c =
      readLuminousRegionConfig(tableOf(root).getTable("luminous_region"));
  EXPECT_EQ(c.position, Vector3(0.0, 0.0, 3.0 * mm));
  EXPECT_EQ(c.sigmaX, 12.5 * um);  // the preset's
  EXPECT_EQ(c.sigmaZ, 40.0 * mm);
  EXPECT_EQ(c.time, 0.5 * ns);
  EXPECT_EQ(c.sigmaT, 0.18 * ns);
  // Without a preset, fields not given are 0.
  const auto bare =
      ConfigTable::parse("[luminous_region]\nsigma_x_mm = 0.01\n", "gen.toml");
  const LuminousRegion::Config b =
      readLuminousRegionConfig(tableOf(bare).getTable("luminous_region"));
  EXPECT_EQ(b.sigmaX, 0.01 * mm);
  EXPECT_EQ(b.sigmaZ, 0.0);
}

TEST(LuminousRegionConfig, BadValuesAreOneLineNamingTheKey) {
  EXPECT_EQ(regionError("sigma_z_mm = -1\n"),
            "gen.toml:2: key 'luminous_region.sigma_z_mm': value -1 out of "
            "range [0, 1000]");
  EXPECT_EQ(regionError("x_mm = nan\n"),
            "gen.toml:2: key 'luminous_region.x_mm': must be finite");
  EXPECT_EQ(regionError("preset = \"lep\"\n"),
            "gen.toml:2: key 'luminous_region.preset': unknown preset 'lep' "
            "(use clic3tev, fccee-z, fccee-ttbar, hllhc, trackml-kaggle, "
            "point)");
  EXPECT_EQ(regionError("sigma_z = 1\n"),
            "gen.toml:2: key 'luminous_region.sigma_z': unknown key");
  EXPECT_EQ(regionError("sigma_t_ns = inf\n"),
            "gen.toml:2: key 'luminous_region.sigma_t_ns': must be finite");
  for (const std::string& m :
       {regionError("sigma_z_mm = -1\n"), regionError("preset = 3\n")}) {
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

// The generators' own keys still work alone, and are refused next to the
// sample's region (where would the width come from?).
TEST(LuminousRegionConfig, GeneratorKeysAreAliasesOnlyWithoutARegion) {
  const auto ttbar = ConfigTable::parse(
      "sample = \"ttbar3tev\"\nbeam_sigma_z_mm = 0.05\n", "gen.toml");
  const auto gen = makeGenerator(tableOf(ttbar));
  const auto* tt = dynamic_cast<const TtbarGenerator*>(gen.get());
  ASSERT_NE(tt, nullptr);
  EXPECT_EQ(tt->config().luminousRegion.sigmaZ, 0.05 * mm);
  const auto gunRoot = ConfigTable::parse(
      "sample = \"gun\"\nvertex_mm = [1, 2, 3]\n", "gen.toml");
  const auto gunGen = makeGenerator(tableOf(gunRoot));
  const auto* gun = dynamic_cast<const ParticleGun*>(gunGen.get());
  ASSERT_NE(gun, nullptr);
  EXPECT_EQ(gun->config().luminousRegion.position,
            Vector3(1.0 * mm, 2.0 * mm, 3.0 * mm));

  const LuminousRegion::Config hl = LuminousRegion::findPreset("hllhc")->config;
  EXPECT_EQ(test::inputErrorOf([&] { makeGenerator(tableOf(ttbar), hl); }),
            "gen.toml:2: key 'beam_sigma_z_mm': the luminous region is already "
            "set ([luminous_region] or --luminous-region/--beam-sigma-z); give "
            "sigma_z_mm there instead");
  EXPECT_EQ(test::inputErrorOf([&] { makeGenerator(tableOf(gunRoot), hl); }),
            "gen.toml:2: key 'vertex_mm': the luminous region is already set "
            "([luminous_region] or --luminous-region/--beam-sigma-z); give "
            "x_mm, y_mm, z_mm there instead");
  const auto overlay =
      ConfigTable::parse("beam_sigma_z_mm = 0.05\n", "gen.toml");
  EXPECT_NE(test::inputErrorOf([&] {
              makeOverlay(tableOf(overlay), hl);
            }).find("key 'beam_sigma_z_mm'"),
            std::string::npos);
  // With a region and no own key: the region.
  const auto plain = makeGenerator("bb500", hl);
  EXPECT_EQ(dynamic_cast<const TtbarGenerator*>(plain.get())
                ->config()
                .luminousRegion.sigmaZ,
            50.0 * mm);
}

// [luminous_region] reaches the signal and the overlay; a region given both
// on the command line (EventSimulation::Config) and in the file is refused.
TEST(LuminousRegionConfig, SampleRegionForSignalAndOverlay) {
  const Detector det = loadDetector("clicdet");
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = 30;
  cfg.generatorToml = "[luminous_region]\npreset = \"fccee-ttbar\"\n";
  cfg.generatorTomlSource = "gen.toml";
  const Event event = EventSimulation(det, cfg).simulate(1);
  std::set<double> signalZ;
  std::set<double> backgroundZ;
  for (const Particle& p : event.particles) {
    if (p.parentId == 0) {
      (p.isBackground() ? backgroundZ : signalZ).insert(p.vertex.z());
      // sigma x = 27 um: every point within 10 sigma of the beam line.
      EXPECT_LT(std::abs(p.vertex.x()), 0.27 * mm);
      EXPECT_NE(p.vertex.x(), 0.0);
    }
  }
  EXPECT_EQ(signalZ.size(), 1u);
  EXPECT_GT(backgroundZ.size(), 30u);
  for (double z : backgroundZ) {
    EXPECT_LT(std::abs(z), 10.0 * 1.27 * mm);
  }
  cfg.luminousRegion = LuminousRegion::findPreset("hllhc")->config;
  EXPECT_EQ(test::inputErrorOf([&] { EventSimulation(det, cfg); }),
            "gen.toml:1: table 'luminous_region': the luminous region is also "
            "set on the command line (--luminous-region/--beam-sigma-z): give "
            "it in one place");
}

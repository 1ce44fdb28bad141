/// @file TrackmlEventsTests.cpp
/// TrackML weights, the shipped TrackML detector against its source table,
/// and TrackML-like events from the fast simulation.

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"
#include "conftrack/simulation/generators/HepMCText.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>

#include "InputErrorOf.hpp"

namespace conftrack {
namespace {

namespace fs = std::filesystem;

const fs::path kTrackmlData = fs::path(CONFTRACK_TEST_DATA_DIR) / "trackml";

const std::vector<TrackmlModule>& trackmlModules() {
  static const std::vector<TrackmlModule> modules = [] {
    fs::path file = kTrackmlData / "detectors.csv.gz";
    return parseTrackmlModules(hepmc::loadFile(file), file.string());
  }();
  return modules;
}

const Detector& trackmlDetector() {
  static const Detector detector = buildTrackmlDetector(trackmlModules());
  return detector;
}

std::shared_ptr<const ModuleLayout> moduleLayout() {
  static const auto layout = std::make_shared<const ModuleLayout>(
      buildTrackmlModuleLayout(trackmlModules(), trackmlDetector()));
  return layout;
}

Particle makeParticle(std::uint64_t id, double pt, double eta, double phi,
                      double charge = 1.0) {
  Particle p;
  p.id = id;
  p.pdg = charge > 0 ? -13 : 13;
  p.charge = charge;
  p.momentum =
      Vector3(pt * std::cos(phi), pt * std::sin(phi), pt * std::sinh(eta));
  return p;
}

HitTruth truthAt(std::uint64_t particle, double z) {
  HitTruth t;
  t.particleId = particle;
  t.position = Vector3(100.0, 0.0, z);
  return t;
}

TEST(TrackmlWeights, PtFactor) {
  EXPECT_EQ(trackmlPtWeight(0.04), 0.0);
  EXPECT_EQ(trackmlPtWeight(0.05), 0.2);
  EXPECT_EQ(trackmlPtWeight(0.3), 0.2);
  EXPECT_EQ(trackmlPtWeight(0.5), 0.2);
  EXPECT_NEAR(trackmlPtWeight(1.75), 0.6, 1e-15);
  EXPECT_EQ(trackmlPtWeight(3.0), 1.0);
  EXPECT_EQ(trackmlPtWeight(100.0), 1.0);
}

TEST(TrackmlWeights, OrderFactor) {
  // 9 hits: the profile itself, normalised (sum 49).
  const double profile[] = {10, 8, 6, 5, 3, 3, 3, 5, 6};
  for (std::uint32_t i = 0; i < 9; ++i) {
    EXPECT_NEAR(trackmlOrderWeight(i, 9), profile[i] / 49.0, 1e-15);
  }
  // 4 hits: the profile at 0, 8/3, 16/3, 8 -> 10, 16/3, 3, 6.
  const double four[] = {10.0, 16.0 / 3.0, 3.0, 6.0};
  const double sum = 10.0 + 16.0 / 3.0 + 3.0 + 6.0;
  for (std::uint32_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(trackmlOrderWeight(i, 4), four[i] / sum, 1e-15);
  }
  EXPECT_EQ(trackmlOrderWeight(0, 3), 0.0);
  EXPECT_EQ(trackmlOrderWeight(20, 25), 0.0);
  EXPECT_EQ(trackmlOrderWeight(5, 25), trackmlOrderWeight(5, 20));
  for (std::uint32_t n = 4; n <= 20; ++n) {
    double total = 0.0;
    for (std::uint32_t i = 0; i < n; ++i) {
      total += trackmlOrderWeight(i, n);
    }
    EXPECT_NEAR(total, 1.0, 1e-14) << n;
  }
}

TEST(TrackmlWeights, EventWeights) {
  std::vector<Particle> particles(3);
  particles[0].id = 10;  // 4 hits, pT 5 GeV, vertex z = 5
  particles[0].momentum = Vector3(3.0, 4.0, 0.0);
  particles[0].vertex.z() = 5.0;
  particles[1].id = 20;  // 2 hits: weight 0
  particles[1].momentum = Vector3(5.0, 0.0, 0.0);
  particles[2].id = 30;  // 4 hits, pT 0.3 GeV
  particles[2].momentum = Vector3(0.3, 0.0, 0.0);
  std::vector<HitTruth> truth = {
      truthAt(10, 105.0), truthAt(10, 0.0),  truthAt(10, 35.0),
      truthAt(10, -55.0),  // |dz| 100, 5, 30, 60: ranks 3, 0, 1, 2
      truthAt(20, 1.0),   truthAt(20, 2.0),  truthAt(0, 3.0),
      truthAt(30, 10.0),  truthAt(30, 20.0), truthAt(30, 20.0),
      truthAt(30, 40.0),  // ties at 20: average rank 2.5 -> ihit 1
      truthAt(99, 1.0)};  // no particle row: 0
  std::vector<double> w = computeTrackmlWeights(truth, particles);
  ASSERT_EQ(w.size(), truth.size());
  const double o0 = trackmlOrderWeight(0, 4);
  const double o1 = trackmlOrderWeight(1, 4);
  const double o2 = trackmlOrderWeight(2, 4);
  const double o3 = trackmlOrderWeight(3, 4);
  const double norm = (o0 + o1 + o2 + o3) * 1.0 + (o0 + o1 + o1 + o3) * 0.2;
  EXPECT_NEAR(w[0], o3 / norm, 1e-15);
  EXPECT_NEAR(w[1], o0 / norm, 1e-15);
  EXPECT_NEAR(w[2], o1 / norm, 1e-15);
  EXPECT_NEAR(w[3], o2 / norm, 1e-15);
  EXPECT_EQ(w[4], 0.0);
  EXPECT_EQ(w[5], 0.0);
  EXPECT_EQ(w[6], 0.0);
  EXPECT_NEAR(w[7], 0.2 * o0 / norm, 1e-15);
  EXPECT_NEAR(w[8], 0.2 * o1 / norm, 1e-15);
  EXPECT_NEAR(w[9], 0.2 * o1 / norm, 1e-15);
  EXPECT_NEAR(w[10], 0.2 * o3 / norm, 1e-15);
  EXPECT_EQ(w[11], 0.0);
  EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, 1e-14);
}

// detectors/trackml.toml is what buildTrackmlDetectorToml makes of the
// Kaggle table: regenerate it when the builder changes.
TEST(TrackmlDetectorFile, MatchesGenerator) {
  TrackmlDetectorOptions options;
  options.source = "data/trackml/detectors.csv.gz";
  std::string expected = buildTrackmlDetectorToml(trackmlModules(), options);
  std::string shipped =
      readConfigText(resolveDetectorPath("trackml"), "detector");
  EXPECT_EQ(shipped, expected);
}

TEST(TrackmlEvents, CentralAndForwardParticles) {
  TrackmlEventSimulation sim(trackmlDetector(), moduleLayout(), {});
  std::vector<Particle> particles = {makeParticle(1, 10.0, 0.05, 0.3),
                                     makeParticle(2, 10.0, 3.0, -2.0, -1.0),
                                     makeParticle(3, 10.0, -3.0, 1.0)};
  Event event = sim.simulate(7, particles);
  const Detector& det = trackmlDetector();
  std::map<std::uint64_t, std::map<std::uint32_t, int>> volumes;
  for (std::size_t i = 0; i < event.hits.size(); ++i) {
    const Hit& hit = event.hits[i];
    EXPECT_EQ(hit.id, i + 1);
    const SensitiveLayer& layer =
        det.layers()[det.findLayer(hit.detId).value()];
    ++volumes[event.truth[i].particleId][layer.trackmlVolume];
    // Real TrackML module ids; the true crossing lies on that sensor's
    // mid-plane, inside it, and the measurement frame is the sensor's.
    const PlanarModule* sensor = moduleLayout()->find(
        det.findLayer(hit.detId).value(), hit.detId.module);
    ASSERT_NE(sensor, nullptr) << layer.name << " " << hit.detId.module;
    const Vector3 local = sensor->toLocal(event.truth[i].position);
    EXPECT_NEAR(local.z(), 0.0, 1e-6);
    EXPECT_TRUE(sensor->contains(local.x(), local.y()));
    EXPECT_NEAR(hit.uAxis.dot(sensor->uAxis()), 1.0, 1e-12);
    EXPECT_NEAR(sensor->toLocal(hit.position).z(), 0.0, 1e-6);
  }
  // Central: 4 pixel, 4 short-strip and 2 long-strip barrel layers, one
  // or two hits each (two where neighbouring sensors overlap).
  EXPECT_GE(volumes[1][8], 4);
  EXPECT_LE(volumes[1][8], 8);
  EXPECT_GE(volumes[1][13], 4);
  EXPECT_LE(volumes[1][13], 8);
  EXPECT_GE(volumes[1][17], 2);
  EXPECT_LE(volumes[1][17], 4);
  EXPECT_EQ(volumes[1].size(), 3u);
  // eta = +-3: the pixel endcap disks of their side (|z| 600-1500, r =
  // |z| / sinh 3 = 60-150 mm), nothing on the other side.
  EXPECT_GE(volumes[2][9], 6);
  EXPECT_GE(volumes[3][7], 6);
  for (std::uint32_t v : {7, 12, 16}) {
    EXPECT_EQ(volumes[2].count(v), 0u) << v;
  }
  for (std::uint32_t v : {9, 14, 18}) {
    EXPECT_EQ(volumes[3].count(v), 0u) << v;
  }
  // Hits ordered by (volume, layer, module); weights sum to 1.
  double sum = 0.0;
  for (const HitTruth& t : event.truth) {
    sum += t.weight;
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  ASSERT_EQ(event.particles.size(), 3u);
  EXPECT_EQ(event.particles[0].nHits,
            static_cast<std::uint32_t>(volumes[1][8] + volumes[1][13] +
                                       volumes[1][17]));
}

TEST(TrackmlEvents, FieldStepsKeepTheSensorsInFrontOfEachDisk) {
  // The TrackML detector has the solenoid field, followed in steps; pixel
  // disks lie at multiples of 50 mm (600, 700, ..., 1500 mm) with their
  // sensors 2.5 mm in front of and behind the disk surface, so a forward
  // particle's step can end between the front sensors and the surface.
  // Those sensors must still give their hits: stiff forward particles
  // (10 GeV at eta 3.6-3.7, where the field is within 10 % of 2 T and the
  // paths differ by a fraction of a millimetre) hit as many sensors as in
  // a uniform field, which needs no steps, but for the odd sensor edge
  // (before the fix the stepped simulation lost one disk's front sensors
  // in five). Ideal simulation: no material, no smearing.
  ASSERT_FALSE(trackmlDetector().field().isUniform());
  std::string text = buildTrackmlDetectorToml(trackmlModules(), {});
  for (const char* key : {"solenoid_radius_mm", "solenoid_half_length_mm"}) {
    const std::size_t line = text.find(key);
    ASSERT_NE(line, std::string::npos) << key;
    text.erase(line, text.find('\n', line) - line + 1);
  }
  const Detector uniform = parseDetector(text, "uniform trackml");
  ASSERT_TRUE(uniform.field().isUniform());
  Simulator::Config config = trackmlSimulatorConfig();
  config.multipleScattering = false;
  config.energyLoss = false;
  config.hadronicInteractions = false;
  config.smearHits = false;
  const Simulator stepped(trackmlDetector(), config, moduleLayout());
  const Simulator unstepped(uniform, config, moduleLayout());
  auto sensors = [](const Simulator& simulator, const Particle& particle) {
    Event event;
    RandomEngine rng(11);
    simulator.simulate({particle}, rng, event);
    std::multiset<DetectorId> hit;
    for (const Hit& h : event.hits) {
      hit.insert(h.detId);
    }
    return hit;
  };
  long uniformHits = 0;
  long steppedHits = 0;
  for (int k = 0; k < 20; ++k) {
    Particle particle = makeParticle(1, 0.55, 3.6 + 0.005 * k, 0.3 * k);
    particle.vertex = Vector3(0.0, 0.0, 0.25 * k);
    uniformHits += static_cast<long>(sensors(unstepped, particle).size());
    steppedHits += static_cast<long>(sensors(stepped, particle).size());
  }
  EXPECT_GE(uniformHits, 200);
  EXPECT_LE(std::abs(steppedHits - uniformHits), 2)
      << steppedHits << " hits in the field, " << uniformHits << " uniform";
}

TEST(TrackmlEvents, NoiseAndPtCut) {
  std::vector<Particle> particles;
  for (int k = 0; k < 200; ++k) {
    particles.push_back(makeParticle(k + 1, 0.5 + 0.05 * k, -2.0 + 0.02 * k,
                                     0.1 * k, k % 2 == 0 ? 1.0 : -1.0));
  }
  particles.push_back(makeParticle(1000, 0.1, 0.0, 0.0));
  TrackmlEventSimulation::Config config;
  config.noiseFraction = 0.2;
  config.minPt = 0.15;
  TrackmlEventSimulation sim(trackmlDetector(), moduleLayout(), config);
  Event event = sim.simulate(3, particles);
  std::size_t noise = 0;
  for (std::size_t i = 0; i < event.truth.size(); ++i) {
    if (event.truth[i].particleId == 0) {
      ++noise;
      EXPECT_EQ(event.truth[i].weight, 0.0);
    }
  }
  const double fraction =
      static_cast<double>(noise) / static_cast<double>(event.hits.size());
  EXPECT_NEAR(fraction, 0.2, 0.02);
  EXPECT_EQ(event.particles.back().id, 1000u);
  EXPECT_EQ(event.particles.back().nHits, 0u);
  // The particle hits do not depend on the noise.
  config.noiseFraction = 0.0;
  Event clean =
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config)
          .simulate(3, particles);
  EXPECT_EQ(clean.hits.size(), event.hits.size() - noise);
  config.noiseFraction = 1.0;
  EXPECT_THROW(TrackmlEventSimulation(trackmlDetector(), nullptr, config),
               std::invalid_argument);
}

/// The real files' noise is a count per sensor, not a share of the hits
/// (kTrackmlNoisePerSensor): the same with 10 or 200 particles, Poisson
/// about rate x sensors from event to event, each layer's in proportion
/// to its sensors.
TEST(TrackmlEvents, NoisePerSensorIgnoresTheOccupancy) {
  const std::size_t sensors = moduleLayout()->modules().size();
  ASSERT_EQ(sensors, 18728u);
  std::vector<Particle> particles;
  for (int k = 0; k < 200; ++k) {
    particles.push_back(makeParticle(k + 1, 0.5 + 0.05 * k, -2.0 + 0.02 * k,
                                     0.1 * k, k % 2 == 0 ? 1.0 : -1.0));
  }
  const std::vector<Particle> few(particles.begin(), particles.begin() + 10);
  TrackmlEventSimulation::Config config;
  config.noisePerSensor = 0.5;
  const TrackmlEventSimulation sim(trackmlDetector(), moduleLayout(), config);
  auto noiseHits = [](const Event& event) {
    std::vector<std::size_t> noise;
    for (std::size_t i = 0; i < event.truth.size(); ++i) {
      if (event.truth[i].particleId == 0) {
        noise.push_back(i);
      }
    }
    return noise;
  };
  // Its own stream: the same noise hits whatever the particles.
  const Event busy = sim.simulate(3, particles);
  const Event quiet = sim.simulate(3, few);
  const std::vector<std::size_t> busyNoise = noiseHits(busy);
  const std::vector<std::size_t> quietNoise = noiseHits(quiet);
  ASSERT_EQ(busyNoise.size(), quietNoise.size());
  EXPECT_EQ(busy.hits[busyNoise.front()].position,
            quiet.hits[quietNoise.front()].position);
  EXPECT_GT(busy.hits.size() - busyNoise.size(),
            5 * (quiet.hits.size() - quietNoise.size()));
  // Poisson about 0.5 x 18,728 = 9,364 (sigma 97) in each event; the
  // layers in proportion to their sensors: the pixel barrel's innermost
  // layer (volume 8, layer 2) holds 224 / 18,728 of them.
  const std::vector<SensitiveLayer>& layers = trackmlDetector().layers();
  std::size_t inner = layers.size();
  for (std::size_t l = 0; l < layers.size(); ++l) {
    if (layers[l].trackmlVolume == 8 && layers[l].trackmlLayer == 2) {
      inner = l;
    }
  }
  ASSERT_LT(inner, layers.size());
  const auto [innerBegin, innerEnd] =
      moduleLayout()->layerRange(static_cast<std::uint32_t>(inner));
  ASSERT_EQ(innerEnd - innerBegin, 224u);
  const double mean = 0.5 * static_cast<double>(sensors);
  double sum = 0.0;
  double sumSquares = 0.0;
  std::size_t innermost = 0;
  std::size_t total = 0;
  const int events = 40;
  for (int e = 0; e < events; ++e) {
    const Event event = sim.simulate(100 + e, few);
    const std::vector<std::size_t> noise = noiseHits(event);
    const double n = static_cast<double>(noise.size());
    sum += n;
    sumSquares += n * n;
    for (std::size_t i : noise) {
      innermost += event.hits[i].detId.sameLayer(layers[inner].id);
    }
    total += noise.size();
  }
  const double average = sum / events;
  const double spread = std::sqrt(sumSquares / events - average * average);
  // 5 sigma of the mean of 40 Poisson counts; the spread within 35 %
  // (40 events), far from the 1,300 of a share of the hits.
  EXPECT_NEAR(average, mean, 5.0 * std::sqrt(mean / events));
  EXPECT_NEAR(spread, std::sqrt(mean), 0.35 * std::sqrt(mean));
  const double innerShare = 224.0 / static_cast<double>(sensors);
  EXPECT_NEAR(static_cast<double>(innermost) / static_cast<double>(total),
              innerShare,
              5.0 * std::sqrt(innerShare / static_cast<double>(total)));
  // A rate needs sensors and is one noise model.
  EXPECT_THROW(TrackmlEventSimulation(trackmlDetector(), nullptr, config),
               std::invalid_argument);
  config.noiseFraction = 0.1;
  EXPECT_THROW(
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config),
      std::invalid_argument);
  config.noiseFraction = 0.0;
  config.noisePerSensor = -1.0;
  EXPECT_THROW(
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config),
      std::invalid_argument);
}

/// The particles of a shipped Kaggle event, read here without io (a few
/// columns suffice); `realReconstructable` counts those with nhits >= 4.
std::vector<Particle> kaggleParticles(
    std::uint64_t event, std::size_t* realReconstructable = nullptr) {
  const fs::path dir = kTrackmlData / "train_100_events_no_truth";
  const std::string text = hepmc::loadFile(
      dir / ("event00000" + std::to_string(event) + "-particles.csv.gz"));
  std::vector<Particle> particles;
  std::size_t pos = text.find('\n') + 1;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    std::string line = text.substr(pos, end - pos);
    pos = end == std::string::npos ? text.size() : end + 1;
    if (line.empty()) {
      continue;
    }
    Particle p;
    double v[9];
    std::istringstream in(line);
    for (double& x : v) {
      in >> x;
      in.ignore(1);
    }
    p.id =
        static_cast<std::uint64_t>(std::stoull(line.substr(0, line.find(','))));
    p.vertex = Vector3(v[1], v[2], v[3]);
    p.momentum = Vector3(v[4], v[5], v[6]);
    p.charge = v[7];
    if (realReconstructable != nullptr) {
      *realReconstructable += v[8] >= 4 ? 1 : 0;
    }
    particles.push_back(p);
  }
  return particles;
}

// The particles of a Kaggle event: about as many reconstructable particles
// as the real event (7563 against 6797 for event 1001: see the differences
// listed at TrackmlEventSimulation).
TEST(TrackmlEvents, KaggleParticles) {
  std::size_t realReconstructable = 0;
  const std::vector<Particle> particles =
      kaggleParticles(1001, &realReconstructable);
  ASSERT_EQ(particles.size(), 8915u);
  ASSERT_EQ(realReconstructable, 6797u);
  TrackmlEventSimulation::Config config;
  config.minPt = 0.15;
  Event event =
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config)
          .simulate(1001, particles);
  std::size_t reconstructable = 0;
  for (const Particle& p : event.particles) {
    reconstructable += p.nHits >= 4 ? 1 : 0;
  }
  EXPECT_GT(reconstructable, 0.9 * realReconstructable);
  EXPECT_LT(reconstructable, 1.25 * realReconstructable);
}

// ---------------------------------------------- interactions and their z

/// A TrackML particle_id: vertex id, generation, and a running number.
std::uint64_t trackmlId(std::uint64_t vertex, std::uint64_t generation,
                        std::uint64_t n) {
  return (vertex << 52) | (n << 36) | (generation << 24);
}

Particle particleAt(std::uint64_t id, const Vector3& vertex) {
  Particle p = makeParticle(id, 1.0, 0.5, 0.2);
  p.vertex = vertex;
  return p;
}

/// The z of the interaction points of a particle list.
std::vector<double> interactionZ(const std::vector<Particle>& particles) {
  std::vector<double> z;
  for (const TrackmlInteraction& i : findTrackmlInteractions(particles)) {
    if (i.vertex) {
      z.push_back(i.vertex->z());
    }
  }
  return z;
}

/// Sample standard deviation.
double spreadOf(const std::vector<double>& x) {
  const double mean =
      std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
  double sum2 = 0.0;
  for (double v : x) {
    sum2 += (v - mean) * (v - mean);
  }
  return std::sqrt(sum2 / static_cast<double>(x.size() - 1));
}

TEST(TrackmlInteractions, GroupedByVertexIdWithTheirSecondaries) {
  const Vector3 pv1(0.01, -0.02, 3.0);
  const Vector3 pv2(-0.01, 0.0, -4.0);
  const Vector3 decay(0.3, 0.2, 5.0);  // e.g. a charm decay, near the beam
  const Vector3 conversion(300.0, 10.0, 250.0);
  std::vector<Particle> particles = {
      particleAt(trackmlId(2, 0, 1), pv2),
      particleAt(trackmlId(1, 0, 1), pv1),
      particleAt(trackmlId(1, 0, 2), pv1),
      particleAt(trackmlId(1, 0, 3), pv1),
      particleAt(trackmlId(1, 0, 4), decay),
      particleAt(trackmlId(1, 0, 5), decay),
      particleAt(trackmlId(1, 1, 6), conversion),
      particleAt(trackmlId(1, 1, 7), conversion),
      particleAt(trackmlId(1, 1, 8), conversion),
      particleAt(trackmlId(1, 1, 9), conversion),
      particleAt(trackmlId(2, 0, 2), pv2),
      // Only the decay products of a long-lived particle: no point.
      particleAt(trackmlId(3, 0, 1), Vector3(20.0, 5.0, 100.0)),
  };
  const auto interactions = findTrackmlInteractions(particles);
  ASSERT_EQ(interactions.size(), 3u);
  EXPECT_EQ(interactions[0].vertexId, 1u);
  EXPECT_EQ(interactions[0].particles,
            (std::vector<std::size_t>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
  // The conversion has the most particles, but generation 1 and far from
  // the beam line; the decay has fewer generation-0 particles.
  EXPECT_EQ(interactions[0].vertex, pv1);
  EXPECT_EQ(interactions[1].vertexId, 2u);
  EXPECT_EQ(interactions[1].particles, (std::vector<std::size_t>{0, 10}));
  EXPECT_EQ(interactions[1].vertex, pv2);
  EXPECT_EQ(interactions[2].vertexId, 3u);
  EXPECT_FALSE(interactions[2].vertex.has_value());
  // A tie goes to the position nearest the beam line; a majority wins.
  particles.push_back(particleAt(trackmlId(1, 0, 10), decay));
  EXPECT_EQ(findTrackmlInteractions(particles)[0].vertex, pv1);
  particles.push_back(particleAt(trackmlId(1, 0, 11), decay));
  EXPECT_EQ(findTrackmlInteractions(particles)[0].vertex, decay);
  // Ids without a vertex id (conftrack numbers its particles 1..n).
  particles.push_back(particleAt(17, pv1));
  EXPECT_EQ(test::inputErrorOf([&] { findTrackmlInteractions(particles); }),
            "particle_id 17: no TrackML vertex id (bits 52-63 are 0); moving "
            "the interactions needs the particle ids of TrackML particle "
            "files");
}

// 4000 interactions of a primary and a displaced decay: the points follow
// the region in z (width within 5 / sqrt(8000) = 5.6 %), every particle
// keeps its offset from its point, x and y are kept.
TEST(TrackmlInteractions, MovedAlongZKeepingDisplacements) {
  auto source = makeEngine(1, 1, RandomStream::eSignalGenerator);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Particle> particles;
  for (std::uint64_t v = 1; v <= 4000; ++v) {
    const Vector3 pv(0.015 * normal(source), 0.015 * normal(source),
                     5.5 * normal(source));
    const Vector3 decay = pv + Vector3(1.0, 2.0, 3.0 * normal(source));
    particles.push_back(particleAt(trackmlId(v, 0, 1), pv));
    particles.push_back(particleAt(trackmlId(v, 0, 2), pv));
    particles.push_back(particleAt(trackmlId(v, 0, 3), decay));
    particles.push_back(particleAt(trackmlId(v, 2, 4), decay * 10.0));
  }
  EXPECT_NEAR(spreadOf(interactionZ(particles)), 5.5,
              5.0 * 5.5 / std::sqrt(8000));
  const LuminousRegion hllhc(LuminousRegion::findPreset("hllhc")->config);
  auto rng = makeEngine(1, 1, RandomStream::eLuminousRegion);
  const std::vector<Particle> moved =
      moveTrackmlInteractions(particles, hllhc, rng);
  ASSERT_EQ(moved.size(), particles.size());
  EXPECT_NEAR(spreadOf(interactionZ(moved)), 50.0,
              5.0 * 50.0 / std::sqrt(8000));
  for (std::size_t i = 0; i < moved.size(); i += 4) {
    const double shift = moved[i].vertex.z() - particles[i].vertex.z();
    for (std::size_t k = i; k < i + 4; ++k) {
      EXPECT_EQ(moved[k].id, particles[k].id);
      EXPECT_EQ(moved[k].vertex.x(), particles[k].vertex.x());
      EXPECT_EQ(moved[k].vertex.y(), particles[k].vertex.y());
      EXPECT_NEAR(moved[k].vertex.z() - particles[k].vertex.z(), shift, 1e-9);
      EXPECT_EQ(moved[k].momentum, particles[k].momentum);
    }
  }
  // Deterministic: the same stream moves them the same way.
  auto again = makeEngine(1, 1, RandomStream::eLuminousRegion);
  EXPECT_EQ(moveTrackmlInteractions(particles, hllhc, again)[7].vertex,
            moved[7].vertex);
}

/// Two interactions: two particles of vertex 1 at z = 2 mm, one of vertex
/// 2 at `second`.
std::vector<Particle> twoInteractions(const Vector3& second) {
  return {particleAt(trackmlId(1, 0, 1), Vector3(0.01, 0.0, 2.0)),
          particleAt(trackmlId(1, 0, 2), Vector3(0.01, 0.0, 2.0)),
          particleAt(trackmlId(2, 0, 1), second)};
}

// By default every particle keeps its own vertex; with a region the event
// holds the moved particles, the same for the same (seed, event).
TEST(TrackmlEvents, RealVerticesKeptUnlessARegionIsGiven) {
  const std::vector<Particle> particles =
      twoInteractions(Vector3(0.0, 0.02, -7.0));
  TrackmlEventSimulation::Config config;
  const Event kept =
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config)
          .simulate(5, particles);
  ASSERT_EQ(kept.particles.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(kept.particles[i].vertex, particles[i].vertex);
  }
  config.luminousRegion = LuminousRegion::findPreset("hllhc")->config;
  const TrackmlEventSimulation hl(trackmlDetector(), moduleLayout(), config);
  const Event moved = hl.simulate(5, particles);
  ASSERT_EQ(moved.particles.size(), 3u);
  EXPECT_NE(moved.particles[0].vertex.z(), 2.0);
  EXPECT_EQ(moved.particles[0].vertex, moved.particles[1].vertex);
  EXPECT_EQ(moved.particles[2].vertex.x(), 0.0);
  EXPECT_EQ(moved.particles[2].vertex.y(), 0.02);
  const Event again = hl.simulate(5, particles);
  EXPECT_EQ(again.particles[2].vertex, moved.particles[2].vertex);
  EXPECT_EQ(again.hits.size(), moved.hits.size());
  config.seed = 2;
  const Event other =
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config)
          .simulate(5, particles);
  EXPECT_NE(other.particles[2].vertex, moved.particles[2].vertex);
  config.luminousRegion->sigmaZ = -1.0;
  EXPECT_EQ(test::inputErrorOf([&] {
              TrackmlEventSimulation(trackmlDetector(), nullptr, config);
            }),
            "TrackmlEventSimulation: config field 'luminousRegion.sigmaZ': "
            "must lie in [0, 1000] mm (got -1)");
}

TEST(TrackmlEvents, BeamLineMovesTheWholeEventTransversely) {
  // --beam-line: every particle moves by (x, y), alone or after the move
  // along z of a luminous region; z, momenta and ids stay.
  // (The second interaction's particle produced 30 mm out moves too.)
  const std::vector<Particle> particles =
      twoInteractions(Vector3(30.0, 0.02, -7.0));
  TrackmlEventSimulation::Config config;
  config.beamLine = Vector2(0.5, -0.5);
  const Event off =
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config)
          .simulate(5, particles);
  ASSERT_EQ(off.particles.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const Vector3 shift = off.particles[i].vertex - particles[i].vertex;
    EXPECT_NEAR(shift.x(), 0.5, 1e-12) << i;
    EXPECT_NEAR(shift.y(), -0.5, 1e-12) << i;
    EXPECT_EQ(shift.z(), 0.0) << i;
    EXPECT_EQ(off.particles[i].momentum, particles[i].momentum);
    EXPECT_EQ(off.particles[i].id, particles[i].id);
  }
  // With a region: first along z (as without the line), then across.
  config.luminousRegion = LuminousRegion::findPreset("hllhc")->config;
  const Event both =
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config)
          .simulate(5, particles);
  config.beamLine = Vector2::Zero();
  const Event alongZ =
      TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config)
          .simulate(5, particles);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(both.particles[i].vertex.z(), alongZ.particles[i].vertex.z());
    EXPECT_NEAR(both.particles[i].vertex.x() - alongZ.particles[i].vertex.x(),
                0.5, 1e-12);
  }
  // Beyond the reconstruction's range, or not a number.
  for (const Vector2& bad :
       {Vector2(10.5, 0.0), Vector2(0.0, -11.0),
        Vector2(std::numeric_limits<double>::quiet_NaN(), 0.0)}) {
    config.beamLine = bad;
    EXPECT_THROW(
        TrackmlEventSimulation(trackmlDetector(), moduleLayout(), config),
        std::invalid_argument);
  }
}

// The five shipped Kaggle events (713 interactions with a point): the
// Kaggle length, 5.31 mm, within 5 standard errors (0.14 mm) of 5.5 mm;
// moved to the HL-LHC region, 50 mm within 5 standard errors (1.33 mm);
// every interaction moved as a whole.
TEST(TrackmlEvents, HllhcRegionOnTheFiveRealEvents) {
  TrackmlEventSimulation::Config config;
  config.minPt = 1e9;  // no propagation: the vertices are the point here
  config.luminousRegion = LuminousRegion::findPreset("hllhc")->config;
  const TrackmlEventSimulation sim(trackmlDetector(), moduleLayout(), config);
  std::vector<double> before;
  std::vector<double> after;
  for (std::uint64_t event : {1001, 1003, 1005, 1009, 1010}) {
    const std::vector<Particle> real = kaggleParticles(event);
    const Event moved = sim.simulate(event, real);
    ASSERT_EQ(moved.particles.size(), real.size());
    std::map<std::uint64_t, const Particle*> byId;
    for (const Particle& p : moved.particles) {
      byId[p.id] = &p;
    }
    std::map<std::uint64_t, double> shift;  // per vertex id
    for (const Particle& p : real) {
      const Particle& m = *byId.at(p.id);
      EXPECT_EQ(m.vertex.x(), p.vertex.x());
      EXPECT_EQ(m.vertex.y(), p.vertex.y());
      const double dz = m.vertex.z() - p.vertex.z();
      const auto [it, first] = shift.emplace(trackmlVertexId(p.id), dz);
      if (!first) {
        ASSERT_NEAR(dz, it->second, 1e-9) << "particle " << p.id;
      }
    }
    for (double z : interactionZ(real)) {
      before.push_back(z);
    }
    for (double z : interactionZ(moved.particles)) {
      after.push_back(z);
    }
  }
  ASSERT_EQ(before.size(), 713u);
  ASSERT_EQ(after.size(), 713u);
  EXPECT_NEAR(spreadOf(before), 5.5, 5.0 * 0.14);
  EXPECT_NEAR(spreadOf(after), 50.0, 5.0 * 1.33);
}
}  // namespace
}  // namespace conftrack

// The fit's measurement on the hit's own sensor plane (issue 15, item 1):
// the tangent plane of an ideal layer gives the fit on the layer; hits of
// flat, tilted, staggered and overlapping sensors (two hits on one layer)
// give unbiased pulls; sensor axes from a module layout for hits that carry
// only their layer's axes; the fitter's input is hit indices (item 6).

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/fitting/HelixState.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace conftrack {
namespace {

constexpr double kPi = std::numbers::pi;

/// Six barrel layers, 2 T, 1 % X0 each.
Detector toyBarrel() {
  std::string text =
      "[detector]\nname = \"Toy\"\nmodel = \"toy\"\nbz_T = 2.0\n"
      "envelope_r_mm = 900.0\nenvelope_z_mm = 4000.0\n\n"
      "[[subdetector]]\nname = \"Barrel\"\nkind = \"barrel\"\n";
  int i = 0;
  for (double r : {40.0, 80.0, 120.0, 200.0, 300.0, 450.0}) {
    text += "  [[subdetector.layer]]\n  name = \"L" + std::to_string(i++) +
            "\"\n  r_mm = " + std::to_string(r) +
            "\n  half_z_mm = 600.0\n  x_over_x0 = 0.01\n"
            "  sigma_rphi_um = 10.0\n  sigma_z_um = 20.0\n";
  }
  return parseDetector(text, "toy.toml");
}

/// Per layer a ring of flat sensors, each 25 % wider than its phi sector
/// (overlaps: two hits on one layer), alternately 4 mm inside and outside
/// the layer radius and tilted by 10 degrees about their long (z) axis,
/// as real barrel staves (overlapping sensors at least 1.5 mm apart).
std::shared_ptr<const ModuleLayout> tiltedRings(const Detector& detector) {
  std::vector<PlanarModule> modules;
  const double tilt = 10.0 * units::degree;
  for (std::uint32_t l = 0; l < detector.layers().size(); ++l) {
    const SensitiveLayer& layer = detector.layers()[l];
    const int n = static_cast<int>(std::ceil(2.0 * kPi * layer.r / 30.0));
    for (int k = 0; k < n; ++k) {
      const double phi = 2.0 * kPi * k / n;
      const double r = layer.r + (k % 2 == 0 ? -4.0 : 4.0);
      const double a = phi + tilt;
      PlanarModule m;
      m.layer = l;
      m.module = static_cast<std::uint32_t>(k + 1);
      m.center = Vector3(r * std::cos(phi), r * std::sin(phi), 0.0);
      m.rotation.col(0) = Vector3(-std::sin(a), std::cos(a), 0.0);
      m.rotation.col(1) = Vector3::UnitZ();
      m.rotation.col(2) = Vector3(std::cos(a), std::sin(a), 0.0);
      m.minHalfU = m.maxHalfU =
          1.25 * layer.r * std::tan(kPi / n) / std::cos(tilt);
      m.halfV = layer.zMax;
      m.thickness = 0.2;
      m.thicknessX0 = 0.008;
      m.sigmaU = 0.01;
      m.sigmaV = 0.02;
      modules.push_back(m);
    }
  }
  return std::make_shared<const ModuleLayout>(
      detector, modules, std::vector<double>(detector.layers().size(), 0.002));
}

/// Fitted and true helix of one particle.
struct FittedParticle {
  Track track;
  TrackVector truth;
  bool twoHitsOnALayer = false;
};

/// `n` muons of 3 to 30 GeV, |eta| < 1, from the origin, simulated with
/// `simulator`; each fitted from its truth hits in path order.
std::vector<FittedParticle> fitMuons(const Detector& detector,
                                     const Simulator& simulator,
                                     const KalmanFitter& fitter, int n,
                                     std::uint64_t seed) {
  std::vector<FittedParticle> out;
  RandomEngine rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < n; ++i) {
    Particle p;
    p.id = 1;
    p.pdg = i % 2 == 0 ? 13 : -13;
    p.charge = p.pdg > 0 ? -1.0 : 1.0;
    const double pt = 3.0 + 27.0 * uniform(rng);
    const double phi = 2.0 * kPi * uniform(rng);
    const double eta = -1.0 + 2.0 * uniform(rng);
    p.momentum =
        Vector3(pt * std::cos(phi), pt * std::sin(phi), pt * std::sinh(eta));
    Event event;
    simulator.simulate({p}, rng, event);
    std::vector<HitIndex> hits;
    std::map<std::uint32_t, int> perLayer;
    for (std::size_t h = 0; h < event.hits.size(); ++h) {
      hits.push_back(static_cast<HitIndex>(h));
      ++perLayer[event.hits[h].detId.layer];
    }
    if (hits.size() < 4) {
      continue;
    }
    FittedParticle f;
    f.track = fitter.fit(event.hits, {hits});
    f.truth = helixParametersAt(p.vertex, p.momentum, p.charge, detector.bz());
    for (const auto& [layer, count] : perLayer) {
      f.twoHitsOnALayer = f.twoHitsOnALayer || count > 1;
    }
    out.push_back(std::move(f));
  }
  return out;
}

/// Mean and RMS of the pulls of parameter k over the fitted tracks.
std::array<double, 2> pullMoments(const std::vector<FittedParticle>& fits,
                                  int k, bool onlyTwoHits) {
  double sum = 0.0;
  double sum2 = 0.0;
  double n = 0.0;
  for (const FittedParticle& f : fits) {
    if (!f.track.fitted || (onlyTwoHits && !f.twoHitsOnALayer)) {
      continue;
    }
    const double d = wrapAngle(f.track.atIp.parameters[k] - f.truth[k]);
    const double pull = d / std::sqrt(f.track.atIp.covariance(k, k));
    sum += pull;
    sum2 += pull * pull;
    n += 1.0;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(sum2 / n - mean * mean)};
}

/// A simulation without material (the pulls test the measurement model
/// alone; the fitter is told the same).
Simulator::Config noMaterial() {
  Simulator::Config config;
  config.multipleScattering = false;
  config.energyLoss = false;
  return config;
}

KalmanFitter::Config fitterConfig(bool sensorPlanes, bool material) {
  KalmanFitter::Config config;
  config.pdg = 13;
  config.sensorPlanes = sensorPlanes;
  config.multipleScattering = material;
  config.energyLoss = material;
  return config;
}

TEST(SensorPlaneFit, OverlappingTiltedSensorsGiveUnbiasedPulls) {
  const Detector detector = toyBarrel();
  const Simulator simulator(detector, noMaterial(), tiltedRings(detector));
  const KalmanFitter planes(detector, fitterConfig(true, false));
  const std::vector<FittedParticle> fits =
      fitMuons(detector, simulator, planes, 1500, 11);
  std::size_t twoHits = 0;
  std::size_t fitted = 0;
  for (const FittedParticle& f : fits) {
    fitted += f.track.fitted ? 1 : 0;
    twoHits += f.track.fitted && f.twoHitsOnALayer ? 1 : 0;
  }
  EXPECT_EQ(fitted, fits.size());
  // Every hit is used (none is an outlier or unreachable).
  for (const FittedParticle& f : fits) {
    EXPECT_EQ(f.track.numOutliers(), 0u);
  }
  // 25 % overlaps on six layers: most tracks have two hits on a layer.
  ASSERT_GT(twoHits, 800u);
  // Statistical precision of the width: 1/sqrt(2 N) < 0.025.
  for (int k = 0; k < 5; ++k) {
    const auto [mean, width] = pullMoments(fits, k, true);
    std::printf(
        "[two hits on a layer, %zu tracks] pull %d: mean %.3f, "
        "width %.3f\n",
        twoHits, k, mean, width);
    EXPECT_LT(std::abs(mean), 0.05) << k;
    EXPECT_NEAR(width, 1.0, 0.05) << k;
  }
  // The same hits measured on the layer cylinder (the fit before sensor
  // planes): the 4 mm stagger and the tilt are 100s of sigma_u, so the
  // fit is far off.
  const KalmanFitter layers(detector, fitterConfig(false, false));
  const std::vector<FittedParticle> old =
      fitMuons(detector, simulator, layers, 200, 11);
  double chi2 = 0.0;
  double ndf = 0.0;
  for (const FittedParticle& f : old) {
    if (f.track.fitted) {
      chi2 += f.track.chi2;
      ndf += f.track.ndf;
    }
  }
  std::printf("[layer surfaces] chi2/ndf %.1f\n", chi2 / ndf);
  EXPECT_GT(chi2, 10.0 * ndf);
}

TEST(SensorPlaneFit, TangentPlaneOfAnIdealLayerGivesTheLayerFit) {
  // CLICdet with its material: barrel (cylinder) and endcap (disk) hits.
  const Detector detector = loadDetector("clicdet");
  const Simulator simulator(detector);
  const KalmanFitter planes(detector, fitterConfig(true, true));
  const KalmanFitter layers(detector, fitterConfig(false, true));
  RandomEngine rng(5);
  int compared = 0;
  for (double theta : {20.0, 50.0, 89.0}) {
    for (double p : {1.0, 10.0, 100.0}) {
      for (int i = 0; i < 10; ++i) {
        Particle particle;
        particle.id = 1;
        particle.pdg = 13;
        particle.charge = -1.0;
        const double phi = 0.6 * i;
        const double t = theta * units::degree;
        particle.momentum =
            p * Vector3(std::sin(t) * std::cos(phi),
                        std::sin(t) * std::sin(phi), std::cos(t));
        Event event;
        simulator.simulate({particle}, rng, event);
        std::vector<HitIndex> hits;
        for (std::size_t h = 0; h < event.hits.size(); ++h) {
          hits.push_back(static_cast<HitIndex>(h));
        }
        if (hits.size() < 4) {
          continue;
        }
        const Track a = planes.fit(event.hits, {hits});
        const Track b = layers.fit(event.hits, {hits});
        ASSERT_EQ(a.fitted, b.fitted);
        if (!a.fitted) {
          continue;
        }
        ++compared;
        EXPECT_EQ(a.numOutliers(), b.numOutliers());
        // "Well within the errors": 2 % of sigma for every parameter.
        for (int k = 0; k < 5; ++k) {
          const double sigma = std::sqrt(b.atIp.covariance(k, k));
          EXPECT_NEAR(wrapAngle(a.atIp.parameters[k] - b.atIp.parameters[k]),
                      0.0, 0.02 * sigma)
              << "theta " << theta << " p " << p << " k " << k;
          EXPECT_NEAR(std::sqrt(a.atIp.covariance(k, k)), sigma, 0.01 * sigma)
              << k;
        }
        EXPECT_NEAR(a.chi2, b.chi2, 0.02 * b.chi2 + 0.05);
      }
    }
  }
  EXPECT_GT(compared, 80);
}

TEST(SensorPlaneFit, SensorAxesFromTheLayoutForHitsWithLayerAxes) {
  const Detector detector = toyBarrel();
  const std::shared_ptr<const ModuleLayout> layout = tiltedRings(detector);
  const Simulator simulator(detector, noMaterial(), layout);
  const KalmanFitter plain(detector, fitterConfig(true, false));
  const KalmanFitter withLayout(detector, fitterConfig(true, false), layout);
  RandomEngine rng(3);
  double largestChange = 0.0;
  for (int i = 0; i < 20; ++i) {
    Particle p;
    p.id = 1;
    p.pdg = 13;
    p.charge = -1.0;
    p.momentum = Vector3(5.0 * std::cos(0.3 * i), 5.0 * std::sin(0.3 * i),
                         0.5 * (i % 5 - 2));
    Event event;
    simulator.simulate({p}, rng, event);
    std::vector<HitIndex> hits;
    for (std::size_t h = 0; h < event.hits.size(); ++h) {
      hits.push_back(static_cast<HitIndex>(h));
    }
    ASSERT_GE(hits.size(), 6u);
    // As read from a file (TrackmlReader): the layer's axes (u flipped:
    // the fitter matches the sensor's axes to them by direction only).
    std::vector<Hit> read = event.hits;
    for (Hit& hit : read) {
      const SensitiveLayer& layer = detector.layers()[hit.detId.layer];
      layer.localAxes(hit.position, hit.uAxis, hit.vAxis);
      hit.uAxis = -hit.uAxis;
    }
    const Track truth = plain.fit(event.hits, {hits});
    const Track layerAxes = plain.fit(read, {hits});
    const Track sensorAxes = withLayout.fit(read, {hits});
    ASSERT_TRUE(truth.fitted && layerAxes.fitted && sensorAxes.fitted);
    for (int k = 0; k < 5; ++k) {
      const double sigma = std::sqrt(truth.atIp.covariance(k, k));
      EXPECT_NEAR(sensorAxes.atIp.parameters[k], truth.atIp.parameters[k],
                  1e-6 * sigma)
          << k;
    }
    EXPECT_NEAR(sensorAxes.chi2, truth.chi2, 1e-6 * truth.chi2 + 1e-9);
    // The layer's tangent plane through the hit is 10 degrees off the
    // sensor: a different (if close, the plane goes through the hit)
    // fit.
    double change = 0.0;
    for (int k = 0; k < 5; ++k) {
      change = std::max(change, std::abs(layerAxes.atIp.parameters[k] -
                                         truth.atIp.parameters[k]) /
                                    std::sqrt(truth.atIp.covariance(k, k)));
    }
    largestChange = std::max(largestChange, change);
  }
  std::printf("[layer axes] largest change %.3f sigma\n", largestChange);
  EXPECT_GT(largestChange, 1e-3);
  // A layout of another detector is refused.
  const Detector other = loadDetector("clicdet");
  EXPECT_THROW(KalmanFitter(other, fitterConfig(true, false), layout),
               std::invalid_argument);
}

TEST(SensorPlaneFit, FinderTrackToFitterInputAndBack) {
  FoundTrack found;
  found.hits = {4, 2, 7};
  found.fitBackward = true;
  found.step = 3;
  found.pt = 2.5;
  found.charge = -1;
  const FitInput input = fitInput(found);
  EXPECT_EQ(input.hits.data(), found.hits.data());
  EXPECT_EQ(input.hits.size(), 3u);
  EXPECT_TRUE(input.backward);
  Track fitted;
  fitted.hits = found.hits;
  fitted.outlier = {0, 1, 0};
  fitted.fitted = true;
  fitted.chi2 = 1.5;
  fitted.ndf = 1;
  fitted.atIp.parameters[eOmega] = 0.01;
  const Track track = withFit(found, fitted);
  EXPECT_EQ(track.hits, found.hits);
  EXPECT_EQ(track.outlier, fitted.outlier);
  EXPECT_TRUE(track.fitted);
  EXPECT_EQ(track.findingStep, 3);
  EXPECT_EQ(track.ptEstimate, 2.5);
  EXPECT_EQ(track.chargeEstimate, -1);
  EXPECT_EQ(track.chi2, 1.5);
  EXPECT_EQ(track.ndf, 1);
  EXPECT_EQ(track.atIp.parameters[eOmega], 0.01);
}

}  // namespace
}  // namespace conftrack

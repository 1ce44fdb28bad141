// Flat sensors of a layer (ModuleLayout), their grid lookup and the search
// for the sensors a helix crosses (findModuleCrossings), against brute
// force on the real TrackML module table; the azimuthal neighbourhood of a
// disk lookup (DiskPhiNeighbourhood).

#include "conftrack/core/Random.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/DiskPhiNeighbourhood.hpp"
#include "conftrack/geometry/Helix.hpp"
#include "conftrack/geometry/ModuleCrossings.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "Gunzip.hpp"

namespace conftrack {
namespace {

constexpr double kPi = std::numbers::pi;

using test::gunzip;

struct TrackmlGeometry {
  std::vector<TrackmlModule> modules;
  Detector detector;
  ModuleLayout layout;
};

const TrackmlGeometry& trackml() {
  static const TrackmlGeometry geometry = [] {
    const auto file = std::filesystem::path(CONFTRACK_TEST_DATA_DIR) /
                      "trackml" / "detectors.csv.gz";
    std::vector<TrackmlModule> modules =
        parseTrackmlModules(gunzip(file), file.string());
    Detector detector = buildTrackmlDetector(modules);
    ModuleLayout layout = buildTrackmlModuleLayout(modules, detector);
    return TrackmlGeometry{std::move(modules), std::move(detector),
                           std::move(layout)};
  }();
  return geometry;
}

TEST(ModuleLayout, HoldsEveryTrackmlModuleExactlyOrthonormal) {
  const TrackmlGeometry& g = trackml();
  EXPECT_EQ(g.layout.modules().size(), 18728u);
  for (const PlanarModule& m : g.layout.modules()) {
    ASSERT_TRUE((m.rotation.transpose() * m.rotation)
                    .isApprox(Matrix3::Identity(), 1e-12));
    ASSERT_LT(m.layer, g.detector.layers().size());
  }
  for (std::uint32_t l = 0; l < g.detector.layers().size(); ++l) {
    EXPECT_TRUE(g.layout.hasModules(l)) << g.detector.layers()[l].name;
    // The sensors lie close to the layer surface (a few mm).
    EXPECT_GT(g.layout.shellHalfThickness(l), 0.0);
    EXPECT_LT(g.layout.shellHalfThickness(l), 15.0)
        << g.detector.layers()[l].name;
  }
}

TEST(ModuleLayout, RejectsBadSensors) {
  const TrackmlGeometry& g = trackml();
  PlanarModule good = g.layout.modules().front();
  auto build = [&](const PlanarModule& m) {
    ModuleLayout(g.detector, std::vector<PlanarModule>{m});
  };
  EXPECT_NO_THROW(build(good));
  PlanarModule bad = good;
  bad.layer = 1000;
  EXPECT_THROW(build(bad), std::invalid_argument);
  bad = good;
  bad.halfV = 0.0;
  EXPECT_THROW(build(bad), std::invalid_argument);
  bad = good;
  bad.rotation(0, 0) += 0.1;
  EXPECT_THROW(build(bad), std::invalid_argument);
  EXPECT_THROW(ModuleLayout(g.detector, {good, good}), std::invalid_argument);
  EXPECT_THROW(ModuleLayout(g.detector, {good}, {0.01}), std::invalid_argument);
}

/// Sensors of `layer` crossed by `helix` within `window` of sLayer, by
/// sampling the distance to every sensor plane of the layer in steps of
/// 0.05 mm and bisecting each sign change.
std::set<std::uint32_t> bruteForceCrossings(const Helix& helix, double sLayer,
                                            double window, std::uint32_t layer,
                                            const ModuleLayout& layout) {
  std::set<std::uint32_t> out;
  const auto [begin, end] = layout.layerRange(layer);
  const Vector3 atLayer = helix.position(sLayer);
  // The arc of length <= window (3-D path >= transverse arc) stays within
  // `window` of the layer point: only sensors that reach that ball.
  const double reach = window + 1.0;
  for (std::uint32_t i = begin; i < end; ++i) {
    const PlanarModule& m = layout.modules()[i];
    const double diagonal =
        std::hypot(std::max(m.minHalfU, m.maxHalfU), m.halfV);
    if ((m.center - atLayer).norm() > reach + diagonal) {
      continue;
    }
    auto f = [&](double s) {
      return m.normal().dot(helix.position(s) - m.center);
    };
    constexpr double kStep = 0.05;
    for (double a = std::max(1e-4, sLayer - window); a < sLayer + window;
         a += kStep) {
      double lo = a;
      double hi = a + kStep;
      if (f(lo) * f(hi) > 0.0) {
        continue;
      }
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (f(lo) * f(mid) <= 0.0 ? hi : lo) = mid;
      }
      const Vector3 local = m.toLocal(helix.position(0.5 * (lo + hi)));
      if (m.contains(local.x(), local.y())) {
        out.insert(i);
      }
    }
  }
  return out;
}

TEST(DiskPhiNeighbourhood, BinsTrackmlDisksByTheirSmallestRing) {
  const TrackmlGeometry& g = trackml();
  const DiskPhiNeighbourhood neighbourhood(g.layout);
  for (std::uint32_t l = 0; l < g.detector.layers().size(); ++l) {
    const SensitiveLayer& layer = g.detector.layers()[l];
    if (!g.layout.layerIsDisk(l)) {
      EXPECT_EQ(neighbourhood.bins(l), 0u) << layer.name;
      continue;
    }
    // Rings of 40 + 68 (pixels), 54 + 56 + 60 (short strips), 48 + 50.
    const double r = g.layout.modules()[g.layout.layerRange(l).first]
                         .center.head<2>()
                         .norm();
    const std::uint32_t expected = r < 200.0 ? 40u : r < 730.0 ? 54u : 48u;
    EXPECT_EQ(neighbourhood.bins(l), expected) << layer.name;
  }
}

TEST(DiskPhiNeighbourhood, KeepsThreeOfTheInnerPixelRingsOverlaps) {
  const TrackmlGeometry& g = trackml();
  const DiskPhiNeighbourhood neighbourhood(g.layout);
  std::uint32_t disk = 0;
  while (!g.layout.layerIsDisk(disk)) {
    ++disk;
  }
  const auto [begin, end] = g.layout.layerRange(disk);
  const double z = g.layout.modules()[begin].center.z();
  // Points at r = 33 mm all around the disk: which sensors hold them, and
  // which of those the lookup returns.
  std::size_t mostHolding = 0;
  std::size_t mostReturned = 0;
  std::size_t fewestReturned = 100;
  for (int k = 0; k < 3600; ++k) {
    const double phi = -kPi + 2.0 * kPi * (k + 0.5) / 3600.0;
    std::size_t holding = 0;
    std::size_t returned = 0;
    for (std::uint32_t i = begin; i < end; ++i) {
      const PlanarModule& m = g.layout.modules()[i];
      const Vector3 point(33.0 * std::cos(phi), 33.0 * std::sin(phi),
                          m.center.z());
      const Vector3 local = m.toLocal(point);
      if (!m.contains(local.x(), local.y())) {
        continue;
      }
      ++holding;
      returned += neighbourhood.contains(disk, i, phi) ? 1 : 0;
    }
    mostHolding = std::max(mostHolding, holding);
    mostReturned = std::max(mostReturned, returned);
    fewestReturned = std::min(fewestReturned, returned);
  }
  EXPECT_GE(mostHolding, 4u) << "disk at z = " << z;
  EXPECT_EQ(mostReturned, 3u);
  EXPECT_GE(fewestReturned, 2u);
  // A sensor is in its own bin's neighbourhood, in the next bin's, and not
  // two bins away.
  const PlanarModule& m = g.layout.modules()[begin];
  const double centre = std::atan2(m.center.y(), m.center.x());
  const double step = 2.0 * kPi / neighbourhood.bins(disk);
  EXPECT_TRUE(neighbourhood.contains(disk, begin, centre));
  EXPECT_TRUE(neighbourhood.contains(disk, begin, centre + step));
  EXPECT_TRUE(neighbourhood.contains(disk, begin, centre - step));
  EXPECT_FALSE(neighbourhood.contains(disk, begin, centre + 2.0 * step));
  EXPECT_FALSE(neighbourhood.contains(disk, begin, centre - 2.0 * step));
}

TEST(ModuleCrossings, AgreeWithBruteForceOnTrackml) {
  // Particles from near the origin, 0.5-10 GeV, |eta| < 3.5, through the
  // first pixel barrel layer and the first pixel disk: the grid search
  // finds exactly the sensors that a brute-force scan of all sensors of
  // the layer finds (within 60 mm of the layer crossing), at most a
  // handful.
  const TrackmlGeometry& g = trackml();
  RandomEngine rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::size_t crossings = 0;
  std::size_t doubles = 0;
  std::size_t tested = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double pt = 0.5 + 9.5 * uniform(rng);
    const double eta =
        (trial % 2 == 0 ? 1.0 : 2.5) * (2.0 * uniform(rng) - 1.0) +
        (trial % 2 == 0 ? 0.0 : (uniform(rng) < 0.5 ? 1.0 : -1.0));
    const double phi = kPi * (2.0 * uniform(rng) - 1.0);
    const Helix helix(
        Vector3(0.1, -0.05, 20.0 * (uniform(rng) - 0.5)),
        Vector3(pt * std::cos(phi), pt * std::sin(phi), pt * std::sinh(eta)),
        trial % 3 == 0 ? -1.0 : 1.0, g.detector.bz());
    for (std::uint32_t l = 0; l < g.detector.layers().size(); ++l) {
      const SensitiveLayer& layer = g.detector.layers()[l];
      const double sLayer =
          layer.isDisk() ? helix.nextDiskCrossing(layer.z(), layer.rMin,
                                                  layer.rMax, 0.0, 1e9)
                         : helix.nextCylinderCrossing(layer.r, layer.zMin,
                                                      layer.zMax, 0.0, 1e9);
      if (!(sLayer < 1e9)) {
        continue;
      }
      std::vector<std::uint32_t> scratch;
      std::vector<ModuleCrossing> found;
      findModuleCrossings(helix, sLayer, 1e-4, l, g.layout, scratch, found);
      std::set<std::uint32_t> foundSet;
      for (std::size_t k = 0; k < found.size(); ++k) {
        foundSet.insert(found[k].module);
        if (k > 0) {
          EXPECT_LE(found[k - 1].s, found[k].s);
        }
        const PlanarModule& m = g.layout.modules()[found[k].module];
        EXPECT_NEAR(m.toLocal(helix.position(found[k].s)).z(), 0.0, 1e-6);
      }
      EXPECT_EQ(foundSet, bruteForceCrossings(helix, sLayer, 60.0, l, g.layout))
          << layer.name << " trial " << trial;
      EXPECT_LE(scratch.size(), 120u) << layer.name;
      crossings += found.size();
      doubles += found.size() >= 2 ? 1 : 0;
      ++tested;
      if (l >= 4 && trial > 40) {
        break;  // the pixel layers are the dense ones; keep it fast
      }
    }
  }
  EXPECT_GT(tested, 500u);
  // Overlaps exist: a good fraction of layer crossings give two sensors.
  EXPECT_GT(doubles, tested / 10);
  EXPECT_GT(crossings, tested * 9 / 10);
}

}  // namespace
}  // namespace conftrack

// The flat sensors of CLICdet and CLD built from their layout files
// (buildLayoutModules): counts, frames, distance to the navigation
// surfaces, coverage by straight tracks and the refusal of bad files.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/Helix.hpp"
#include "conftrack/geometry/LayoutModules.hpp"
#include "conftrack/geometry/ModuleCrossings.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "Gunzip.hpp"
#include "InputErrorOf.hpp"

namespace conftrack {
namespace {

using nlohmann::json;
using units::mm;

constexpr double kPi = std::numbers::pi;

struct Geometry {
  std::string text;  ///< the layout JSON
  Detector detector;
  ModuleLayout layout;
};

Geometry load(const std::string& name) {
  const auto file = std::filesystem::path(CONFTRACK_TEST_DATA_DIR) / "layouts" /
                    (name + "_layout.json.gz");
  std::string text = test::gunzip(file);
  Detector detector = loadDetector(name);
  ModuleLayout layout = buildLayoutModules(text, detector, file.string());
  return Geometry{std::move(text), std::move(detector), std::move(layout)};
}

const Geometry& clicdet() {
  static const Geometry g = load("clicdet");
  return g;
}

const Geometry& cld() {
  static const Geometry g = load("cld");
  return g;
}

std::uint32_t layerIndex(const Detector& det, const std::string& name) {
  for (std::uint32_t l = 0; l < det.layers().size(); ++l) {
    if (det.layers()[l].name == name) {
      return l;
    }
  }
  throw std::runtime_error("no layer " + name);
}

std::size_t numSensors(const ModuleLayout& layout, std::uint32_t layer) {
  const auto [begin, end] = layout.layerRange(layer);
  return end - begin;
}

/// Sensors per layer that the file describes, counted from the JSON.
std::size_t expectedSensors(const json& entry) {
  if (entry.contains("n_staves")) {
    return entry["n_staves"].get<std::size_t>();
  }
  if (entry.contains("n_petals")) {
    return entry["n_petals"].get<std::size_t>();
  }
  if (entry.contains("rings")) {
    std::size_t n = 0;
    for (const json& ring : entry["rings"]) {
      n += ring["n_modules"].get<std::size_t>();
    }
    return n;
  }
  return entry["n_phi_modules"].get<std::size_t>() *
         entry["n_z_modules"].get<std::size_t>();
}

void checkCountsAndFrames(const Geometry& g) {
  const json doc = json::parse(g.text);
  std::size_t total = 0;
  for (const char* list : {"barrel_layers", "endcap_disks"}) {
    for (const json& entry : doc[list]) {
      const std::string name = entry["name"].get<std::string>();
      const bool disk = std::string(list) == "endcap_disks";
      for (const std::string& layer :
           disk ? std::vector<std::string>{name + "_pos", name + "_neg"}
                : std::vector<std::string>{name}) {
        EXPECT_EQ(numSensors(g.layout, layerIndex(g.detector, layer)),
                  expectedSensors(entry))
            << layer;
        total += expectedSensors(entry);
      }
    }
  }
  // Every layer of the detector has sensors, and nothing else does.
  EXPECT_EQ(g.layout.modules().size(), total);
  std::map<std::uint32_t, std::set<std::uint32_t>> numbers;
  for (std::uint32_t l = 0; l < g.detector.layers().size(); ++l) {
    EXPECT_TRUE(g.layout.hasModules(l)) << g.detector.layers()[l].name;
  }
  for (const PlanarModule& m : g.layout.modules()) {
    // Orthonormal frame, u perpendicular to the z axis (r-phi or
    // tangential), v along z on barrels and radial on disks.
    EXPECT_NEAR((m.rotation.transpose() * m.rotation - Matrix3::Identity())
                    .cwiseAbs()
                    .maxCoeff(),
                0.0, 1e-12);
    EXPECT_NEAR(m.uAxis().z(), 0.0, 1e-12);
    const bool disk = g.layout.layerIsDisk(m.layer);
    if (disk) {
      const Vector3 radial(m.center.x(), m.center.y(), 0.0);
      EXPECT_NEAR(m.vAxis().dot(radial.normalized()), 1.0, 1e-9);
    } else {
      EXPECT_NEAR(m.vAxis().z(), 1.0, 1e-12);
    }
    EXPECT_TRUE(numbers[m.layer].insert(m.module).second);
    EXPECT_GT(m.sigmaU, 0.0);
    EXPECT_GT(m.sigmaV, 0.0);
  }
}

TEST(LayoutModules, ClicdetSensorCountsAndFrames) {
  checkCountsAndFrames(clicdet());
  const Geometry& g = clicdet();
  // detectors.md 1.4: IT_B_L0 is 28 x 32 modules.
  EXPECT_EQ(numSensors(g.layout, layerIndex(g.detector, "IT_B_L0")), 896u);
  EXPECT_EQ(numSensors(g.layout, layerIndex(g.detector, "OT_E_L3_neg")), 144u);
  EXPECT_EQ(numSensors(g.layout, layerIndex(g.detector, "VXD_B_L0")), 16u);
}

TEST(LayoutModules, CldSensorCountsAndFrames) {
  checkCountsAndFrames(cld());
  const Geometry& g = cld();
  EXPECT_EQ(numSensors(g.layout, layerIndex(g.detector, "OT_B_L2")),
            452u * 84u);
  EXPECT_EQ(numSensors(g.layout, layerIndex(g.detector, "VXD_E_L5_pos")), 8u);
}

TEST(LayoutModules, MaterialResolutionAndThicknessFromTheFile) {
  const Geometry& g = clicdet();
  const std::uint32_t it = layerIndex(g.detector, "IT_B_L0");
  const PlanarModule& module =
      g.layout.modules()[g.layout.layerRange(it).first];
  EXPECT_DOUBLE_EQ(module.thicknessX0, 0.008843);
  EXPECT_DOUBLE_EQ(g.layout.supportX0(it), 0.001687);
  EXPECT_DOUBLE_EQ(module.sigmaU, 7.0 * units::um);
  EXPECT_DOUBLE_EQ(module.sigmaV, 90.0 * units::um);
  EXPECT_DOUBLE_EQ(module.thickness, 100.0 * units::um);
  EXPECT_DOUBLE_EQ(module.halfV, 15.05 * mm);
  // Vertex staves: only thickness_X0 is given; all of it is the stave's.
  const std::uint32_t vxd = layerIndex(g.detector, "VXD_B_L0");
  EXPECT_DOUBLE_EQ(
      g.layout.modules()[g.layout.layerRange(vxd).first].thicknessX0, 0.002029);
  EXPECT_DOUBLE_EQ(g.layout.supportX0(vxd), 0.0);
  // Disk 0 of the inner tracker is a pixel disk: 5 x 5 um.
  const std::uint32_t disk = layerIndex(g.detector, "IT_E_L0_neg");
  const PlanarModule& pixel =
      g.layout.modules()[g.layout.layerRange(disk).first];
  EXPECT_DOUBLE_EQ(pixel.sigmaV, 5.0 * units::um);
  EXPECT_LT(pixel.center.z(), 0.0);
}

TEST(LayoutModules, SensorsLieNearTheNavigationSurfaces) {
  // The sensors of a layer lie within a few mm of its cylinder or disk
  // (staggering 2.5-5.5 mm, disk modules +-3 mm and the sensor 1.85 mm
  // off the module centre, the edges of flat sensors): at most 6 mm.
  // Exception: the CLICdet vertex-endcap spiral, whose 8 petals span 41 mm
  // in z around the layer's mean z (detectors.md 1.3).
  for (const Geometry* g : {&clicdet(), &cld()}) {
    for (std::uint32_t l = 0; l < g->detector.layers().size(); ++l) {
      const std::string& name = g->detector.layers()[l].name;
      const bool spiral = g == &clicdet() && name.starts_with("VXD_E_");
      EXPECT_LT(g->layout.shellHalfThickness(l), spiral ? 22.0 * mm : 6.0 * mm)
          << g->detector.name() << " " << name;
      EXPECT_GT(g->layout.shellHalfThickness(l), 0.0) << name;
    }
  }
}

/// Layer crossings of straight tracks: how many, how many without a sensor
/// and how many with two.
struct Coverage {
  std::size_t crossings = 0;
  std::size_t misses = 0;
  std::size_t doubles = 0;
  double missFraction() const {
    return static_cast<double>(misses) / static_cast<double>(crossings);
  }
  double doubleFraction() const {
    return static_cast<double>(doubles) / static_cast<double>(crossings);
  }
};

/// Straight tracks (1 TeV) from the origin through random (phi, eta),
/// crossing the barrel layers (or the disks) away from their edges: the
/// sensors each crosses, per layer name.
std::map<std::string, Coverage> straightTrackCoverage(const Geometry& g,
                                                      bool disks,
                                                      std::uint64_t seed) {
  RandomEngine rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::map<std::string, Coverage> coverage;
  std::vector<std::uint32_t> scratch;
  std::vector<ModuleCrossing> found;
  const double pt = 1000.0 * units::GeV;
  for (int trial = 0; trial < 6000; ++trial) {
    const double phi = kPi * (2.0 * uniform(rng) - 1.0);
    const double eta = (disks ? 3.0 : 1.6) * (2.0 * uniform(rng) - 1.0);
    const Helix helix(
        Vector3::Zero(),
        Vector3(pt * std::cos(phi), pt * std::sin(phi), pt * std::sinh(eta)),
        trial % 2 == 0 ? 1.0 : -1.0, g.detector.bz());
    for (std::uint32_t l = 0; l < g.detector.layers().size(); ++l) {
      const SensitiveLayer& layer = g.detector.layers()[l];
      if (layer.isDisk() != disks) {
        continue;
      }
      // Away from the edges: flat and staggered sensors move the edge of
      // the covered area by a few per cent (the spiral petals by 12 %).
      const double sLayer =
          layer.isDisk()
              ? helix.nextDiskCrossing(layer.z(), 1.25 * layer.rMin,
                                       0.85 * layer.rMax, 0.0, 1e9)
              : helix.nextCylinderCrossing(layer.r, 0.9 * layer.zMin,
                                           0.9 * layer.zMax, 0.0, 1e9);
      if (!(sLayer < 1e9)) {
        continue;
      }
      found.clear();
      findModuleCrossings(helix, sLayer, 1e-4, l, g.layout, scratch, found);
      EXPECT_LE(found.size(), 2u) << layer.name;
      Coverage& c = coverage[layer.name];
      c.crossings += 1;
      c.misses += found.empty() ? 1 : 0;
      c.doubles += found.size() >= 2 ? 1 : 0;
    }
  }
  for (const auto& [name, c] : coverage) {
    EXPECT_GT(c.crossings, 200u) << name;
  }
  return coverage;
}

/// The outer sensor of a vertex double layer (VXD_B_L1, L3, L5): same stave
/// width and offset as the inner one 1-2 mm further out, so its staves
/// leave gaps of 0.5-4 % of the azimuth (detectors.md 1.2 and 2.2; e.g.
/// CLICdet L1: 16 x (atan(8.5 / 33.215) + atan(4.5 / 33.215)) = 353 deg).
/// The inner sensor of the same double layer covers them.
bool outerVertexSublayer(const std::string& name) {
  return name == "VXD_B_L1" || name == "VXD_B_L3" || name == "VXD_B_L5";
}

TEST(LayoutModules, StraightTracksFindNoGapInTheBarrels) {
  for (const Geometry* g : {&clicdet(), &cld()}) {
    for (const auto& [name, c] : straightTrackCoverage(*g, false, 3)) {
      // Staves and modules overlap in phi (e.g. IT_B_L0: 28 x 30.1 mm on
      // a 2 pi x 127 mm circle) and abut in z: every crossing has a
      // sensor, some two.
      if (outerVertexSublayer(name)) {
        EXPECT_LT(c.missFraction(), 0.05) << g->detector.name() << " " << name;
      } else {
        EXPECT_EQ(c.misses, 0u) << g->detector.name() << " " << name;
        EXPECT_GT(c.doubleFraction(), 0.003)
            << g->detector.name() << " " << name;
      }
      EXPECT_LT(c.doubleFraction(), 0.2) << g->detector.name() << " " << name;
    }
  }
}

TEST(LayoutModules, StraightTracksFindNoGapInTheDisks) {
  for (const Geometry* g : {&clicdet(), &cld()}) {
    for (const auto& [name, c] : straightTrackCoverage(*g, true, 4)) {
      if (name.starts_with("VXD_E_")) {
        // The petals tile their sectors: one petal per straight track.
        EXPECT_EQ(c.misses, 0u) << g->detector.name() << " " << name;
        EXPECT_EQ(c.doubles, 0u) << g->detector.name() << " " << name;
        continue;
      }
      // Rectangular modules overlap in phi. Where a ring's modules are
      // narrower than 2 r_max sin(pi / n) (e.g. CLD OT_E ring 1: 125.3 <
      // 129.4 mm), small triangles at the ring boundary stay uncovered,
      // as in the file: below 1 % of the crossings.
      EXPECT_LT(c.missFraction(), 0.01) << g->detector.name() << " " << name;
      EXPECT_GT(c.doubleFraction(), 0.02) << g->detector.name() << " " << name;
      EXPECT_LT(c.doubleFraction(), 0.8) << g->detector.name() << " " << name;
    }
  }
}

TEST(LayoutModules, MirroredDisksAndSpiralPetals) {
  const Geometry& g = clicdet();
  const std::uint32_t pos = layerIndex(g.detector, "VXD_E_L0_pos");
  const std::uint32_t neg = layerIndex(g.detector, "VXD_E_L0_neg");
  const auto [pBegin, pEnd] = g.layout.layerRange(pos);
  const auto [nBegin, nEnd] = g.layout.layerRange(neg);
  ASSERT_EQ(pEnd - pBegin, 8u);
  ASSERT_EQ(nEnd - nBegin, 8u);
  for (std::uint32_t k = 0; k < 8; ++k) {
    const PlanarModule& p = g.layout.modules()[pBegin + k];
    const PlanarModule& n = g.layout.modules()[nBegin + k];
    // detectors.md 1.3: petal k at z = 158.975 + 5.913 k mm, mirrored
    // with the order reversed; azimuth 9 pi / 8 + k pi / 4.
    EXPECT_NEAR(p.center.z(), 158.975 * mm + k * 5.913 * mm, 0.01 * mm);
    EXPECT_NEAR(n.center.z(), -(158.975 * mm + (7 - k) * 5.913 * mm),
                0.01 * mm);
    EXPECT_NEAR(std::remainder(std::atan2(p.center.y(), p.center.x()) -
                                   (9.0 * kPi / 8.0 + k * kPi / 4.0),
                               2.0 * kPi),
                0.0, 1e-4);
    // The petal tiles its sector: its side edges lie on the radial lines
    // at +-pi/8 from its centre.
    const auto c = p.corners();
    const double centre = std::atan2(p.center.y(), p.center.x());
    for (const Vector3& corner : c) {
      EXPECT_NEAR(std::abs(std::remainder(
                      std::atan2(corner.y(), corner.x()) - centre, 2.0 * kPi)),
                  kPi / 8.0, 1e-9);
    }
  }
  // Tracker disks: modules alternate by +-3 mm around z, the sensor 1.85
  // mm away from the IP in disk 0 ("Out" stack).
  const std::uint32_t it = layerIndex(g.detector, "IT_E_L0_neg");
  const auto [begin, end] = g.layout.layerRange(it);
  EXPECT_NEAR(g.layout.modules()[begin].center.z(), -(524.0 + 3.0 + 1.8515),
              1e-9);
  EXPECT_NEAR(g.layout.modules()[begin + 1].center.z(), -(524.0 - 3.0 + 1.8515),
              1e-9);
  EXPECT_GT(end, begin + 1);
}

/// The CLICdet layout text with `edit` applied to its JSON.
std::string edited(const std::function<void(json&)>& edit) {
  json doc = json::parse(clicdet().text);
  edit(doc);
  return doc.dump();
}

std::string errorOf(const std::string& text, const Detector& detector) {
  return test::inputErrorOf(
      [&] { buildLayoutModules(text, detector, "layout.json"); });
}

TEST(LayoutModules, BadFilesGiveOneLineErrorsNamingTheKey) {
  const Detector& det = clicdet().detector;
  EXPECT_EQ(errorOf(edited([](json& d) {
                      d["barrel_layers"][6].erase("module_size_mm");
                    }),
                    det),
            "layout.json: key 'barrel_layers[6].module_size_mm': missing");
  EXPECT_EQ(errorOf(edited([](json& d) {
                      d["barrel_layers"][6]["module_size_mm"][0] = -30.1;
                    }),
                    det),
            "layout.json: key 'barrel_layers[6].module_size_mm': sizes must "
            "be positive");
  EXPECT_EQ(
      errorOf(
          edited([](json& d) { d["barrel_layers"][0]["stave_width_mm"] = 0; }),
          det),
      "layout.json: key 'barrel_layers[0].stave_width_mm': must be positive");
  EXPECT_EQ(errorOf(edited([](json& d) {
                      d["endcap_disks"][7]["rings"][1]["n_modules"] = -24;
                    }),
                    det),
            "layout.json: key 'endcap_disks[7].rings[1].n_modules': expected a "
            "whole number between 3 and 100000");
  EXPECT_EQ(errorOf(edited([](json& d) {
                      d["endcap_disks"][0]["z_petals_mm"][3] = "x";
                    }),
                    det),
            "layout.json: key 'endcap_disks[0].z_petals_mm[3]': expected a "
            "finite number");
  EXPECT_EQ(errorOf(edited([](json& d) {
                      d["endcap_disks"][7]["module_X0"] = -0.01;
                    }),
                    det),
            "layout.json: key 'endcap_disks[7].module_X0': must not be "
            "negative");
  EXPECT_EQ(
      errorOf(edited([](json& d) { d["barrel_layers"][1]["layer_id"] = 0; }),
              det),
      "layout.json: key 'barrel_layers[1].layer_id': layer VXD_B_L0 is "
      "given twice");
  EXPECT_EQ(errorOf(edited([](json& d) {
                      d["barrel_layers"][2]["subdetector"] = "Muon";
                    }),
                    det),
            "layout.json: key 'barrel_layers[2].subdetector': 'Muon' is not a "
            "barrel subdetector of detector CLICdet");
  EXPECT_EQ(errorOf("{\"barrel_layers\": [", det)
                .rfind("layout.json: invalid JSON: ", 0),
            0u);
  EXPECT_EQ(errorOf("[]", det), "layout.json: expected a JSON object");
  // The CLICdet file on the CLD detector: IT_B_L1 is at 340 mm, not 400.
  const std::string wrong = errorOf(clicdet().text, cld().detector);
  EXPECT_NE(wrong.find("key 'barrel_layers["), std::string::npos) << wrong;
  EXPECT_NE(wrong.find("detector CLD"), std::string::npos) << wrong;
}

}  // namespace
}  // namespace conftrack

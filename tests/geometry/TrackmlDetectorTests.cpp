/// @file TrackmlDetectorTests.cpp
/// The TrackML module table to conftrack detector conversion, on a small
/// hand-made table, and the shipped detectors/trackml.toml.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "InputErrorOf.hpp"

namespace conftrack {
namespace {

using units::mm;
using units::um;

constexpr double kPi = std::numbers::pi;
const char* kHeader =
    "volume_id,layer_id,module_id,cx,cy,cz,rot_xu,rot_xv,rot_xw,rot_yu,rot_"
    "yv,rot_yw,rot_zu,rot_zv,rot_zw,module_t,module_minhu,module_maxhu,"
    "module_hv,pitch_u,pitch_v\n";

void row(std::ostringstream& o, int volume, int layer, int module,
         const Vector3& c, const Matrix3& r, double t, double minHu,
         double maxHu, double hv, double pu, double pv) {
  o << volume << ',' << layer << ',' << module << ',' << c.x() << ',' << c.y()
    << ',' << c.z();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      o << ',' << r(i, j);
    }
  }
  o << ',' << t << ',' << minHu << ',' << maxHu << ',' << hv << ',' << pu << ','
    << pv << '\n';
}

/// A small TrackML-like table: pixel barrel volume 8 (one layer at r = 50,
/// 8 phi x 2 z modules) and pixel endcaps 7 / 9 (two disks per side at
/// |z| = 200 and 300, 6 modules at r = 60). Module ids count from 1 as in
/// TrackML; endcap layer ids increase with z on both sides.
std::string smallTable() {
  std::ostringstream o;
  o.precision(17);
  o << kHeader;
  int id = 1;
  for (double z : {-30.0, 30.0}) {
    for (int k = 0; k < 8; ++k) {
      const double phi = -kPi + (k + 0.5) * kPi / 4.0;
      const Vector3 c(50.0 * std::cos(phi), 50.0 * std::sin(phi), z);
      Matrix3 r;
      // u tangential, v = z, w radial.
      r.col(0) = Vector3(-std::sin(phi), std::cos(phi), 0.0);
      r.col(1) = Vector3::UnitZ();
      r.col(2) = Vector3(std::cos(phi), std::sin(phi), 0.0);
      row(o, 8, 2, id++, c, r, 0.15, 21.0, 21.0, 32.0, 0.05, 0.05625);
    }
  }
  for (auto [volume, layer, z] :
       {std::tuple{7, 2, -300.0}, std::tuple{7, 4, -200.0},
        std::tuple{9, 2, 200.0}, std::tuple{9, 4, 300.0}}) {
    for (int k = 0; k < 6; ++k) {
      const double phi = -kPi + (k + 0.5) * kPi / 3.0;
      const Vector3 c(60.0 * std::cos(phi), 60.0 * std::sin(phi), z);
      Matrix3 r;
      // u tangential, v radial (outwards), w along z.
      r.col(0) = Vector3(-std::sin(phi), std::cos(phi), 0.0);
      r.col(1) = Vector3(std::cos(phi), std::sin(phi), 0.0);
      r.col(2) = Vector3::UnitZ();
      row(o, volume, layer, k + 1, c, r, 0.15, 20.0, 30.0, 25.0, 0.05, 0.05625);
    }
  }
  return o.str();
}

std::vector<TrackmlModule> smallModules() {
  return parseTrackmlModules(smallTable(), "small.csv");
}

std::string errorOf(const std::string& text) {
  return test::inputErrorOf([&] { parseTrackmlModules(text, "bad.csv"); });
}

const SensitiveLayer& layerNamed(const Detector& det, const std::string& n) {
  for (const SensitiveLayer& l : det.layers()) {
    if (l.name == n) {
      return l;
    }
  }
  throw std::runtime_error("no layer " + n);
}

TEST(TrackmlDetector, ParsesModules) {
  std::vector<TrackmlModule> modules = smallModules();
  ASSERT_EQ(modules.size(), 16u + 24u);
  const TrackmlModule& m = modules.front();
  EXPECT_EQ(m.volume, 8u);
  EXPECT_EQ(m.layer, 2u);
  EXPECT_EQ(m.module, 1u);
  EXPECT_NEAR(m.center.head<2>().norm(), 50.0 * mm, 1e-9);
  EXPECT_NEAR(m.halfV, 32.0 * mm, 1e-12);
  // The corners lie at (+-hu, +-hv) of the local frame (rotation columns).
  const Vector3 corner = m.rotation.transpose() * (m.corners()[2] - m.center);
  EXPECT_NEAR(corner.x(), 21.0, 1e-9);
  EXPECT_NEAR(corner.y(), 32.0, 1e-9);
  EXPECT_NEAR(corner.z(), 0.0, 1e-9);
  // Trapezoid: narrow at v = -hv.
  const TrackmlModule& disk = modules.back();
  EXPECT_NEAR(disk.minHalfU, 20.0, 1e-12);
  EXPECT_NEAR(disk.maxHalfU, 30.0, 1e-12);
}

TEST(TrackmlDetector, Summaries) {
  std::vector<TrackmlLayerSummary> s = summarizeTrackmlLayers(smallModules());
  ASSERT_EQ(s.size(), 5u);  // (7,2) (7,4) (8,2) (9,2) (9,4)
  const TrackmlLayerSummary& barrel = s[2];
  EXPECT_EQ(barrel.volume, 8u);
  EXPECT_TRUE(barrel.barrel);
  EXPECT_NEAR(barrel.position, 50.0, 1e-9);
  EXPECT_NEAR(barrel.halfZ, 62.0, 1e-9);
  EXPECT_EQ(barrel.nPhi, 8u);
  EXPECT_EQ(barrel.nRows, 2u);
  EXPECT_EQ(barrel.maxModuleId, 16u);
  // 16 modules of 42 x 64 mm^2 on a cylinder of r 50, length 124.
  EXPECT_NEAR(barrel.coverage, 16 * 42.0 * 64.0 / (2 * kPi * 50.0 * 124.0),
              1e-9);
  const TrackmlLayerSummary& disk = s[0];
  EXPECT_EQ(disk.volume, 7u);
  EXPECT_EQ(disk.layer, 2u);
  EXPECT_FALSE(disk.barrel);
  EXPECT_NEAR(disk.meanZ, -300.0, 1e-9);
  EXPECT_NEAR(disk.position, 300.0, 1e-9);
  EXPECT_NEAR(disk.rMin, 35.0, 1e-9);  // inner edge 60 - 25
  EXPECT_NEAR(disk.rMax, std::hypot(85.0, 30.0), 1e-9);
  EXPECT_EQ(disk.nPhi, 6u);
  EXPECT_EQ(disk.nRows, 1u);
}

TEST(TrackmlDetector, TomlLoadsWithIdsAndResolutions) {
  std::string toml = buildTrackmlDetectorToml(smallModules());
  Detector det = parseDetector(toml, "small.toml");
  EXPECT_EQ(det.name(), "TrackML");
  EXPECT_DOUBLE_EQ(det.bz(), 2.0);
  ASSERT_EQ(det.subdetectors().size(), 2u);
  EXPECT_EQ(det.subdetectors()[0].name, "PixelBarrel");
  EXPECT_EQ(det.subdetectors()[1].name, "PixelEndcap");
  const SensitiveLayer& barrel = layerNamed(det, "PXB_L0");
  EXPECT_NEAR(barrel.r, 50.0 * mm, 1e-9);
  EXPECT_NEAR(barrel.zMax, 62.0 * mm, 1e-9);
  EXPECT_NEAR(barrel.sigmaU, 50.0 * um / std::sqrt(12.0), 0.01 * um);
  EXPECT_NEAR(barrel.sigmaV, 56.25 * um / std::sqrt(12.0), 0.01 * um);
  // Real ids 1..16 fit: 8 x 3 > 16.
  EXPECT_EQ(barrel.nPhiModules, 8u);
  EXPECT_EQ(barrel.nZModules, 3u);
  EXPECT_EQ(barrel.trackmlVolume, 8u);
  EXPECT_EQ(barrel.trackmlLayer, 2u);
  const SensitiveLayer& disk = layerNamed(det, "PXE_D0_pos");
  EXPECT_NEAR(disk.z(), 200.0 * mm, 1e-9);
  EXPECT_EQ(disk.trackmlVolume, 9u);
  EXPECT_EQ(disk.trackmlLayer, 2u);
  EXPECT_EQ(disk.nPhiModules * disk.nZModules, 12u);
  // Material: coverage x 0.15 / 93.65 plus 1 mm / 95.7 mm support.
  const double coverage = 16 * 42.0 * 64.0 / (2 * kPi * 50.0 * 124.0);
  EXPECT_NEAR(barrel.thicknessX0, coverage * 0.15 / 93.65 + 1.0 / 95.7, 1e-6);
  // Only the beam pipe fits this small envelope.
  EXPECT_EQ(det.passives().size(), 1u);
  EXPECT_GT(det.envelopeR(), std::hypot(85.0, 30.0));
  EXPECT_GT(det.envelopeZ(), 300.0);
  // Without perSideLayerIds the file has no trackml_layer_neg.
  TrackmlDetectorOptions plain;
  plain.perSideLayerIds = false;
  EXPECT_EQ(
      buildTrackmlDetectorToml(smallModules(), plain).find("trackml_layer_neg"),
      std::string::npos);
  TrackmlDetectorOptions perSide;
  perSide.perSideLayerIds = true;
  EXPECT_NE(buildTrackmlDetectorToml(smallModules(), perSide)
                .find("trackml_layer_neg = 4"),
            std::string::npos);
}

TEST(TrackmlDetector, BuiltDetectorMirrorsNegativeEndcapIds) {
  Detector det = buildTrackmlDetector(smallModules());
  // TrackML: (7, 2) is the disk at z = -300, (7, 4) at -200, (9, 2) at 200.
  auto zOf = [&](std::uint32_t v, std::uint32_t l) {
    return det.layers()[det.findTrackmlLayer(v, l).value()].z();
  };
  EXPECT_NEAR(zOf(7, 2), -300.0, 1e-9);
  EXPECT_NEAR(zOf(7, 4), -200.0, 1e-9);
  EXPECT_NEAR(zOf(9, 2), 200.0, 1e-9);
  EXPECT_NEAR(zOf(9, 4), 300.0, 1e-9);
}

TEST(TrackmlDetector, ModuleLayoutFindsEverySensorAtItsCentre) {
  const std::vector<TrackmlModule> modules = smallModules();
  const Detector det = buildTrackmlDetector(modules);
  const ModuleLayout layout = buildTrackmlModuleLayout(modules, det);
  ASSERT_EQ(layout.modules().size(), modules.size());
  std::vector<std::uint32_t> found;
  for (const TrackmlModule& m : modules) {
    const std::uint32_t layer = det.findTrackmlLayer(m.volume, m.layer).value();
    const PlanarModule* sensor = layout.find(layer, m.module);
    ASSERT_NE(sensor, nullptr) << m.volume << " " << m.layer << " " << m.module;
    EXPECT_TRUE(sensor->center.isApprox(m.center));
    EXPECT_NEAR(sensor->sigmaU, m.pitchU / std::sqrt(12.0), 1e-12);
    EXPECT_NEAR(sensor->thicknessX0, m.thickness / 93.65, 1e-12);
    // The grid returns it for its own centre, without any margin.
    found.clear();
    const double v =
        layout.layerIsDisk(layer) ? m.center.head<2>().norm() : m.center.z();
    layout.candidates(layer, std::atan2(m.center.y(), m.center.x()), v, 0.0,
                      0.0, found);
    EXPECT_NE(
        std::find(found.begin(), found.end(),
                  static_cast<std::uint32_t>(sensor - &layout.modules()[0])),
        found.end());
  }
  EXPECT_NEAR(layout.supportX0(0), 1.0 / 95.7, 1e-12);
  EXPECT_EQ(layout.find(0, 999999), nullptr);
}

TEST(TrackmlDetector, ParseErrorsNameFileAndLine) {
  // A barrel module at (50, 0, 0): u = y, v = z, w = x.
  auto line = [](const std::string& thickness, int module = 1) {
    return "8,2," + std::to_string(module) + ",50,0,0,0,0,1,1,0,0,0,1,0," +
           thickness + ",21,21,32,0.05,0.05625\n";
  };
  const std::string header = kHeader;
  EXPECT_EQ(errorOf(header + line("0.15")), "(accepted)");
  EXPECT_EQ(errorOf(""), "bad.csv: empty file (no header line)");
  EXPECT_EQ(errorOf("volume_id,layer_id\n"),
            "bad.csv:1: missing column 'module_id'");
  EXPECT_EQ(errorOf(header), "bad.csv: no modules (header line only)");
  EXPECT_EQ(errorOf(header + line("0.15") + "\n" + line("abc", 2)),
            "bad.csv:4: column 'module_t': 'abc' is not a number");
  EXPECT_EQ(errorOf(header + line("-0.1")),
            "bad.csv:2: column 'module_t': '-0.1' must be positive");
  EXPECT_EQ(errorOf(header + line("0.15") + line("0.15")),
            "bad.csv:3: duplicate module (volume_id, layer_id, module_id) = "
            "(8, 2, 1)");
  EXPECT_EQ(errorOf(header + "8,2,1,3\n"),
            "bad.csv:2: 4 fields, the header has 21");
  std::string skewed = line("0.15");
  skewed.replace(skewed.find("0,0,1,1,0,0"), 11, "0,0,2,1,0,0");
  EXPECT_EQ(errorOf(header + skewed),
            "bad.csv:2: the rotation matrix (rot_*) is not orthonormal");
}

TEST(TrackmlDetector, BuildErrors) {
  std::vector<TrackmlModule> modules = smallModules();
  TrackmlDetectorOptions options;
  options.source = "x.csv";
  std::vector<TrackmlModule> unknown = modules;
  unknown[0].volume = 5;
  EXPECT_THROW(
      {
        try {
          buildTrackmlDetectorToml(unknown, options);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(),
                       "x.csv: volume_id 5 is not a TrackML volume (7, 8, 9, "
                       "12, 13, 14, 16, 17, 18)");
          throw;
        }
      },
      InputError);
  // One side moved by 5 mm: the sides no longer mirror each other.
  std::vector<TrackmlModule> shifted = modules;
  for (TrackmlModule& m : shifted) {
    if (m.volume == 9 && m.layer == 2) {
      m.center.z() += 5.0;
    }
  }
  EXPECT_THROW(buildTrackmlDetectorToml(shifted, options), InputError);
}

// The shipped file (generated from the Kaggle detectors.csv).
TEST(TrackmlDetector, ShippedFile) {
  Detector det = loadDetector("trackml");
  EXPECT_EQ(det.name(), "TrackML");
  EXPECT_DOUBLE_EQ(det.bz(), 2.0);
  auto count = [&](const char* name) {
    return det.subdetectors()[det.findSubdetector(name).value()].layers.size();
  };
  EXPECT_EQ(count("PixelBarrel"), 4u);
  EXPECT_EQ(count("PixelEndcap"), 14u);
  EXPECT_EQ(count("ShortStripBarrel"), 4u);
  EXPECT_EQ(count("ShortStripEndcap"), 12u);
  EXPECT_EQ(count("LongStripBarrel"), 2u);
  EXPECT_EQ(count("LongStripEndcap"), 12u);
  EXPECT_EQ(det.numLayers(), 48u);
  // Radii of the TrackML barrel layers and the real module counts (ids
  // 1..N must stay below n_phi x n_z).
  struct Expected {
    std::uint32_t volume, layer;
    double r;
    std::uint32_t modules;
  };
  for (const Expected& e :
       {Expected{8, 2, 32, 224}, Expected{8, 8, 172, 1092},
        Expected{13, 2, 260, 840}, Expected{13, 8, 660, 2142},
        Expected{17, 2, 820, 2520}, Expected{17, 4, 1020, 3192}}) {
    const SensitiveLayer& l =
        det.layers()[det.findTrackmlLayer(e.volume, e.layer).value()];
    EXPECT_NEAR(l.r, e.r, 0.1) << l.name;
    EXPECT_GT(l.nPhiModules * l.nZModules, e.modules) << l.name;
  }
  const SensitiveLayer& pix = layerNamed(det, "PXB_L0");
  EXPECT_NEAR(pix.sigmaU, 50 * um / std::sqrt(12.0), 0.01 * um);
  EXPECT_NEAR(pix.zMax, 491.0, 1e-9);
  const SensitiveLayer& ls = layerNamed(det, "LSB_L0");
  EXPECT_NEAR(ls.sigmaV, 10.8 * mm / std::sqrt(12.0), 0.01 * um);
  // Positive endcap sides carry the TrackML layer ids.
  EXPECT_NEAR(det.layers()[det.findTrackmlLayer(9, 2).value()].z(), 600.0,
              1e-9);
  EXPECT_NEAR(det.layers()[det.findTrackmlLayer(14, 12).value()].z(), 2949.0,
              0.1);
  EXPECT_NEAR(det.layers()[det.findTrackmlLayer(18, 2).value()].z(), 1220.0,
              0.1);
  for (const SensitiveLayer& l : det.layers()) {
    EXPECT_GT(l.thicknessX0, 0.01) << l.name;  // >= the 1 mm support
    EXPECT_LT(l.thicknessX0, 0.02) << l.name;
  }
}

}  // namespace
}  // namespace conftrack

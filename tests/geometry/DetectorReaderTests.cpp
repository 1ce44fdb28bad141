#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"

#include <gtest/gtest.h>

#include <string>

#include "InputErrorOf.hpp"

namespace conftrack {
namespace {

using units::mm;
using units::um;

/// A valid minimal detector; tests break one thing at a time.
const std::string kMinimal = R"([detector]
name = "Mini"
bz_T = 2.0
envelope_r_mm = 1000.0
envelope_z_mm = 1000.0

[[subdetector]]
name = "Barrel"
kind = "barrel"

  [[subdetector.layer]]
  name = "B0"
  r_mm = 50.0
  half_z_mm = 200.0
  x_over_x0 = 0.01
  sigma_rphi_um = 5.0
  sigma_z_um = 5.0

  [[subdetector.layer]]
  name = "B1"
  r_mm = 100.0
  half_z_mm = 200.0
  x_over_x0 = 0.01
  sigma_rphi_um = 5.0
  sigma_z_um = 5.0

[[subdetector]]
name = "Endcap"
kind = "endcap"

  [[subdetector.layer]]
  name = "E0"
  z_mm = 300.0
  r_min_mm = 20.0
  r_max_mm = 150.0
  x_over_x0 = 0.01
  sigma_rphi_um = 5.0
  sigma_r_um = 50.0

[[passive.cylinder]]
name = "Pipe"
r_mm = 20.0
z_max_mm = 500.0
x_over_x0 = 0.002
)";

std::string replace(std::string text, const std::string& from,
                    const std::string& to) {
  auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

/// Parses and returns the error message ("" if it parsed).
std::string errorOf(const std::string& text) {
  return test::inputErrorOf([&] { parseDetector(text, "test.toml"); });
}

TEST(DetectorReader, MinimalDetector) {
  Detector det = parseDetector(kMinimal, "test.toml");
  EXPECT_EQ(det.name(), "Mini");
  EXPECT_DOUBLE_EQ(det.bz(), 2.0);
  ASSERT_EQ(det.subdetectors().size(), 2u);
  // Two barrel layers plus one disk per side.
  ASSERT_EQ(det.layers().size(), 4u);
  const SensitiveLayer& neg = det.layers()[2];
  const SensitiveLayer& pos = det.layers()[3];
  EXPECT_EQ(neg.name, "E0_neg");
  EXPECT_EQ(neg.id.side, Side::eNegative);
  EXPECT_DOUBLE_EQ(neg.z(), -300.0 * mm);
  EXPECT_EQ(pos.id.side, Side::ePositive);
  EXPECT_DOUBLE_EQ(pos.sigmaV, 50.0 * um);
  EXPECT_EQ(det.subdetectors()[1].nLayers, 1);
  // TrackML volumes are assigned consecutively: barrel 1, endcap 2 / 3.
  EXPECT_EQ(det.layers()[0].trackmlVolume, 1u);
  EXPECT_EQ(neg.trackmlVolume, 2u);
  EXPECT_EQ(pos.trackmlVolume, 3u);
  EXPECT_EQ(det.findTrackmlLayer(3, 2).value(), 3u);
  EXPECT_EQ(det.findLayer(pos.id).value(), 3u);
  EXPECT_FALSE(det.findTrackmlLayer(9, 2).has_value());
  EXPECT_EQ(det.findSubdetector("Endcap").value(), 1);
  ASSERT_EQ(det.passives().size(), 1u);
  EXPECT_DOUBLE_EQ(det.passives()[0].zMin, -500.0 * mm);
}

TEST(DetectorReader, SolenoidKeysSelectASolenoidField) {
  EXPECT_TRUE(parseDetector(kMinimal, "test.toml").field().isUniform());
  const Detector solenoid =
      parseDetector(replace(kMinimal, "bz_T = 2.0\n",
                            "bz_T = 2.0\nsolenoid_radius_mm = 2770.0\n"
                            "solenoid_half_length_mm = 2930.0\n"),
                    "test.toml");
  EXPECT_FALSE(solenoid.field().isUniform());
  EXPECT_DOUBLE_EQ(solenoid.bz(), 2.0);
  EXPECT_DOUBLE_EQ(solenoid.field().config().solenoidRadius, 2770.0 * mm);
  EXPECT_DOUBLE_EQ(solenoid.field().config().solenoidHalfLength, 2930.0 * mm);
  // Half a solenoid names the missing key; a negative radius its own.
  const std::string half = errorOf(replace(
      kMinimal, "bz_T = 2.0\n", "bz_T = 2.0\nsolenoid_radius_mm = 2770.0\n"));
  EXPECT_NE(half.find("'detector.solenoid_half_length_mm'"), std::string::npos)
      << half;
  const std::string negative =
      errorOf(replace(kMinimal, "bz_T = 2.0\n",
                      "bz_T = 2.0\nsolenoid_radius_mm = -1.0\n"
                      "solenoid_half_length_mm = 2930.0\n"));
  EXPECT_NE(negative.find("'detector.solenoid_radius_mm'"), std::string::npos)
      << negative;
}

TEST(DetectorReader, SyntaxErrorNamesLine) {
  std::string msg = errorOf(replace(kMinimal, "bz_T = 2.0", "bz_T = = 2"));
  EXPECT_NE(msg.find("test.toml:3"), std::string::npos) << msg;
}

TEST(DetectorReader, UnknownKey) {
  std::string msg = errorOf(
      replace(kMinimal, "  r_mm = 100.0", "  r_mm = 100.0\n  colour = 3"));
  EXPECT_NE(msg.find("test.toml:22"), std::string::npos) << msg;
  EXPECT_NE(msg.find("colour"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
}

TEST(DetectorReader, MissingKey) {
  std::string msg = errorOf(
      replace(kMinimal,
              "  half_z_mm = 200.0\n  x_over_x0 = 0.01\n  sigma_rphi_um = "
              "5.0\n  sigma_z_um = 5.0\n\n[[subdetector]]",
              "  x_over_x0 = 0.01\n  sigma_rphi_um = 5.0\n  sigma_z_um = "
              "5.0\n\n[[subdetector]]"));
  EXPECT_NE(msg.find("half_z_mm"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
  EXPECT_NE(msg.find("test.toml:19"), std::string::npos) << msg;
}

TEST(DetectorReader, NegativeSize) {
  std::string msg = errorOf(replace(kMinimal, "r_mm = 50.0", "r_mm = -50.0"));
  EXPECT_NE(msg.find("test.toml:13"), std::string::npos) << msg;
  EXPECT_NE(msg.find("subdetector[0].layer[0].r_mm"), std::string::npos) << msg;
}

TEST(DetectorReader, NonFiniteSize) {
  EXPECT_NE(
      errorOf(replace(kMinimal, "r_mm = 50.0", "r_mm = nan")).find("finite"),
      std::string::npos);
  EXPECT_NE(errorOf(replace(kMinimal, "half_z_mm = 200.0", "half_z_mm = inf"))
                .find("half_z_mm"),
            std::string::npos);
}

TEST(DetectorReader, WrongType) {
  std::string msg =
      errorOf(replace(kMinimal, "sigma_r_um = 50.0", "sigma_r_um = \"50\""));
  EXPECT_NE(msg.find("expected a number"), std::string::npos) << msg;
}

TEST(DetectorReader, DuplicateName) {
  std::string msg =
      errorOf(replace(kMinimal, "name = \"B1\"", "name = \"B0\""));
  EXPECT_NE(msg.find("duplicate name 'B0'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("test.toml:20"), std::string::npos) << msg;
}

TEST(DetectorReader, OverlappingLayers) {
  std::string msg = errorOf(replace(kMinimal, "r_mm = 100.0", "r_mm = 50.05"));
  EXPECT_NE(msg.find("overlaps layer 'B0'"), std::string::npos) << msg;
  // A disk cutting through a barrel cylinder.
  msg = errorOf(replace(kMinimal, "z_mm = 300.0", "z_mm = 150.0"));
  EXPECT_NE(msg.find("overlaps"), std::string::npos) << msg;
}

TEST(DetectorReader, RangeOrder) {
  std::string msg =
      errorOf(replace(kMinimal, "r_min_mm = 20.0", "r_min_mm = 200.0"));
  EXPECT_NE(msg.find("r_max_mm"), std::string::npos) << msg;
}

TEST(DetectorReader, OutsideEnvelope) {
  std::string msg = errorOf(replace(kMinimal, "r_mm = 100.0", "r_mm = 1100.0"));
  EXPECT_NE(msg.find("envelope"), std::string::npos) << msg;
}

TEST(DetectorReader, SharedTrackmlVolume) {
  // Two barrels in one TrackML volume: the hits of the second would be
  // read onto the layers of the first.
  const std::string second = R"(
[[subdetector]]
name = "Outer"
kind = "barrel"
trackml_volume = 1

  [[subdetector.layer]]
  name = "O0"
  r_mm = 500.0
  half_z_mm = 600.0
  x_over_x0 = 0.01
  sigma_rphi_um = 5.0
  sigma_z_um = 5.0
)";
  std::string text = kMinimal;
  text.insert(text.find("[[passive.cylinder]]"), second + "\n");
  std::string msg = errorOf(text);
  EXPECT_NE(msg.find("test.toml:44: key 'subdetector[2].trackml_volume': "
                     "TrackML volume 1 is already that of Barrel"),
            std::string::npos)
      << msg;
  // The endcap's default volumes (2, 3) taken by an explicit barrel volume.
  msg = errorOf(replace(text, "trackml_volume = 1", "trackml_volume = 3"));
  EXPECT_NE(msg.find("TrackML volume 3 is already that of Endcap (+z)"),
            std::string::npos)
      << msg;
  EXPECT_EQ(errorOf(replace(text, "trackml_volume = 1", "trackml_volume = 4")),
            "(accepted)");
}

TEST(DetectorReader, DuplicateTrackmlLayer) {
  std::string msg = errorOf(replace(kMinimal, "  name = \"B1\"",
                                    "  name = \"B1\"\n  trackml_layer = 2"));
  EXPECT_NE(msg.find("key 'subdetector[0].layer[1].trackml_layer': TrackML "
                     "(volume, layer) = (1, 2) is already that of layer 'B0'"),
            std::string::npos)
      << msg;
}

TEST(DetectorReader, BadKind) {
  std::string msg =
      errorOf(replace(kMinimal, "kind = \"endcap\"", "kind = \"disk\""));
  EXPECT_NE(msg.find("kind"), std::string::npos) << msg;
}

TEST(DetectorReader, MissingFile) {
  EXPECT_THROW(readDetector("/nonexistent/detector.toml"), InputError);
  EXPECT_THROW(loadDetector("no-such-detector"), InputError);
}

TEST(DetectorReader, ModulesAndLocalAxes) {
  Detector det = parseDetector(kMinimal, "test.toml");
  SensitiveLayer layer = det.layers()[0];
  layer.nPhiModules = 4;
  layer.nZModules = 2;
  // phi in [0, pi/2) is the third quarter of [-pi, pi); z > 0 second slice.
  Vector3 p(35.0, 35.0, 10.0);
  EXPECT_EQ(layer.moduleAt(p), 1u * 4 + 2);
  Vector3 u;
  Vector3 v;
  layer.localAxes(p, u, v);
  EXPECT_NEAR(u.dot(Vector3(p.x(), p.y(), 0.0)), 0.0, 1e-12);
  EXPECT_NEAR(u.norm(), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(v.z(), 1.0);
  det.layers()[3].localAxes(p, u, v);
  EXPECT_NEAR(v.x(), std::sqrt(0.5), 1e-12);
  EXPECT_DOUBLE_EQ(v.z(), 0.0);
}

}  // namespace
}  // namespace conftrack

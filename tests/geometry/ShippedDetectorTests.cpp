#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"

#include <gtest/gtest.h>

namespace conftrack {
namespace {

using units::mm;
using units::um;

const SensitiveLayer& layerNamed(const Detector& det, const std::string& n) {
  for (const SensitiveLayer& l : det.layers()) {
    if (l.name == n) {
      return l;
    }
  }
  throw std::runtime_error("no layer " + n);
}

std::size_t countLayers(const Detector& det, const std::string& sub) {
  return det.subdetectors()[det.findSubdetector(sub).value()].layers.size();
}

// Numbers from ../shared/reference/detectors.md, section 1 (CLIC_o3_v14).
TEST(ShippedDetectors, Clicdet) {
  Detector det = loadDetector("clicdet");
  EXPECT_EQ(det.model(), "CLIC_o3_v14");
  EXPECT_DOUBLE_EQ(det.bz(), 4.0);
  EXPECT_EQ(countLayers(det, "VertexBarrel"), 6u);
  EXPECT_EQ(countLayers(det, "VertexEndcap"), 12u);
  EXPECT_EQ(countLayers(det, "InnerTrackerBarrel"), 3u);
  EXPECT_EQ(countLayers(det, "InnerTrackerEndcap"), 14u);
  EXPECT_EQ(countLayers(det, "OuterTrackerBarrel"), 3u);
  EXPECT_EQ(countLayers(det, "OuterTrackerEndcap"), 8u);
  EXPECT_NEAR(layerNamed(det, "VXD_B_L0").r, 31.165 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "VXD_B_L5").zMax, 130.0 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "VXD_B_L0").sigmaU, 3.0 * um, 1e-12);
  EXPECT_NEAR(layerNamed(det, "IT_B_L2").r, 553.9685 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "IT_B_L2").sigmaV, 90.0 * um, 1e-12);
  EXPECT_NEAR(layerNamed(det, "IT_E_L0_pos").sigmaV, 5.0 * um, 1e-12);
  EXPECT_NEAR(layerNamed(det, "IT_E_L0_neg").z(), -524.0 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "OT_B_L2").r, 1487.8515 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "OT_E_L3_pos").rMax, 1430.1 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "VXD_E_L0_pos").z(), 179.6706 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "IT_B_L0").thicknessX0, 0.01053, 1e-9);
  EXPECT_FALSE(det.passives().empty());
}

// detectors.md section 2 (CLD_o2_v05).
TEST(ShippedDetectors, Cld) {
  Detector det = loadDetector("cld");
  EXPECT_EQ(det.model(), "CLD_o2_v05");
  EXPECT_DOUBLE_EQ(det.bz(), 2.0);
  EXPECT_EQ(countLayers(det, "VertexBarrel"), 6u);
  EXPECT_EQ(countLayers(det, "InnerTrackerEndcap"), 14u);
  EXPECT_NEAR(layerNamed(det, "VXD_B_L0").r, 13.26 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "VXD_B_L0").thicknessX0, 0.003043, 1e-9);
  EXPECT_NEAR(layerNamed(det, "OT_B_L2").r, 2137.8515 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "VXD_E_L4_pos").rMin, 45.0 * mm, 1e-9);
  EXPECT_NEAR(layerNamed(det, "OT_E_L0_pos").rMax, 2080.0 * mm, 1e-9);
}

}  // namespace
}  // namespace conftrack

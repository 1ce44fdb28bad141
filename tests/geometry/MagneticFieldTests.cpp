// The tracker field (MagneticField): uniform, and the paraxial field of a
// finite solenoid against its textbook on-axis formula, Maxwell's
// equations (the detector-file keys that select it: DetectorReaderTests).

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/MagneticField.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace conftrack {
namespace {

using units::mm;
using units::T;

/// B_z on the axis of a thin solenoid sheet (radius a, half-length L),
/// written out: B0 (cos of the angles subtended by its two ends at z).
double onAxis(double z, double a, double half) {
  auto ends = [&](double at) {
    return (half - at) / std::hypot(half - at, a) +
           (half + at) / std::hypot(half + at, a);
  };
  return 2.0 * T * ends(z) / ends(0.0);
}

/// A long solenoid (the first fit to the TrackML events, before the
/// reconstruction followed the field).
const MagneticField kLongSolenoid({2.0 * T, 2770.0 * mm, 2930.0 * mm});

TEST(MagneticField, UniformIsAlongZEverywhere) {
  const MagneticField uniform({2.0 * T, 0.0, 0.0});
  EXPECT_TRUE(uniform.isUniform());
  const Vector3 b = uniform.at(Vector3(300.0, -200.0, 2500.0));
  EXPECT_EQ(b, Vector3(0.0, 0.0, 2.0 * T));
}

TEST(MagneticField, SolenoidOnAxisMatchesTheFiniteSheetFormula) {
  EXPECT_FALSE(kLongSolenoid.isUniform());
  for (const double z : {0.0, 600.0, 1500.0, 2500.0, 2930.0, 3500.0}) {
    const Vector3 b = kLongSolenoid.at(Vector3(0.0, 0.0, z));
    EXPECT_NEAR(b.z(), onAxis(z, 2770.0, 2930.0), 1e-12) << z;
    EXPECT_EQ(b.x(), 0.0);
    EXPECT_EQ(b.y(), 0.0);
  }
}

TEST(MagneticField, SolenoidIsMirrorSymmetricAndDivergesOutwardBeyondZero) {
  const Vector3 front = kLongSolenoid.at(Vector3(400.0, 300.0, 1800.0));
  const Vector3 back = kLongSolenoid.at(Vector3(400.0, 300.0, -1800.0));
  EXPECT_NEAR(front.z(), back.z(), 1e-12);
  EXPECT_NEAR(front.x(), -back.x(), 1e-12);
  EXPECT_GT(front.x(), 0.0);  // field lines open up towards the end
  EXPECT_GT(front.y(), 0.0);
  EXPECT_LT(front.z(), 2.0 * T);
}

TEST(MagneticField, SolenoidIsDivergenceFreeAndNearlyCurlFree) {
  // Inside the tracker (r <= 1 m, |z| <= 3 m): div B = 0 to rounding,
  // curl B = O(r^3 g'''') small against B0 / a.
  const double h = 0.01;
  for (const double r : {100.0, 500.0, 1000.0}) {
    for (const double z : {0.0, 1000.0, 2000.0, 2900.0}) {
      auto bz = [&](double rr, double zz) {
        return kLongSolenoid.at(Vector3(rr, 0.0, zz)).z();
      };
      auto br = [&](double rr, double zz) {
        return kLongSolenoid.at(Vector3(rr, 0.0, zz)).x();
      };
      const double curl = (br(r, z + h) - br(r, z - h)) / (2 * h) -
                          (bz(r + h, z) - bz(r - h, z)) / (2 * h);
      const double div =
          ((r + h) * br(r + h, z) - (r - h) * br(r - h, z)) / (2 * h * r) +
          (bz(r, z + h) - bz(r, z - h)) / (2 * h);
      EXPECT_NEAR(div, 0.0, 1e-7) << r << " " << z;
      EXPECT_LT(std::abs(curl) * 2770.0 / (2.0 * T), 0.02) << r << " " << z;
    }
  }
}

TEST(MagneticField, RefusesImpossibleSettings) {
  EXPECT_THROW(MagneticField({-1.0, 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(MagneticField({2.0, -5.0, 100.0}), std::invalid_argument);
  EXPECT_THROW(MagneticField({2.0, 1000.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(MagneticField({0.0, 1000.0, 100.0}), std::invalid_argument);
}

TEST(MagneticField, ShippedTrackmlDetectorHasTheFittedSolenoid) {
  const Detector trackml = loadDetector("trackml");
  EXPECT_FALSE(trackml.field().isUniform());
  EXPECT_DOUBLE_EQ(trackml.bz(), 2.0 * T);
  EXPECT_TRUE(loadDetector("clicdet").field().isUniform());
}

}  // namespace
}  // namespace conftrack

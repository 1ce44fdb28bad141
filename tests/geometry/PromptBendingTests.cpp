// The bending factor of tracks from the beam line in a non-uniform field
// (PromptBending): against a fine integration of the Lorentz force, the
// azimuth of a track at (r, z) is that of the central field's circle at
// radius g r.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/PromptBending.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "LorentzIntegration.hpp"

namespace conftrack {
namespace {

using units::mm;
using units::T;

/// A long solenoid (the first fit to the TrackML events, before the
/// reconstruction followed the field).
const MagneticField kLongSolenoid({2.0 * T, 2770.0 * mm, 2930.0 * mm});

TEST(PromptBending, IsOneInAUniformField) {
  const PromptBending bending(MagneticField({2.0 * T, 0.0, 0.0}), 1000.0,
                              3000.0);
  EXPECT_TRUE(bending.isUniform());
  EXPECT_EQ(bending.factor(500.0, 2500.0), 1.0);
}

TEST(PromptBending, RefusesAnEmptyEnvelope) {
  EXPECT_THROW(PromptBending(kLongSolenoid, 0.0, 3000.0),
               std::invalid_argument);
  EXPECT_THROW(PromptBending(kLongSolenoid, 1000.0, -1.0),
               std::invalid_argument);
}

TEST(PromptBending, TableFollowsTheIntegralAndWeakensTowardsTheEnds) {
  const PromptBending bending(kLongSolenoid, 1030.0, 3000.0);
  EXPECT_FALSE(bending.isUniform());
  // Between the nodes, within 1e-3 of the direct integral.
  for (double r : {33.0, 171.0, 505.0, 1011.0}) {
    for (double z : {-2917.0, -1203.0, 0.0, 611.0, 1777.0, 2949.0}) {
      EXPECT_NEAR(bending.factor(r, z),
                  PromptBending::integrate(kLongSolenoid, r, z), 1e-3)
          << r << " " << z;
    }
  }
  // Central tracks see the central field; forward ones less, more so
  // towards the ends (g averages the local bending along the path).
  EXPECT_NEAR(bending.factor(500.0, 0.0), 1.0, 2e-3);
  EXPECT_LT(bending.factor(300.0, 2000.0), bending.factor(300.0, 1000.0));
  EXPECT_LT(bending.factor(300.0, 2900.0), 0.9);
  EXPECT_GT(bending.factor(300.0, 2900.0), 0.6);
  EXPECT_EQ(bending.factor(300.0, -2000.0), bending.factor(300.0, 2000.0));
}

TEST(PromptBending, PutsForwardTracksOnTheCentralFieldsCircle) {
  // Tracks from the origin (0.5-2 GeV, eta 1.5-2.5) integrated through
  // the solenoid field to disks at |z| = 1.2-2.9 m: their azimuth there is
  // that of the circle of the central field at radius g r within a twentieth
  // of the error of taking it at radius r.
  for (const MagneticField& field :
       {kLongSolenoid, MagneticField({2.0 * T, kTrackmlSolenoidRadius,
                                      kTrackmlSolenoidHalfLength})}) {
    const PromptBending bending(field, 1030.0, 3000.0);
    int compared = 0;
    for (const test::ForwardTrack& c : test::kForwardTracks) {
      const Vector3 p = c.momentum();
      const double omega =
          c.charge * constants::kPtPerTeslaMm * field.centralBz() / c.pt;
      // Azimuth of the central field's circle from the origin along +x at
      // radius rho (a positive charge turns clockwise).
      auto circlePhi = [&](double rho) {
        return -std::asin(rho * omega / 2.0);
      };
      for (double z : {1200.0, 1800.0, 2400.0, 2900.0}) {
        const Vector3 x =
            test::rungeKuttaAtZ(field, Vector3::Zero(), p, c.charge, z);
        const double r = x.head<2>().norm();
        if (r > 1000.0 || r * std::abs(omega) > 1.6) {
          continue;  // outside the tracker or turning back
        }
        const double phi = std::atan2(x.y(), x.x());
        const double uncorrected = std::abs(phi - circlePhi(r));
        const double corrected =
            std::abs(phi - circlePhi(bending.factor(r, z) * r));
        EXPECT_GT(uncorrected, 1e-3) << c.pt << " " << c.eta << " " << z;
        EXPECT_LT(corrected, 0.05 * uncorrected)
            << c.pt << " " << c.eta << " " << z;
        ++compared;
      }
    }
    EXPECT_GE(compared, 12);
  }
}

}  // namespace
}  // namespace conftrack

// The simulation in a non-uniform field (a solenoid's, MagneticField):
// hits against an independent fine Runge-Kutta integration of the Lorentz
// force, and the surfaces around field-step boundaries.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include "IdealSimulatorConfig.hpp"
#include "LorentzIntegration.hpp"

namespace conftrack {
namespace {

/// Disks every 250 mm in z from 250 to 2750 mm and a barrel layer at
/// r = 500 mm, no material, in a solenoid field that falls to 0.6 of its
/// central value at z = 2.75 m.
Detector solenoidDetector() {
  std::string text = R"([detector]
name = "Solenoid"
bz_T = 2.0
solenoid_radius_mm = 2770.0
solenoid_half_length_mm = 2930.0
envelope_r_mm = 1100.0
envelope_z_mm = 3000.0

[[subdetector]]
name = "Barrel"
kind = "barrel"

  [[subdetector.layer]]
  name = "B0"
  r_mm = 500.0
  half_z_mm = 200.0
  x_over_x0 = 0.0
  sigma_rphi_um = 5.0
  sigma_z_um = 5.0

[[subdetector]]
name = "Endcap"
kind = "endcap"
)";
  for (int k = 1; k <= 11; ++k) {
    text += "\n  [[subdetector.layer]]\n  name = \"E" + std::to_string(k) +
            "\"\n  z_mm = " + std::to_string(250 * k) +
            "\n  r_min_mm = 5.0\n  r_max_mm = 1050.0\n  x_over_x0 = 0.0\n"
            "  sigma_rphi_um = 5.0\n  sigma_r_um = 5.0\n";
  }
  return parseDetector(text, "solenoid.toml");
}

TEST(FieldSimulation, HitsFollowTheLorentzForceInASolenoidField) {
  // Forward tracks of 0.5-2 GeV reach the disks out to 2.75 m, where the
  // field has fallen to 0.6 of its central value; the 25 mm field steps
  // (B_z of the step's middle, transverse kick) put the hits within 0.5 mm
  // of the integrated path, against 5-100 mm off for a uniform field.
  const Detector detector = solenoidDetector();
  const Simulator simulator(detector, test::idealSimulatorConfig());
  int compared = 0;
  for (const test::ForwardTrack& c : test::kForwardTracks) {
    const Vector3 p = c.momentum();
    Particle particle;
    particle.id = 1;
    particle.pdg = 211;
    particle.charge = c.charge;
    particle.vertex = Vector3(0.0, 0.0, 10.0);
    particle.momentum = p;
    Event event;
    RandomEngine rng(5);
    simulator.simulate({particle}, rng, event);
    ASSERT_GE(event.hits.size(), 5u) << c.pt << " " << c.eta;
    double worstUniform = 0.0;
    for (const HitTruth& truth : event.truth) {
      const double z = truth.position.z();
      if (z < 240.0) {
        continue;
      }
      const Vector3 expected = test::rungeKuttaAtZ(
          detector.field(), particle.vertex, p, c.charge, z);
      EXPECT_LT((truth.position - expected).norm(), 0.5)
          << "pt " << c.pt << " eta " << c.eta << " z " << z;
      const Vector3 uniform = test::rungeKuttaAtZ(
          MagneticField({2.0, 0.0, 0.0}), particle.vertex, p, c.charge, z);
      worstUniform = std::max(worstUniform, (uniform - expected).norm());
      ++compared;
    }
    EXPECT_GT(worstUniform, 5.0) << "the field must matter here";
  }
  EXPECT_GE(compared, 30);
}

TEST(FieldSimulation, RefusesANonPositiveFieldStep) {
  const Detector detector = solenoidDetector();
  Simulator::Config config = test::idealSimulatorConfig();
  config.fieldStep = 0.0;
  EXPECT_THROW(Simulator(detector, config), std::invalid_argument);
}

TEST(FieldSimulation, EveryLayerOfAFieldStepBoundaryKeepsItsHits) {
  // The disks lie every 250 mm, five 50 mm field steps apart: a step can
  // end just in front of a disk. Every disk the track reaches gives its
  // hit (with sensor modules, every sensor in front of the surface too:
  // Simulator::crossModules' lookBehind).
  const Detector detector = solenoidDetector();
  const Simulator simulator(detector, test::idealSimulatorConfig());
  for (double vz = -20.0; vz <= 20.0; vz += 0.7) {
    Particle particle;
    particle.id = 1;
    particle.pdg = 211;
    particle.charge = 1.0;
    particle.vertex = Vector3(0.0, 0.0, vz);
    particle.momentum = Vector3(3.0, 0.5, 30.0);
    Event event;
    RandomEngine rng(9);
    simulator.simulate({particle}, rng, event);
    std::map<double, int> disks;
    for (const HitTruth& truth : event.truth) {
      ++disks[std::round(truth.position.z())];
    }
    EXPECT_EQ(disks.size(), 11u) << "vz " << vz;
  }
}

TEST(FieldSimulation, LoopPathFromProductionIsAFixedPathLength) {
  // Half a turn of a 0.15 GeV track at eta 1.8 ends near z = 2.3 m if the
  // path is fixed with the central field (ACTS's loop protection), but
  // past z = 2.5 m if the turns are counted, because the field along the
  // way falls to 0.7 of its central value.
  const Detector detector = solenoidDetector();
  Particle particle;
  particle.id = 1;
  particle.pdg = 211;
  particle.charge = 1.0;
  particle.vertex = Vector3(0.0, 0.0, 0.0);
  const double pt = 0.15;
  const double tanLambda = std::sinh(1.8);
  particle.momentum = Vector3(pt, 0.0, pt * tanLambda);
  const double path =
      0.5 * 2.0 * std::numbers::pi * particle.momentum.norm() /
      (constants::kPtPerTeslaMm * detector.field().at(particle.vertex).norm());
  const double zEnd = path * tanLambda / std::sqrt(1.0 + tanLambda * tanLambda);
  auto lastZ = [&](bool loopPathFromProduction) {
    Simulator::Config config = test::idealSimulatorConfig();
    config.maxTurns = 0.5;
    config.loopPathFromProduction = loopPathFromProduction;
    const Simulator simulator(detector, config);
    Event event;
    RandomEngine rng(3);
    simulator.simulate({particle}, rng, event);
    double last = 0.0;
    for (const HitTruth& truth : event.truth) {
      last = std::max(last, truth.position.z());
    }
    return last;
  };
  const double fixedPath = lastZ(true);
  EXPECT_LE(fixedPath, zEnd + 1.0);
  EXPECT_GT(fixedPath, zEnd - 250.0);  // the last disk before the end
  EXPECT_GT(lastZ(false), zEnd + 100.0);
}

}  // namespace
}  // namespace conftrack

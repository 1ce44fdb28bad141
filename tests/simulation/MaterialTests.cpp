// Material interactions (physics.md sections 4 and 5): the pure formulas
// against the reference table, and the simulator's scattering and energy
// loss through a single layer against the formulas.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/MaterialInteractions.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace conftrack {
namespace {

using namespace units;

/// Mass stopping power in MeV cm^2/g.
double stoppingPowerMeV(double betaGamma, double mass) {
  return betheStoppingPower(betaGamma, mass, 1.0) / MeV;
}

TEST(MaterialBethe, MuonInSiliconTable) {
  // physics.md section 5: <dE/dx> of muons in silicon; required to 1 %.
  struct Row {
    double betaGamma;
    double dEdx;
  };
  for (const Row& row : {Row{3.5, 1.663}, Row{10.0, 1.792}, Row{100.0, 2.162},
                         Row{1000.0, 2.392}}) {
    const double value = stoppingPowerMeV(row.betaGamma, constants::kMuonMass);
    EXPECT_NEAR(value / row.dEdx, 1.0, 0.01) << "beta gamma " << row.betaGamma;
  }
}

TEST(MaterialBethe, ShapeAndScaling) {
  // Minimum ionising near beta gamma 3-4, rising below; charge^2 scaling;
  // the mean loss is stopping power times x/X0 * 21.82 g/cm^2.
  const double m = constants::kPionMass;
  EXPECT_GT(stoppingPowerMeV(1.0, m), stoppingPowerMeV(3.5, m));
  EXPECT_GT(stoppingPowerMeV(0.3, m), 3.0 * stoppingPowerMeV(3.5, m));
  EXPECT_NEAR(betheStoppingPower(4.0, m, 2.0) / betheStoppingPower(4.0, m, 1.0),
              4.0, 1e-12);
  const double p = 1.0;
  EXPECT_NEAR(betheMeanEnergyLoss(p, m, 1.0, 0.01),
              betheStoppingPower(p / m, m, 1.0) * 0.01 * 21.82, 1e-15);
  // ~0.36 MeV in a 1 % X0 silicon layer for a MIP (physics.md 5).
  EXPECT_NEAR(betheMeanEnergyLoss(0.5, constants::kMuonMass, 1.0, 0.01) / MeV,
              0.36, 0.02);
}

TEST(MaterialBethe, DensityEffectIsContinuous) {
  // Continuous up to the rounding of the tabulated PDG parameters.
  const double x0 = kSilicon.x0;
  const double x1 = kSilicon.x1;
  for (double x : {x0, x1}) {
    const double below = densityEffect(std::pow(10.0, x - 1e-9));
    const double above = densityEffect(std::pow(10.0, x + 1e-9));
    EXPECT_NEAR(below, above, 1e-3) << "x " << x;
  }
  EXPECT_NEAR(densityEffect(std::pow(10.0, x0)), kSilicon.delta0, 1e-3);
}

TEST(MaterialHighland, TypicalValues) {
  // physics.md section 4, 1 GeV muon: VXD layer (0.20 % X0) 0.47 mrad,
  // IT barrel layer (1.05 %) 1.16 mrad, IT disk (1.37 %) 1.34 mrad.
  const double p = 1.0;
  const double beta = p / std::hypot(p, constants::kMuonMass);
  EXPECT_NEAR(highlandTheta0(p, beta, 1.0, 0.0020) / mrad, 0.47, 0.01);
  EXPECT_NEAR(highlandTheta0(p, beta, 1.0, 0.0105) / mrad, 1.16, 0.01);
  EXPECT_NEAR(highlandTheta0(p, beta, 1.0, 0.0137) / mrad, 1.34, 0.01);
  // Explicit formula with the log term.
  const double x = 0.01;
  const double expected = 0.0136 / (beta * p) * std::sqrt(x) *
                          (1.0 + 0.038 * std::log(x / (beta * beta)));
  EXPECT_NEAR(highlandTheta0(p, beta, 1.0, x), expected, 1e-15);
  // Rossi-Greisen for electrons.
  EXPECT_NEAR(rossiGreisenTheta0(2.0, -1.0, x),
              0.0175 / 2.0 * std::sqrt(x) * (1.0 + 0.125 * std::log10(0.1)),
              1e-15);
}

/// A field-free detector with a layer of `thickness` X0 at r = 100 mm and a
/// massless layer at r = 100.5 mm whose hit records the momentum that left
/// the first (its incoming momentum).
Detector singleLayerDetector(double thickness) {
  std::vector<SensitiveLayer> layers(2);
  for (std::uint16_t i = 0; i < 2; ++i) {
    SensitiveLayer& l = layers[i];
    l.id.subdetector = 0;
    l.id.layer = i;
    l.shape = SurfaceShape::eCylinder;
    l.r = l.rMin = l.rMax = 100.0 + 0.5 * i;
    l.zMin = -1000.0;
    l.zMax = 1000.0;
    l.thicknessX0 = i == 0 ? thickness : 0.0;
    l.sigmaU = l.sigmaV = 0.01;
  }
  layers[0].name = "L0";
  layers[1].name = "L1";
  Subdetector sub{"Barrel", SubdetectorKind::eBarrel, {0, 1}, 2};
  return Detector("OneLayer", "OneLayer", MagneticField({0.0, 0.0, 0.0}), 200.0,
                  1500.0, {sub}, layers, {});
}

Particle muon(std::uint64_t id, double p, double theta) {
  Particle particle;
  particle.id = id;
  particle.pdg = 13;
  particle.charge = -1.0;
  particle.momentum = p * Vector3(std::sin(theta), 0.0, std::cos(theta));
  return particle;
}

TEST(MaterialSimulator, ScatteringMatchesHighland) {
  // 10^5 muons of 1 GeV through 1 % X0 at normal incidence and at 45 deg
  // (x/X0 = t/sin theta): the RMS of each projected angle equals theta0
  // within 2 % (statistical precision 0.2 %).
  const double thickness = 0.01;
  const Detector detector = singleLayerDetector(thickness);
  Simulator::Config config;
  config.energyLoss = false;
  config.smearHits = false;
  const Simulator simulator(detector, config);
  const double p = 1.0;
  const double beta = p / std::hypot(p, constants::kMuonMass);
  for (double theta : {std::numbers::pi / 2, std::numbers::pi / 4}) {
    std::vector<Particle> particles;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
      particles.push_back(muon(i + 1, p, theta));
    }
    Event event;
    RandomEngine rng(2024);
    simulator.simulate(particles, rng, event);
    ASSERT_EQ(event.hits.size(), 2u * n);
    // Projections on two axes perpendicular to the initial direction.
    const Vector3 d(std::sin(theta), 0.0, std::cos(theta));
    const Vector3 e1 = Vector3::UnitY();
    const Vector3 e2 = d.cross(e1);
    double sum1 = 0, sum11 = 0, sum22 = 0, sum12 = 0;
    for (std::size_t i = 1; i < event.truth.size(); i += 2) {
      const Vector3& out = event.truth[i].momentum;
      const double a1 = std::atan2(out.dot(e1), out.dot(d));
      const double a2 = std::atan2(out.dot(e2), out.dot(d));
      sum1 += a1;
      sum11 += a1 * a1;
      sum22 += a2 * a2;
      sum12 += a1 * a2;
    }
    const double theta0 =
        highlandTheta0(p, beta, -1.0, thickness / std::sin(theta));
    EXPECT_NEAR(std::sqrt(sum11 / n) / theta0, 1.0, 0.02) << "theta " << theta;
    EXPECT_NEAR(std::sqrt(sum22 / n) / theta0, 1.0, 0.02) << "theta " << theta;
    EXPECT_NEAR(sum1 / n / theta0, 0.0, 0.02);
    EXPECT_NEAR(sum12 / n / (theta0 * theta0), 0.0, 0.02);
    // Scattering does not change |p|.
    EXPECT_NEAR(event.truth[1].momentum.norm(), p, 1e-12);
  }
}

TEST(MaterialSimulator, EnergyLossMatchesBethe) {
  // Momentum after the layer: E' = E - <dE/dx> x/X0 X0, at normal and
  // oblique incidence, for a muon and a slow pion.
  const double thickness = 0.02;
  const Detector detector = singleLayerDetector(thickness);
  Simulator::Config config;
  config.multipleScattering = false;
  config.smearHits = false;
  const Simulator simulator(detector, config);
  for (double theta : {std::numbers::pi / 2, 0.5}) {
    for (double p : {0.15, 1.0, 10.0}) {
      Event event;
      RandomEngine rng(5);
      Particle particle = muon(1, p, theta);
      simulator.simulate({particle}, rng, event);
      ASSERT_EQ(event.truth.size(), 2u);
      const double m = constants::kMuonMass;
      const double xOverX0 = thickness / std::sin(theta);
      const double e =
          std::hypot(p, m) - betheMeanEnergyLoss(p, m, -1.0, xOverX0);
      const double expected = std::sqrt(e * e - m * m);
      EXPECT_NEAR(event.truth[0].momentum.norm(), p, 1e-12 * p);
      EXPECT_NEAR(event.truth[1].momentum.norm() / expected, 1.0, 1e-12)
          << "p " << p << " theta " << theta;
      // The direction is unchanged without scattering.
      EXPECT_NEAR(event.truth[1].momentum.normalized().dot(
                      particle.momentum.normalized()),
                  1.0, 1e-14);
    }
  }
}

TEST(MaterialSimulator, ElectronBremsstrahlungMean) {
  // E_after / (E_before - Bethe loss) has mean exp(-t) (Bethe-Heitler).
  const double thickness = 0.05;
  const Detector detector = singleLayerDetector(thickness);
  Simulator::Config config;
  config.multipleScattering = false;
  config.smearHits = false;
  config.minMomentum = 0.0;
  const Simulator simulator(detector, config);
  const double p = 5.0;
  const int n = 100000;
  std::vector<Particle> particles;
  for (int i = 0; i < n; ++i) {
    Particle e = muon(i + 1, p, std::numbers::pi / 2);
    e.pdg = 11;
    particles.push_back(e);
  }
  Event event;
  RandomEngine rng(11);
  simulator.simulate(particles, rng, event);
  const double me = constants::kElectronMass;
  const double eMid =
      std::hypot(p, me) - betheMeanEnergyLoss(p, me, -1.0, thickness);
  double sum = 0;
  int nOut = 0;
  for (std::size_t i = 0; i < event.truth.size(); ++i) {
    if (event.hits[i].detId.layer == 1) {
      sum += std::hypot(event.truth[i].momentum.norm(), me) / eMid;
      ++nOut;
    }
  }
  // Electrons that lost (almost) everything stop before the second layer
  // and count as 0; they are very rare at t = 0.05 but do not bias the
  // mean more than ~1e-4.
  EXPECT_NEAR(sum / n, std::exp(-thickness), 0.003);
  EXPECT_GT(nOut, n * 0.99);
  EXPECT_NEAR(bremsstrahlungMeanLossFraction(thickness),
              1.0 - std::exp(-thickness), 1e-15);
}

}  // namespace
}  // namespace conftrack

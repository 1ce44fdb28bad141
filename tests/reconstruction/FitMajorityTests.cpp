/// @file FitMajorityTests.cpp
/// The fitter's majority refit (KalmanFitter::Config::majorityRefit): a few
/// wrong hits at the start of the filter pass must not turn the particle's
/// own hits into outliers.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/simulation/Simulator.hpp"
#include "conftrack/simulation/generators/ParticleGun.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace conftrack {
namespace {

const Detector& clicdet() {
  static const Detector detector = loadDetector("clicdet");
  return detector;
}

/// A 10 GeV muon at 80 degrees in CLICdet: its hits in path order.
Event muonEvent() {
  ParticleGun::Config gun;
  gun.pdg = 13;
  gun.momentumMin = 10.0 * units::GeV;
  gun.momentumMax = gun.momentumMin;
  gun.angleSampling = ParticleGun::AngleSampling::eUniformTheta;
  gun.thetaMin = 80.0 * units::degree;
  gun.thetaMax = gun.thetaMin;
  RandomEngine genRng = makeEngine(11, 0, RandomStream::eSignalGenerator);
  const std::vector<Particle> particles = ParticleGun(gun).generate(genRng);
  Event event;
  RandomEngine simRng = makeEngine(11, 0, RandomStream::eSimulation);
  Simulator(clicdet()).simulate(particles, simRng, event);
  return event;
}

KalmanFitter fitter(bool majorityRefit) {
  KalmanFitter::Config config;
  config.pdg = 13;
  config.majorityRefit = majorityRefit;
  return KalmanFitter(clicdet(), config);
}

TEST(FitMajority, WrongHitsAtThePassStartBecomeTheOutliers) {
  Event event = muonEvent();
  const std::size_t n = event.hits.size();
  ASSERT_GE(n, 10u);
  std::vector<HitIndex> candidate(n);
  for (std::size_t h = 0; h < n; ++h) {
    candidate[h] = static_cast<HitIndex>(h);
  }
  // The outermost three hits moved 40 mm along z together: a consistent
  // piece of another track, where the backward pass starts (and through
  // which the three-hit prefit goes).
  constexpr std::size_t kWrong = 3;
  for (std::size_t k = n - kWrong; k < n; ++k) {
    event.hits[k].position.z() += 40.0 * units::mm;
  }
  const FitInput input{candidate, true};

  FitInfo info;
  const Track refitted = fitter(true).fit(event.hits, input, &info);
  ASSERT_TRUE(refitted.fitted);
  EXPECT_TRUE(info.majority);
  EXPECT_EQ(refitted.numOutliers(), kWrong);
  for (std::size_t k = 0; k < n; ++k) {
    EXPECT_EQ(refitted.outlier[k], k >= n - kWrong ? 1 : 0) << k;
  }
  EXPECT_EQ(refitted.ndf, 2 * static_cast<int>(n - kWrong) - 5);
  EXPECT_EQ(refitted.hits, candidate);
  // z0 of the muon (produced at the origin) within 5 sigma.
  EXPECT_LT(std::abs(refitted.atIp.parameters[eZ0]),
            5.0 * std::sqrt(refitted.atIp.covariance(eZ0, eZ0)));

  // Without it the fit follows the wrong hits (this is what the refit
  // repairs; if the plain fit ever gets this right, the test needs a
  // harder case).
  const Track plain = fitter(false).fit(event.hits, input);
  ASSERT_TRUE(plain.fitted);
  EXPECT_GT(plain.numOutliers(), n / 2);
  // The refit keeps the candidate's beam line (FitInput::beamLine): its
  // perigee about the same line as the first fit's would have been.
  const FitInput offAxis{candidate, true, Vector2(0.3, -0.2)};
  const Track aboutLine = fitter(true).fit(event.hits, offAxis, &info);
  ASSERT_TRUE(aboutLine.fitted);
  EXPECT_TRUE(info.majority);
  EXPECT_EQ(aboutLine.atIp.reference, Vector3(0.3, -0.2, 0.0));
}

TEST(FitMajority, CleanTracksAreLeftAlone) {
  const Event event = muonEvent();
  std::vector<HitIndex> candidate(event.hits.size());
  for (std::size_t h = 0; h < candidate.size(); ++h) {
    candidate[h] = static_cast<HitIndex>(h);
  }
  for (bool backward : {false, true}) {
    FitInfo info;
    const Track a = fitter(true).fit(event.hits, {candidate, backward}, &info);
    const Track b = fitter(false).fit(event.hits, {candidate, backward});
    EXPECT_FALSE(info.majority);
    ASSERT_TRUE(a.fitted && b.fitted);
    EXPECT_EQ(a.atIp.parameters, b.atIp.parameters);
    EXPECT_EQ(a.chi2, b.chi2);
  }
}

}  // namespace
}  // namespace conftrack

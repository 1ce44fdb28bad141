// True track parameters, residuals, pulls (with the pT and theta
// Jacobians) and the kinematics of reconstructed tracks.

#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/TrackResiduals.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "EvaluationTestEvents.hpp"

namespace conftrack {
namespace {

constexpr double kBz = 4.0 * units::T;

TEST(TrackResiduals, TrueParametersOfAPrimary) {
  const double pt = 10.0;
  const double phi = 0.3;
  const double theta = 50.0 * units::degree;
  const Particle mu = test::makeParticle(
      1, Vector3(pt * std::cos(phi), pt * std::sin(phi), pt / std::tan(theta)),
      -1.0);
  const TrackVector p = trueTrackParameters(mu, kBz);
  EXPECT_NEAR(p[eD0], 0.0, 1e-12);
  EXPECT_NEAR(p[eZ0], 0.0, 1e-12);
  EXPECT_NEAR(p[ePhi0], phi, 1e-12);
  // physics.md 3: Omega = q 2.998e-4 B / pT, sign(Omega) = sign(q).
  EXPECT_NEAR(p[eOmega], -constants::kPtPerTeslaMm * 4.0 / pt, 1e-15);
  EXPECT_NEAR(p[eTanLambda], 1.0 / std::tan(theta), 1e-12);
}

TEST(TrackResiduals, TrueParametersAreInvariantAlongTheHelix) {
  // A positive particle from the origin, moved along its helix (physics.md
  // 3 trajectory): the parameters at the origin must not change.
  const double pt = 0.8;
  const double phi0 = -1.0;
  const double tanLambda = 0.7;
  const double omega = constants::kPtPerTeslaMm * kBz / pt;
  const double s = 300.0;  // transverse arc length [mm]
  const Vector3 x((std::sin(phi0) - std::sin(phi0 - omega * s)) / omega,
                  -(std::cos(phi0) - std::cos(phi0 - omega * s)) / omega,
                  s * tanLambda);
  const double phi = phi0 - omega * s;
  const Particle p = test::makeParticle(
      2, Vector3(pt * std::cos(phi), pt * std::sin(phi), pt * tanLambda), 1.0,
      ParticleOrigin::eSignal, x);
  const TrackVector q = trueTrackParameters(p, kBz);
  EXPECT_NEAR(q[eD0], 0.0, 1e-9);
  EXPECT_NEAR(q[ePhi0], phi0, 1e-12);
  EXPECT_NEAR(q[eOmega], omega, 1e-15);
  EXPECT_NEAR(q[eZ0], 0.0, 1e-9);
  EXPECT_NEAR(q[eTanLambda], tanLambda, 1e-12);
}

TEST(TrackResiduals, ResidualsAndPullsOfAKnownOffset) {
  const double pt = 10.0;
  const double theta = 50.0 * units::degree;
  const Particle mu = test::makeParticle(
      1,
      Vector3(pt * std::cos(3.141), pt * std::sin(3.141), pt / std::tan(theta)),
      -1.0);
  const TrackVector truth = trueTrackParameters(mu, kBz);

  // Offsets of 2 sigma in d0, phi0, Omega and z0, 0.5 sigma in tanLambda;
  // phi0 crosses +-pi so that the wrapping is tested.
  TrackVector sigma;
  sigma << 5 * units::um, 0.5 * units::mrad, 1e-7, 10 * units::um, 2e-3;
  TrackVector offset;
  offset << 2 * sigma[0], 2 * sigma[1], 2 * sigma[2], 2 * sigma[3],
      0.5 * sigma[4];
  Track track;
  track.fitted = true;
  track.atIp.parameters = truth + offset;
  track.atIp.parameters[ePhi0] -= 2.0 * std::numbers::pi * (truth[ePhi0] > 0);
  for (int i = 0; i < 5; ++i) {
    track.atIp.covariance(i, i) = sigma[i] * sigma[i];
  }
  const TrackResidual r = computeTrackResidual(track, mu, kBz);

  EXPECT_NEAR(r.truePt, pt, 1e-12);
  EXPECT_NEAR(r.trueTheta, theta, 1e-12);
  EXPECT_NEAR(r.residuals[eResidualD0], offset[eD0], 1e-12);
  EXPECT_NEAR(r.residuals[eResidualZ0], offset[eZ0], 1e-12);
  EXPECT_NEAR(r.residuals[eResidualPhi0], offset[ePhi0], 1e-12);
  EXPECT_NEAR(r.pulls[ePullD0], 2.0, 1e-9);
  EXPECT_NEAR(r.pulls[ePullPhi0], 2.0, 1e-6);
  EXPECT_NEAR(r.pulls[ePullOmega], 2.0, 1e-6);
  EXPECT_NEAR(r.pulls[ePullZ0], 2.0, 1e-9);
  EXPECT_NEAR(r.pulls[ePullTanLambda], 0.5, 1e-9);

  // pT and theta through the Jacobians.
  const double omegaReco = truth[eOmega] + offset[eOmega];
  const double ptReco = constants::kPtPerTeslaMm * kBz / std::abs(omegaReco);
  EXPECT_NEAR(r.residuals[eResidualPt], ptReco - pt, 1e-9);
  EXPECT_NEAR(r.residuals[eResidualPtOverPt2], (ptReco - pt) / (pt * pt),
              1e-12);
  const double sigmaPt = ptReco * sigma[eOmega] / std::abs(omegaReco);
  EXPECT_NEAR(r.pulls[ePullPt], (ptReco - pt) / sigmaPt, 1e-9);
  // Omega < 0 here: +2 sigma lowers |Omega| and raises pT.
  EXPECT_GT(r.pulls[ePullPt], 0.0);
  const double tanReco = truth[eTanLambda] + offset[eTanLambda];
  const double thetaReco = std::atan2(1.0, tanReco);
  EXPECT_NEAR(r.residuals[eResidualTheta], thetaReco - theta, 1e-12);
  const double sigmaTheta = sigma[eTanLambda] / (1.0 + tanReco * tanReco);
  EXPECT_NEAR(r.pulls[ePullTheta], (thetaReco - theta) / sigmaTheta, 1e-9);
  EXPECT_NEAR(r.pulls[ePullTheta], -0.5, 0.01);  // small-offset limit
}

TEST(TrackResiduals, TruthIsTakenAboutTheTrackReference) {
  // A particle from a beam line 1 mm off the axis, perpendicular to its
  // momentum: d0 = 0 about the line, 1 mm about the axis. A track fitted
  // about the line (reference (1, 0, 0)) is compared with the truth about
  // the same line, not about the axis.
  const double pt = 3.0;
  const Particle p = test::makeParticle(
      1, Vector3(0.0, pt, 0.5 * pt), 1.0, ParticleOrigin::eSignal,
      Vector3(1.0 * units::mm, 0.0, 0.2 * units::mm));
  const Vector3 line(1.0 * units::mm, 0.0, 0.0);
  const TrackVector aboutLine = trueTrackParameters(p, kBz, line);
  const TrackVector aboutAxis = trueTrackParameters(p, kBz);
  EXPECT_NEAR(aboutLine[eD0], 0.0, 1e-12);
  EXPECT_NEAR(aboutLine[eZ0], 0.2 * units::mm, 1e-12);
  EXPECT_NEAR(std::abs(aboutAxis[eD0]), 1.0 * units::mm, 1e-9);
  Track track;
  track.fitted = true;
  track.atIp.reference = line;
  track.atIp.parameters = aboutLine;
  track.atIp.parameters[eD0] += 3.0 * units::um;
  track.atIp.covariance.diagonal().setConstant(1e-6);
  const TrackResidual r = computeTrackResidual(track, p, kBz);
  EXPECT_NEAR(r.residuals[eResidualD0], 3.0 * units::um, 1e-12);
  EXPECT_NEAR(r.residuals[eResidualZ0], 0.0, 1e-12);
  EXPECT_NEAR(r.pulls[ePullD0], 3.0, 1e-9);
}

TEST(TrackResiduals, MissingVarianceGivesNanPull) {
  const Particle mu = test::makeParticle(1, Vector3(1.0, 0.0, 0.0));
  Track track;
  track.fitted = true;
  track.atIp.parameters = trueTrackParameters(mu, kBz);
  const TrackResidual r = computeTrackResidual(track, mu, kBz);
  EXPECT_TRUE(std::isnan(r.pulls[ePullD0]));
  EXPECT_NEAR(r.residuals[eResidualD0], 0.0, 1e-12);
}

TEST(TrackResiduals, KinematicsOfFittedAndUnfittedTracks) {
  const test::EventWithTracks e = test::referenceEvent();
  const TrackKinematics unfitted = trackKinematics(e.tracks[0], e.event, kBz);
  EXPECT_FALSE(unfitted.fromFit);
  EXPECT_DOUBLE_EQ(unfitted.pt, 5.1);
  EXPECT_NEAR(unfitted.theta, 0.5 * std::numbers::pi, 1e-12);
  EXPECT_NEAR(unfitted.phi, 0.0, 1e-12);

  Track fitted = e.tracks[0];
  fitted.fitted = true;
  fitted.atIp.parameters << 0.0, 0.2, -constants::kPtPerTeslaMm * 4.0 / 2.0,
      0.0, 1.0;
  const TrackKinematics k = trackKinematics(fitted, e.event, kBz);
  EXPECT_TRUE(k.fromFit);
  EXPECT_NEAR(k.pt, 2.0, 1e-12);
  EXPECT_NEAR(k.theta, 0.25 * std::numbers::pi, 1e-12);
  EXPECT_NEAR(k.phi, 0.2, 1e-12);
}

TEST(TrackResiduals, ResolutionCurvesAndPullsFromSyntheticMuons) {
  // 400 muons at theta = 30 deg, pT = 10 GeV with residuals drawn from
  // muonSigmas(): the fitted resolutions and pull widths must match.
  std::mt19937_64 rng(11);
  PerformanceCollector collector(PerformanceConfig::singleParticleSample());
  for (std::size_t i = 0; i < 400; ++i) {
    const test::EventWithTracks e = test::muonEvent(i, 30.0, 10.0, kBz, rng);
    collector.addEvent(i, e.event, e.tracks, kBz, {}, {});
  }
  const PerformanceSummary s = collector.summary();
  EXPECT_EQ(s.data.residuals.size(), 400u);
  ASSERT_EQ(s.pulls.size(), std::size_t(eNumPullQuantities));
  for (const PullResult& p : s.pulls) {
    EXPECT_EQ(p.fit.entries, 400u) << pullName(p.quantity);
    EXPECT_NEAR(p.fit.mean, 0.0, 0.2) << pullName(p.quantity);
    EXPECT_NEAR(p.fit.sigma, 1.0, 0.15) << pullName(p.quantity);
  }
  // One curve point per residual quantity (theta 30, the pT = 10 GeV bin).
  ASSERT_EQ(s.resolutions.size(), std::size_t(eNumResidualQuantities));
  const TrackVector sigma = test::muonSigmas(10.0);
  for (const ResolutionPoint& p : s.resolutions) {
    EXPECT_NEAR(p.theta, 30.0 * units::degree, 1e-12);
    EXPECT_NEAR(p.ptMean, 10.0, 1e-9);
    EXPECT_LT(p.ptLow, 10.0);
    EXPECT_GT(p.ptHigh, 10.0);
    if (p.quantity == eResidualD0) {
      EXPECT_NEAR(p.fit.sigma, sigma[eD0], 0.15 * sigma[eD0]);
    }
    if (p.quantity == eResidualZ0) {
      EXPECT_NEAR(p.fit.sigma, sigma[eZ0], 0.15 * sigma[eZ0]);
    }
    if (p.quantity == eResidualPtOverPt2) {
      // sigma(pT)/pT^2 = sigma(Omega) / (kPtPerTeslaMm B) for small errors.
      const double expected = sigma[eOmega] / (constants::kPtPerTeslaMm * kBz);
      EXPECT_NEAR(p.fit.sigma, expected, 0.15 * expected);
    }
  }
}

}  // namespace
}  // namespace conftrack

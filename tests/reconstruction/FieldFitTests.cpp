// The fit in a non-uniform field (KalmanFitter::Config::followField):
// forward muons through the TrackML detector's solenoid field, whose
// bending falls to 0.7 of the central one towards |z| = 3 m.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/fitting/HelixState.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/simulation/Simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace conftrack {
namespace {

struct PullMoments {
  double mean = 0.0;
  double width = 0.0;
  std::size_t fitted = 0;
  double outlierFraction = 0.0;
};

/// Muons of transverse momentum pt at eta 1.6-2.4 from the origin, in the
/// TrackML detector (its layers, its field) with all material effects,
/// their truth hits fitted: mean and RMS of the Omega pull at the IP (times
/// the charge).
PullMoments omegaPulls(const Detector& detector, bool followField, double pt,
                       std::size_t n) {
  const Simulator simulator(detector);
  KalmanFitter::Config config;
  config.pdg = 13;
  config.followField = followField;
  const KalmanFitter fitter(detector, config);
  std::vector<double> pulls;
  std::size_t outliers = 0;
  std::size_t hits = 0;
  for (std::size_t i = 0; i < n; ++i) {
    RandomEngine rng = makeEngine(77, i, RandomStream::eSignalGenerator);
    const double eta = 1.6 + 0.8 * (static_cast<double>(i) + 0.5) / n;
    const double phi = 0.37 * static_cast<double>(i);
    Particle muon;
    muon.id = 1;
    muon.pdg = i % 2 == 0 ? 13 : -13;
    muon.charge = i % 2 == 0 ? -1.0 : 1.0;
    muon.vertex = Vector3::Zero();
    muon.momentum =
        Vector3(pt * std::cos(phi), pt * std::sin(phi), pt * std::sinh(eta));
    Event event;
    simulator.simulate({muon}, rng, event);
    std::vector<HitIndex> candidate;
    for (std::size_t h = 0; h < event.hits.size(); ++h) {
      candidate.push_back(static_cast<HitIndex>(h));
    }
    if (candidate.size() < 5) {
      continue;
    }
    const Track track = fitter.fit(event.hits, {candidate});
    if (!track.fitted) {
      continue;
    }
    outliers += track.numOutliers();
    hits += track.hits.size();
    const TrackVector truth = helixParametersAt(muon.vertex, muon.momentum,
                                                muon.charge, detector.bz());
    // Signed with the charge: a fit that bends too little gives the same
    // sign for both charges.
    pulls.push_back(muon.charge *
                    (track.atIp.parameters[eOmega] - truth[eOmega]) /
                    std::sqrt(track.atIp.covariance(eOmega, eOmega)));
  }
  PullMoments m;
  m.fitted = pulls.size();
  for (double p : pulls) {
    m.mean += p;
  }
  m.mean /= static_cast<double>(std::max<std::size_t>(pulls.size(), 1));
  for (double p : pulls) {
    m.width += (p - m.mean) * (p - m.mean);
  }
  m.width = std::sqrt(
      m.width / static_cast<double>(std::max<std::size_t>(pulls.size(), 1)));
  m.outlierFraction = static_cast<double>(outliers) /
                      static_cast<double>(std::max<std::size_t>(hits, 1));
  return m;
}

TEST(FieldFit, ForwardMomentaAreUnbiasedInTheSolenoidField) {
  // Taking the field as uniform, the fit sees the outer hits bend less
  // and overestimates pT: the Omega pull (times the charge) is biased by
  // many standard deviations, and hits become outliers. Following the
  // field, the pull is of unit width, its bias below one standard
  // deviation, and no hit is an outlier.
  const Detector detector = loadDetector("trackml");
  ASSERT_FALSE(detector.field().isUniform());
  const std::size_t n = 400;
  for (double pt : {1.0, 5.0}) {
    const PullMoments follow = omegaPulls(detector, true, pt, n);
    const PullMoments uniform = omegaPulls(detector, false, pt, n);
    std::printf(
        "[field fit] pT %.0f GeV: Omega pull %+.3f/%.3f, outliers %.3f "
        "(uniform field: %+.3f/%.3f, %.3f)\n",
        pt, follow.mean, follow.width, follow.outlierFraction, uniform.mean,
        uniform.width, uniform.outlierFraction);
    EXPECT_GE(follow.fitted, n * 95 / 100);
    // What is left (measured +0.33 at 1 GeV, +0.32 at 5 GeV: 0.3-0.6 %
    // of Omega, with field steps of 100 or 40 mm alike) is half the
    // simulation's own error (hits within 0.5 mm of the integrated path,
    // FieldSimulation): with 5 mm steps in the simulation instead of 25,
    // +0.14 and +0.14. -15 and -17 for the uniform field, with 17 % and
    // 12 % of the hits outliers.
    EXPECT_LT(std::abs(follow.mean), 0.5) << pt;
    EXPECT_NEAR(follow.width, 1.0, 0.15) << pt;
    EXPECT_LT(follow.outlierFraction, 0.01) << pt;
    EXPECT_LT(uniform.mean, -3.0) << pt;
    EXPECT_GT(uniform.outlierFraction, 0.03) << pt;
  }
}

TEST(FieldFit, RefusesANonPositiveFieldStep) {
  const Detector detector = loadDetector("trackml");
  KalmanFitter::Config config;
  config.fieldStep = 0.0;
  EXPECT_THROW(KalmanFitter(detector, config), std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

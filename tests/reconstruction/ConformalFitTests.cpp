#include "conftrack/core/Error.hpp"
#include "conftrack/reconstruction/finding/ConformalFit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>

#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

using test::barrelDetector;
using test::helixHits;

std::vector<ConfIndex> allOf(const ConformalHits& ch) {
  std::vector<ConfIndex> v(ch.size());
  std::iota(v.begin(), v.end(), 0);
  return v;
}

TEST(ConformalTransform, CoordinatesAndErrors) {
  Detector det = barrelDetector();
  std::vector<Hit> hits{test::barrelHit(det, 2, 30.0, 40.0, 7.0, 1)};
  ConformalHits ch = makeConformalHits(hits, det);
  // R = 50: u = x/R^2, v = y/R^2.
  EXPECT_DOUBLE_EQ(ch.u[0], 30.0 / 2500.0);
  EXPECT_DOUBLE_EQ(ch.v[0], 40.0 / 2500.0);
  EXPECT_DOUBLE_EQ(ch.rc[0], 1.0 / 50.0);
  // Numerical Jacobian: a tangential shift d moves (u, v) by d/R^2 along
  // the tangential direction; its variance is sigma^2/R^4.
  double d = 1e-4;
  double x = 30.0 - d * 0.8;
  double y = 40.0 + d * 0.6;
  double r2 = x * x + y * y;
  Vector2 shift(x / r2 - ch.u[0], y / r2 - ch.v[0]);
  EXPECT_NEAR(shift.norm(), d / 2500.0, 1e-3 * d / 2500.0);
  Matrix2 cov = ch.covariance(0);
  Vector2 t = shift.normalized();
  double sigma = 5e-3;
  EXPECT_NEAR(t.dot(cov * t), sigma * sigma / (2500.0 * 2500.0),
              1e-4 * sigma * sigma / (2500.0 * 2500.0));
  // Barrel hits have no radial conformal error.
  Vector2 radial(0.6, 0.8);
  EXPECT_NEAR(radial.dot(cov * radial), 0.0, 1e-25);
}

TEST(ConformalTransform, BendingFactorMovesTheHitToRadiusGR) {
  // In a solenoid field a hit maps as if at radius g r on its azimuth
  // (PromptBending): coordinates, conformal radius and errors scale by
  // 1/g; the measured position stays.
  Detector det = barrelDetector();
  std::vector<Hit> hits{test::barrelHit(det, 2, 30.0, 40.0, 400.0, 1)};
  const PromptBending bending(MagneticField({2.0, 2770.0, 2930.0}),
                              det.envelopeR(), det.envelopeZ());
  const double g = bending.factor(50.0, 400.0);
  ASSERT_LT(g, 1.0);
  const ConformalHits plain = makeConformalHits(hits, det);
  const ConformalHits mapped = makeConformalHits(hits, det, &bending);
  EXPECT_DOUBLE_EQ(mapped.u[0], plain.u[0] / g);
  EXPECT_DOUBLE_EQ(mapped.v[0], plain.v[0] / g);
  EXPECT_DOUBLE_EQ(mapped.rc[0], plain.rc[0] / g);
  EXPECT_NEAR(mapped.covUU[0], plain.covUU[0] / (g * g),
              1e-12 * plain.covUU[0]);
  EXPECT_EQ(mapped.radius[0], plain.radius[0]);
  EXPECT_EQ(mapped.phi[0], plain.phi[0]);
}

TEST(ConformalTransform, MapIsTakenAboutTheBeamSpot) {
  // A beam line at (1.5, -2) mm: the hit's position, radius and azimuth
  // relative to it, and u, v of that position; z unchanged. The hit 0.5 um
  // from it has no mapping, wherever the detector axis is.
  Detector det = barrelDetector();
  const Vector2 beam(1.5, -2.0);
  std::vector<Hit> hits{test::barrelHit(det, 2, 31.5, 38.0, 7.0, 1)};
  const ConformalHits ch = makeConformalHits(hits, det, nullptr, beam);
  EXPECT_DOUBLE_EQ(ch.x[0], 30.0);
  EXPECT_DOUBLE_EQ(ch.y[0], 40.0);
  EXPECT_DOUBLE_EQ(ch.z[0], 7.0);
  EXPECT_DOUBLE_EQ(ch.radius[0], 50.0);
  EXPECT_DOUBLE_EQ(ch.phi[0], std::atan2(40.0, 30.0));
  EXPECT_DOUBLE_EQ(ch.u[0], 30.0 / 2500.0);
  EXPECT_DOUBLE_EQ(ch.v[0], 40.0 / 2500.0);
  EXPECT_DOUBLE_EQ(ch.rc[0], 1.0 / 50.0);
  // The default is the detector axis.
  const ConformalHits axis = makeConformalHits(hits, det);
  EXPECT_DOUBLE_EQ(axis.x[0], 31.5);
  EXPECT_DOUBLE_EQ(axis.u[0], 31.5 / (31.5 * 31.5 + 38.0 * 38.0));
  std::vector<Hit> onBeam{test::barrelHit(det, 2, 1.5, -1.9995, 7.0, 2)};
  EXPECT_THROW(makeConformalHits(onBeam, det, nullptr, beam), InputError);
  EXPECT_NO_THROW(makeConformalHits(onBeam, det));
}

TEST(ConformalTransform, HitOnAxisIsRejected) {
  Detector det = barrelDetector();
  std::vector<Hit> hits{test::barrelHit(det, 2, 0.0, 0.0, 7.0, 1)};
  EXPECT_THROW(makeConformalHits(hits, det), InputError);
}

TEST(ConformalFit, StraightLineOnCircleThroughOrigin) {
  Detector det = barrelDetector();
  for (int q : {1, -1}) {
    double rho = 2000.0;
    std::vector<Hit> hits = helixHits(det, rho, 0.7, q, 0.5, 1);
    ConformalHits ch = makeConformalHits(hits, det);
    auto track = allOf(ch);
    ConformalFitResult fit = fitConformal(ch, track, false);
    ASSERT_TRUE(fit.valid);
    EXPECT_EQ(fit.ndf, 6);
    EXPECT_LT(fit.chi2, 1e-12);
    EXPECT_NEAR(fit.radius, rho, 1e-6 * rho);
    EXPECT_EQ(fit.charge(), q);
    // pT = 0.3 B rho.
    EXPECT_NEAR(fit.pt(4.0), constants::kPtPerTeslaMm * 4.0 * rho, 1e-6);
  }
}

TEST(ConformalFit, QuadraticTermAbsorbsImpactParameter) {
  Detector det = barrelDetector();
  double rho = 1000.0;
  std::vector<Hit> hits = helixHits(det, rho, 0.3, 1, 0.2, 1, 0.5);
  ConformalHits ch = makeConformalHits(hits, det);
  auto track = allOf(ch);
  ConformalFitResult line = fitConformal(ch, track, false);
  ConformalFitResult quad = fitConformal(ch, track, true);
  ASSERT_TRUE(line.valid && quad.valid);
  EXPECT_EQ(quad.ndf, 5);
  // A 0.5 mm impact parameter is far outside 5 um errors for the line...
  EXPECT_GT(line.chi2PerNdf(), 100.0);
  // ...and mostly absorbed by the quadratic term.
  EXPECT_LT(quad.chi2, 1e-3 * line.chi2);
}

TEST(ConformalFit, DeltaChi2MatchesRefit) {
  Detector det = barrelDetector();
  std::vector<Hit> hits = helixHits(det, 800.0, -2.0, -1, 1.0, 1, 0.2);
  // Shift the last hit by 20 um along r-phi so that it costs chi2.
  Hit& last = hits.back();
  last.position += 0.02 * last.uAxis;
  ConformalHits ch = makeConformalHits(hits, det);
  auto track = allOf(ch);
  std::vector<ConfIndex> first(track.begin(), track.end() - 1);
  ConformalFitResult partial = fitConformal(ch, first, true);
  ConformalFitResult full = fitConformal(ch, track, true, &partial);
  double predicted = partial.deltaChi2(ch, track.back());
  EXPECT_GT(predicted, 1.0);
  EXPECT_NEAR(full.chi2 - partial.chi2, predicted, 0.02 * predicted);
}

TEST(SzFit, RecoversDipAndOffset) {
  Detector det = barrelDetector();
  for (double tanL : {-1.5, 0.0, 0.8}) {
    std::vector<Hit> hits = helixHits(det, 600.0, 1.0, 1, tanL, 1);
    ConformalHits ch = makeConformalHits(hits, det);
    auto track = allOf(ch);
    ConformalFitResult uv = fitConformal(ch, track, false);
    SzFitResult sz = fitSz(ch, track, makeArcFrame(uv, ch, track.front()));
    ASSERT_TRUE(sz.valid);
    EXPECT_NEAR(sz.tanLambda, tanL, 1e-9);
    // z of the first hit is its arc length times tanL; s starts there.
    EXPECT_NEAR(sz.z0, ch.z[0], 1e-9);
    EXPECT_LT(sz.chi2, 1e-9);
    EXPECT_EQ(sz.ndf, 6);
  }
}

TEST(SzFit, TrackRunningMoreThanHalfATurnBetweenTwoHits) {
  // A looper (radius 70 mm, tanLambda 0.5) on its way out through layers
  // at 30, 40 and 50 mm and back in through 50 and 40 mm: 336 mm of arc
  // between the two 50 mm hits, more than half of the 440 mm turn. The
  // nearest turn would put the return hits a turn back (z off by 220 mm);
  // the z slope of the hits before picks the one they lie on.
  Detector det = barrelDetector();
  constexpr double kRadius = 70.0;
  constexpr double kTanL = 0.5;
  constexpr double kPhi = 0.4;
  std::vector<Hit> hits;
  std::uint64_t id = 1;
  for (bool out : {true, false}) {
    for (std::uint16_t layer : {0, 1, 2}) {
      const std::uint16_t l =
          out ? layer : static_cast<std::uint16_t>(2 - layer);
      const double turning =
          2.0 * std::asin(det.layers()[l].r / (2.0 * kRadius));
      const double s =
          kRadius * (out ? turning : 2.0 * std::numbers::pi - turning);
      const double x =
          kRadius * (std::sin(kPhi) - std::sin(kPhi - s / kRadius));
      const double y =
          -kRadius * (std::cos(kPhi) - std::cos(kPhi - s / kRadius));
      hits.push_back(test::barrelHit(det, l, x, y, kTanL * s, id++));
    }
  }
  ConformalHits ch = makeConformalHits(hits, det);
  std::vector<ConfIndex> track;
  for (std::uint64_t want = 1; want <= 6; ++want) {
    for (ConfIndex c = 0; c < ch.size(); ++c) {
      if (ch.id[c] == want) {
        track.push_back(c);
      }
    }
  }
  ConformalFitResult uv = fitConformal(ch, track, false);
  ASSERT_TRUE(uv.valid);
  EXPECT_NEAR(uv.radius, kRadius, 0.01);
  SzFitResult sz = fitSz(ch, track, makeArcFrame(uv, ch, track.front()));
  ASSERT_TRUE(sz.valid);
  EXPECT_NEAR(sz.tanLambda, kTanL, 1e-4);
  EXPECT_LT(sz.chi2PerNdf(), 1.0);
  // The last hit lies most of a turn on from the first.
  EXPECT_GT(sz.lastS, std::numbers::pi * kRadius);
}

TEST(SzFit, DegenerateIsInvalid) {
  Detector det = barrelDetector();
  std::vector<Hit> hits{test::barrelHit(det, 0, 30.0, 0.0, 1.0, 1),
                        test::barrelHit(det, 0, 30.0, 0.0, 2.0, 2)};
  // Two hits at the same point in x-y: all s equal.
  ConformalHits ch = makeConformalHits(hits, det);
  std::vector<ConfIndex> track{0, 1};
  ConformalFitResult uv;
  uv.valid = true;
  uv.centreX = 1000.0;
  uv.radius = 1000.0;
  SzFitResult sz = fitSz(ch, track, makeArcFrame(uv, ch, 0));
  EXPECT_FALSE(sz.valid);
}

}  // namespace
}  // namespace conftrack

// The transverse prediction error of a helix path (HelixPredictionError):
// the resolution part against the Lagrange extrapolation of three hits
// and a least-squares fit by hand, the scattering part against its limits
// and a Monte Carlo of kinked tracks.

#include "conftrack/reconstruction/finding/detail/HelixPredictionError.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace conftrack::detail {
namespace {

TEST(HelixPredictionError, ThreeHitsExtrapolateLikeLagrange) {
  // Three hits at s = 0, L/2, L with equal errors: the parabola through
  // them predicts at L + d with the weights of the Lagrange basis
  // polynomials, (1 + 2r)r, -4r(1 + r), (1 + r)(1 + 2r) for r = d / L.
  // Three pixel-disk hits 13 mm apart extrapolated 16.5 mm: 5.7 sigma.
  HelixPredictionError error;
  const double sigma = 0.015;
  const std::vector<double> s = {0.0, 13.0, 26.0};
  const std::vector<double> sig(3, sigma);
  const std::vector<double> kink(3, 0.0);
  ASSERT_TRUE(error.reset(s, sig, kink));
  for (double d : {0.0, 5.0, 16.5, 60.0}) {
    const double r = d / 26.0;
    const double l0 = (1.0 + 2.0 * r) * r;
    const double l1 = -4.0 * r * (1.0 + r);
    const double l2 = (1.0 + r) * (1.0 + 2.0 * r);
    const double expected = sigma * sigma * (l0 * l0 + l1 * l1 + l2 * l2);
    EXPECT_NEAR(error.resolutionVariance(d), expected, 1e-9 * expected + 1e-15)
        << "d = " << d;
    EXPECT_EQ(error.scatteringVariance(d), 0.0);
  }
  EXPECT_NEAR(std::sqrt(error.resolutionVariance(16.5)) / sigma, 5.7, 0.05);
}

TEST(HelixPredictionError, ManyHitsMatchAWeightedLeastSquaresFit) {
  // Ten hits with unequal errors: the variance of the fit's prediction,
  // from its normal equations written out here.
  const std::vector<double> s = {0, 11, 19, 42, 55, 80, 96, 130, 151, 170};
  std::vector<double> sig;
  for (std::size_t k = 0; k < s.size(); ++k) {
    sig.push_back(0.01 + 0.004 * double(k % 3));
  }
  const std::vector<double> kink(s.size(), 0.0);
  HelixPredictionError error;
  ASSERT_TRUE(error.reset(s, sig, kink));
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Eigen::Vector3d f(1.0, s[k], s[k] * s[k]);
    normal += f * f.transpose() / (sig[k] * sig[k]);
  }
  const Eigen::Matrix3d cov = normal.inverse();
  for (double d : {0.0, 40.0, 150.0}) {
    const double at = 170.0 + d;
    const Eigen::Vector3d f(1.0, at, at * at);
    const double expected = f.dot(cov * f);
    EXPECT_NEAR(error.resolutionVariance(d), expected, 1e-6 * expected);
  }
  // At the last hit, ten hits predict better than its own error.
  EXPECT_LT(error.resolutionVariance(0.0), sig.back() * sig.back());
}

TEST(HelixPredictionError, RefusesPathsThatFixNoParabola) {
  HelixPredictionError error;
  const std::vector<double> one(2, 0.01);
  const std::vector<double> zero2(2, 0.0);
  EXPECT_FALSE(error.reset(std::vector<double>{0.0, 10.0}, one, zero2));
  const std::vector<double> sig(3, 0.01);
  const std::vector<double> zero3(3, 0.0);
  // Two distinct arc lengths only (an overlap pair and one hit).
  EXPECT_FALSE(error.reset(std::vector<double>{0.0, 0.0, 10.0}, sig, zero3));
  EXPECT_EQ(error.resolutionVariance(5.0), 0.0);
  EXPECT_FALSE(error.reset(std::vector<double>{0.0, 5.0, 10.0},
                           std::vector<double>{0.01, 0.0, 0.01}, zero3));
}

TEST(HelixPredictionError, KinksBeyondTheFitsReachAndWithinIt) {
  // A kink in the last hit's layer is not seen by the fit: it moves the
  // prediction by theta d. A kink at the first hit of three moves the
  // other two onto a line the parabola follows exactly: no error.
  HelixPredictionError error;
  const std::vector<double> s = {0.0, 40.0, 90.0};
  const std::vector<double> sig(3, 0.01);
  ASSERT_TRUE(error.reset(s, sig, std::vector<double>{0.0, 0.0, 0.002}));
  EXPECT_NEAR(error.scatteringVariance(50.0), std::pow(0.002 * 50.0, 2), 1e-12);
  ASSERT_TRUE(error.reset(s, sig, std::vector<double>{0.002, 0.0, 0.0}));
  EXPECT_NEAR(error.scatteringVariance(50.0), 0.0, 1e-12);
}

TEST(HelixPredictionError, ScatteringMatchesAMonteCarloOfKinkedTracks) {
  // Straight tracks with a Gaussian kink at each of eight hits and
  // Gaussian hit errors, fitted with the weighted parabola: the spread of
  // the prediction 120 mm beyond the last hit against the sum of both
  // variances. 20,000 tracks: the variance is known to 1 % (2 sigma 2 %).
  const std::vector<double> s = {0, 35, 72, 110, 160, 210, 260, 330};
  const std::vector<double> sig = {0.01, 0.01, 0.01, 0.01,
                                   0.03, 0.03, 0.03, 0.03};
  const std::vector<double> kink = {0.001,  0.001,  0.001,  0.001,
                                    0.0015, 0.0015, 0.0015, 0.0015};
  HelixPredictionError error;
  ASSERT_TRUE(error.reset(s, sig, kink));
  const double d = 120.0;
  const double predicted =
      error.resolutionVariance(d) + error.scatteringVariance(d);
  Eigen::MatrixXd design(s.size(), 3);
  for (std::size_t k = 0; k < s.size(); ++k) {
    design.row(static_cast<Eigen::Index>(k)) << 1.0 / sig[k], s[k] / sig[k],
        s[k] * s[k] / sig[k];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  constexpr int kTracks = 20000;
  double sum2 = 0.0;
  Eigen::VectorXd y(static_cast<Eigen::Index>(s.size()));
  for (int t = 0; t < kTracks; ++t) {
    // The true path: kinks accumulate in its slope.
    std::vector<double> truth(s.size() + 1, 0.0);
    double slope = 0.0;
    double pos = 0.0;
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (k > 0) {
        pos += slope * (s[k] - s[k - 1]);
      }
      truth[k] = pos;
      slope += kink[k] * gauss(rng);
    }
    const double truthAt = pos + slope * d;
    for (std::size_t k = 0; k < s.size(); ++k) {
      y(static_cast<Eigen::Index>(k)) =
          (truth[k] + sig[k] * gauss(rng)) / sig[k];
    }
    const Eigen::Vector3d c = qr.solve(y);
    const double at = s.back() + d;
    const double fitted = c(0) + c(1) * at + c(2) * at * at;
    sum2 += (fitted - truthAt) * (fitted - truthAt);
  }
  const double observed = sum2 / kTracks;
  EXPECT_NEAR(observed / predicted, 1.0, 0.03)
      << "observed " << observed << " predicted " << predicted;
}

}  // namespace
}  // namespace conftrack::detail

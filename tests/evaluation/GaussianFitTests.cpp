// The Gaussian core fit on generated samples: pure Gaussians, Gaussians with
// wide tails and with a flat background.

#include "conftrack/evaluation/GaussianFit.hpp"
#include "conftrack/evaluation/Histograms.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace conftrack {
namespace {

std::vector<double> gaussian(std::size_t n, double mean, double sigma,
                             std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(mean, sigma);
  std::vector<double> v(n);
  for (double& x : v) {
    x = g(rng);
  }
  return v;
}

double rms(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) {
    m += x;
  }
  m /= v.size();
  double s = 0.0;
  for (double x : v) {
    s += (x - m) * (x - m);
  }
  return std::sqrt(s / v.size());
}

TEST(GaussianFit, PureGaussian) {
  const auto v = gaussian(20000, 0.5, 2.0, 1);
  const GaussianFit f = fitGaussianCore(v);
  EXPECT_TRUE(f.converged);
  EXPECT_EQ(f.entries, 20000u);
  // Statistical precision: sigma/sqrt(N) ~ 0.014 for the mean; the clipped
  // width has about 1.3 % relative spread at N = 20000 (core ~ 95 %).
  EXPECT_NEAR(f.mean, 0.5, 0.05);
  EXPECT_NEAR(f.sigma, 2.0, 0.04);  // 2 %
  EXPECT_NEAR(f.sigmaError, f.sigma / std::sqrt(2.0 * f.coreEntries), 1e-12);
  EXPECT_GT(f.coreEntries, 18500u);  // about 95.4 % within +-2 sigma
  EXPECT_LT(f.coreEntries, 19600u);
}

TEST(GaussianFit, GaussianWithWideTails) {
  // 90 % N(0, 1) + 10 % N(0, 5): the RMS is 1.84, the core stays near 1.
  auto v = gaussian(27000, 0.0, 1.0, 2);
  const auto tails = gaussian(3000, 0.0, 5.0, 3);
  v.insert(v.end(), tails.begin(), tails.end());
  EXPECT_GT(rms(v), 1.7);
  const GaussianFit f = fitGaussianCore(v);
  EXPECT_TRUE(f.converged);
  EXPECT_NEAR(f.mean, 0.0, 0.03);
  // Tolerance 8 %: the tail component puts ~3 % of the entries under the
  // core, which widens it slightly (by ~4-5 % here).
  EXPECT_NEAR(f.sigma, 1.0, 0.08);
}

TEST(GaussianFit, GaussianWithFlatBackgroundAndOffset) {
  // 95 % N(3, 0.01) + 5 % uniform in [2.8, 3.2] (outliers of a resolution).
  auto v = gaussian(19000, 3.0, 0.01, 4);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> flat(2.8, 3.2);
  for (int i = 0; i < 1000; ++i) {
    v.push_back(flat(rng));
  }
  const GaussianFit f = fitGaussianCore(v);
  EXPECT_NEAR(f.mean, 3.0, 0.0005);
  EXPECT_NEAR(f.sigma, 0.01, 0.0005);  // 5 %
}

TEST(GaussianFit, IndependentOfOrder) {
  auto v = gaussian(1000, 1.0, 0.3, 6);
  const GaussianFit a = fitGaussianCore(v);
  std::reverse(v.begin(), v.end());
  std::shuffle(v.begin(), v.end(), std::mt19937_64(9));
  const GaussianFit b = fitGaussianCore(v);
  // Bitwise identical: the values are sorted before any sum.
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.sigma, b.sigma);
}

TEST(GaussianFit, FewEntriesGiveMeanAndRms) {
  const std::vector<double> v = {1.0, 2.0, 3.0, 4.0};
  const GaussianFit f = fitGaussianCore(v);
  EXPECT_FALSE(f.converged);
  EXPECT_DOUBLE_EQ(f.mean, 2.5);
  EXPECT_DOUBLE_EQ(f.sigma, std::sqrt(1.25));
}

TEST(GaussianFit, DegenerateInputs) {
  EXPECT_EQ(fitGaussianCore(std::vector<double>{}).entries, 0u);
  const std::vector<double> same(50, 7.0);
  const GaussianFit f = fitGaussianCore(same);
  EXPECT_DOUBLE_EQ(f.mean, 7.0);
  EXPECT_DOUBLE_EQ(f.sigma, 0.0);
  std::vector<double> withNan = gaussian(200, 0.0, 1.0, 8);
  withNan.push_back(std::nan(""));
  withNan.push_back(INFINITY);
  EXPECT_EQ(fitGaussianCore(withNan).entries, 200u);
}

TEST(Histograms, RatioAndWilsonInterval) {
  Ratio r{9, 10};
  EXPECT_DOUBLE_EQ(r.value(), 0.9);
  EXPECT_DOUBLE_EQ(r.uncertainty(), std::sqrt(0.9 * 0.1 / 10));
  const auto [lo, hi] = r.wilsonInterval();
  EXPECT_LT(lo, 0.9);
  EXPECT_GT(hi, 0.9);
  const Ratio full{10, 10};
  EXPECT_DOUBLE_EQ(full.uncertainty(), 0.0);
  EXPECT_LT(full.wilsonInterval().first, 1.0);  // not zero width
  EXPECT_DOUBLE_EQ(full.wilsonInterval().second, 1.0);
  EXPECT_TRUE(std::isnan(Ratio{}.value()));
}

TEST(Histograms, LogAxisAndRatioHistogram) {
  const VariableAxis axis = logAxis(3, 0.1, 100.0);
  RatioHistogram h(axis);
  ASSERT_EQ(h.size(), 3u);
  EXPECT_DOUBLE_EQ(h.lowerEdge(0), 0.1);
  EXPECT_NEAR(h.upperEdge(0), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(h.upperEdge(2), 100.0);
  h.fill(0.5, true);
  h.fill(0.5, false);
  h.fill(50.0, true);
  h.fill(1000.0, true);  // overflow: not in total()
  h.fill(std::nan(""), true);
  EXPECT_EQ(h.bin(0).passed, 1u);
  EXPECT_EQ(h.bin(0).total, 2u);
  EXPECT_EQ(h.total().total, 3u);
  RatioHistogram g(axis);
  g.fill(5.0, false);
  h += g;
  EXPECT_EQ(h.bin(1).total, 1u);
  EXPECT_EQ(h.total().passed, 2u);
}

}  // namespace
}  // namespace conftrack

#include "conftrack/evaluation/GaussianFit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace conftrack {

namespace {

/// RMS / sigma of a Gaussian truncated symmetrically at +-k sigma.
double truncatedRmsFactor(double k) {
  const double phi = std::exp(-0.5 * k * k) / std::sqrt(2.0 * std::numbers::pi);
  const double inside = std::erf(k / std::numbers::sqrt2);  // 2 Phi(k) - 1
  return std::sqrt(std::max(1e-12, 1.0 - 2.0 * k * phi / inside));
}

double median(const std::vector<double>& sorted) {
  const std::size_t n = sorted.size();
  return n % 2 == 1 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
}

/// Mean and RMS of sorted[first, last), summed in index order.
void moments(const std::vector<double>& sorted, std::size_t first,
             std::size_t last, double& mean, double& rms) {
  const double n = double(last - first);
  double sum = 0.0;
  for (std::size_t i = first; i < last; ++i) {
    sum += sorted[i];
  }
  mean = sum / n;
  double sum2 = 0.0;
  for (std::size_t i = first; i < last; ++i) {
    sum2 += (sorted[i] - mean) * (sorted[i] - mean);
  }
  rms = std::sqrt(sum2 / n);
}

}  // namespace

GaussianFit fitGaussianCore(std::span<const double> values, double nSigma,
                            std::size_t minEntries, std::size_t maxIterations) {
  std::vector<double> sorted;
  sorted.reserve(values.size());
  for (double v : values) {
    if (std::isfinite(v)) {
      sorted.push_back(v);
    }
  }
  // Sorting makes every sum below independent of the input order.
  std::sort(sorted.begin(), sorted.end());
  GaussianFit fit;
  fit.entries = sorted.size();
  if (sorted.empty()) {
    return fit;
  }
  const auto setErrors = [&fit](std::size_t n) {
    fit.coreEntries = n;
    fit.meanError = fit.sigma / std::sqrt(double(n));
    fit.sigmaError = fit.sigma / std::sqrt(2.0 * double(n));
  };
  if (sorted.size() < std::max<std::size_t>(minEntries, 3)) {
    moments(sorted, 0, sorted.size(), fit.mean, fit.sigma);
    setErrors(sorted.size());
    return fit;
  }

  // Robust start: median and MAD (consistent with sigma for a Gaussian).
  double mean = median(sorted);
  std::vector<double> deviations(sorted.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    deviations[i] = std::abs(sorted[i] - mean);
  }
  std::sort(deviations.begin(), deviations.end());
  double sigma = 1.4826 * median(deviations);
  if (!(sigma > 0.0)) {
    // More than half the values are equal: the core has no width.
    double rms = 0.0;
    moments(sorted, 0, sorted.size(), mean, rms);
    if (!(rms > 0.0)) {
      fit.mean = mean;
      fit.sigma = 0.0;
      fit.converged = true;
      setErrors(sorted.size());
      return fit;
    }
    sigma = rms;
  }

  const double factor = truncatedRmsFactor(nSigma);
  std::size_t first = 0;
  std::size_t last = sorted.size();
  for (std::size_t iteration = 0; iteration < maxIterations; ++iteration) {
    first = static_cast<std::size_t>(
        std::lower_bound(sorted.begin(), sorted.end(), mean - nSigma * sigma) -
        sorted.begin());
    last = static_cast<std::size_t>(
        std::upper_bound(sorted.begin(), sorted.end(), mean + nSigma * sigma) -
        sorted.begin());
    if (last - first < 3) {
      break;
    }
    double newMean = 0.0;
    double rms = 0.0;
    moments(sorted, first, last, newMean, rms);
    const double newSigma = rms / factor;
    const bool settled = std::abs(newMean - mean) <= 1e-9 * newSigma &&
                         std::abs(newSigma - sigma) <= 1e-9 * newSigma;
    mean = newMean;
    sigma = newSigma;
    if (settled || !(sigma > 0.0)) {
      fit.converged = true;
      break;
    }
  }
  fit.mean = mean;
  fit.sigma = sigma;
  setErrors(std::max<std::size_t>(last - first, 1));
  return fit;
}

}  // namespace conftrack

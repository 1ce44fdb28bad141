#pragma once

/// @file GaussianFit.hpp
/// The Gaussian fit to the core of a residual or pull distribution, whose
/// standard deviation is the resolution (evaluation.md A1).

#include <cstddef>
#include <span>

namespace conftrack {

/// Result of fitGaussianCore().
struct GaussianFit {
  /// Fitted mean and standard deviation of the core Gaussian.
  double mean = 0.0;
  double sigma = 0.0;
  /// Approximate statistical errors sigma/sqrt(nCore) and
  /// sigma/sqrt(2 nCore).
  double meanError = 0.0;
  double sigmaError = 0.0;
  /// Entries given and entries inside the final window.
  std::size_t entries = 0;
  std::size_t coreEntries = 0;
  /// False if the iteration did not settle (the last estimate is returned)
  /// or there were too few entries for a core fit (then mean and sigma are
  /// the plain mean and RMS).
  bool converged = false;
};

/// Fits a Gaussian to the core of `values`: an iterative +-nSigma clipped
/// fit, the usual "fit the core within two sigma, re-centre, repeat" done
/// without binning.
///
/// Start: median and 1.4826 * MAD (robust against tails). Each iteration
/// keeps the values within mean +- nSigma * sigma and takes their mean and
/// RMS; the RMS of a Gaussian truncated at +-k sigma is
/// sigma * sqrt(1 - 2 k phi(k) / (2 Phi(k) - 1)) (0.880 sigma for k = 2),
/// so the RMS is divided by that factor. This is the moment (method of
/// moments) estimate of a truncated Gaussian, which has the same
/// expectation as a maximum-likelihood fit of the clipped core. The
/// iteration stops when mean and sigma change by less than 1e-9 sigma.
///
/// The values are sorted internally, so the result does not depend on their
/// order. Fewer than `minEntries` values: plain mean and RMS, converged =
/// false. Non-finite values are ignored.
GaussianFit fitGaussianCore(std::span<const double> values, double nSigma = 2.0,
                            std::size_t minEntries = 10,
                            std::size_t maxIterations = 100);

}  // namespace conftrack

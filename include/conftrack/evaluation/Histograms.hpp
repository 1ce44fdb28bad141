#pragma once

/// @file Histograms.hpp
/// Counting histograms (Boost.Histogram) and pass/total ratios with binomial
/// uncertainties: the building blocks of efficiency, fake-rate and
/// duplicate-rate distributions.
///
/// All contents are integer counts, so that merging partial results gives
/// the same numbers in any order (the collector's determinism relies on it).

#include <boost/histogram.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

namespace conftrack {

/// A binning with arbitrary edges (covers uniform and logarithmic bins).
using VariableAxis = boost::histogram::axis::variable<double>;

/// One-dimensional histogram of integer counts.
using CountHistogram =
    boost::histogram::histogram<std::tuple<VariableAxis>,
                                boost::histogram::dense_storage<std::uint64_t>>;

/// `n` uniform bins over [low, high].
VariableAxis uniformAxis(std::size_t n, double low, double high);
/// `n` bins over [low, high] uniform in log(x); requires 0 < low < high.
VariableAxis logAxis(std::size_t n, double low, double high);
/// An empty counting histogram with this axis.
CountHistogram makeCountHistogram(const VariableAxis& axis);

/// A ratio passed / total of integer counts (an efficiency or a rate).
struct Ratio {
  std::uint64_t passed = 0;
  std::uint64_t total = 0;

  /// Counts one entry.
  void add(bool pass) {
    ++total;
    passed += pass ? 1u : 0u;
  }
  Ratio& operator+=(const Ratio& other) {
    passed += other.passed;
    total += other.total;
    return *this;
  }
  /// passed / total, NaN when total is 0.
  double value() const;
  /// Binomial standard error sqrt(p (1 - p) / total), NaN when total is 0.
  /// Zero at p = 0 or 1: use wilsonInterval() for an interval there.
  double uncertainty() const;
  /// Wilson score interval for `z` standard deviations (default: 68.3 %),
  /// {lower, upper}; {NaN, NaN} when total is 0.
  std::pair<double, double> wilsonInterval(double z = 1.0) const;
};

/// Histogram of a ratio: per bin the entries that passed and all entries.
class RatioHistogram {
 public:
  /// An empty ratio histogram on `axis`.
  explicit RatioHistogram(const VariableAxis& axis);

  /// Counts one entry at x (NaN is ignored; out-of-range values go to the
  /// under- and overflow bins, which the CSV output leaves out).
  void fill(double x, bool passed);
  /// Adds the counts of `other`; the axes must be equal.
  RatioHistogram& operator+=(const RatioHistogram& other);

  /// Number of regular bins.
  std::size_t size() const;
  /// Lower and upper edge of regular bin i.
  double lowerEdge(std::size_t i) const;
  double upperEdge(std::size_t i) const;
  /// Counts of regular bin i.
  Ratio bin(std::size_t i) const;
  /// Sum over the regular bins (under- and overflow excluded).
  Ratio total() const;
  /// Counts of bin i, -1 being the underflow and size() the overflow bin.
  Ratio counts(int i) const;
  /// Replaces the counts of bin i (-1: underflow, size(): overflow): how
  /// saved results are read back (PerformanceDataJson.hpp).
  void setCounts(int i, const Ratio& counts);

  const CountHistogram& numerator() const { return m_numerator; }
  const CountHistogram& denominator() const { return m_denominator; }

 private:
  CountHistogram m_numerator;
  CountHistogram m_denominator;
};

}  // namespace conftrack

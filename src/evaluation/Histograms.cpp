#include "conftrack/evaluation/Histograms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace conftrack {

VariableAxis uniformAxis(std::size_t n, double low, double high) {
  if (n == 0 || !(low < high)) {
    throw std::invalid_argument("uniformAxis: need n > 0 and low < high");
  }
  std::vector<double> edges(n + 1);
  for (std::size_t i = 0; i <= n; ++i) {
    edges[i] = low + (high - low) * double(i) / double(n);
  }
  // Exact end points whatever the rounding of the steps.
  edges.back() = high;
  return VariableAxis(edges);
}

VariableAxis logAxis(std::size_t n, double low, double high) {
  if (n == 0 || !(low > 0.0 && low < high)) {
    throw std::invalid_argument("logAxis: need n > 0 and 0 < low < high");
  }
  std::vector<double> edges(n + 1);
  const double l0 = std::log10(low);
  const double l1 = std::log10(high);
  for (std::size_t i = 0; i <= n; ++i) {
    double exponent = l0 + (l1 - l0) * double(i) / double(n);
    // Decade edges exactly (1 GeV, not 0.9999999999 GeV): values at a
    // decade then fall into the bin above it, as one expects.
    if (std::abs(exponent - std::round(exponent)) < 1e-9) {
      exponent = std::round(exponent);
    }
    edges[i] = std::pow(10.0, exponent);
  }
  edges.front() = low;
  edges.back() = high;
  return VariableAxis(edges);
}

CountHistogram makeCountHistogram(const VariableAxis& axis) {
  return boost::histogram::make_histogram_with(
      boost::histogram::dense_storage<std::uint64_t>(), axis);
}

double Ratio::value() const {
  return total > 0 ? double(passed) / double(total)
                   : std::numeric_limits<double>::quiet_NaN();
}

double Ratio::uncertainty() const {
  if (total == 0) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double p = value();
  return std::sqrt(p * (1.0 - p) / double(total));
}

std::pair<double, double> Ratio::wilsonInterval(double z) const {
  if (total == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  const double n = double(total);
  const double p = value();
  const double z2 = z * z;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half =
      z * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / (1.0 + z2 / n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

RatioHistogram::RatioHistogram(const VariableAxis& axis)
    : m_numerator(makeCountHistogram(axis)),
      m_denominator(makeCountHistogram(axis)) {}

void RatioHistogram::fill(double x, bool passed) {
  if (std::isnan(x)) {
    return;
  }
  m_denominator(x);
  if (passed) {
    m_numerator(x);
  }
}

RatioHistogram& RatioHistogram::operator+=(const RatioHistogram& other) {
  m_numerator += other.m_numerator;
  m_denominator += other.m_denominator;
  return *this;
}

std::size_t RatioHistogram::size() const {
  return static_cast<std::size_t>(m_denominator.axis().size());
}

double RatioHistogram::lowerEdge(std::size_t i) const {
  return m_denominator.axis().bin(static_cast<int>(i)).lower();
}

double RatioHistogram::upperEdge(std::size_t i) const {
  return m_denominator.axis().bin(static_cast<int>(i)).upper();
}

Ratio RatioHistogram::bin(std::size_t i) const {
  return Ratio{m_numerator.at(static_cast<int>(i)),
               m_denominator.at(static_cast<int>(i))};
}

Ratio RatioHistogram::counts(int i) const {
  return Ratio{m_numerator.at(i), m_denominator.at(i)};
}

void RatioHistogram::setCounts(int i, const Ratio& counts) {
  m_numerator.at(i) = counts.passed;
  m_denominator.at(i) = counts.total;
}

Ratio RatioHistogram::total() const {
  Ratio sum;
  for (std::size_t i = 0; i < size(); ++i) {
    sum += bin(i);
  }
  return sum;
}

}  // namespace conftrack

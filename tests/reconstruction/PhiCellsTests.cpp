/// @file PhiCellsTests.cpp
/// The azimuth cells of the HitPool's searches (detail/PhiCells.hpp):
/// their lookup must give exactly std::lower_bound, and the windows
/// started from it exactly the entries and order of the binary searches.

#include "conftrack/reconstruction/finding/detail/PhiCells.hpp"
#include "conftrack/reconstruction/finding/detail/PhiWindow.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace conftrack::detail {
namespace {

constexpr double kPi = std::numbers::pi;

/// Sorted azimuths in ranges of the given sizes: uniform, clustered (a
/// narrow band, as a layer's hits near one track) and with repeats and the
/// ends +-pi.
std::vector<double> sortedRanges(const std::vector<std::uint32_t>& sizes,
                                 std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(-kPi, kPi);
  std::normal_distribution<double> band(0.7, 0.01);
  std::vector<double> phis;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    const std::size_t begin = phis.size();
    for (std::uint32_t i = 0; i < sizes[r]; ++i) {
      double phi = r % 3 == 1 ? std::clamp(band(rng), -kPi, kPi) : uniform(rng);
      if (r % 3 == 2 && i % 4 == 0 && i > 0) {
        phi = phis.back();  // a repeat
      }
      if (r % 3 == 2 && i == 1) {
        phi = -kPi;
      }
      if (r % 3 == 2 && i == 2) {
        phi = kPi;
      }
      phis.push_back(phi);
    }
    std::sort(phis.begin() + static_cast<std::ptrdiff_t>(begin), phis.end());
  }
  return phis;
}

TEST(PhiCells, LowerBoundIsStdLowerBound) {
  std::mt19937_64 rng(5);
  const std::vector<std::uint32_t> sizes = {0, 1, 3, 4, 9, 64, 200, 1000, 37};
  const std::vector<double> phis = sortedRanges(sizes, rng);
  PhiCells cells;
  cells.reserve(sizes.size(), phis.size());
  std::vector<std::uint32_t> begins;
  std::uint32_t begin = 0;
  for (std::uint32_t n : sizes) {
    EXPECT_EQ(cells.add(phis, begin, begin + n), begins.size());
    begins.push_back(begin);
    begin += n;
  }
  std::uniform_real_distribution<double> probe(-4.0, 4.0);
  std::vector<double> queries = {-kPi,
                                 kPi,
                                 -2.0 * kPi,
                                 2.0 * kPi,
                                 0.0,
                                 std::nextafter(kPi, 0.0),
                                 std::nextafter(-kPi, 0.0),
                                 std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(),
                                 std::numeric_limits<double>::quiet_NaN()};
  for (int i = 0; i < 2000; ++i) {
    queries.push_back(probe(rng));
  }
  for (std::uint32_t r = 0; r < sizes.size(); ++r) {
    const auto first = phis.begin() + begins[r];
    const auto last = first + sizes[r];
    EXPECT_EQ(cells.begin(r), begins[r]);
    EXPECT_EQ(cells.end(r), begins[r] + sizes[r]);
    // Every stored value and its neighbours, too.
    std::vector<double> own = queries;
    for (auto it = first; it != last; ++it) {
      own.push_back(*it);
      own.push_back(std::nextafter(*it, -4.0));
      own.push_back(std::nextafter(*it, 4.0));
    }
    for (double lo : own) {
      const auto expected = static_cast<std::size_t>(
          std::lower_bound(first, last, lo) - phis.begin());
      EXPECT_EQ(cells.lowerBound(phis, r, lo), expected)
          << "range " << r << ", lo " << lo;
    }
  }
}

TEST(PhiCells, WindowsVisitTheSameEntriesInTheSameOrder) {
  std::mt19937_64 rng(9);
  const std::vector<std::uint32_t> sizes = {500, 40, 2, 120};
  const std::vector<double> phis = sortedRanges(sizes, rng);
  PhiCells cells;
  std::uint32_t begin = 0;
  std::vector<std::uint32_t> begins;
  for (std::uint32_t n : sizes) {
    cells.add(phis, begin, begin + n);
    begins.push_back(begin);
    begin += n;
  }
  std::uniform_real_distribution<double> centre(-kPi, kPi);
  std::uniform_real_distribution<double> width(0.0, 1.0);
  for (int i = 0; i < 3000; ++i) {
    // Windows across the wrap at +-pi, wider than pi, and empty.
    const double phi = i % 7 == 0 ? kPi - 0.01 : centre(rng);
    const double half = i % 11 == 0 ? 4.0 : width(rng) * width(rng);
    for (std::uint32_t r = 0; r < sizes.size(); ++r) {
      std::vector<std::size_t> expected;
      std::vector<std::size_t> got;
      // Reference: two binary searches per interval.
      const auto first = phis.begin() + begins[r];
      const auto last = first + sizes[r];
      forEachPhiInterval(phi, half, [&](double lo, double hi) {
        const auto from = std::lower_bound(first, last, lo);
        const auto to = std::upper_bound(from, last, hi);
        for (auto it = from; it != to; ++it) {
          expected.push_back(static_cast<std::size_t>(it - phis.begin()));
        }
      });
      forEachInPhiWindow(phis, cells, r, phi, half,
                         [&](std::size_t k) { got.push_back(k); });
      EXPECT_EQ(got, expected)
          << "range " << r << ", phi " << phi << ", half-width " << half;
    }
  }
}

}  // namespace
}  // namespace conftrack::detail

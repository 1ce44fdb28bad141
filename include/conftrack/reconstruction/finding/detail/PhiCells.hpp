#pragma once

/// @file PhiCells.hpp
/// An index of equal azimuth cells over the ranges of a phi-sorted array
/// (a layer's or a bin's hits in the HitPool; internal): where each cell's
/// entries begin, so that an azimuth window starts with a lookup and a
/// short scan instead of a binary search (docs/algorithm.md section 6).

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

namespace conftrack::detail {

class PhiCells {
 public:
  /// Mean number of entries per cell: the scan after the lookup passes
  /// about half of them.
  static constexpr std::uint32_t kEntriesPerCell = 4;

  /// Indexes the range [begin, end) of `phis`, sorted ascending (azimuths
  /// in [-pi, pi]; any values are allowed, the lookup stays exact).
  /// Returns the range's id (0, 1, ... in the order of the calls).
  std::uint32_t add(const std::vector<double>& phis, std::uint32_t begin,
                    std::uint32_t end);

  /// The first index i of range `range` with !(phis[i] < lo), or its end:
  /// exactly std::lower_bound over the range, for any lo (NaN included).
  /// `phis` must be the array the range was added from, unchanged.
  std::size_t lowerBound(const std::vector<double>& phis, std::uint32_t range,
                         double lo) const {
    const Range& r = m_ranges[range];
    // The cell holding lo; rounding may pick a neighbour, and the scans
    // below correct any start, so the result is the lower bound whatever
    // the cell (NaN and values outside [-pi, pi] land in the end cells).
    const double x = (lo + std::numbers::pi) * r.cellsPerRadian;
    std::uint32_t cell = 0;
    if (x >= static_cast<double>(r.cells)) {
      cell = r.cells - 1;
    } else if (x > 0.0) {
      cell = static_cast<std::uint32_t>(x);
    }
    std::size_t s = m_cellStart[r.firstCell + cell];
    while (s > r.begin && !(phis[s - 1] < lo)) {
      --s;
    }
    while (s < r.end && phis[s] < lo) {
      ++s;
    }
    return s;
  }

  /// [begin, end) of range `range`.
  std::uint32_t begin(std::uint32_t range) const {
    return m_ranges[range].begin;
  }
  std::uint32_t end(std::uint32_t range) const { return m_ranges[range].end; }

  void reserve(std::size_t ranges, std::size_t entries);

 private:
  struct Range {
    std::uint32_t begin;
    std::uint32_t end;
    std::uint32_t firstCell;  ///< into m_cellStart
    std::uint32_t cells;
    double cellsPerRadian;
  };
  std::vector<Range> m_ranges;
  /// Per cell: the first index of the range with azimuth >= the cell's
  /// lower edge, -pi + c / cellsPerRadian (the lower bound of that edge).
  std::vector<std::uint32_t> m_cellStart;
};

}  // namespace conftrack::detail

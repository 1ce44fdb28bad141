#include "conftrack/reconstruction/finding/detail/PhiCells.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace conftrack::detail {

namespace {
double cellEdge(std::uint32_t cell, double cellsPerRadian) {
  return -std::numbers::pi + static_cast<double>(cell) / cellsPerRadian;
}
}  // namespace

void PhiCells::reserve(std::size_t ranges, std::size_t entries) {
  m_ranges.reserve(ranges);
  m_cellStart.reserve(entries / kEntriesPerCell + ranges);
}

std::uint32_t PhiCells::add(const std::vector<double>& phis,
                            std::uint32_t begin, std::uint32_t end) {
  const std::uint32_t cells =
      std::max<std::uint32_t>(1, (end - begin) / kEntriesPerCell);
  const double cellsPerRadian =
      static_cast<double>(cells) / (2.0 * std::numbers::pi);
  const auto firstCell = static_cast<std::uint32_t>(m_cellStart.size());
  // One merge pass: each cell starts at the lower bound of its edge.
  std::uint32_t i = begin;
  for (std::uint32_t c = 0; c < cells; ++c) {
    const double edge = cellEdge(c, cellsPerRadian);
    while (i < end && phis[i] < edge) {
      ++i;
    }
    m_cellStart.push_back(i);
  }
  m_ranges.push_back({begin, end, firstCell, cells, cellsPerRadian});
  return static_cast<std::uint32_t>(m_ranges.size() - 1);
}

}  // namespace conftrack::detail

#pragma once

/// @file PhiWindow.hpp
/// Small helpers shared by the HitPool searches (HitPool.cpp,
/// HitPoolCone.cpp, HitPoolRz.cpp; internal).

#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/detail/PhiCells.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

namespace conftrack::detail {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Cosine and sine of an angle, recomputed only when it changes: most
/// searches use one half-angle throughout (one cache per call site and
/// thread).
struct TrigCache {
  double angle = 0.0;
  double cos = 1.0;
  double sin = 0.0;
  void update(double a) {
    if (a != angle) {
      angle = a;
      cos = std::cos(a);
      sin = std::sin(a);
    }
  }
};

/// Calls scan(lo, hi) for each azimuth interval of the window of
/// halfWidth about phi: one, or two where it wraps at +-pi (the part from
/// -pi on each side of the wrap second), or [-2 pi, 2 pi] for a window of
/// pi or more.
template <typename Scan>
inline void forEachPhiInterval(double phi, double halfWidth, Scan&& scan) {
  if (halfWidth >= std::numbers::pi) {
    scan(-kTwoPi, kTwoPi);
    return;
  }
  const double lo = phi - halfWidth;
  const double hi = phi + halfWidth;
  scan(std::max(lo, -std::numbers::pi), std::min(hi, std::numbers::pi));
  if (lo < -std::numbers::pi) {
    scan(lo + kTwoPi, std::numbers::pi);
  }
  if (hi > std::numbers::pi) {
    scan(-std::numbers::pi, hi - kTwoPi);
  }
}

/// Calls visit(i) for each index i of range `range` of `cells` (indexing
/// the phi-sorted `phis`) within halfWidth of phi, wrapping at +-pi, in the
/// order of the range (from -pi on each side of the wrap): each interval
/// starts at a cell lookup and ends in the visiting loop, where two binary
/// searches would find the same indices.
template <typename Visit>
inline void forEachInPhiWindow(const std::vector<double>& phis,
                               const PhiCells& cells, std::uint32_t range,
                               double phi, double halfWidth, Visit&& visit) {
  const std::size_t end = cells.end(range);
  forEachPhiInterval(phi, halfWidth, [&](double lo, double hi) {
    // Up to the first entry above hi: std::upper_bound's end.
    for (std::size_t i = cells.lowerBound(phis, range, lo);
         i != end && !(hi < phis[i]); ++i) {
      visit(i);
    }
  });
}

/// Appends the ids (parallel to `phis`) of range `range` of `cells` within
/// halfWidth of phi, wrapping at +-pi.
inline void collectPhiWindow(const std::vector<double>& phis,
                             const std::vector<ConfIndex>& ids,
                             const PhiCells& cells, std::uint32_t range,
                             double phi, double halfWidth,
                             std::vector<ConfIndex>& out) {
  forEachInPhiWindow(phis, cells, range, phi, halfWidth,
                     [&](std::size_t i) { out.push_back(ids[i]); });
}

}  // namespace conftrack::detail

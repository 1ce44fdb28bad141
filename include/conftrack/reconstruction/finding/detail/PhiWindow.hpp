#pragma once

/// @file PhiWindow.hpp
/// Small helpers shared by the HitPool searches (HitPool.cpp,
/// HitPoolCone.cpp, HitPoolRz.cpp; internal).

#include "conftrack/reconstruction/finding/ConformalHits.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
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

/// Calls visit(i) for each index i of the phi-sorted range [begin, end) of
/// `phis` within halfWidth of phi, wrapping at +-pi, in the order of the
/// range (from -pi on each side of the wrap).
template <typename Visit>
inline void forEachInPhiWindow(const std::vector<double>& phis,
                               std::size_t begin, std::size_t end, double phi,
                               double halfWidth, Visit&& visit) {
  auto scan = [&](double lo, double hi) {
    auto first = std::lower_bound(phis.begin() + begin, phis.begin() + end, lo);
    auto last = std::upper_bound(first, phis.begin() + end, hi);
    const auto firstIndex = static_cast<std::size_t>(first - phis.begin());
    const auto lastIndex = static_cast<std::size_t>(last - phis.begin());
    for (std::size_t i = firstIndex; i != lastIndex; ++i) {
      visit(i);
    }
  };
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

/// Appends the entries of the phi-sorted range [begin, end) of `phis`
/// (ids parallel) within halfWidth of phi, wrapping at +-pi.
inline void collectPhiWindow(const std::vector<double>& phis,
                             const std::vector<ConfIndex>& ids,
                             std::size_t begin, std::size_t end, double phi,
                             double halfWidth, std::vector<ConfIndex>& out) {
  forEachInPhiWindow(phis, begin, end, phi, halfWidth,
                     [&](std::size_t i) { out.push_back(ids[i]); });
}

}  // namespace conftrack::detail

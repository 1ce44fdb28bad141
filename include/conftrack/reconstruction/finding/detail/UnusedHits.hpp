#pragma once

/// @file UnusedHits.hpp
/// The hits no track holds, in strips of x sorted by y (internal): the
/// looper rule's searches for single hits on a track's further turns
/// (TrackMergingTurnHits.cpp, TrackMergingTurnFollower.cpp) read only the
/// hits in the box of the arc they may still run.

#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <tuple>
#include <vector>

namespace conftrack::detail {

/// Width of the strips of x of UnusedHits [mm].
inline constexpr double kUnusedStripWidth = 20.0;

/// Most strips (a wider spread of hits gets wider strips).
inline constexpr std::size_t kUnusedMaxStrips = 1024;

/// The unused hits in strips of x, each sorted by y: the hits in a box
/// are those of a few strips, each a binary search. The index is built
/// once; hits marked used afterwards (`used`, held by reference) are
/// skipped, so several searches can share it while each takes hits.
class UnusedHits {
 public:
  /// The hits h with used[h] == 0; `used` must outlive the index.
  UnusedHits(const ConformalHits& hits, const std::vector<std::uint8_t>& used)
      : m_used(&used) {
    double xMax = -std::numeric_limits<double>::infinity();
    for (ConfIndex h = 0; h < hits.size(); ++h) {
      if (used[h] == 0) {
        m_x0 = std::min(m_x0, hits.x[h]);
        xMax = std::max(xMax, hits.x[h]);
      }
    }
    if (!(m_x0 <= xMax)) {
      return;  // no unused hit
    }
    m_width =
        std::max(kUnusedStripWidth, (xMax - m_x0) / (kUnusedMaxStrips - 1));
    const std::size_t strips = stripOf(xMax) + 1;
    m_start.assign(strips + 1, 0);
    for (ConfIndex h = 0; h < hits.size(); ++h) {
      if (used[h] == 0) {
        ++m_start[stripOf(hits.x[h]) + 1];
      }
    }
    for (std::size_t k = 1; k <= strips; ++k) {
      m_start[k] += m_start[k - 1];
    }
    m_byY.resize(m_start.back());
    std::vector<std::uint32_t> fill(m_start.begin(), m_start.end() - 1);
    for (ConfIndex h = 0; h < hits.size(); ++h) {
      if (used[h] == 0) {
        m_byY[fill[stripOf(hits.x[h])]++] = h;
      }
    }
    for (std::size_t k = 0; k < strips; ++k) {
      std::sort(m_byY.begin() + m_start[k], m_byY.begin() + m_start[k + 1],
                [&](ConfIndex a, ConfIndex b) {
                  return std::tie(hits.y[a], a) < std::tie(hits.y[b], b);
                });
    }
    m_y.reserve(m_byY.size());
    for (ConfIndex h : m_byY) {
      m_y.push_back(hits.y[h]);
    }
  }

  /// Calls f(h) for each hit still unused in the box of the arc of circle
  /// `c` that starts at angle `start` round its centre and runs `sweep`
  /// radians along the motion (the whole circle from 2 pi on), widened by
  /// `band`: a superset of the unused hits within `band` of the arc.
  template <class F>
  void forEachNear(const TransverseCircle& c, double band, double start,
                   double sweep, F&& f) const {
    if (m_y.empty()) {
      return;
    }
    double xLo = c.cx - c.rho;
    double xHi = c.cx + c.rho;
    double yLo = c.cy - c.rho;
    double yHi = c.cy + c.rho;
    if (sweep < 2.0 * std::numbers::pi) {
      // The arc's ends, and each axis extreme that the arc passes.
      const auto include = [&](double angle) {
        const double x = c.cx + c.rho * std::cos(angle);
        const double y = c.cy + c.rho * std::sin(angle);
        xLo = std::min(xLo, x);
        xHi = std::max(xHi, x);
        yLo = std::min(yLo, y);
        yHi = std::max(yHi, y);
      };
      xLo = yLo = std::numeric_limits<double>::infinity();
      xHi = yHi = -xLo;
      include(start);
      include(start + c.orientation * sweep);
      for (int q = 0; q < 4; ++q) {
        const double axis = 0.5 * std::numbers::pi * q;
        double ahead = std::remainder(c.orientation * (axis - start),
                                      2.0 * std::numbers::pi);
        if (ahead < 0.0) {
          ahead += 2.0 * std::numbers::pi;
        }
        if (ahead <= sweep) {
          include(axis);
        }
      }
    }
    if (xHi + band < m_x0) {
      return;
    }
    const std::size_t strips = m_start.size() - 1;
    const std::size_t first = xLo - band <= m_x0 ? 0 : stripOf(xLo - band);
    const std::size_t last = std::min(stripOf(xHi + band), strips - 1);
    for (std::size_t k = first; k <= last; ++k) {
      const auto begin = m_y.begin() + m_start[k];
      const auto end = m_y.begin() + m_start[k + 1];
      for (auto it = std::lower_bound(begin, end, yLo - band);
           it != end && *it <= yHi + band; ++it) {
        const ConfIndex h = m_byY[static_cast<std::size_t>(it - m_y.begin())];
        if ((*m_used)[h] == 0) {
          f(h);
        }
      }
    }
  }

 private:
  std::size_t stripOf(double x) const {
    return static_cast<std::size_t>((x - m_x0) / m_width);
  }

  const std::vector<std::uint8_t>* m_used;
  double m_x0 = std::numeric_limits<double>::infinity();
  double m_width = kUnusedStripWidth;
  std::vector<std::uint32_t> m_start;  ///< first hit of each strip
  std::vector<ConfIndex> m_byY;        ///< unused hits by strip, then y
  std::vector<double> m_y;             ///< their y
};

}  // namespace conftrack::detail

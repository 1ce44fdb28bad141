// The beam-line pre-pass (BeamSpotPrepass.hpp, algorithm.md 3.24): circles
// through triplets of hits on three inner barrel layers, and the point they
// pass closest to, fitted with trimming.

#include "conftrack/reconstruction/finding/BeamSpotPrepass.hpp"

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/detail/PhiWindow.hpp"
#include "conftrack/reconstruction/finding/detail/PrepassLayers.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace conftrack {

namespace {

constexpr double kPi = std::numbers::pi;
/// Iterations of the trimmed fit (it converges in three or four).
constexpr int kMaxIterations = 10;
/// The fit stops once a step moves the point by less than this [mm].
constexpr double kConvergence = 1e-4;
/// ... or, when the set of circles in the window keeps changing, once the
/// last step is below this [mm] (far below the estimate's accuracy).
constexpr double kSettled = 1e-3;
/// Least weight of the circles along the weaker axis of the plane (the
/// smaller eigenvalue of the sum of g g^T, in circles): both coordinates
/// must be measured. A tt-bar event's tracks come in a few jets, and the
/// circles of one jet measure one direction only.
constexpr double kMinWeakWeight = 1.0;

/// The hits of one layer in (azimuth, id) order.
struct LayerHits {
  std::vector<double> phi, r, x, y, z;
};

/// The hits of each of `layers` (one pass over the event), each in
/// (azimuth, id) order.
std::vector<LayerHits> layerHits(std::span<const Hit> hits,
                                 const Detector& detector,
                                 const std::vector<std::uint32_t>& layers) {
  std::vector<std::vector<std::pair<double, std::size_t>>> order(layers.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const std::optional<std::uint32_t> l = detector.findLayer(hits[i].detId);
    const auto it =
        l ? std::find(layers.begin(), layers.end(), *l) : layers.end();
    if (it != layers.end()) {
      const Vector3& p = hits[i].position;
      order[static_cast<std::size_t>(it - layers.begin())].emplace_back(
          std::atan2(p.y(), p.x()), i);
    }
  }
  std::vector<LayerHits> out(layers.size());
  for (std::size_t k = 0; k < layers.size(); ++k) {
    std::sort(
        order[k].begin(), order[k].end(), [&](const auto& a, const auto& b) {
          return a.first != b.first ? a.first < b.first
                                    : hits[a.second].id < hits[b.second].id;
        });
    for (const auto& [phi, i] : order[k]) {
      const Vector3& p = hits[i].position;
      out[k].phi.push_back(phi);
      out[k].r.push_back(std::hypot(p.x(), p.y()));
      out[k].x.push_back(p.x());
      out[k].y.push_back(p.y());
      out[k].z.push_back(p.z());
    }
  }
  return out;
}

/// Calls f(k) for the hits of `l` within `half` of azimuth `phi`.
template <typename F>
void forEachInWindow(const LayerHits& l, double phi, double half, F&& f) {
  const std::vector<double>& p = l.phi;
  detail::forEachPhiInterval(phi, half, [&](double lo, double hi) {
    auto it = std::lower_bound(p.begin(), p.end(), lo);
    for (; it != p.end() && *it <= hi; ++it) {
      f(static_cast<std::size_t>(it - p.begin()));
    }
  });
}

/// A circle of the fit: centre and radius [mm].
struct Circle {
  double cx, cy, rho;
};

/// The circle through three points; false if they are (nearly) collinear.
bool circleThrough(double ax, double ay, double bx, double by, double cx,
                   double cy, Circle& out) {
  const double ux = bx - ax;
  const double uy = by - ay;
  const double vx = cx - ax;
  const double vy = cy - ay;
  const double d = 2.0 * (ux * vy - uy * vx);
  const double u2 = ux * ux + uy * uy;
  const double v2 = vx * vx + vy * vy;
  if (!(std::abs(d) > 1e-12 * std::sqrt(u2 * v2))) {
    return false;
  }
  const double ox = (vy * u2 - uy * v2) / d;
  const double oy = (ux * v2 - vx * u2) / d;
  out = {ax + ox, ay + oy, std::hypot(ox, oy)};
  return std::isfinite(out.rho);
}

/// Cell sizes of the coarse vote over the whole range and of the fine one
/// about its result [mm], and the fine vote's half-width: the fine cells
/// are below the spread of good circles at the beam line (tens of um).
constexpr double kCoarseCell = 0.25;
constexpr double kFineCell = 0.02;
constexpr double kFineHalf = 0.5;

/// Direction sectors of the vote (over pi: a track and one in the
/// opposite direction measure the same coordinate).
constexpr int kSectors = 8;

/// The point of a grid of half-width `half` about `start` (cells of
/// `cell`) that the circles from the most directions cross: each circle
/// marks the cells it crosses with the sector of its direction there, and
/// each 3 x 3 block of cells scores the number of sectors marked in it
/// (ties: the most crossings, then the lowest cell). Counting crossings
/// alone, the random triplets of one dense jet, nearly parallel circles,
/// cross each other more often somewhere along the jet than the tracks
/// cross at the beam line; only at the beam line do circles from all
/// directions meet.
Vector2 votedPoint(const std::vector<Circle>& circles, const Vector2& start,
                   double half, double cell) {
  const int n = static_cast<int>(std::ceil(2.0 * half / cell));
  const auto cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  std::vector<std::uint8_t> sectors(cells, 0);
  std::vector<std::uint32_t> crossings(cells, 0);
  const double x0 = start.x() - half;
  const double y0 = start.y() - half;
  for (const Circle& c : circles) {
    const Vector2 toStart(start.x() - c.cx, start.y() - c.cy);
    // The circle's direction at the start is perpendicular to toStart.
    double angle = std::atan2(toStart.x(), -toStart.y());
    angle = angle < 0.0 ? angle + kPi : angle;
    const auto bit = static_cast<std::uint8_t>(
        1U << std::min(kSectors - 1, static_cast<int>(angle / kPi * kSectors)));
    // One cell per column (or row) along the axis the circle runs closer
    // to: it is nearly straight across the grid.
    const bool alongX = std::abs(toStart.y()) >= std::abs(toStart.x());
    const double side = alongX ? toStart.y() : toStart.x();
    for (int k = 0; k < n; ++k) {
      const double t = (alongX ? x0 : y0) + (k + 0.5) * cell;
      const double d = t - (alongX ? c.cx : c.cy);
      const double h2 = c.rho * c.rho - d * d;
      if (h2 < 0.0) {
        continue;
      }
      // The branch on the start's side of the centre.
      const double other =
          (alongX ? c.cy : c.cx) + std::copysign(std::sqrt(h2), side);
      // Checked as a double: a circle far from the grid would overflow the
      // conversion to int.
      const double row = std::floor((other - (alongX ? y0 : x0)) / cell);
      if (!(row >= 0.0 && row < double(n))) {
        continue;
      }
      const auto m = static_cast<int>(row);
      const std::size_t at = alongX ? static_cast<std::size_t>(m) * n + k
                                    : static_cast<std::size_t>(k) * n + m;
      sectors[at] |= bit;
      ++crossings[at];
    }
  }
  int bestSectors = -1;
  std::uint64_t bestCrossings = 0;
  int bi = n / 2;
  int bj = n / 2;
  for (int j = 1; j + 1 < n; ++j) {
    for (int i = 1; i + 1 < n; ++i) {
      std::uint8_t mask = 0;
      std::uint64_t sum = 0;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          const std::size_t at =
              static_cast<std::size_t>(j + dj) * n + (i + di);
          mask |= sectors[at];
          sum += crossings[at];
        }
      }
      const int count = std::popcount(mask);
      if (count > bestSectors ||
          (count == bestSectors && sum > bestCrossings)) {
        bestSectors = count;
        bestCrossings = sum;
        bi = i;
        bj = j;
      }
    }
  }
  return {x0 + (bi + 0.5) * cell, y0 + (bj + 0.5) * cell};
}

/// Signed distance of point b from circle c (positive outside).
double residual(const Circle& c, const Vector2& b) {
  return std::hypot(b.x() - c.cx, b.y() - c.cy) - c.rho;
}

/// The innermost layer, then each first one at least `gap` further out;
/// fewer than three if the layers do not allow it.
std::vector<std::uint32_t> spacedLayers(const Detector& detector,
                                        const std::vector<std::uint32_t>& all,
                                        double gap) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t l : all) {
    if (out.empty() ||
        detector.layers()[l].r >= detector.layers()[out.back()].r + gap) {
      out.push_back(l);
    }
    if (out.size() == 3) {
      break;
    }
  }
  return out;
}

}  // namespace

std::optional<std::pair<std::string, std::string>> BeamSpotPrepass::findProblem(
    const Config& c, const Detector& detector) {
  using units::GeV;
  using units::mm;
  using units::rad;
  struct Q {
    const char* key = nullptr;
    double value = 0.0;
    Range range;
  };
  const double halfPi = kPi / 2.0;
  for (const Q& q : {
           Q{"min_layer_gap_mm", c.minLayerGap / mm, Range{0.0, 1e4, false}},
           Q{"max_dphi", c.maxDeltaPhi / rad, Range{0.0, halfPi, false}},
           Q{"confirm_dphi", c.confirmPhi / rad, Range{0.0, halfPi, false}},
           Q{"confirm_dz_mm", c.confirmZ / mm, Range{0.0, 1e4, false}},
           Q{"max_z_mm", c.maxAbsZ / mm, Range{0.0, 1e5, false}},
           Q{"min_pt_GeV", c.minPt / GeV, Range{0.0, 1e4, false}},
           Q{"max_d0_mm", c.maxD0 / mm, Range{0.0, 10.0, false}},
           Q{"max_seed_hits", static_cast<double>(c.maxSeedHits),
             Range::closed(1.0, 1e9)},
           Q{"min_triplets", static_cast<double>(c.minTriplets),
             Range::closed(3.0, 1e9)},
           Q{"min_scale_mm", c.minScale / mm, Range{0.0, 100.0, false}},
       }) {
    std::string what = rangeViolation(q.value, q.range);
    if (!what.empty()) {
      return std::make_pair(std::string(q.key), what);
    }
  }
  if (c.collections.empty()) {
    return std::make_pair(std::string("collections"),
                          std::string("must not be empty"));
  }
  if (auto what = subdetectorListProblem(c.collections, detector)) {
    return std::make_pair(std::string("collections"), *what);
  }
  const std::vector<std::uint32_t> spaced = spacedLayers(
      detector, detail::barrelLayersByRadius(detector, c.collections),
      c.minLayerGap);
  if (spaced.size() < 3) {
    return std::make_pair(std::string("collections"),
                          "need three barrel layers at least "
                          "min_layer_gap_mm apart (have " +
                              std::to_string(spaced.size()) + ")");
  }
  return std::nullopt;
}

BeamSpotPrepass::BeamSpotPrepass(const Detector& detector, Config config)
    : m_detector(&detector), m_config(std::move(config)) {
  if (auto p = findProblem(m_config, detector)) {
    throw std::invalid_argument("BeamSpotPrepass: key '" + p->first +
                                "': " + p->second);
  }
  m_layers = spacedLayers(
      detector, detail::barrelLayersByRadius(detector, m_config.collections),
      m_config.minLayerGap);
}

BeamSpotPrepass::Result BeamSpotPrepass::run(std::span<const Hit> hits,
                                             const Vector2& start) const {
  const auto t0 = std::chrono::steady_clock::now();
  const Config& c = m_config;
  const std::vector<LayerHits> onLayers =
      layerHits(hits, *m_detector, m_layers);
  const LayerHits& l0 = onLayers[0];
  const LayerHits& l1 = onLayers[1];
  const LayerHits& l2 = onLayers[2];
  const double r0 = m_detector->layers()[m_layers[0]].r;
  const double r1 = m_detector->layers()[m_layers[1]].r;
  const double r2 = m_detector->layers()[m_layers[2]].r;
  // A straight track from a beam line d off the configured one reaches
  // radius r at an azimuth offset by about d / r: the pair's window widens
  // by the difference over its two layers, the third hit's by how far that
  // offset departs from the linear extrapolation, both for d = maxD0.
  const double pairWindow = c.maxDeltaPhi + c.maxD0 * (1.0 / r0 - 1.0 / r1);
  const double linear =
      1.0 / r1 + (1.0 / r1 - 1.0 / r0) * (r2 - r1) / (r1 - r0);
  const double confirmWindow =
      c.confirmPhi + c.maxD0 * std::abs(1.0 / r2 - linear);
  // Radius of a minPt track's circle in the detector's central field.
  const double minRho =
      c.minPt / (constants::kPtPerTeslaMm * std::abs(m_detector->bz()));
  Result result;
  result.position = start;
  std::vector<Circle> circles;
  const std::size_t stride = (l0.phi.size() + c.maxSeedHits - 1) /
                             std::max<std::size_t>(1, c.maxSeedHits);
  for (std::size_t a = 0; a < l0.phi.size();
       a += std::max<std::size_t>(1, stride)) {
    forEachInWindow(l1, l0.phi[a], pairWindow, [&](std::size_t b) {
      const double dr = l1.r[b] - l0.r[a];
      if (!(dr > 0.0)) {
        return;
      }
      const double slope = (l1.z[b] - l0.z[a]) / dr;
      const double z0 = l0.z[a] - slope * l0.r[a];
      if (std::abs(z0) > c.maxAbsZ) {
        return;
      }
      const double dphi = detail::wrapAzimuth(l1.phi[b] - l0.phi[a]);
      const double predicted =
          detail::wrapAzimuth(l1.phi[b] + dphi * (r2 - l1.r[b]) / dr);
      forEachInWindow(l2, predicted, confirmWindow, [&](std::size_t k) {
        if (std::abs(l2.z[k] - (z0 + slope * l2.r[k])) > c.confirmZ) {
          return;
        }
        Circle circle{};
        if (!circleThrough(l0.x[a], l0.y[a], l1.x[b], l1.y[b], l2.x[k], l2.y[k],
                           circle) ||
            circle.rho < minRho ||
            std::abs(residual(circle, start)) > c.maxD0) {
          return;
        }
        circles.push_back(circle);
      });
    });
  }
  result.triplets = circles.size();
  // Random triplets of other particles' hits outnumber the tracks' in jets
  // and with overlay, so the start of the fit is found by a vote: each
  // circle votes for the cells of a grid about the start that it crosses,
  // and the fit starts at the cell most voted for (with its neighbours).
  Vector2 b = start;
  if (circles.size() >= c.minTriplets) {
    b = votedPoint(circles, start, c.maxD0, kCoarseCell);
    b = votedPoint(circles, b, kFineHalf, kFineCell);
  }
  // Then least squares of |b - c_i| - rho_i = 0 (Gauss-Newton) over the
  // circles within a window about b: at first five fine cells, then three
  // robust standard deviations (1.4826 times their median absolute
  // residual, at least minScale) of the residuals inside it, never wider.
  double window = 5.0 * kFineCell;
  std::size_t inliers = 0;
  Matrix2 normal = Matrix2::Zero();
  double scale = c.minScale;
  bool converged = false;
  std::vector<double> inside;
  for (int it = 0; it < kMaxIterations && circles.size() >= c.minTriplets;
       ++it) {
    normal.setZero();
    Vector2 rhs = Vector2::Zero();
    inliers = 0;
    inside.clear();
    for (const Circle& circle : circles) {
      const double r = residual(circle, b);
      if (std::abs(r) > window) {
        continue;
      }
      const Vector2 d(b.x() - circle.cx, b.y() - circle.cy);
      const Vector2 g = d / d.norm();
      normal += g * g.transpose();
      rhs -= g * r;
      inside.push_back(std::abs(r));
      ++inliers;
    }
    if (inliers < c.minTriplets) {
      break;
    }
    const double weaker =
        normal.selfadjointView<Eigen::Upper>().eigenvalues().minCoeff();
    if (!(weaker >= kMinWeakWeight)) {
      break;
    }
    const Vector2 step = normal.ldlt().solve(rhs);
    b += step;
    const auto mid = inside.begin() + static_cast<std::ptrdiff_t>(inliers / 2);
    std::nth_element(inside.begin(), mid, inside.end());
    scale = std::max(c.minScale, 1.4826 * *mid);
    window = std::min(window, 3.0 * scale);
    converged = step.norm() < kSettled;
    if (step.norm() < kConvergence) {
      break;
    }
  }
  // A point at the edge of the vote's grid is that of circles cut by
  // maxD0, not the beam line; and the finder maps about a beam line within
  // kMaxBeamLineOffset only.
  const bool onGrid =
      (b - start).cwiseAbs().maxCoeff() <= c.maxD0 - 3.0 * kCoarseCell;
  if (converged && onGrid && std::abs(b.x()) <= kMaxBeamLineOffset &&
      std::abs(b.y()) <= kMaxBeamLineOffset) {
    result.valid = true;
    result.position = b;
    result.inliers = inliers;
    const Matrix2 cov = normal.inverse() * scale * scale;
    result.uncertainty = std::sqrt(std::max(cov(0, 0), cov(1, 1)));
  }
  result.milliseconds = std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - t0)
                            .count();
  return result;
}

}  // namespace conftrack

#include "conftrack/geometry/ModuleLayout.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>

namespace conftrack {

namespace {

constexpr double kPi = std::numbers::pi;

double wrapPhi(double phi) { return std::remainder(phi, 2.0 * kPi); }

/// Distance of the z axis from a convex sensor in the transverse plane:
/// 0 if the sensor covers the axis, else the nearest edge point.
double nearestRadius(const std::array<Vector3, 4>& corners) {
  double best = std::numeric_limits<double>::infinity();
  int nLeft = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Vector2 a = corners[i].head<2>();
    const Vector2 ab = corners[(i + 1) % 4].head<2>() - a;
    const double t = ab.squaredNorm() > 0.0
                         ? std::clamp(-a.dot(ab) / ab.squaredNorm(), 0.0, 1.0)
                         : 0.0;
    best = std::min(best, (a + t * ab).norm());
    nLeft += (ab.x() * a.y() - ab.y() * a.x()) < 0.0 ? 1 : 0;
  }
  return (nLeft == 0 || nLeft == 4) ? 0.0 : best;
}

std::string moduleName(const PlanarModule& m) {
  return "ModuleLayout: module " + std::to_string(m.module) + " of layer " +
         std::to_string(m.layer);
}

}  // namespace

ModuleLayout::ModuleLayout(const Detector& detector,
                           std::vector<PlanarModule> modules,
                           std::vector<double> supportX0)
    : m_layers(detector.layers().size()) {
  if (!supportX0.empty() && supportX0.size() != m_layers.size()) {
    throw std::invalid_argument(
        "ModuleLayout: supportX0 needs one value per layer (" +
        std::to_string(m_layers.size()) + "), got " +
        std::to_string(supportX0.size()));
  }
  for (const PlanarModule& m : modules) {
    if (m.layer >= m_layers.size()) {
      throw std::invalid_argument(moduleName(m) + ": layer index out of range");
    }
    if (!(m.minHalfU > 0.0 && m.maxHalfU > 0.0 && m.halfV > 0.0 &&
          m.thickness > 0.0 && m.thicknessX0 >= 0.0 && m.sigmaU > 0.0 &&
          m.sigmaV > 0.0)) {
      throw std::invalid_argument(moduleName(m) +
                                  ": sizes and resolutions must be positive");
    }
    if (!(m.rotation.transpose() * m.rotation)
             .isApprox(Matrix3::Identity(), 1e-3)) {
      throw std::invalid_argument(moduleName(m) +
                                  ": rotation is not orthonormal");
    }
  }
  // Rotations read from files carry a few printed digits: make them exactly
  // orthonormal (Gram-Schmidt, keeping the u axis), so that hit frames are.
  for (PlanarModule& m : modules) {
    const Vector3 u = m.rotation.col(0).normalized();
    const Vector3 v =
        (m.rotation.col(1) - m.rotation.col(1).dot(u) * u).normalized();
    const double handedness =
        u.cross(v).dot(m.rotation.col(2)) < 0.0 ? -1.0 : 1.0;
    m.rotation.col(0) = u;
    m.rotation.col(1) = v;
    m.rotation.col(2) = handedness * u.cross(v);
  }
  std::stable_sort(modules.begin(), modules.end(),
                   [](const PlanarModule& a, const PlanarModule& b) {
                     return a.layer < b.layer;
                   });
  m_modules = std::move(modules);
  m_extents.resize(m_modules.size());
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  for (std::uint32_t i = 0; i < m_modules.size(); ++i) {
    const PlanarModule& m = m_modules[i];
    if (!seen.insert({m.layer, m.module}).second) {
      throw std::invalid_argument(moduleName(m) + ": duplicate module number");
    }
    Layer& layer = m_layers[m.layer];
    if (layer.end == 0) {
      layer.begin = i;
    }
    layer.end = i + 1;
  }
  for (std::uint32_t l = 0; l < m_layers.size(); ++l) {
    Layer& layer = m_layers[l];
    const SensitiveLayer& surface = detector.layers()[l];
    layer.disk = surface.isDisk();
    if (!supportX0.empty()) {
      if (!(supportX0[l] >= 0.0)) {
        throw std::invalid_argument("ModuleLayout: supportX0 of layer " +
                                    std::to_string(l) + " is negative");
      }
      layer.supportX0 = supportX0[l];
    }
    for (std::uint32_t i = layer.begin; i < layer.end; ++i) {
      const PlanarModule& m = m_modules[i];
      Extent& e = m_extents[i];
      const std::array<Vector3, 4> corners = m.corners();
      e.phi = std::atan2(m.center.y(), m.center.x());
      e.vMin = std::numeric_limits<double>::infinity();
      e.vMax = -std::numeric_limits<double>::infinity();
      for (const Vector3& c : corners) {
        e.halfPhi = std::max(
            e.halfPhi, std::abs(wrapPhi(std::atan2(c.y(), c.x()) - e.phi)));
        const double v = layer.disk ? c.head<2>().norm() : c.z();
        e.vMin = std::min(e.vMin, v);
        e.vMax = std::max(e.vMax, v);
        // The sensor extends by thickness/2 on either side of the plane.
        const double offset = layer.disk
                                  ? std::abs(c.z() - surface.z())
                                  : std::abs(c.head<2>().norm() - surface.r);
        layer.shell = std::max(layer.shell, offset + 0.5 * m.thickness);
      }
      if (layer.disk) {
        e.vMin = nearestRadius(corners);
        if (e.vMin == 0.0) {
          e.halfPhi = kPi;  // the sensor covers the axis
        }
      }
    }
    buildGrid(layer);
  }
}

void ModuleLayout::buildGrid(Layer& layer) {
  const std::uint32_t n = layer.end - layer.begin;
  if (n == 0) {
    layer.binStart.assign(2, 0);
    return;
  }
  double meanPhi = 0.0;
  double meanV = 0.0;
  layer.vLow = std::numeric_limits<double>::infinity();
  layer.vHigh = -std::numeric_limits<double>::infinity();
  for (std::uint32_t i = layer.begin; i < layer.end; ++i) {
    const Extent& e = m_extents[i];
    meanPhi += 2.0 * e.halfPhi;
    meanV += e.vMax - e.vMin;
    layer.vLow = std::min(layer.vLow, e.vMin);
    layer.vHigh = std::max(layer.vHigh, e.vMax);
  }
  meanPhi /= n;
  meanV /= n;
  // About one sensor per bin: the bins are as wide as a mean sensor.
  layer.nPhi = static_cast<std::uint32_t>(
      std::clamp(std::round(2.0 * kPi / std::max(meanPhi, 1e-3)), 1.0, 4096.0));
  layer.nV = static_cast<std::uint32_t>(
      std::clamp(std::round((layer.vHigh - layer.vLow) / std::max(meanV, 1e-3)),
                 1.0, 4096.0));
  const double phiWidth = 2.0 * kPi / layer.nPhi;
  std::vector<std::vector<std::uint32_t>> bins(
      static_cast<std::size_t>(layer.nPhi) * layer.nV);
  for (std::uint32_t i = layer.begin; i < layer.end; ++i) {
    const Extent& e = m_extents[i];
    const auto lo = static_cast<std::int64_t>(
        std::floor((e.phi - e.halfPhi + kPi) / phiWidth));
    const auto hi = static_cast<std::int64_t>(
        std::floor((e.phi + e.halfPhi + kPi) / phiWidth));
    const std::uint32_t vLo = vBin(layer, e.vMin);
    const std::uint32_t vHi = vBin(layer, e.vMax);
    const std::int64_t span = std::min<std::int64_t>(hi - lo, layer.nPhi - 1);
    for (std::int64_t k = lo; k <= lo + span; ++k) {
      const auto p = static_cast<std::uint32_t>(
          ((k % layer.nPhi) + layer.nPhi) % layer.nPhi);
      for (std::uint32_t v = vLo; v <= vHi; ++v) {
        bins[static_cast<std::size_t>(p) * layer.nV + v].push_back(i);
      }
    }
  }
  layer.binStart.assign(bins.size() + 1, 0);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    layer.binStart[b + 1] =
        layer.binStart[b] + static_cast<std::uint32_t>(bins[b].size());
    layer.binModules.insert(layer.binModules.end(), bins[b].begin(),
                            bins[b].end());
  }
}

std::uint32_t ModuleLayout::vBin(const Layer& layer, double v) const {
  const double width = (layer.vHigh - layer.vLow) / layer.nV;
  if (!(width > 0.0)) {
    return 0;
  }
  const double f = std::floor((v - layer.vLow) / width);
  if (!(f > 0.0)) {
    return 0;  // below the grid (or not a number)
  }
  return static_cast<std::uint32_t>(
      std::min(f, static_cast<double>(layer.nV - 1)));
}

void ModuleLayout::candidates(std::uint32_t layerIndex, double phi, double v,
                              double marginPhi, double marginV,
                              std::vector<std::uint32_t>& out) const {
  const Layer& layer = m_layers[layerIndex];
  if (!(std::isfinite(phi) && std::isfinite(v) && marginPhi >= 0.0 &&
        marginPhi < 10.0 && marginV >= 0.0 && std::isfinite(marginV))) {
    return;  // no point to look around (a margin of 10 rad covers all)
  }
  if (layer.end == layer.begin || v + marginV < layer.vLow ||
      v - marginV > layer.vHigh) {
    return;
  }
  const std::size_t first = out.size();
  const double phiWidth = 2.0 * kPi / layer.nPhi;
  const auto lo =
      static_cast<std::int64_t>(std::floor((phi - marginPhi + kPi) / phiWidth));
  const auto hi =
      static_cast<std::int64_t>(std::floor((phi + marginPhi + kPi) / phiWidth));
  const std::int64_t span = std::min<std::int64_t>(hi - lo, layer.nPhi - 1);
  const std::uint32_t vLo = vBin(layer, v - marginV);
  const std::uint32_t vHi = vBin(layer, v + marginV);
  for (std::int64_t k = lo; k <= lo + span; ++k) {
    const auto p = static_cast<std::uint32_t>(((k % layer.nPhi) + layer.nPhi) %
                                              layer.nPhi);
    for (std::uint32_t b = vLo; b <= vHi; ++b) {
      const std::size_t bin = static_cast<std::size_t>(p) * layer.nV + b;
      for (std::uint32_t j = layer.binStart[bin]; j < layer.binStart[bin + 1];
           ++j) {
        const std::uint32_t i = layer.binModules[j];
        const Extent& e = m_extents[i];
        if (std::abs(wrapPhi(phi - e.phi)) <= e.halfPhi + marginPhi &&
            v >= e.vMin - marginV && v <= e.vMax + marginV) {
          out.push_back(i);
        }
      }
    }
  }
  // A sensor spanning several bins is found in each.
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
  out.erase(
      std::unique(out.begin() + static_cast<std::ptrdiff_t>(first), out.end()),
      out.end());
}

const PlanarModule* ModuleLayout::find(std::uint32_t layerIndex,
                                       std::uint32_t module) const {
  if (layerIndex >= m_layers.size()) {
    return nullptr;
  }
  const Layer& layer = m_layers[layerIndex];
  for (std::uint32_t i = layer.begin; i < layer.end; ++i) {
    if (m_modules[i].module == module) {
      return &m_modules[i];
    }
  }
  return nullptr;
}

}  // namespace conftrack

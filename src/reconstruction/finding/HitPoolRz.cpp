// The (z, R) cones of the HitPool searches (HitPool.hpp): which part of a
// layer a cone reaches (rzRange), and the bounding box of its reach in the
// pool (rzReach), the cheap test that refuses most layers first.

#include "conftrack/reconstruction/finding/HitPool.hpp"
#include "conftrack/reconstruction/finding/detail/PhiWindow.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace conftrack {

namespace {

/// Passes to add(z, r) the vertices of the convex polygon where the (z, R)
/// cone `p` (a HitPool::PreparedRz) meets the box `b` (zMin, zMax, rMin,
/// rMax): the box corners inside the cone, the apex if inside the box, and
/// the crossings of the cone's edges with the box's sides; inside tests
/// with tolerance `tol`. The cone (half-angle below pi/2) is the
/// intersection of the half-planes left of its first edge and right of its
/// second: false, before any other vertex, if all four corners lie outside
/// one of them (the polygon is empty).
template <class Prepared, class Box, class Add>
bool coneBoxVertices(const Prepared& p, const Box& b, double tol, Add&& add) {
  const auto& rz = p.cone;
  int outside1 = 0;
  int outside2 = 0;
  for (double z : {b.zMin, b.zMax}) {
    for (double r : {b.rMin, b.rMax}) {
      const double pz = z - rz.z;
      const double pr = r - rz.r;
      const bool in1 = p.edgeZ[0] * pr - p.edgeR[0] * pz >= -tol;
      const bool in2 = pz * p.edgeR[1] - pr * p.edgeZ[1] >= -tol;
      outside1 += in1 ? 0 : 1;
      outside2 += in2 ? 0 : 1;
      if (in1 && in2) {
        add(z, r);
      }
    }
  }
  if (outside1 == 4 || outside2 == 4) {
    return false;
  }
  if (rz.z >= b.zMin - tol && rz.z <= b.zMax + tol && rz.r >= b.rMin - tol &&
      rz.r <= b.rMax + tol) {
    add(rz.z, rz.r);
  }
  for (int e = 0; e < 2; ++e) {
    const double ez = p.edgeZ[e];
    const double er = p.edgeR[e];
    if (ez != 0.0) {
      for (double z : {b.zMin, b.zMax}) {
        const double t = (z - rz.z) / ez;
        const double r = rz.r + t * er;
        if (t >= -tol && r >= b.rMin - tol && r <= b.rMax + tol) {
          add(z, r);
        }
      }
    }
    if (er != 0.0) {
      for (double r : {b.rMin, b.rMax}) {
        const double t = (r - rz.r) / er;
        const double z = rz.z + t * ez;
        if (t >= -tol && z >= b.zMin - tol && z <= b.zMax + tol) {
          add(z, r);
        }
      }
    }
  }
  return true;
}

}  // namespace

HitPool::PreparedRz::PreparedRz(const RzCone& rz) : cone(rz) {
  // A margin on the angle: members passing the caller's exact angle cut
  // must not be lost to rounding.
  const double a = rz.halfAngle + 1e-9;
  if (!(a < 0.5 * std::numbers::pi)) {
    unbounded = true;
    return;
  }
  // The edges: the axis rotated by -a and +a.
  thread_local detail::TrigCache trig;
  trig.update(a);
  const double cosA = trig.cos;
  const double sinA = trig.sin;
  const double norm = std::sqrt(rz.dz * rz.dz + rz.dr * rz.dr);
  const double cz = norm > 0.0 ? rz.dz / norm : 0.0;
  const double cr = norm > 0.0 ? rz.dr / norm : 1.0;
  edgeZ[0] = cz * cosA + cr * sinA;
  edgeR[0] = cr * cosA - cz * sinA;
  edgeZ[1] = cz * cosA - cr * sinA;
  edgeR[1] = cr * cosA + cz * sinA;
  for (int e = 0; e < 2; ++e) {
    dzdr[e] = edgeR[e] != 0.0 ? edgeZ[e] / edgeR[e] : 0.0;
    drdz[e] = edgeZ[e] != 0.0 ? edgeR[e] / edgeZ[e] : 0.0;
  }
}

bool HitPool::rzRange(const PreparedRz& p, const LayerBins& b, double& wLo,
                      double& wHi) {
  if (p.unbounded) {
    wLo = -std::numeric_limits<double>::infinity();
    wHi = std::numeric_limits<double>::infinity();
    return true;
  }
  const RzCone& rz = p.cone;
  // Closed form when the layer lies across the cone's path: both edges run
  // towards the layer's band of its short coordinate (R of a barrel layer,
  // z of a disk) from an apex outside it. The cone within the band is then
  // a trapezoid whose extent in w runs between the edges' w at the band's
  // two borders, clipped to the layer.
  {
    // u: the short coordinate, w: the long one.
    const double u0 = b.alongZ ? rz.r : rz.z;
    const double w0 = b.alongZ ? rz.z : rz.r;
    const double* du = b.alongZ ? p.edgeR : p.edgeZ;
    const double* slope = b.alongZ ? p.dzdr : p.drdz;
    const double uLo = b.alongZ ? b.rMin : b.zMin;
    const double uHi = b.alongZ ? b.rMax : b.zMax;
    const bool below = u0 < uLo && du[0] > 0.0 && du[1] > 0.0;
    const bool above = u0 > uHi && du[0] < 0.0 && du[1] < 0.0;
    if (below || above) {
      const double w00 = w0 + (uLo - u0) * slope[0];
      const double w01 = w0 + (uHi - u0) * slope[0];
      const double w10 = w0 + (uLo - u0) * slope[1];
      const double w11 = w0 + (uHi - u0) * slope[1];
      const double lo = std::min(std::min(w00, w01), std::min(w10, w11));
      const double hi = std::max(std::max(w00, w01), std::max(w10, w11));
      const double wMinLayer = b.alongZ ? b.zMin : b.rMin;
      const double wMaxLayer = b.alongZ ? b.zMax : b.rMax;
      if (hi < wMinLayer || lo > wMaxLayer) {
        return false;
      }
      wLo = std::max(lo, wMinLayer);
      wHi = std::min(hi, wMaxLayer);
      const double margin =
          1e-6 * (1.0 + std::max(std::abs(wLo), std::abs(wHi)));
      wLo -= margin;
      wHi += margin;
      return true;
    }
  }
  // The cone is convex: the extremes of w over its intersection with the
  // layer's (z, R) box lie at vertices of that polygon, i.e. box corners
  // inside the cone, intersections of the cone's edges with the box's
  // edges, and the apex if inside the box.
  wLo = std::numeric_limits<double>::infinity();
  wHi = -wLo;
  auto add = [&](double z, double r) {
    double w = b.alongZ ? z : r;
    wLo = std::min(wLo, w);
    wHi = std::max(wHi, w);
  };
  if (!coneBoxVertices(p, b, 0.0, add)) {
    return false;
  }
  if (wLo > wHi) {
    return false;
  }
  const double margin = 1e-6 * (1.0 + std::max(std::abs(wLo), std::abs(wHi)));
  wLo -= margin;
  wHi += margin;
  return true;
}

bool HitPool::rzReach(const PreparedRz& p, const RzBox& b, RzBox& out) {
  if (p.unbounded || !(b.zMin <= b.zMax && b.rMin <= b.rMax)) {
    return false;
  }
  const RzCone& rz = p.cone;
  // The vertices of the convex polygon cone-and-box, as in rzRange(), but
  // with a tolerance on every inside test: a vertex on an edge is never
  // lost to rounding (extra points only widen the box).
  const double scale =
      1.0 + std::max({std::abs(b.zMin), std::abs(b.zMax), std::abs(b.rMin),
                      std::abs(b.rMax), std::abs(rz.z), std::abs(rz.r)});
  const double tol = 1e-9 * scale;
  out = {std::numeric_limits<double>::infinity(),
         -std::numeric_limits<double>::infinity(),
         std::numeric_limits<double>::infinity(),
         -std::numeric_limits<double>::infinity()};
  auto add = [&](double z, double r) {
    out.zMin = std::min(out.zMin, z);
    out.zMax = std::max(out.zMax, z);
    out.rMin = std::min(out.rMin, r);
    out.rMax = std::max(out.rMax, r);
  };
  coneBoxVertices(p, b, tol, add);
  if (!(out.zMin <= out.zMax)) {
    return false;  // no part found: no pre-filter (rzRange() decides)
  }
  const double margin = 1e-6 * scale;
  out.zMin -= margin;
  out.zMax += margin;
  out.rMin -= margin;
  out.rMax += margin;
  return true;
}

bool HitPool::prepareReach(const RzCone* rz,
                           std::optional<PreparedRz>& prepared,
                           RzBox& reach) const {
  if (rz == nullptr) {
    return false;
  }
  prepared.emplace(*rz);
  return rzReach(*prepared, m_box, reach);
}

}  // namespace conftrack

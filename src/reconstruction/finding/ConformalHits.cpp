#include "conftrack/reconstruction/finding/ConformalHits.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace conftrack {

namespace {
/// Hits closer to the beam line have no conformal coordinates.
constexpr double kMinConformalRadius = 1.0 * units::um;

/// Covariance of (u, v) from the tangential and radial variances.
Matrix2 uvCovariance(double phi, double varT, double varR) {
  double c = std::cos(phi);
  double s = std::sin(phi);
  Vector2 t(-s, c);
  Vector2 r(c, s);
  return varT * t * t.transpose() + varR * r * r.transpose();
}
}  // namespace

Matrix2 ConformalHits::covariance(ConfIndex i) const {
  Matrix2 m;
  m << covUU[i], covUV[i], covUV[i], covVV[i];
  return m;
}

ConformalHits makeConformalHits(std::span<const Hit> hits,
                                const Detector& detector,
                                const PromptBending* bending,
                                const Vector2& beamSpot) {
  const bool warp = bending != nullptr && !bending->isUniform();
  const std::size_t n = hits.size();
  // Transverse positions relative to the beam line.
  std::vector<Vector2> xy(n);
  std::vector<double> radius(n);
  for (std::size_t i = 0; i < n; ++i) {
    xy[i] = hits[i].position.head<2>() - beamSpot;
    radius[i] = xy[i].norm();
    // As the hits reader: within 1 um of the beam line u = x / r^2 and the
    // variances / r^4 overflow; a non-finite position has no mapping.
    if (!(radius[i] >= kMinConformalRadius) || !std::isfinite(radius[i]) ||
        !std::isfinite(hits[i].position.z())) {
      throw InputError("hit " + std::to_string(hits[i].id) +
                       " lies on the beam line or is not finite: conformal "
                       "coordinates are undefined");
    }
  }
  std::vector<HitIndex> order(n);
  std::iota(order.begin(), order.end(), 0);
  // Total order: innermost first, ties by hit id (independent of input).
  std::sort(order.begin(), order.end(), [&](HitIndex a, HitIndex b) {
    if (radius[a] != radius[b]) {
      return radius[a] < radius[b];
    }
    return hits[a].id < hits[b].id;
  });

  ConformalHits ch;
  auto reserve = [n](auto&... vs) { (vs.reserve(n), ...); };
  reserve(ch.original, ch.id, ch.x, ch.y, ch.z, ch.radius, ch.u, ch.v, ch.rc,
          ch.phi, ch.varT, ch.varR, ch.covUU, ch.covUV, ch.covVV, ch.varZ,
          ch.varRxy, ch.layer, ch.subdetector, ch.side, ch.module);
  for (HitIndex i : order) {
    const Hit& h = hits[i];
    std::optional<std::uint32_t> layer = detector.findLayer(h.detId);
    if (!layer) {
      throw InputError("hit " + std::to_string(h.id) +
                       " is on a layer the detector does not have "
                       "(subdetector " +
                       std::to_string(h.detId.subdetector) + ", layer " +
                       std::to_string(h.detId.layer) + ")");
    }
    const SensitiveLayer& l = detector.layers()[*layer];
    double r = radius[i];
    // The conformal map of the hit moved to radius g r (PromptBending).
    const double g = warp ? bending->factor(r, h.position.z()) : 1.0;
    double r2 = r * r * g;
    ch.original.push_back(i);
    ch.id.push_back(h.id);
    const double x = xy[i].x();
    const double y = xy[i].y();
    ch.x.push_back(x);
    ch.y.push_back(y);
    ch.z.push_back(h.position.z());
    ch.radius.push_back(r);
    ch.u.push_back(x / r2);
    ch.v.push_back(y / r2);
    ch.rc.push_back(1.0 / (r * g));
    ch.phi.push_back(std::atan2(y, x));
    // u is r-phi on both barrels and disks; v is z (barrel) or radial.
    double sigmaT = h.sigmaU;
    double sigmaR = l.isDisk() ? h.sigmaV : 0.0;
    ch.varT.push_back(sigmaT * sigmaT / (r2 * r2));
    ch.varR.push_back(sigmaR * sigmaR / (r2 * r2));
    // The fits need the (u, v) covariance of every hit many times.
    const Matrix2 cov =
        uvCovariance(ch.phi.back(), ch.varT.back(), ch.varR.back());
    ch.covUU.push_back(cov(0, 0));
    ch.covUV.push_back(cov(0, 1));
    ch.covVV.push_back(cov(1, 1));
    ch.varZ.push_back(l.isDisk() ? 0.0 : h.sigmaV * h.sigmaV);
    ch.varRxy.push_back(sigmaR * sigmaR);
    ch.layer.push_back(*layer);
    ch.subdetector.push_back(h.detId.subdetector);
    ch.side.push_back(static_cast<std::int8_t>(h.detId.side));
    ch.module.push_back(h.detId.module);
  }
  return ch;
}

}  // namespace conftrack

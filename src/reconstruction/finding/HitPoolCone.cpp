// The conformal cone search of the HitPool (HitPool.hpp, HitPool::cone):
// the azimuth window of each layer that a cone from a seed hit reaches.

#include "conftrack/reconstruction/finding/HitPool.hpp"
#include "conftrack/reconstruction/finding/detail/PhiWindow.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

namespace conftrack {

namespace {

/// atan2 to within 1e-5 rad, several times faster than std::atan2: the
/// azimuth windows only need to be conservative, and get a margin of
/// kFastAtanMargin. Minimax polynomial for atan on [0, 1] (max error about
/// 1e-5 rad), extended by octant symmetries.
constexpr double kFastAtanMargin = 1e-4;
double fastAtan2(double y, double x) {
  double ax = std::abs(x);
  double ay = std::abs(y);
  double mx = std::max(ax, ay);
  if (mx == 0.0) {
    return 0.0;
  }
  double a = std::min(ax, ay) / mx;
  double s = a * a;
  double r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a + a;
  if (ay > ax) {
    r = 0.5 * std::numbers::pi - r;
  }
  if (x < 0.0) {
    r = std::numbers::pi - r;
  }
  return y < 0.0 ? -r : r;
}

double wrap(double a) {
  while (a > std::numbers::pi) {
    a -= detail::kTwoPi;
  }
  while (a <= -std::numbers::pi) {
    a += detail::kTwoPi;
  }
  return a;
}

/// True if the triangle contains the origin (boundary included).
bool containsOrigin(const Vector2 (&tri)[3]) {
  auto cross = [](const Vector2& p, const Vector2& q) {
    return p.x() * q.y() - p.y() * q.x();
  };
  double s0 = cross(tri[1] - tri[0], -tri[0]);
  double s1 = cross(tri[2] - tri[1], -tri[1]);
  double s2 = cross(tri[0] - tri[2], -tri[2]);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

/// A search triangle with what annulusWindow() needs of it that does not
/// depend on the annulus, computed once per search instead of once per
/// layer (the same expressions, so the same values).
struct Triangle {
  explicit Triangle(const Vector2 (&t)[3]) : origin(containsOrigin(t)) {
    for (int k = 0; k < 3; ++k) {
      p0[k] = t[k];
      norm[k] = t[k].norm();
      d[k] = t[(k + 1) % 3] - t[k];
      aa[k] = d[k].squaredNorm();
      bb[k] = 2.0 * p0[k].dot(d[k]);
      p0Sq[k] = p0[k].squaredNorm();
    }
  }
  bool origin;
  Vector2 p0[3];
  double norm[3];
  Vector2 d[3];
  double aa[3], bb[3], p0Sq[3];
};

/// Azimuth window of the part of triangle (a, b, c) between the circles of
/// radius rhoMin and rhoMax around the origin. Returns false if they do not
/// meet; halfWidth >= pi if the triangle contains the origin. The azimuth is
/// monotonic along a segment that misses the origin and along an arc, so
/// its extremes lie at corners: triangle vertices inside the annulus and
/// edge-circle intersections.
bool annulusWindow(const Triangle& tri, double rhoMin, double rhoMax,
                   double& centre, double& halfWidth) {
  // Origin inside the triangle: every azimuth.
  if (tri.origin) {
    centre = 0.0;
    halfWidth = detail::kTwoPi;
    return true;
  }
  // The triangle misses the origin, so all its points lie within an arc
  // shorter than pi as seen from there, where the sign of a cross product
  // orders azimuths: the extremes are found without arctangents, and only
  // the two winners are converted.
  bool any = false;
  Vector2 loP;
  Vector2 hiP;
  auto corner = [&](const Vector2& p) {
    if (!any) {
      loP = hiP = p;
      any = true;
      return;
    }
    if (hiP.x() * p.y() - hiP.y() * p.x() > 0.0) {
      hiP = p;  // p lies counter-clockwise of the highest so far
    }
    if (p.x() * loP.y() - p.y() * loP.x() > 0.0) {
      loP = p;  // p lies clockwise of the lowest so far
    }
  };
  for (int k = 0; k < 3; ++k) {
    double r = tri.norm[k];
    if (r >= rhoMin && r <= rhoMax) {
      corner(tri.p0[k]);
    }
    const Vector2& p0 = tri.p0[k];
    const Vector2& d = tri.d[k];
    double aa = tri.aa[k];
    if (!(aa > 0.0)) {
      continue;
    }
    double bb = tri.bb[k];
    for (double rho : {rhoMin, rhoMax}) {
      double cc = tri.p0Sq[k] - rho * rho;
      double disc = bb * bb - 4.0 * aa * cc;
      if (disc < 0.0) {
        continue;
      }
      double sq = std::sqrt(disc);
      for (double t : {(-bb - sq) / (2.0 * aa), (-bb + sq) / (2.0 * aa)}) {
        if (t >= 0.0 && t <= 1.0) {
          corner(p0 + t * d);
        }
      }
    }
  }
  if (!any) {
    return false;
  }
  const double lo = fastAtan2(loP.y(), loP.x());
  const double span = std::max(0.0, wrap(fastAtan2(hiP.y(), hiP.x()) - lo));
  centre = wrap(lo + 0.5 * span);
  halfWidth = 0.5 * span;
  return true;
}

}  // namespace

void HitPool::cone(double u, double v, double du, double dv, double halfAngle,
                   double discU, double discV, double discRadius,
                   std::vector<ConfIndex>& out,
                   const std::function<bool(ConfIndex)>& keep,
                   const RzCone* rz) const {
  out.clear();
  // The cone cut off by the disc: a triangle reaching past the disc's far
  // edge (length / cos keeps the triangle around the circular cap).
  const double du0 = discU - u;
  const double dv0 = discV - v;
  double reach = std::sqrt(du0 * du0 + dv0 * dv0) + discRadius;
  thread_local detail::TrigCache trig;
  trig.update(halfAngle);
  const double c = trig.cos;
  const double s = trig.sin;
  double len = reach / std::max(c, 1e-3);
  // Stop short of the origin: beyond it lie hits on the opposite side of
  // the detector, which no track reaches. Cutting at 0.995 of the distance
  // loses only R > 200 R(apex), outside any tracker, and keeps the origin
  // out of the triangle so that windows stay narrow.
  double towardsOrigin = -(u * du + v * dv);
  if (towardsOrigin > 0.0) {
    len = std::min(len, 0.995 * towardsOrigin);
  }
  // The triangle's far edge, as a distance along the axis.
  const double maxAlong = len * c * (1.0 + 1e-12);
  Vector2 apex(u, v);
  Vector2 left(du * c - dv * s, du * s + dv * c);
  Vector2 right(du * c + dv * s, -du * s + dv * c);
  const Vector2 tri[3] = {apex, apex + len * left, apex + len * right};
  const Triangle triangle(tri);
  const double r2 = discRadius * discRadius;
  const double cosCut = c;
  // The margin covers the approximate arctangent of the window corners.
  constexpr double kMargin = kFastAtanMargin;
  // Conformal radii the disc can reach: skip layers outside at once.
  double discCentreRc = std::sqrt(discU * discU + discV * discV);
  double rcLow = discCentreRc - discRadius;
  double rcHigh = discCentreRc + discRadius;
  // ... and the triangle: its largest conformal radius is at a vertex, its
  // smallest at the nearest point of an edge (0 if it holds the origin).
  {
    double triHigh = 0.0;
    double triLow = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const Vector2& a = tri[k];
      const Vector2& b = tri[(k + 1) % 3];
      triHigh = std::max(triHigh, a.norm());
      const Vector2 e = b - a;
      const double ee = e.squaredNorm();
      const double t = ee > 0.0 ? std::clamp(-a.dot(e) / ee, 0.0, 1.0) : 0.0;
      triLow = std::min(triLow, (a + t * e).norm());
    }
    if (triangle.origin) {
      triLow = 0.0;
    }
    rcLow = std::max(rcLow, triLow - 1e-12);
    rcHigh = std::min(rcHigh, triHigh + 1e-12);
  }
  std::optional<PreparedRz> prepared;
  RzBox rzBox{};
  const bool useReach = prepareReach(rz, prepared, rzBox);
  for (std::size_t k = 0; k < m_layers.size(); ++k) {
    if (m_layerRc[k].second < rcLow || m_layerRc[k].first > rcHigh) {
      continue;
    }
    if (useReach && !rzBox.overlaps(m_layerBins[k])) {
      continue;  // outside the (z, R) cone: rzRange() would refuse it
    }
    // The (z, R) cone first: it skips most layers of a long barrel or of
    // many disks at once.
    double wLo = 0.0;
    double wHi = 0.0;
    if (prepared && !rzRange(*prepared, m_layerBins[k], wLo, wHi)) {
      continue;
    }
    double centre = 0.0;
    double half = 0.0;
    if (!annulusWindow(triangle, m_layerRc[k].first, m_layerRc[k].second,
                       centre, half)) {
      continue;
    }
    std::size_t before = out.size();
    if (!prepared) {
      detail::collectPhiWindow(m_layerPhis, m_layerHits, m_layerCells,
                               static_cast<std::uint32_t>(k), centre,
                               half + kMargin, out);
    } else {
      collectLayer(k, wLo, wHi, centre, half + kMargin, out);
    }
    // Exact cuts: inside the disc and the triangle.
    std::size_t kept = before;
    const double cos2 = cosCut * cosCut * (1.0 - 1e-12);
    for (std::size_t i = before; i < out.size(); ++i) {
      ConfIndex h = out[i];
      double eu = m_hits->u[h] - discU;
      double ev = m_hits->v[h] - discV;
      double au = m_hits->u[h] - u;
      double av = m_hits->v[h] - v;
      double dot = au * du + av * dv;
      double a2 = au * au + av * av;
      // Inside the disc, within the cone (dot >= cos * |a|) and short of
      // its end.
      if (eu * eu + ev * ev <= r2 && a2 > 0.0 && dot > 0.0 && dot <= maxAlong &&
          dot * dot >= cos2 * a2 && (!keep || keep(h))) {
        out[kept++] = h;
      }
    }
    out.resize(kept);
  }
  auto dist2 = [&](ConfIndex h) {
    double eu = m_hits->u[h] - discU;
    double ev = m_hits->v[h] - discV;
    return eu * eu + ev * ev;
  };
  std::sort(out.begin(), out.end(), [&](ConfIndex a, ConfIndex b) {
    double da = dist2(a);
    double db = dist2(b);
    return da != db ? da < db : a < b;
  });
}

}  // namespace conftrack

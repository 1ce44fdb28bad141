#include "conftrack/reconstruction/finding/HitPool.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>

namespace conftrack {

namespace {
/// nanoflann dataset adaptor over the pool's conformal coordinates.
struct Cloud {
  // The member buffer, not the vector: it survives moving the HitPool.
  const ConformalHits* hits;
  const ConfIndex* members;
  std::size_t size;
  std::size_t kdtree_get_point_count() const { return size; }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    ConfIndex h = members[i];
    return dim == 0 ? hits->u[h] : hits->v[h];
  }
  template <class Box>
  bool kdtree_get_bbox(Box& /*unused*/) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 2, std::uint32_t>;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

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

/// Appends the entries of a phi-sorted range within the window.
void collectWindow(const std::vector<double>& phis,
                   const std::vector<ConfIndex>& ids, std::size_t begin,
                   std::size_t end, double phi, double halfWidth,
                   std::vector<ConfIndex>& out) {
  auto scan = [&](double lo, double hi) {
    auto first = std::lower_bound(phis.begin() + begin, phis.begin() + end, lo);
    auto last = std::upper_bound(first, phis.begin() + end, hi);
    for (auto it = first; it != last; ++it) {
      out.push_back(ids[it - phis.begin()]);
    }
  };
  if (halfWidth >= std::numbers::pi) {
    scan(-kTwoPi, kTwoPi);
    return;
  }
  double lo = phi - halfWidth;
  double hi = phi + halfWidth;
  scan(std::max(lo, -std::numbers::pi), std::min(hi, std::numbers::pi));
  if (lo < -std::numbers::pi) {
    scan(lo + kTwoPi, std::numbers::pi);
  }
  if (hi > std::numbers::pi) {
    scan(-std::numbers::pi, hi - kTwoPi);
  }
}
}  // namespace

struct HitPool::Tree {
  Cloud cloud;
  KdTree index;
  Tree(const ConformalHits& hits, const std::vector<ConfIndex>& members)
      : cloud{&hits, members.data(), members.size()},
        index(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

HitPool::HitPool(const ConformalHits& hits, std::vector<ConfIndex> members)
    : m_hits(&hits), m_members(std::move(members)) {
  std::sort(m_members.begin(), m_members.end());
  m_members.erase(std::unique(m_members.begin(), m_members.end()),
                  m_members.end());
  m_tree = std::make_unique<Tree>(hits, m_members);
  auto byPhi = [&](ConfIndex a, ConfIndex b) {
    return hits.phi[a] != hits.phi[b] ? hits.phi[a] < hits.phi[b] : a < b;
  };
  m_byPhi = m_members;
  std::sort(m_byPhi.begin(), m_byPhi.end(), byPhi);
  m_phis.reserve(m_byPhi.size());
  for (ConfIndex i : m_byPhi) {
    m_phis.push_back(hits.phi[i]);
  }
  m_layerHits = m_members;
  std::sort(m_layerHits.begin(), m_layerHits.end(),
            [&](ConfIndex a, ConfIndex b) {
              if (hits.layer[a] != hits.layer[b]) {
                return hits.layer[a] < hits.layer[b];
              }
              return byPhi(a, b);
            });
  for (std::uint32_t k = 0; k < m_layerHits.size(); ++k) {
    std::uint32_t l = hits.layer[m_layerHits[k]];
    m_layerPhis.push_back(hits.phi[m_layerHits[k]]);
    double rc = hits.rc[m_layerHits[k]];
    if (m_layers.empty() || m_layers.back() != l) {
      m_layers.push_back(l);
      m_layerRange.emplace_back(k, k);
      m_layerRc.emplace_back(rc, rc);
    }
    m_layerRange.back().second = k + 1;
    m_layerRc.back().first = std::min(m_layerRc.back().first, rc);
    m_layerRc.back().second = std::max(m_layerRc.back().second, rc);
  }
  // Bins along each layer's long coordinate, about kHitsPerBin members
  // each, filled in azimuth order (a counting sort keeps it per bin).
  constexpr std::size_t kHitsPerBin = 32;
  constexpr std::size_t kMaxBins = 256;
  m_binHits.reserve(m_layerHits.size());
  m_binPhis.reserve(m_layerHits.size());
  std::vector<std::uint32_t> binOfHit;
  for (std::size_t k = 0; k < m_layers.size(); ++k) {
    auto [begin, end] = m_layerRange[k];
    LayerBins b;
    b.zMin = b.rMin = std::numeric_limits<double>::infinity();
    b.zMax = b.rMax = -b.zMin;
    for (std::uint32_t i = begin; i < end; ++i) {
      ConfIndex h = m_layerHits[i];
      b.zMin = std::min(b.zMin, hits.z[h]);
      b.zMax = std::max(b.zMax, hits.z[h]);
      b.rMin = std::min(b.rMin, hits.radius[h]);
      b.rMax = std::max(b.rMax, hits.radius[h]);
    }
    b.alongZ = b.zMax - b.zMin >= b.rMax - b.rMin;
    b.wMin = b.alongZ ? b.zMin : b.rMin;
    double wMax = b.alongZ ? b.zMax : b.rMax;
    b.nBins = static_cast<std::uint32_t>(
        std::clamp<std::size_t>((end - begin) / kHitsPerBin, 1, kMaxBins));
    b.binWidth = (wMax - b.wMin) / b.nBins;
    if (!(b.binWidth > 0.0)) {
      b.nBins = 1;
    }
    b.firstBin = static_cast<std::uint32_t>(m_binRange.size());
    binOfHit.resize(end - begin);
    std::vector<std::uint32_t> count(b.nBins + 1, 0);
    for (std::uint32_t i = begin; i < end; ++i) {
      ConfIndex h = m_layerHits[i];
      binOfHit[i - begin] = b.binOf(b.alongZ ? hits.z[h] : hits.radius[h]);
      ++count[binOfHit[i - begin] + 1];
    }
    std::partial_sum(count.begin(), count.end(), count.begin());
    auto offset = static_cast<std::uint32_t>(m_binHits.size());
    for (std::uint32_t n = 0; n < b.nBins; ++n) {
      m_binRange.emplace_back(offset + count[n], offset + count[n + 1]);
    }
    m_binHits.resize(offset + (end - begin));
    m_binPhis.resize(offset + (end - begin));
    for (std::uint32_t i = begin; i < end; ++i) {
      std::uint32_t slot = offset + count[binOfHit[i - begin]]++;
      m_binHits[slot] = m_layerHits[i];
      m_binPhis[slot] = m_layerPhis[i];
    }
    m_layerBins.push_back(b);
  }
  m_box = {std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};
  for (const LayerBins& b : m_layerBins) {
    m_box = {std::min(m_box.zMin, b.zMin), std::max(m_box.zMax, b.zMax),
             std::min(m_box.rMin, b.rMin), std::max(m_box.rMax, b.rMax)};
  }
}

std::uint32_t HitPool::LayerBins::binOf(double w) const {
  if (nBins <= 1) {
    return 0;
  }
  double x = std::floor((w - wMin) / binWidth);
  if (!(x > 0.0)) {
    return 0;
  }
  return x >= nBins - 1 ? nBins - 1 : static_cast<std::uint32_t>(x);
}

HitPool::~HitPool() = default;
HitPool::HitPool(HitPool&&) noexcept = default;
HitPool& HitPool::operator=(HitPool&&) noexcept = default;

void HitPool::disc(double u, double v, double radius,
                   std::vector<ConfIndex>& out) const {
  out.clear();
  if (m_members.empty()) {
    return;
  }
  std::vector<std::pair<std::uint32_t, double>> found;
  const double query[2] = {u, v};
  m_tree->index.radiusSearch(query, radius * radius, found,
                             nanoflann::SearchParams(32, 0.0F, false));
  std::sort(found.begin(), found.end(), [&](const auto& a, const auto& b) {
    return a.second != b.second ? a.second < b.second
                                : m_members[a.first] < m_members[b.first];
  });
  out.reserve(found.size());
  for (const auto& f : found) {
    out.push_back(m_members[f.first]);
  }
}

void HitPool::discWindow(double u, double v, double radius, double phi,
                         double halfWidth, std::vector<ConfIndex>& out,
                         const std::function<bool(ConfIndex)>& keep,
                         const RzCone* rz) const {
  out.clear();
  if (halfWidth >= std::numbers::pi && rz == nullptr) {
    disc(u, v, radius, out);
    if (keep) {
      std::erase_if(out, [&](ConfIndex h) { return !keep(h); });
    }
    return;
  }
  // Squared distances as nanoflann computes them (query - point, strict
  // comparison), so that the set and its order are exactly disc()'s.
  const double r2 = radius * radius;
  const double rc = std::sqrt(u * u + v * v);
  const bool all = halfWidth >= std::numbers::pi;  // with a (z, R) cone
  std::vector<std::pair<ConfIndex, double>> found;
  std::vector<ConfIndex> window;
  std::optional<PreparedRz> prepared;
  RzBox rzBox{};
  bool useReach = false;
  if (rz != nullptr) {
    prepared.emplace(*rz);
    useReach = rzReach(*prepared, m_box, rzBox);
  }
  for (std::size_t k = 0; k < m_layers.size(); ++k) {
    // A member within the disc has |rc_h - rc| < radius (margin for
    // rounding).
    if (m_layerRc[k].second < rc - radius - 1e-12 ||
        m_layerRc[k].first > rc + radius + 1e-12) {
      continue;
    }
    if (useReach && !rzBox.overlaps(m_layerBins[k])) {
      continue;  // outside the (z, R) cone: rzRange() would refuse it
    }
    window.clear();
    const double half = all ? 2.0 * std::numbers::pi : halfWidth + 1e-9;
    if (rz == nullptr) {
      auto [begin, end] = m_layerRange[k];
      collectWindow(m_layerPhis, m_layerHits, begin, end, phi, half, window);
    } else {
      const LayerBins& bins = m_layerBins[k];
      double wLo = 0.0;
      double wHi = 0.0;
      if (!rzRange(*prepared, bins, wLo, wHi)) {
        continue;
      }
      collectLayer(k, wLo, wHi, phi, half, window);
    }
    for (ConfIndex h : window) {
      double du = u - m_hits->u[h];
      double dv = v - m_hits->v[h];
      double d2 = du * du + dv * dv;
      if (d2 < r2 && (!keep || keep(h))) {
        found.emplace_back(h, d2);
      }
    }
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second < b.second : a.first < b.first;
  });
  out.reserve(found.size());
  for (const auto& f : found) {
    out.push_back(f.first);
  }
}

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
    a -= kTwoPi;
  }
  while (a <= -std::numbers::pi) {
    a += kTwoPi;
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
    halfWidth = kTwoPi;
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
  thread_local TrigCache trig;
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
  bool useReach = false;
  if (rz != nullptr) {
    prepared.emplace(*rz);
    useReach = rzReach(*prepared, m_box, rzBox);
  }
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
      auto [begin, end] = m_layerRange[k];
      collectWindow(m_layerPhis, m_layerHits, begin, end, centre,
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

void HitPool::azimuthWindow(double phi, double halfWidth,
                            std::vector<ConfIndex>& out) const {
  out.clear();
  collectWindow(m_phis, m_byPhi, 0, m_byPhi.size(), phi, halfWidth, out);
  auto dphi = [&](ConfIndex i) {
    double d = std::abs(m_hits->phi[i] - phi);
    return d > std::numbers::pi ? kTwoPi - d : d;
  };
  std::sort(out.begin(), out.end(), [&](ConfIndex a, ConfIndex b) {
    double da = dphi(a);
    double db = dphi(b);
    return da != db ? da < db : a < b;
  });
}

void HitPool::layerWindow(std::uint32_t layer, double phi, double halfWidth,
                          std::vector<ConfIndex>& out, const RzCone* rz) const {
  auto it = std::lower_bound(m_layers.begin(), m_layers.end(), layer);
  if (it == m_layers.end() || *it != layer) {
    return;
  }
  const auto k = static_cast<std::size_t>(it - m_layers.begin());
  if (rz == nullptr) {
    auto [begin, end] = m_layerRange[k];
    collectWindow(m_layerPhis, m_layerHits, begin, end, phi, halfWidth, out);
    return;
  }
  const LayerBins& bins = m_layerBins[k];
  double wLo = 0.0;
  double wHi = 0.0;
  if (!rzRange(PreparedRz(*rz), bins, wLo, wHi)) {
    return;
  }
  collectLayer(k, wLo, wHi, phi, halfWidth, out);
}

void HitPool::layerBox(std::uint32_t layer, double phi, double halfWidth,
                       double zLo, double zHi, double rLo, double rHi,
                       std::vector<ConfIndex>& out) const {
  auto it = std::lower_bound(m_layers.begin(), m_layers.end(), layer);
  if (it == m_layers.end() || *it != layer) {
    return;
  }
  const auto k = static_cast<std::size_t>(it - m_layers.begin());
  const LayerBins& bins = m_layerBins[k];
  const double lo =
      bins.alongZ ? std::max(zLo, bins.zMin) : std::max(rLo, bins.rMin);
  const double hi =
      bins.alongZ ? std::min(zHi, bins.zMax) : std::min(rHi, bins.rMax);
  if (lo > hi) {
    return;
  }
  collectLayer(k, lo, hi, phi, halfWidth, out);
}

void HitPool::collectLayer(std::size_t k, double wLo, double wHi, double phi,
                           double halfWidth,
                           std::vector<ConfIndex>& out) const {
  const LayerBins& bins = m_layerBins[k];
  const std::uint32_t first = bins.binOf(wLo);
  const std::uint32_t last = bins.binOf(wHi);
  // Each bin costs two binary searches: over a wide range of w one search
  // in the whole layer, then a test of w per hit, is cheaper.
  constexpr std::uint32_t kMaxBinSearches = 4;
  if (last - first + 1 <= kMaxBinSearches) {
    for (std::uint32_t n = first; n <= last; ++n) {
      auto [begin, end] = m_binRange[bins.firstBin + n];
      collectWindow(m_binPhis, m_binHits, begin, end, phi, halfWidth, out);
    }
    return;
  }
  const std::size_t before = out.size();
  auto [begin, end] = m_layerRange[k];
  collectWindow(m_layerPhis, m_layerHits, begin, end, phi, halfWidth, out);
  const std::vector<double>& w = bins.alongZ ? m_hits->z : m_hits->radius;
  std::size_t kept = before;
  for (std::size_t i = before; i < out.size(); ++i) {
    const double wi = w[out[i]];
    if (wi >= wLo && wi <= wHi) {
      out[kept++] = out[i];
    }
  }
  out.resize(kept);
}

}  // namespace conftrack

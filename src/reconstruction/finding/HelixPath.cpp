// Real-space pieces of the helix step (HelixPath.hpp).

#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"

#include "conftrack/core/Units.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace conftrack::detail {

/// The circle through three points, oriented from the first to the last;
/// false if they are (numerically) on a line.
bool circleThrough(double x1, double y1, double x2, double y2, double x3,
                   double y3, TransverseCircle& out) {
  const double ax = x2 - x1;
  const double ay = y2 - y1;
  const double bx = x3 - x1;
  const double by = y3 - y1;
  const double cross = ax * by - ay * bx;
  const double a2 = ax * ax + ay * ay;
  const double b2 = bx * bx + by * by;
  // |cross| = |a| |b| sin(angle): below 1e-12 the radius exceeds any
  // detector by far and the centre is numerically meaningless.
  if (!(std::abs(cross) > 1e-12 * std::sqrt(a2 * b2))) {
    return false;
  }
  const double d = 2.0 * cross;
  const double ux = (by * a2 - ay * b2) / d;
  const double uy = (ax * b2 - bx * a2) / d;
  out.cx = x1 + ux;
  out.cy = y1 + uy;
  out.rho = norm2(ux, uy);
  out.orientation = cross > 0.0 ? 1 : -1;
  return true;
}

/// Least-squares circle through points (algebraic distance, Kasa): exact
/// for three points; false if degenerate or (numerically) straight.
/// `orientation` comes from the first, middle and last points.
bool fitCircle(const ConformalHits& hits, std::span<const ConfIndex> idx,
               TransverseCircle& out) {
  const std::size_t n = idx.size();
  if (n == 3) {
    return circleThrough(hits.x[idx[0]], hits.y[idx[0]], hits.x[idx[1]],
                         hits.y[idx[1]], hits.x[idx[2]], hits.y[idx[2]], out);
  }
  // Centred on the first point for conditioning.
  const double x0 = hits.x[idx[0]];
  const double y0 = hits.y[idx[0]];
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (ConfIndex h : idx) {
    const double x = hits.x[h] - x0;
    const double y = hits.y[h] - y0;
    const Eigen::Vector3d row(x, y, 1.0);
    const double rhs = -(x * x + y * y);
    a += row * row.transpose();
    b += row * rhs;
  }
  const Eigen::Vector3d sol = a.ldlt().solve(b);
  if (!sol.allFinite()) {
    return false;
  }
  const double cx = -0.5 * sol(0);
  const double cy = -0.5 * sol(1);
  const double r2 = cx * cx + cy * cy - sol(2);
  if (!(r2 > 0.0) || r2 > 1e16) {
    return false;
  }
  const ConfIndex m = idx[n / 2];
  const ConfIndex e = idx[n - 1];
  const double cross =
      (hits.x[m] - x0) * (hits.y[e] - y0) - (hits.y[m] - y0) * (hits.x[e] - x0);
  out.cx = x0 + cx;
  out.cy = y0 + cy;
  out.rho = std::sqrt(r2);
  out.orientation = cross > 0.0 ? 1 : -1;
  return true;
}

/// Smallest distance between two layers' extents [mm].
double layerDistance(const SensitiveLayer& a, const SensitiveLayer& b) {
  auto gap = [](double lo1, double hi1, double lo2, double hi2) {
    return std::max({0.0, lo2 - hi1, lo1 - hi2});
  };
  const double dz = gap(a.zMin, a.zMax, b.zMin, b.zMax);
  const double dr = gap(a.rMin, a.rMax, b.rMin, b.rMax);
  return norm2(dz, dr);
}

void fitPathSz(const ConformalHits& hits, HelixPath& p) {
  double sw = 0.0, sws = 0.0, swz = 0.0, swss = 0.0, swsz = 0.0;
  for (std::size_t k = 0; k < p.hits.size(); ++k) {
    const ConfIndex h = p.hits[k];
    const double var = hits.varZ[h] + p.t * p.t * hits.varRxy[h] + 1e-6;
    const double w = 1.0 / var;
    sw += w;
    sws += w * p.s[k];
    swz += w * hits.z[h];
    swss += w * p.s[k] * p.s[k];
    swsz += w * p.s[k] * hits.z[h];
  }
  const double det = sw * swss - sws * sws;
  if (det > 0.0) {
    p.t = (sw * swsz - sws * swz) / det;
    p.z0 = (swz - p.t * sws) / sw;
  }
}

SzState filterPathSz(const ConformalHits& hits, const HelixPath& p,
                     const std::vector<SensitiveLayer>& layers, double minPt,
                     double pt) {
  SzState st;
  const ConfIndex first = p.hits[0];
  st.t = p.t;
  st.z = hits.z[first];
  st.varZ = hits.varZ[first] + p.t * p.t * hits.varRxy[first] + 1e-6;
  st.varT = 1.0;  // the slope comes from the hits that follow
  for (std::size_t k = 1; k < p.hits.size(); ++k) {
    const ConfIndex h = p.hits[k];
    const double ds = p.s[k] - p.s[k - 1];
    const double secL2 = 1.0 + st.t * st.t;
    const double ms =
        helixTheta0(layers[hits.layer[p.hits[k - 1]]], minPt, pt, st.t) * secL2;
    // Propagate: z += t ds.
    st.z += st.t * ds;
    st.varZ += 2.0 * ds * st.covZt + ds * ds * st.varT;
    st.covZt += ds * st.varT;
    st.varT += ms * ms;
    // Update with the hit's z.
    const double r = hits.varZ[h] + st.t * st.t * hits.varRxy[h] + 1e-6;
    const double sVar = st.varZ + r;
    const double kz = st.varZ / sVar;
    const double kt = st.covZt / sVar;
    const double res = hits.z[h] - st.z;
    st.z += kz * res;
    st.t += kt * res;
    const double varZ = (1.0 - kz) * st.varZ;
    const double covZt = (1.0 - kz) * st.covZt;
    st.varT -= kt * st.covZt;
    st.varZ = varZ;
    st.covZt = covZt;
  }
  return st;
}

double helixTheta0(const SensitiveLayer& layer, double minPt, double pt,
                   double t) {
  return layerTheta0(layer, std::max(pt, minPt) * norm2(1.0, t), t);
}

double transverseSigma(const ConformalHits& hits, ConfIndex h) {
  return std::sqrt(hits.varT[h]) * hits.radius[h] * hits.radius[h];
}

void predictionErrorInputs(const ConformalHits& hits,
                           const std::vector<SensitiveLayer>& layers,
                           std::span<const ConfIndex> path, double minPt,
                           double pt, double t, std::vector<double>& sigma,
                           std::vector<double>& kink) {
  const std::size_t n = path.size();
  const double secL = norm2(1.0, t);
  sigma.resize(n);
  kink.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const ConfIndex h = path[k];
    sigma[k] = transverseSigma(hits, h);
    const bool sameCrossing = k > 0 && hits.layer[h] == hits.layer[path[k - 1]];
    kink[k] = sameCrossing
                  ? 0.0
                  : helixTheta0(layers[hits.layer[h]], minPt, pt, t) * secL;
  }
}

double circlePt(const TransverseCircle& c, double bz) {
  return constants::kPtPerTeslaMm * std::abs(bz) * c.rho;
}

}  // namespace conftrack::detail

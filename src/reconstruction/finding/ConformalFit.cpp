#include "conftrack/reconstruction/finding/ConformalFit.hpp"

#include "conftrack/core/Units.hpp"

#include <Eigen/LU>

#include <cmath>
#include <numbers>

namespace conftrack {

namespace {

/// Variances below this are raised to it: keeps weights finite for hits
/// whose error along a direction is exactly zero.
constexpr double kMinConformalVariance = 1e-20;  // (1e-10 / mm)^2
constexpr double kMinZVariance = 1e-6;           // (1 um)^2

/// Coordinates and covariance of hit i in the rotated frame.
struct FramePoint {
  double x;
  double y;
  double varX;
  double varY;
  double covXY;
};

FramePoint toFrame(const ConformalHits& hits, ConfIndex i, double cosA,
                   double sinA) {
  FramePoint p;
  p.x = cosA * hits.u[i] + sinA * hits.v[i];
  p.y = -sinA * hits.u[i] + cosA * hits.v[i];
  Matrix2 rot;
  rot << cosA, sinA, -sinA, cosA;
  Matrix2 c = rot * hits.covariance(i) * rot.transpose();
  p.varX = c(0, 0);
  p.varY = c(1, 1);
  p.covXY = c(0, 1);
  return p;
}

/// Variance of the vertical residual for local slope `slope`.
double residualVariance(const FramePoint& p, double slope) {
  double var = p.varY - 2.0 * slope * p.covXY + slope * slope * p.varX;
  return std::max(var, kMinConformalVariance);
}

double wrapAngle(double a) {
  while (a > std::numbers::pi) {
    a -= 2.0 * std::numbers::pi;
  }
  while (a <= -std::numbers::pi) {
    a += 2.0 * std::numbers::pi;
  }
  return a;
}

}  // namespace

double ConformalFitResult::pt(double bz) const {
  return constants::kPtPerTeslaMm * bz * radius;
}

double ConformalFitResult::deltaChi2(const ConformalHits& hits, ConfIndex i,
                                     double extraVariance) const {
  FramePoint p = toFrame(hits, i, cosA, sinA);
  Eigen::Vector3d h(1.0, p.x, quadratic ? p.x * p.x : 0.0);
  double slope = params(1) + 2.0 * params(2) * p.x;
  double e = p.y - h.dot(params);
  // A displacement perpendicular to the curve moves the vertical residual
  // by sqrt(1 + slope^2) times as much.
  double var = residualVariance(p, slope) +
               extraVariance * (1.0 + slope * slope) + h.dot(covariance * h);
  return e * e / var;
}

double ConformalFitResult::residual(const ConformalHits& hits, ConfIndex i,
                                    double& variance) const {
  FramePoint p = toFrame(hits, i, cosA, sinA);
  Eigen::Vector3d h(1.0, p.x, quadratic ? p.x * p.x : 0.0);
  variance = residualVariance(p, params(1) + 2.0 * params(2) * p.x);
  return p.y - h.dot(params);
}

ConformalFitResult fitConformal(const ConformalHits& hits,
                                std::span<const ConfIndex> track,
                                bool quadratic,
                                const ConformalFitResult* frameFrom) {
  ConformalFitResult r;
  r.quadratic = quadratic;
  const int nPar = quadratic ? 3 : 2;
  const int n = static_cast<int>(track.size());
  if (n < nPar) {
    return r;
  }
  if (frameFrom != nullptr) {
    r.cosA = frameFrom->cosA;
    r.sinA = frameFrom->sinA;
  } else {
    // x' along the track's extent in the conformal plane: the fitted
    // curve is then nearly horizontal and its slope is small (no
    // near-vertical lines, upstream.md 7.1 "rotation").
    double du = hits.u[track.back()] - hits.u[track.front()];
    double dv = hits.v[track.back()] - hits.v[track.front()];
    double norm = std::hypot(du, dv);
    if (!(norm > 0.0)) {
      return r;
    }
    r.cosA = du / norm;
    r.sinA = dv / norm;
  }

  // A scratch buffer per thread: the finder fits hundreds of thousands of
  // short paths per event, and a fresh vector per fit cost an allocation
  // each (the fit does not call itself).
  thread_local std::vector<FramePoint> pts;
  pts.clear();
  for (ConfIndex i : track) {
    pts.push_back(toFrame(hits, i, r.cosA, r.sinA));
  }

  // The normal equations are solved in x~ = x'/scale: conformal
  // coordinates span 1e-4..3e-2 /mm and weights 1e10..1e17, so unscaled
  // matrices are too ill-conditioned for a rank test.
  double scale = 0.0;
  for (const FramePoint& p : pts) {
    scale = std::max(scale, std::abs(p.x));
  }
  if (!(scale > 0.0)) {
    return r;
  }
  Eigen::Vector3d params = Eigen::Vector3d::Zero();  // unscaled (c, m, q)
  Eigen::Matrix3d inv = Eigen::Matrix3d::Zero();
  // Two passes: weights from the y' variance, then effective variances
  // with the fitted local slope.
  for (int pass = 0; pass < 2; ++pass) {
    // The sums of w h h^T and w y h, h = (1, x~, x~^2), entry by entry:
    // the finder fits every path of its cellular automaton, and Eigen's
    // 3x3 outer product spent most of its time on the zeros of straight
    // lines. Entry (i, j) is the product h_j (w h_i) that the outer product
    // formed, so the fit is the same to the last bit; (0, j) and (j, 0)
    // are both w h_j, while (1, 2) and (2, 1) round apart.
    double n00 = 0.0;
    double n01 = 0.0;
    double n02 = 0.0;
    double n11 = 0.0;
    double n12 = 0.0;
    double n21 = 0.0;
    double n22 = 0.0;
    double r0 = 0.0;
    double r1 = 0.0;
    double r2 = 0.0;
    for (const FramePoint& p : pts) {
      double slope = pass == 0 ? 0.0 : params(1) + 2.0 * params(2) * p.x;
      double w = 1.0 / residualVariance(p, slope);
      double xs = p.x / scale;
      const double wx = w * xs;
      const double wy = w * p.y;
      n00 += w;
      n01 += wx;
      n11 += xs * wx;
      r0 += wy;
      r1 += wy * xs;
      if (quadratic) {
        const double x2 = xs * xs;
        const double wx2 = w * x2;
        n02 += wx2;
        n12 += x2 * wx;
        n21 += xs * wx2;
        n22 += x2 * wx2;
        r2 += wy * x2;
      }
    }
    Eigen::Matrix3d normal;
    normal << n00, n01, n02, n01, n11, n12, n02, n21, n22;
    const Eigen::Vector3d rhs(r0, r1, r2);
    Eigen::Matrix3d scaledInv = Eigen::Matrix3d::Zero();
    Eigen::Vector3d scaled = Eigen::Vector3d::Zero();
    if (quadratic) {
      Eigen::FullPivLU<Eigen::Matrix3d> lu(normal);
      lu.setThreshold(1e-12);
      if (!lu.isInvertible()) {
        return r;
      }
      scaledInv = lu.inverse();
      scaled = scaledInv * rhs;
    } else {
      Eigen::Matrix2d n2 = normal.topLeftCorner<2, 2>();
      double det = n2.determinant();
      if (!(std::abs(det) > 1e-12 * n2(0, 0) * n2(1, 1))) {
        return r;
      }
      scaledInv.topLeftCorner<2, 2>() = n2.inverse();
      scaled.head<2>() = scaledInv.topLeftCorner<2, 2>() * rhs.head<2>();
    }
    Eigen::Vector3d d(1.0, 1.0 / scale, 1.0 / (scale * scale));
    params = d.cwiseProduct(scaled);
    inv = d.asDiagonal() * scaledInv * d.asDiagonal();
    if (!params.allFinite()) {
      return r;
    }
  }
  double chi2 = 0.0;
  for (const FramePoint& p : pts) {
    double slope = params(1) + 2.0 * params(2) * p.x;
    double e = p.y - (params(0) + params(1) * p.x + params(2) * p.x * p.x);
    chi2 += e * e / residualVariance(p, slope);
  }
  r.params = params;
  r.covariance = inv;
  r.chi2 = chi2;
  r.ndf = n - nPar;

  // Circle through the origin: v' = 1/(2b') - (a'/b') u' (paper eq. 2).
  double c = params(0);
  double m = params(1);
  double bPrime = std::abs(c) > 1e-15 ? 0.5 / c : std::copysign(5e14, c);
  double aPrime = -m * bPrime;
  r.centreX = r.cosA * aPrime - r.sinA * bPrime;
  r.centreY = r.sinA * aPrime + r.cosA * bPrime;
  r.radius = std::hypot(aPrime, bPrime);
  // Motion leaves the origin towards the first hit; the centre on its
  // left means counter-clockwise motion.
  ConfIndex first = track.front();
  double cross = hits.x[first] * r.centreY - hits.y[first] * r.centreX;
  r.orientation = cross > 0.0 ? 1 : -1;
  r.valid = std::isfinite(r.chi2);
  return r;
}

double ArcFrame::arcLength(double x, double y, double near) const {
  double beta = std::atan2(y - centreY, x - centreX);
  double turn = orientation * wrapAngle(beta - beta0);
  // Choose the turn (multiple of 2 pi) closest to the expected value.
  double period = 2.0 * std::numbers::pi;
  double expected = radius > 0.0 ? near / radius : 0.0;
  double k = std::round((expected - turn) / period);
  return radius * (turn + k * period);
}

double ArcFrame::hitArcLength(const ConformalHits& hits, ConfIndex h,
                              double near) const {
  const double g = hits.mapFactor(h);
  return arcLength(g * hits.x[h], g * hits.y[h], near * g) / g;
}

double ArcFrame::helixArcLength(const ConformalHits& hits, ConfIndex h,
                                double near, double sRef, double zRef,
                                double tanLambda, bool follows) const {
  const double nearest = hitArcLength(hits, h, near);
  const double period = 2.0 * std::numbers::pi * radius;
  const auto zDistance = [&](double s) {
    return std::abs(hits.z[h] - (zRef + tanLambda * (s - sRef)));
  };
  double best = nearest;
  double bestDistance = zDistance(nearest) - kTurnChoiceMargin;
  for (double other : {nearest - period, nearest + period}) {
    if (follows && !(other > near && nearest < near)) {
      continue;
    }
    const double d = zDistance(other);
    if (d < bestDistance) {
      best = other;
      bestDistance = d;
    }
  }
  return best;
}

Vector2 ArcFrame::pointAt(double s) const {
  double beta = beta0 + orientation * (radius > 0.0 ? s / radius : 0.0);
  return {centreX + radius * std::cos(beta), centreY + radius * std::sin(beta)};
}

ArcFrame makeArcFrame(const ConformalFitResult& circle,
                      const ConformalHits& hits, ConfIndex first) {
  ArcFrame a;
  a.centreX = circle.centreX;
  a.centreY = circle.centreY;
  a.radius = circle.radius;
  a.orientation = circle.orientation;
  // The first hit's position in the conformal map (hitArcLength).
  const double g = hits.mapFactor(first);
  a.beta0 =
      std::atan2(g * hits.y[first] - a.centreY, g * hits.x[first] - a.centreX);
  return a;
}

double SzFitResult::deltaChi2(double s, double z, double varZ,
                              double varS) const {
  Eigen::Vector2d h(1.0, s);
  double e = z - (z0 + tanLambda * s);
  double var = std::max(varZ + tanLambda * tanLambda * varS, kMinZVariance) +
               h.dot(covariance * h);
  return e * e / var;
}

double SzFitResult::residual(double s, double z, double varZ, double varS,
                             double& variance) const {
  variance = std::max(varZ + tanLambda * tanLambda * varS, kMinZVariance);
  return z - (z0 + tanLambda * s);
}

SzFitResult fitSz(const ConformalHits& hits, std::span<const ConfIndex> track,
                  const ArcFrame& arc) {
  SzFitResult r;
  const int n = static_cast<int>(track.size());
  if (n < 2) {
    return r;
  }
  // Per-thread scratch, as in fitConformal.
  thread_local std::vector<double> s;
  s.resize(track.size());
  // Unwrapped against the previous hit: the turn closest to it, unless
  // the z slope of the hits so far puts the hit a turn away (a track can
  // run more than half a turn between two hits: helixArcLength).
  for (std::size_t k = 0; k < track.size(); ++k) {
    ConfIndex i = track[k];
    if (k == 0) {
      s[k] = 0.0;
    } else if (k == 1 || !(std::abs(s[k - 1]) > 0.0)) {
      s[k] = arc.hitArcLength(hits, i, s[k - 1]);
    } else {
      const double slope = (hits.z[track[k - 1]] - hits.z[track[0]]) / s[k - 1];
      s[k] = arc.helixArcLength(hits, i, s[k - 1], s[k - 1],
                                hits.z[track[k - 1]], slope, true);
    }
  }
  Eigen::Vector2d params = Eigen::Vector2d::Zero();
  Eigen::Matrix2d inv = Eigen::Matrix2d::Zero();
  for (int pass = 0; pass < 2; ++pass) {
    // The sums of h h^T / var and z h / var, h = (1, s), entry by entry
    // (as in fitConformal: the same products and quotients, fewer of them).
    double n00 = 0.0;
    double n01 = 0.0;
    double n11 = 0.0;
    double r0 = 0.0;
    double r1 = 0.0;
    for (std::size_t k = 0; k < track.size(); ++k) {
      ConfIndex i = track[k];
      double t = pass == 0 ? 1.0 : params(1);
      double var =
          std::max(hits.varZ[i] + t * t * hits.varRxy[i], kMinZVariance);
      const double sk = s[k];
      const double z = hits.z[i];
      n00 += 1.0 / var;
      n01 += sk / var;
      n11 += (sk * sk) / var;
      r0 += z / var;
      r1 += (z * sk) / var;
    }
    Eigen::Matrix2d normal;
    normal << n00, n01, n01, n11;
    const Eigen::Vector2d rhs(r0, r1);
    double det = normal.determinant();
    if (!(std::abs(det) > 1e-12 * normal(0, 0) * normal(1, 1))) {
      return r;
    }
    inv = normal.inverse();
    params = inv * rhs;
  }
  double chi2 = 0.0;
  for (std::size_t k = 0; k < track.size(); ++k) {
    ConfIndex i = track[k];
    double var = std::max(hits.varZ[i] + params(1) * params(1) * hits.varRxy[i],
                          kMinZVariance);
    double e = hits.z[i] - (params(0) + params(1) * s[k]);
    chi2 += e * e / var;
  }
  r.z0 = params(0);
  r.tanLambda = params(1);
  r.covariance = inv;
  r.chi2 = chi2;
  r.ndf = n - 2;
  r.lastS = s.back();
  r.valid = std::isfinite(chi2) && params.allFinite();
  return r;
}

}  // namespace conftrack

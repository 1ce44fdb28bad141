#include "conftrack/geometry/Helix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace conftrack {

namespace {

/// Restricts the window [lo, hi] of transverse arc lengths to those where
/// z0 + s tanL lies in [zMin, zMax]. Returns false if it becomes empty.
bool clipToZRange(double z0, double tanLambda, double zMin, double zMax,
                  double& lo, double& hi) {
  if (tanLambda == 0.0) {
    return z0 >= zMin && z0 <= zMax && lo <= hi;
  }
  const double s1 = (zMin - z0) / tanLambda;
  const double s2 = (zMax - z0) / tanLambda;
  lo = std::max(lo, std::min(s1, s2));
  hi = std::min(hi, std::max(s1, s2));
  return lo <= hi;
}

/// Smallest t > 0 with a t^2 + b t + c = 0; infinity if there is none.
double smallestPositiveRoot(double a, double b, double c) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (a == 0.0) {
    const double t = b != 0.0 ? -c / b : -1.0;
    return t > 0.0 ? t : kInf;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) {
    return kInf;
  }
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double best = kInf;
  for (double t : {q / a, q != 0.0 ? c / q : 0.0}) {
    if (t > 0.0 && t < best) {
      best = t;
    }
  }
  return best;
}

}  // namespace

void Helix::computeRadialRange() {
  const double r0sq = m_position.head<2>().squaredNorm();
  const double sign = m_omega < 0.0 ? -1.0 : 1.0;
  m_omegaC = std::sqrt(
      std::max(0.0, 1.0 - 2.0 * m_omega * m_e + m_omega * m_omega * r0sq));
  m_minRadius =
      std::abs(r0sq * std::abs(m_omega) - 2.0 * m_e * sign) / (1.0 + m_omegaC);
  m_maxRadius =
      m_omega == 0.0 ? kNoCrossing : (1.0 + m_omegaC) / std::abs(m_omega);
}

// Cylinder crossing. With D = P0.t, E = P0.n and Delta = R^2 - r0^2, the
// radius along the helix obeys (expand |P(s)|^2 with the form in Helix.hpp)
//
//     Omega^2 Delta / 2 = Omega D sin w + (1 - Omega E)(1 - cos w).
//
// The half-angle substitution u = tan(w/2) = Omega sigma / 2 turns this
// into the quadratic  A sigma^2 + 2 D sigma - Delta = 0  with
// A = 1 - Omega E - Omega^2 Delta / 4, which is the straight-line equation
// |P0 + sigma t|^2 = R^2 for Omega -> 0: no 1/Omega appears, so it is
// precise for stiff tracks. A root sigma is reached after
//
//     s = 2 atan(|Omega| sigma / 2) / |Omega|     (+ period if sigma < 0)
//
// (s -> sigma for Omega -> 0; sigma = infinity, A = 0, is half a turn), and
// again after every further period: the crossings of a looper are
// s_k + n * period. Since s grows with sigma on each sign branch, the
// order of the two crossings is known before any atan is evaluated.
double Helix::nextCylinderCrossing(double r, double zMin, double zMax,
                                   double sMin, double sMax) const {
  double lo = sMin;
  double hi = sMax;
  if (!clipToZRange(m_position.z(), m_tanLambda, zMin, zMax, lo, hi)) {
    return kNoCrossing;
  }
  const double r0 = m_position.head<2>().norm();
  const double delta = (r - r0) * (r + r0);
  const double a = 1.0 - m_omega * m_e - 0.25 * m_omega * m_omega * delta;
  const double disc = m_d * m_d + a * delta;
  if (disc < 0.0) {
    return kNoCrossing;
  }
  // Numerically stable roots: sigma1 = q/A, sigma2 = -Delta/q.
  const double q = -(m_d + std::copysign(std::sqrt(disc), m_d));
  if (q == 0.0) {
    // Tangent at the start point: nothing ahead.
    return kNoCrossing;
  }
  double first = q / a;
  double second = -delta / q;
  // Crossing order: non-negative sigma first, then by increasing sigma.
  if ((first < 0.0) == (second < 0.0) ? second < first : first < 0.0) {
    std::swap(first, second);
  }
  const double absOmega = std::abs(m_omega);
  if (absOmega == 0.0) {
    // Straight line: only forward roots, no repetition.
    for (double s : {first, second}) {
      if (s > sMin && s >= lo) {
        return s <= hi ? s : kNoCrossing;
      }
    }
    return kNoCrossing;
  }
  const double period = this->period();
  auto arc = [&](double sigma) {
    const double s = 2.0 * std::atan(0.5 * absOmega * sigma) / absOmega;
    return s < 0.0 ? s + period : s;
  };
  // Next repetition of s at or after lo (and strictly after sMin).
  auto next = [&](double s) {
    if (s < lo) {
      s += period * std::ceil((lo - s) / period);
    }
    return s <= sMin ? s + period : s;
  };
  const double s1 = arc(first);
  if (s1 >= lo && s1 > sMin) {
    // The earliest crossing of the turn is in the window, or none is.
    return s1 <= hi ? s1 : kNoCrossing;
  }
  const double best = std::min(next(s1), next(arc(second)));
  return best <= hi ? best : kNoCrossing;
}

double Helix::planeCrossing(const Vector3& point, const Vector3& normal,
                            double sStart, double maxShift, int maxIterations,
                            double tolerance, double onPlane) const {
  double s = sStart;
  for (int iteration = 0; iteration < maxIterations; ++iteration) {
    Vector3 p;
    Vector3 q;
    positionAndMomentum(s, p, q);
    const double f = normal.dot(p - point);
    if (iteration == 0 && std::abs(f) <= onPlane) {
      return s;
    }
    const double slope = normal.dot(q) / m_pt;  // df/ds
    if (!(std::abs(slope) > 1e-12)) {
      return kNoCrossing;  // along the plane
    }
    const double step = -f / slope;
    s += step;
    if (!(std::abs(s - sStart) <= maxShift)) {
      return kNoCrossing;
    }
    if (std::abs(step) <= tolerance) {
      return s;
    }
  }
  return kNoCrossing;
}

double Helix::nextDiskCrossing(double z, double rMin, double rMax, double sMin,
                               double sMax) const {
  if (m_tanLambda == 0.0) {
    return kNoCrossing;
  }
  const double s = (z - m_position.z()) / m_tanLambda;
  if (!(s > sMin && s <= sMax)) {
    return kNoCrossing;
  }
  const double r2 = position(s).head<2>().squaredNorm();
  if (r2 < rMin * rMin || r2 > rMax * rMax) {
    return kNoCrossing;
  }
  return s;
}

// Cone crossing: a bracketing root search on g(s) = r(s) - rCone(z(s)).
// From a point with distance g the next root is at least a "safe step"
// away, from bounds on g' and g'' (|dr/ds| <= 1 for the transverse arc
// length, and the curvature bound below), so stepping by
// max(safe step, kConeMinStep) cannot jump over a crossing except a pair
// closer than kConeMinStep (a grazing touch). The first sign change is then
// refined by Newton steps kept inside the bracket (bisection when a step
// leaves it), to machine precision. The window is first cut to the z range
// of the cone and to where the cone radius is reachable by the helix.
double Helix::nextConeCrossing(double zMin, double zMax, double r1,
                               double slope, double sMin, double sMax) const {
  if (slope == 0.0) {
    return nextCylinderCrossing(r1, zMin, zMax, sMin, sMax);  // analytic
  }
  double lo = sMin;
  double hi = sMax;
  if (!clipToZRange(m_position.z(), m_tanLambda, zMin, zMax, lo, hi)) {
    return kNoCrossing;
  }
  const double r2 = r1 + (zMax - zMin) * slope;
  const double rcMin = std::min(r1, r2);
  const double rcMax = std::max(r1, r2);
  const double reachMin = minRadius();
  const double reachMax = maxRadius();
  if (reachMin > rcMax || reachMax < rcMin) {
    return kNoCrossing;
  }
  // Along the helix the cone radius is linear in s, rc(s) = rc0 + s dr; a
  // crossing needs rc(s) within the radii the helix reaches, which cuts the
  // window further (e.g. a small looping circle inside a widening cone).
  {
    const double margin = 1e-9 * (1.0 + reachMin);
    const double rc0 = r1 + (m_position.z() - zMin) * slope;
    const double drds = slope * m_tanLambda;
    if (drds != 0.0) {
      const double sa = (reachMin - margin - rc0) / drds;
      const double sb = (reachMax + margin - rc0) / drds;
      lo = std::max(lo, std::min(sa, sb));
      hi = std::min(hi, std::max(sa, sb));
    } else if (rc0 < reachMin - margin || rc0 > reachMax + margin) {
      return kNoCrossing;
    }
  }
  // The transverse distance travelled bounds the radial change.
  const double r0 = m_position.head<2>().norm();
  const double radialGap = std::max({0.0, rcMin - r0, r0 - rcMax});
  lo = std::max(lo, radialGap);
  if (m_tanLambda == 0.0 && m_omega != 0.0) {
    // Constant z on a closed circle: one period sees every crossing.
    hi = std::min(hi, lo + period());
  }
  if (lo > hi) {
    return kNoCrossing;
  }
  const double dr = slope * m_tanLambda;  // d(rCone)/ds
  // Distance to the cone g, the radius r and the derivative g' at s, from
  // one sincos.
  struct Point {
    double g;
    double r;
    double gPrime;
  };
  auto evaluate = [&](double s) {
    Vector3 p;
    Vector3 mom;
    positionAndMomentum(s, p, mom);
    const double r = p.head<2>().norm();
    return Point{r - (r1 + (p.z() - zMin) * slope), r,
                 (p.x() * mom.x() + p.y() * mom.y()) / (r * m_pt) - dr};
  };
  // Safe step: a length t such that no root of g lies in (s, s + t); the
  // largest of three rigorous bounds:
  //  1. r' in [-1, 1], so g' = r' - dr lies in [-1 - dr, 1 - dr];
  //  2. outside the cone (g > 0) the radius stays above rcMin until the
  //     first root, and |r''| = |(1 - r'^2)/r +- |Omega| sqrt(1 - r'^2)|
  //     <= 1/rcMin + |Omega| = M there: g(s + t) >= g + g' t - M t^2 / 2
  //     (long steps for a stiff track running nearly parallel to the cone);
  //  3. r^2 = |C|^2 + rho^2 + 2 rho |C| cos(psi(s)) has |(r^2)''| <=
  //     2 |Omega||C| = 2K (K = 1 for a line), and a root needs
  //     r^2 = (rc + dr t)^2: the first t where the bound
  //     r^2 + (r^2)' t +- K t^2 reaches (rc + dr t)^2 (long steps for a
  //     track inside the cone moving away from it).
  const double curvatureBound = 1.0 / rcMin + std::abs(m_omega);
  const double k = m_omegaC;
  auto safeStep = [&](const Point& p) {
    const double rc = p.r - p.g;
    const double b = 2.0 * (p.r * (p.gPrime + dr) - rc * dr);
    const double c = (p.r - rc) * (p.r + rc);
    if (p.g > 0.0) {
      const double rate = 1.0 + dr;
      const double first = rate > 0.0 ? p.g / rate : kNoCrossing;
      const double second = (p.gPrime + std::sqrt(p.gPrime * p.gPrime +
                                                  2.0 * curvatureBound * p.g)) /
                            curvatureBound;
      const double third = smallestPositiveRoot(-k - dr * dr, b, c);
      return std::max({first, second, third});
    }
    const double rate = 1.0 - dr;
    const double first = rate > 0.0 ? -p.g / rate : kNoCrossing;
    const double third = smallestPositiveRoot(k - dr * dr, b, c);
    return std::max(first, third);
  };
  double s = lo;
  Point at = evaluate(s);
  constexpr int kMaxSteps = 100000;
  for (int step = 0; step < kMaxSteps; ++step) {
    const double g = at.g;
    if (g == 0.0 && s > sMin) {
      return s;
    }
    const double safe = safeStep(at);
    if (safe >= hi - s) {
      return kNoCrossing;  // no root can lie before hi
    }
    const double s1 = std::min(hi, s + std::max(safe, kConeMinStep));
    const Point next = evaluate(s1);
    const double g1 = next.g;
    if ((g < 0.0 && g1 > 0.0) || (g > 0.0 && g1 < 0.0) ||
        (g1 == 0.0 && s1 > sMin)) {
      // Refine in the bracket [s, s1]: Newton, bisection when a step
      // leaves the bracket.
      double a = s;
      double ga = g;
      double b = s1;
      double x = s1;
      if (g1 != 0.0) {
        x = a - ga * (b - a) / (g1 - ga);  // secant start
        for (int it = 0; it < 100; ++it) {
          const Point px = evaluate(x);
          const double gx = px.g;
          const double dg = px.gPrime;
          if (gx == 0.0) {
            break;
          }
          if ((gx < 0.0) == (ga < 0.0)) {
            a = x;
            ga = gx;
          } else {
            b = x;
          }
          double xn = dg != 0.0 ? x - gx / dg : 0.5 * (a + b);
          if (!(xn > a && xn < b)) {
            xn = 0.5 * (a + b);
          }
          const bool converged =
              std::abs(xn - x) <= 1e-13 * (1.0 + std::abs(x));
          x = xn;
          if (converged || b - a <= 1e-13 * (1.0 + std::abs(a))) {
            break;
          }
        }
      }
      return x > sMin ? x : kNoCrossing;
    }
    if (s1 >= hi) {
      return kNoCrossing;
    }
    s = s1;
    at = next;
  }
  return kNoCrossing;
}

}  // namespace conftrack

#include "conftrack/simulation/Helix.hpp"

#include <algorithm>

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

}  // namespace

double Helix::minRadius() const {
  const double r0sq = m_position.head<2>().squaredNorm();
  const double absOmega = std::abs(m_omega);
  const double sign = m_omega < 0.0 ? -1.0 : 1.0;
  const double omegaC =
      std::sqrt(std::max(0.0, 1.0 - 2.0 * m_omega * m_e +
                                  m_omega * m_omega * r0sq));
  return std::abs(r0sq * absOmega - 2.0 * m_e * sign) / (1.0 + omegaC);
}

double Helix::maxRadius() const {
  if (m_omega == 0.0) {
    return kNoCrossing;
  }
  const double r0sq = m_position.head<2>().squaredNorm();
  const double omegaC =
      std::sqrt(std::max(0.0, 1.0 - 2.0 * m_omega * m_e +
                                  m_omega * m_omega * r0sq));
  return (1.0 + omegaC) / std::abs(m_omega);
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
// precise for stiff tracks. Each root gives w = 2 atan(u) (atan2 also covers
// u = infinity, i.e. w = pi), hence s = w/Omega modulo the period; the
// crossings of a looper are s_k + n * period.
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
  double best = kNoCrossing;
  if (m_omega == 0.0) {
    for (double s : {q / a, -delta / q}) {
      if (s > sMin && s >= lo && s <= hi) {
        best = std::min(best, s);
      }
    }
    return best;
  }
  const double period = this->period();
  const double w[2] = {2.0 * std::atan2(m_omega * q, 2.0 * a),
                       2.0 * std::atan2(-m_omega * delta, 2.0 * q)};
  for (double wk : w) {
    double s = wk / m_omega;
    s -= period * std::floor(s / period);  // first crossing in [0, period)
    if (s < lo) {
      s += period * std::ceil((lo - s) / period);
    }
    if (s <= sMin) {
      s += period;
    }
    if (s <= hi) {
      best = std::min(best, s);
    }
  }
  return best;
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

double Helix::coneDistance(double s, double zMin, double r1,
                           double slope) const {
  const Vector3 p = position(s);
  return p.head<2>().norm() - (r1 + (p.z() - zMin) * slope);
}

// Cone crossing. g(s) = r(s) - rCone(z(s)) changes at most by
// L = 1 + |slope tanL| per unit s (|dr/ds| <= 1 for the transverse arc
// length), so from a point with distance g no root lies closer than |g|/L:
// stepping by max(|g|/L, kConeMinStep) cannot jump over a crossing except
// a pair closer than kConeMinStep (a grazing touch). The first sign change
// is then refined by Newton steps kept inside the bracket (bisection when
// a step leaves it), to machine precision.
double Helix::nextConeCrossing(double zMin, double zMax, double r1,
                               double slope, double sMin, double sMax) const {
  double lo = sMin;
  double hi = sMax;
  if (!clipToZRange(m_position.z(), m_tanLambda, zMin, zMax, lo, hi)) {
    return kNoCrossing;
  }
  const double r2 = r1 + (zMax - zMin) * slope;
  const double rcMin = std::min(r1, r2);
  const double rcMax = std::max(r1, r2);
  if (minRadius() > rcMax || maxRadius() < rcMin) {
    return kNoCrossing;
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
  const double lipschitz = 1.0 + std::abs(slope * m_tanLambda);
  double s = lo;
  double g = coneDistance(s, zMin, r1, slope);
  constexpr int kMaxSteps = 100000;
  for (int step = 0; step < kMaxSteps; ++step) {
    if (g == 0.0 && s > sMin) {
      return s;
    }
    if (s >= hi) {
      return kNoCrossing;
    }
    const double s1 =
        std::min(hi, s + std::max(std::abs(g) / lipschitz, kConeMinStep));
    const double g1 = coneDistance(s1, zMin, r1, slope);
    if ((g < 0.0 && g1 > 0.0) || (g > 0.0 && g1 < 0.0) ||
        (g1 == 0.0 && s1 > sMin)) {
      // Refine in the bracket [s, s1].
      double a = s;
      double ga = g;
      double b = s1;
      double x = s1;
      double gx = g1;
      if (g1 != 0.0) {
        x = a - ga * (b - a) / (g1 - ga);  // secant start
        for (int it = 0; it < 100; ++it) {
          gx = coneDistance(x, zMin, r1, slope);
          if (gx == 0.0) {
            break;
          }
          if ((gx < 0.0) == (ga < 0.0)) {
            a = x;
            ga = gx;
          } else {
            b = x;
          }
          const Vector3 p = position(x);
          const Vector3 mom = momentum(x);
          const double rr = p.head<2>().norm();
          const double dg = (p.x() * mom.x() + p.y() * mom.y()) / (rr * m_pt) -
                            slope * m_tanLambda;
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
    s = s1;
    g = g1;
  }
  return kNoCrossing;
}

}  // namespace conftrack

#include "conftrack/simulation/generators/Kinematics.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

namespace conftrack {

FourMomentum FourMomentum::fromMass(const Vector3& momentum, double mass) {
  return {std::sqrt(momentum.squaredNorm() + mass * mass), momentum};
}

double FourMomentum::mass() const {
  const double m2 = mass2();
  return m2 > 0.0 ? std::sqrt(m2) : 0.0;
}

FourMomentum boost(const FourMomentum& v, const FourMomentum& frame) {
  const double m = frame.mass();
  if (!(m > 0.0)) {
    throw std::invalid_argument("boost: frame four-momentum is not massive");
  }
  const double gamma = frame.e / m;
  const Vector3 u = frame.p / m;  // gamma * beta
  const double up = u.dot(v.p);
  return {gamma * v.e + up, v.p + u * (up / (gamma + 1.0) + v.e)};
}

Vector3 randomDirection(RandomEngine& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double cosTheta = uniform(rng);
  const double phi = std::numbers::pi * uniform(rng);
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

void orthonormalBasis(const Vector3& axis, Vector3& e1, Vector3& e2) {
  // Cross with the coordinate axis least aligned with `axis` for stability.
  Vector3 helper = Vector3::UnitX();
  if (std::abs(axis.y()) < std::abs(axis.x()) &&
      std::abs(axis.y()) <= std::abs(axis.z())) {
    helper = Vector3::UnitY();
  } else if (std::abs(axis.z()) < std::abs(axis.x())) {
    helper = Vector3::UnitZ();
  }
  e1 = axis.cross(helper).normalized();
  e2 = axis.cross(e1);
}

std::pair<FourMomentum, FourMomentum> twoBodyDecay(const FourMomentum& parent,
                                                   double m1, double m2,
                                                   RandomEngine& rng) {
  const double bigM = parent.mass();
  if (!(m1 >= 0.0 && m2 >= 0.0 && m1 + m2 < bigM)) {
    throw std::invalid_argument("twoBodyDecay: daughters (" +
                                std::to_string(m1) + ", " + std::to_string(m2) +
                                ") too heavy for parent mass " +
                                std::to_string(bigM));
  }
  const double sum = m1 + m2;
  const double diff = m1 - m2;
  const double pStar =
      std::sqrt((bigM - sum) * (bigM + sum) * (bigM - diff) * (bigM + diff)) /
      (2.0 * bigM);
  const Vector3 dir = randomDirection(rng);
  const FourMomentum d1 = FourMomentum::fromMass(pStar * dir, m1);
  const FourMomentum d2 = FourMomentum::fromMass(-pStar * dir, m2);
  return {boost(d1, parent), boost(d2, parent)};
}

std::vector<FourMomentum> nBodyDecay(const FourMomentum& parent,
                                     std::span<const double> masses,
                                     RandomEngine& rng) {
  const std::size_t n = masses.size();
  const double bigM = parent.mass();
  const double massSum = std::accumulate(masses.begin(), masses.end(), 0.0);
  if (n < 2 || !(massSum < bigM)) {
    throw std::invalid_argument(
        "nBodyDecay: need >= 2 daughters lighter than the parent (n = " +
        std::to_string(n) + ", sum of masses " + std::to_string(massSum) +
        ", parent mass " + std::to_string(bigM) + ")");
  }
  if (n == 2) {
    auto [a, b] = twoBodyDecay(parent, masses[0], masses[1], rng);
    return {a, b};
  }
  // RAMBO: isotropic massless momenta with energies from x exp(-x), then
  // boosted and scaled so that they sum to (M, 0).
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<FourMomentum> q(n);
  FourMomentum total;
  for (auto& qi : q) {
    const Vector3 dir = randomDirection(rng);
    // 1 - u lies in (0, 1], so the logarithms are finite.
    const double energy =
        -std::log((1.0 - uniform(rng)) * (1.0 - uniform(rng)));
    qi = {energy, energy * dir};
    total += qi;
  }
  const double totalMass = total.mass();
  const Vector3 b = -total.p / totalMass;
  const double gamma = total.e / totalMass;
  const double a = 1.0 / (1.0 + gamma);
  const double x = bigM / totalMass;
  std::vector<FourMomentum> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double bq = b.dot(q[i].p);
    p[i].e = x * (gamma * q[i].e + bq);
    p[i].p = x * (q[i].p + b * q[i].e + a * bq * b);
  }
  // Massive rescaling: find xi with sum_i sqrt(m_i^2 + xi^2 E_i^2) = M. The
  // left side is increasing and convex in xi, from sum(m) (< M) at 0 to
  // >= M at 1, so Newton's method started at xi = 1 converges monotonically.
  double xi = 1.0;
  for (int iter = 0; iter < 100; ++iter) {
    double f = -bigM;
    double df = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e2 = p[i].e * p[i].e;
      const double ei = std::sqrt(masses[i] * masses[i] + xi * xi * e2);
      f += ei;
      df += xi * e2 / ei;
    }
    const double step = f / df;
    xi -= step;
    if (std::abs(step) < 1e-15 * xi) {
      break;
    }
  }
  std::vector<FourMomentum> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const FourMomentum rest = FourMomentum::fromMass(xi * p[i].p, masses[i]);
    out[i] = boost(rest, parent);
  }
  return out;
}

}  // namespace conftrack

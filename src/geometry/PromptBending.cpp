#include "conftrack/geometry/PromptBending.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace conftrack {

namespace {

/// Grid nodes in r and |z|: 10-25 mm spacing over the trackers, where g
/// changes by at most 1e-3 between nodes.
constexpr int kNodesR = 97;
constexpr int kNodesZ = 161;
/// Simpson intervals of the path integral (even).
constexpr int kIntervals = 48;

}  // namespace

double PromptBending::integrate(const MagneticField& field, double r,
                                double z) {
  const double b0 = field.centralBz();
  if (field.isUniform() || !(b0 > 0.0)) {
    return 1.0;
  }
  // Near the beam line the path is a point: its bending is the local one.
  const double rPath = std::max(r, 1e-3);
  const double slope = z / rPath;
  // The straight path from the origin at azimuth 0.
  const Vector3 direction(1.0, 0.0, slope);
  auto weighted = [&](double rho) {
    return (rPath - rho) *
           MagneticField::bendingComponent(field.at(rho * direction),
                                           direction) /
           b0;
  };
  const double h = rPath / kIntervals;
  double sum = weighted(0.0) + weighted(rPath);
  for (int k = 1; k < kIntervals; ++k) {
    sum += (k % 2 == 1 ? 4.0 : 2.0) * weighted(k * h);
  }
  return 2.0 / (rPath * rPath) * sum * h / 3.0;
}

PromptBending::PromptBending(const MagneticField& field, double envelopeR,
                             double envelopeZ) {
  if (!(envelopeR > 0.0) || !(envelopeZ > 0.0)) {
    throw std::invalid_argument(
        "PromptBending: the envelope must have positive r and z");
  }
  if (field.isUniform()) {
    return;
  }
  m_nodesR = kNodesR;
  m_nodesZ = kNodesZ;
  m_stepR = envelopeR / (kNodesR - 1);
  m_stepZ = envelopeZ / (kNodesZ - 1);
  m_table.resize(static_cast<std::size_t>(kNodesR) * kNodesZ);
  for (int i = 0; i < kNodesR; ++i) {
    for (int j = 0; j < kNodesZ; ++j) {
      m_table[static_cast<std::size_t>(i) * kNodesZ + j] =
          integrate(field, i * m_stepR, j * m_stepZ);
    }
  }
}

double PromptBending::factor(double r, double z) const {
  if (m_table.empty()) {
    return 1.0;
  }
  const double x = std::clamp(r / m_stepR, 0.0, m_nodesR - 1.0);
  const double y = std::clamp(std::abs(z) / m_stepZ, 0.0, m_nodesZ - 1.0);
  const int i = std::min(static_cast<int>(x), m_nodesR - 2);
  const int j = std::min(static_cast<int>(y), m_nodesZ - 2);
  const double fx = x - i;
  const double fy = y - j;
  const double* row = &m_table[static_cast<std::size_t>(i) * m_nodesZ + j];
  const double* next = row + m_nodesZ;
  return (1.0 - fx) * ((1.0 - fy) * row[0] + fy * row[1]) +
         fx * ((1.0 - fy) * next[0] + fy * next[1]);
}

}  // namespace conftrack

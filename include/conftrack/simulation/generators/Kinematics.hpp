#pragma once

/// @file Kinematics.hpp
/// Relativistic kinematics for the generators: four-momenta, boosts, and
/// two- and n-body decays at rest with exact four-momentum conservation.

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Types.hpp"

#include <span>
#include <vector>

namespace conftrack {

/// A four-momentum (E, p) [GeV].
struct FourMomentum {
  /// Energy [GeV].
  double e = 0.0;
  /// Momentum [GeV].
  Vector3 p = Vector3::Zero();

  /// From a three-momentum and a mass.
  static FourMomentum fromMass(const Vector3& momentum, double mass);

  /// Invariant mass [GeV]; 0 for (numerically) space-like vectors.
  double mass() const;
  /// Invariant mass squared [GeV^2].
  double mass2() const { return e * e - p.squaredNorm(); }
  /// Velocity p/E (|beta| < 1 for massive particles).
  Vector3 beta() const { return p / e; }

  /// Component-wise sum.
  FourMomentum operator+(const FourMomentum& other) const {
    return {e + other.e, p + other.p};
  }
  /// Component-wise accumulation.
  FourMomentum& operator+=(const FourMomentum& other) {
    e += other.e;
    p += other.p;
    return *this;
  }
};

/// Lorentz transformation of `v` from the rest frame of `frame` (a massive
/// four-momentum) to the frame in which `frame` is given. Written with
/// gamma = E/M and gamma*beta = p/M so that large boosts keep full
/// precision (no 1 - beta^2).
FourMomentum boost(const FourMomentum& v, const FourMomentum& frame);

/// A unit vector isotropic in 4 pi.
Vector3 randomDirection(RandomEngine& rng);

/// Two orthonormal vectors perpendicular to the unit vector `axis`.
void orthonormalBasis(const Vector3& axis, Vector3& e1, Vector3& e2);

/// Isotropic two-body decay of `parent` (lab frame) into masses m1, m2.
/// The daughters' four-momenta are returned in the lab frame; their sum is
/// the parent's four-momentum up to rounding. Throws std::invalid_argument
/// if m1 + m2 exceeds the parent mass.
std::pair<FourMomentum, FourMomentum> twoBodyDecay(const FourMomentum& parent,
                                                   double m1, double m2,
                                                   RandomEngine& rng);

/// Phase-space-like decay of `parent` (lab frame) into particles of the
/// given masses: massless momenta from the RAMBO algorithm (uniform in
/// massless n-body phase space), rescaled to the masses by solving
/// sum sqrt(m_i^2 + xi^2 q_i^2) = M for xi (as RAMBO's massive variant,
/// without the event weight), then boosted to the lab. Energy and momentum
/// are conserved exactly (to rounding); the distribution is isotropic.
/// Requires at least two daughters and sum(m) < M (std::invalid_argument
/// otherwise).
std::vector<FourMomentum> nBodyDecay(const FourMomentum& parent,
                                     std::span<const double> masses,
                                     RandomEngine& rng);

}  // namespace conftrack

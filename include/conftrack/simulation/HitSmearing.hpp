#pragma once

/// @file HitSmearing.hpp
/// Gaussian smearing of a true crossing point in the local measurement
/// frame of a sensitive layer, as DDPlanarDigiProcessor (detectors.md 1.7).

#include "conftrack/core/Random.hpp"
#include "conftrack/core/Types.hpp"
#include "conftrack/geometry/Surfaces.hpp"

#include <random>

namespace conftrack {

/// Smears `truePosition` on `layer` by independent Gaussians of width
/// layer.sigmaU along u and layer.sigmaV along v (SensitiveLayer::localAxes).
///
/// Barrel: u is the r-phi arc length, applied as a rotation by
/// delta_phi = delta_u / R so that the hit stays on the cylinder of radius
/// R = layer.r; v is z. Disk: the point moves in the disk plane by
/// delta_u along the tangential and delta_v along the radial axis at the
/// true point (a flat sensor). If the smeared point leaves the sensitive
/// area (|z| outside [zMin, zMax] on a barrel, r outside [rMin, rMax] on a
/// disk), both offsets are drawn again, at most `maxAttempts` draws in all
/// (DDPlanarDigiProcessor's MaxTries = 10); then the hit is dropped.
///
/// @param normal a standard normal distribution (owned by the caller so that
///        its cached second value is not thrown away)
/// @param[out] measured the smeared position, if accepted
/// @return false if the hit is dropped
bool smearHitPosition(const SensitiveLayer& layer, const Vector3& truePosition,
                      RandomEngine& rng,
                      std::normal_distribution<double>& normal,
                      unsigned maxAttempts, Vector3& measured);

}  // namespace conftrack

#pragma once

/// @file HelixState.hpp
/// The track model of the fit: the five LCIO helix parameters
/// (d0, phi0, Omega, z0, tanLambda) relative to a movable reference point
/// (the "pivot" of KalTest), the exact pivot transformation with its
/// analytic Jacobian, conversions from a point and momentum, and the
/// three-point helix of the prefit (physics.md sections 2 and 3).
///
/// Omega is the geometric signed curvature of the Helix class: positive
/// for a clockwise turn seen from +z, i.e. Omega = q kPtPerTeslaMm Bz / pT
/// (sign(Omega) = sign(q) for Bz > 0, the LCIO convention). Momenta are
/// computed for |q| = 1.

#include "conftrack/core/Track.hpp"
#include "conftrack/core/Types.hpp"
#include "conftrack/geometry/Helix.hpp"

#include <optional>

namespace conftrack {

/// Jacobian d(new parameters)/d(old parameters), indexed by eD0 ... .
using TrackJacobian = Eigen::Matrix<double, 5, 5>;

/// |Omega| below this is treated as this value (a straight line within
/// 1e-12 relative precision over 1 km), so that 1/Omega stays finite.
inline constexpr double kMinAbsOmega = 1e-12 / units::mm;

/// Wraps an angle into (-pi, pi].
double wrapAngle(double phi);

/// Helix parameters relative to a reference point (the pivot): the point
/// of closest approach (PCA) in x-y to the pivot is
/// pivot + d0 (-sin phi0, cos phi0, 0) + z0 z_hat.
struct HelixState {
  /// Reference point [mm].
  Vector3 pivot = Vector3::Zero();
  /// (d0, phi0, Omega, z0, tanLambda).
  TrackVector params = TrackVector::Zero();

  /// Point of closest approach to the pivot [mm].
  Vector3 pca() const;
  /// Unit vector along the momentum at the PCA.
  Vector3 direction() const;
  /// Momentum at the PCA for |q| = 1 in the field bz [GeV].
  Vector3 momentum(double bz) const;
};

/// Moves the reference point of helix parameters from `from` to `to`
/// (physics.md 3 "Moving the reference point", MarlinTrk
/// HelixTrack::moveRefPoint), written without 1/Omega cancellations so
/// that it is exact for stiff tracks and straight lines:
///
/// with (u, w) the components of Delta = to - from along the direction
/// t = (cos phi0, sin phi0) and the left normal n = (-sin phi0, cos phi0),
/// q = 1 - Omega d0 and q' = sgn(q) sqrt((q + Omega w)^2 + (Omega u)^2),
///
///     phi0' = phi0 + atan2(-Omega u, q + Omega w)     (for q > 0)
///     d0'   = d0 - (2 q w + Omega (u^2 + w^2)) / (q + q')
///     z0'   = z0 + s tanLambda - Delta_z,   s = -(phi0' - phi0)/Omega,
///
/// s being the transverse arc length along the motion from the old PCA to
/// the new one; of its values s + k 2 pi/|Omega| (loopers) the one closest
/// to `sExpected` is taken. Omega and tanLambda do not change.
///
/// The analytic Jacobian (derived from the centre invariance
/// (1/Omega - d0)(sin phi0, -cos phi0) = C - pivot, as KalTest's
/// THelicalTrack::MoveTo; verified against numerical differentiation in
/// FitterTests) is, with Y = q + Omega w:
///
///     dd0'/dd0 = Y/q',  dd0'/dphi0 = q u/q',
///     dd0'/dOmega = -2 sin^2(dphi/2)/Omega^2,
///     dphi0'/dd0 = -Omega^2 u/q'^2,  dphi0'/dphi0 = q Y/q'^2,
///     dphi0'/dOmega = -u/q'^2,
///     dz0'/dx = tanLambda ds/dx with ds/dd0 = Omega u/q'^2,
///     ds/dphi0 = (Y w + Omega u^2)/q'^2, ds/dOmega = (u/q'^2 - s)/Omega,
///     dz0'/dz0 = 1, dz0'/dtanLambda = s.
///
/// @param params parameters relative to `from`
/// @param[out] moved parameters relative to `to`
/// @param jacobian if not null, receives d(moved)/d(params)
/// @return s, or NaN if `to` is the centre of the circle (q' = 0)
double movePivot(const TrackVector& params, const Vector3& from,
                 const Vector3& to, double sExpected, TrackVector& moved,
                 TrackJacobian* jacobian = nullptr);

/// Helix parameters relative to `reference` of a particle at `position`
/// with `momentum` [GeV] and `charge` [e] in the field bz [T]
/// (physics.md 3 "From a true particle": the PCA within half a turn of
/// the position). Requires a non-zero transverse momentum.
TrackVector helixParametersAt(const Vector3& position, const Vector3& momentum,
                              double charge, double bz,
                              const Vector3& reference = Vector3::Zero());

/// The geometry Helix of a state, starting at its PCA and moving along the
/// momentum (direction = +1) or against it (direction = -1, the reversed
/// track: momentum and charge flipped, so that the Helix's arc length
/// s > 0 runs backwards along the motion). Requires bz != 0.
Helix makeHelix(const HelixState& state, double bz, int direction);

/// A helix through three points (physics.md 2): the circle through their
/// x-y projections, tanLambda from z versus the arc length between the
/// first and the last point.
struct ThreePointHelix {
  /// Parameters relative to the first point (d0 = z0 = 0).
  TrackVector atFirst = TrackVector::Zero();
  /// Parameters relative to the last point (d0 = z0 = 0).
  TrackVector atLast = TrackVector::Zero();
  /// Transverse arc length from the first to the last point [mm].
  double arcLength = 0.0;
};

/// The helix through p1, p2, p3 traversed in this order (which fixes the
/// sign of Omega). Arc lengths are measured around the fitted circle, so
/// loopers (more than half a turn between points) are handled. Returns
/// nullopt for coincident points in x-y or a zero arc length.
std::optional<ThreePointHelix> threePointHelix(const Vector3& p1,
                                               const Vector3& p2,
                                               const Vector3& p3);

}  // namespace conftrack

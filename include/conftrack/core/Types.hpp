#pragma once

/// @file Types.hpp
/// Fixed-size linear-algebra types and small index types used everywhere.

#include <Eigen/Core>

#include <cstdint>
#include <limits>

namespace conftrack {

using Vector2 = Eigen::Matrix<double, 2, 1>;
using Vector3 = Eigen::Matrix<double, 3, 1>;
using Matrix2 = Eigen::Matrix<double, 2, 2>;
using Matrix3 = Eigen::Matrix<double, 3, 3>;

/// Index of a hit in an event's hit array (internal, dense, 32 bit).
using HitIndex = std::uint32_t;
/// Index of a particle in an event's particle array.
using ParticleIndex = std::uint32_t;

inline constexpr std::uint32_t kInvalidIndex =
    std::numeric_limits<std::uint32_t>::max();

}  // namespace conftrack

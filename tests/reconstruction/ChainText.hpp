#pragma once

/// @file ChainText.hpp
/// Text of a minimal chain for the chain-parsing tests.

#include <string>

namespace conftrack {

/// A chain of one build step ("S0") over `collection` with only the
/// required keys; both cell angles are `cellAngle`.
inline std::string minimalStep(const std::string& collection,
                               const std::string& cellAngle = "0.01") {
  return "[[step]]\nname = \"S0\"\ncollections = [\"" + collection +
         "\"]\nactions = [\"build\"]\nmax_cell_angle = " + cellAngle +
         "\nmax_cell_angle_rz = " + cellAngle +
         "\nchi2_cut = 100.0\nmin_hits = 4\nmax_distance = 0.02\n"
         "slope_z_range = 10.0\nhigh_pt_cut_GeV = 10.0\n";
}

}  // namespace conftrack

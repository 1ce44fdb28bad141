#pragma once

/// @file EventDisplay.hpp
/// Event display (paper figures 2 and 4): one event's hits and found tracks
/// in (x, y), (u, v) and (z, r), drawn by scripts/conftrack_display.py.

#include "conftrack/core/Hit.hpp"
#include "conftrack/core/Track.hpp"

#include <filesystem>
#include <ostream>
#include <span>
#include <string>
#include <vector>

namespace conftrack {

/// Writes the display CSV (x,y,z,track; track -1 for hits on no track).
void writeDisplayCsv(const std::filesystem::path& file,
                     std::span<const Hit> hits, std::span<const Track> tracks);

/// Writes the CSV next to `png` and runs the display script on it. Returns
/// false (after one line to `log` on how to get python3-matplotlib) if it
/// could not draw; never throws for a missing interpreter.
bool drawEventDisplay(const std::filesystem::path& png,
                      std::span<const Hit> hits, std::span<const Track> tracks,
                      const std::string& title, std::ostream& log);

}  // namespace conftrack

#pragma once

/// @file DetectorReader.hpp
/// Reads a Detector from a TOML file (format: README "Detector files").

#include "conftrack/geometry/Detector.hpp"

#include <filesystem>
#include <string>

namespace conftrack {

/// Reads and validates a detector file. Throws InputError with
/// "file:line: key 'k': problem" for unknown or missing keys, bad values,
/// overlapping layers and duplicate names.
Detector readDetector(const std::filesystem::path& file);

/// Reads a detector from TOML text; `sourceName` is used in error messages.
Detector parseDetector(std::string_view text, const std::string& sourceName);

/// Resolves a detector argument: a path to a TOML file, or the name of a
/// shipped detector ("clicdet", "cld", ...) looked up in the detectors/
/// folder (CONFTRACK_DATA_DIR or the source tree).
std::filesystem::path resolveDetectorPath(const std::string& nameOrPath);

/// Reads the detector named or pointed to by `nameOrPath`.
Detector loadDetector(const std::string& nameOrPath);

}  // namespace conftrack

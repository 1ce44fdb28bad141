#pragma once

/// @file LayoutFile.hpp
/// Reading the CLICdet and CLD layout files (data/layouts/) into the
/// flat sensors of a module-level simulation (geometry/LayoutModules.hpp).

#include "conftrack/geometry/Detector.hpp"
#include "conftrack/geometry/ModuleLayout.hpp"

#include <filesystem>

namespace conftrack {

/// The shipped layout file of `detector`:
/// <data>/data/layouts/<name>_layout.json.gz, <name> being the detector
/// name up to its first space or parenthesis, in lower case ("CLICdet" ->
/// clicdet, "CLD (FCC-ee)" -> cld), <data> as in core/DataFiles.hpp
/// (CONFTRACK_DATA_DIR or the source tree).
/// Whether it exists is not checked.
std::filesystem::path shippedLayoutFile(const Detector& detector);

/// Reads the layout JSON `file` (plain or gzip, core/TextFile.hpp) and builds
/// the sensors of `detector` (buildLayoutModules). Throws InputError
/// "file: problem" if it cannot be read or is invalid.
ModuleLayout readLayoutModules(const std::filesystem::path& file,
                               const Detector& detector);

}  // namespace conftrack

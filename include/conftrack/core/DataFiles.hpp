#pragma once

/// @file DataFiles.hpp
/// Locating shipped data files (detectors/, chains/) and reading text files
/// with one-line errors.

#include <cstddef>
#include <filesystem>
#include <string>

namespace conftrack {

/// The folder that holds the shipped detectors/, chains/, data/ and
/// scripts/: the CONFTRACK_DATA_DIR environment variable if set, else the
/// source tree the program was built from.
std::filesystem::path dataDirectory();

/// Resolves `nameOrPath`: a path (contains '/' or ends in .toml) is
/// returned as is; a bare name is looked up as <data>/<folder>/<name>.toml,
/// with <data> from the CONFTRACK_DATA_DIR environment variable or the
/// source tree. `what` ("detector", "chain") names it in errors.
std::filesystem::path resolveShippedFile(const std::string& folder,
                                         const std::string& nameOrPath,
                                         const std::string& what);

/// Upper limit on the size of a configuration file (16 MiB; the shipped
/// ones are a few kB).
inline constexpr std::size_t kMaxConfigFileBytes = std::size_t{1} << 24;

/// Reads a whole text file; InputError "file: cannot open <what> file", or
/// "file: <what> file larger than ..." beyond kMaxConfigFileBytes.
std::string readConfigText(const std::filesystem::path& file,
                           const std::string& what);

}  // namespace conftrack

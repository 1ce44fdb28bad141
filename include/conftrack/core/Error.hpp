#pragma once

/// @file Error.hpp
/// Error types. Bad user input (files, configurations, command lines) is an
/// InputError: the CLI prints its one-line message and exits with code 1.
/// Anything else that escapes is an internal error (exit code 2).

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace conftrack {

/// Bad input: a file, a configuration key or a command-line value.
class InputError : public std::runtime_error {
 public:
  /// Builds "where: what", e.g. "detectors/x.toml:12: key 'r_mm': negative".
  InputError(std::string_view where, std::string_view what);
  /// A message without location.
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

/// Bad input that is a missing file or folder (the Python module raises
/// FileNotFoundError for it; the CLI treats it as any InputError).
class MissingFileError : public InputError {
 public:
  using InputError::InputError;
};

/// Formats a location "file:line" (line omitted when 0).
std::string location(std::string_view file, std::size_t line = 0);

}  // namespace conftrack

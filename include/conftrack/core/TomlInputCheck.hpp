#pragma once

/// @file TomlInputCheck.hpp
/// The check of TOML text that ConfigTable::parse runs before toml++ sees
/// it (docs/fuzzing.md, "Findings").

#include <string>
#include <string_view>

namespace conftrack {

/// Throws InputError "file:line: problem" for TOML text on which Debian's
/// toml++ 3.3.0 has undefined behaviour (a failed TOML_ASSERT_ASSUME or a
/// reached TOML_UNREACHABLE; found by fuzzing), checked before toml++ sees
/// it so that the message names the line:
/// - any byte outside ASCII (e.g. a UTF-8 letter at a line start or an
///   incomplete UTF-8 sequence): which non-ASCII text is safe cannot be
///   told, and conftrack's keys and values are ASCII anyway;
/// - a table header whose '[' or '[[' is followed by anything but a key
///   (e.g. "[@" or "[" at the end of a line);
/// - a '}' outside strings and comments that closes no inline table (e.g.
///   "a = [}"); valid TOML never has one.
/// Control characters other than tab, line feed and carriage return are
/// invalid TOML anywhere; they are refused too. Other inputs that break a
/// parser assumption are caught by ConfigTable.cpp (without a line).
void requireSafeToml(std::string_view text, const std::string& file);

}  // namespace conftrack

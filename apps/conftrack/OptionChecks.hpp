#pragma once

/// @file OptionChecks.hpp
/// Checks of command-line values that CLI11 does not make on its own, so
/// that every bad value is one line naming the option: whole numbers
/// (CLI11 wraps "-1" into a huge unsigned value and calls "1e8" out of
/// range), PDG codes, thread counts, and output folders checked before any
/// work is done.

#include <CLI/CLI.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack::cli {

/// Most threads -j accepts: beyond this a typo (100000) would start that
/// many threads.
inline constexpr std::uint64_t kMaxThreads = 1024;

/// A whole number in [min, max], written in digits ("1e8", "-1", "2.5" and
/// "0x10" are refused with a message saying so).
CLI::Validator wholeNumber(std::uint64_t min, std::uint64_t max);

/// A finite number in [min, max] (CLI11's Range lets NaN through).
CLI::Validator finiteNumber(double min, double max);

/// Adds option `name` taking a beam line's transverse position "X,Y" [mm,
/// as typed] into `xy`: two finite numbers, each within
/// kMaxBeamLineOffset (--beam-spot of the reconstruction, --beam-line of
/// simulate-trackml).
CLI::Option* addBeamLineOption(CLI::App& command, const std::string& name,
                               std::vector<double>& xy,
                               const std::string& help);

/// A PDG code the fitter has a mass for (massHypothesis).
CLI::Validator pdgCode();

/// The name of a luminous-region preset (LuminousRegion::presets()).
CLI::Validator luminousRegionPreset();

/// Makes `dir` (the value of `option`) a folder that can be written to:
/// creates it if needed and writes and removes a probe file. Throws
/// InputError "-o X: problem" if it is a file, cannot be created or is not
/// writable, before any work that would write there.
void prepareOutputFolder(const std::filesystem::path& dir,
                         std::string_view option);

/// The same for the folder of an output file (`file` itself must not be a
/// folder).
void prepareOutputFile(const std::filesystem::path& file,
                       std::string_view option);

}  // namespace conftrack::cli

#include "OptionChecks.hpp"

#include "conftrack/core/BeamLine.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/reconstruction/fitting/KalmanFitter.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <system_error>
#include <unistd.h>

namespace conftrack::cli {

namespace {

std::string where(std::string_view option, const std::filesystem::path& p) {
  return std::string(option) + " " + p.string();
}

/// prepareOutputFolder, with messages located at `at` ("-o X"); `named`:
/// `at` names `dir` itself (not a file in it), so the folder's name is not
/// repeated.
void makeWritableFolder(const std::filesystem::path& dir, const std::string& at,
                        bool named) {
  const std::string folder =
      named ? "the folder" : "the folder '" + dir.string() + "'";
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) &&
      !std::filesystem::is_directory(dir, ec)) {
    throw InputError(at, (named ? std::string("is a file")
                                : "'" + dir.string() + "' is a file") +
                             ", not a folder");
  }
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw InputError(at, "cannot create " + folder + ": " + ec.message());
  }
  // Permissions say little (root, read-only mounts, ACLs): try it.
  std::filesystem::path probe =
      dir / (".conftrack-write-test-" + std::to_string(::getpid()));
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (f == nullptr) {
    const int err = errno;
    throw InputError(at,
                     "cannot write into " + folder + ": " + std::strerror(err));
  }
  std::fclose(f);
  std::filesystem::remove(probe, ec);
}

}  // namespace

CLI::Validator wholeNumber(std::uint64_t min, std::uint64_t max) {
  std::string range =
      "[" + std::to_string(min) + ", " + std::to_string(max) + "]";
  return CLI::Validator(
      [min, max, range](std::string& text) -> std::string {
        std::uint64_t value = 0;
        const char* end = text.data() + text.size();
        auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ptr != end ||
            (ec != std::errc{} && ec != std::errc::result_out_of_range)) {
          return "'" + text + "' is not a whole number in " + range +
                 " (digits only)";
        }
        if (ec == std::errc::result_out_of_range || value < min ||
            value > max) {
          return text + " is out of range " + range;
        }
        return "";
      },
      "INT in " + range);
}

CLI::Validator finiteNumber(double min, double max) {
  std::ostringstream os;
  os << "[" << min << ", " << max << "]";
  std::string range = os.str();
  return CLI::Validator(
      [min, max, range](std::string& text) -> std::string {
        double value = 0.0;
        const char* begin = text.data();
        const char* end = text.data() + text.size();
        auto [ptr, ec] = std::from_chars(begin, end, value);
        if (text.empty() || ptr != end || ec != std::errc{} ||
            !std::isfinite(value)) {
          return "'" + text + "' is not a finite number in " + range;
        }
        if (value < min || value > max) {
          return text + " is out of range " + range;
        }
        return "";
      },
      "NUMBER in " + range);
}

CLI::Validator luminousRegionPreset() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (LuminousRegion::findPreset(text) == nullptr) {
          return "unknown luminous region '" + text +
                 "' (presets: " + LuminousRegion::presetNames() + ")";
        }
        return "";
      },
      "PRESET");
}

CLI::Option* addBeamLineOption(CLI::App& command, const std::string& name,
                               std::vector<double>& xy,
                               const std::string& help) {
  return command.add_option(name, xy, help)
      ->expected(2)
      ->delimiter(',')
      ->check(finiteNumber(-kMaxBeamLineOffset / units::mm,
                           kMaxBeamLineOffset / units::mm));
}

CLI::Validator pdgCode() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::int32_t pdg = 0;
        const char* end = text.data() + text.size();
        auto [ptr, ec] = std::from_chars(text.data(), end, pdg);
        if (text.empty() || ptr != end || ec != std::errc{} ||
            !massHypothesis(pdg)) {
          return "unknown PDG code '" + text +
                 "' (known: " + knownMassHypotheses() + ")";
        }
        return "";
      },
      "PDG");
}

void prepareOutputFolder(const std::filesystem::path& dir,
                         std::string_view option) {
  if (dir.empty()) {
    throw InputError(std::string(option) + ": empty folder name");
  }
  makeWritableFolder(dir, where(option, dir), true);
}

void prepareOutputFile(const std::filesystem::path& file,
                       std::string_view option) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw InputError(where(option, file), "is a folder, expected a file name");
  }
  if (file.empty() || !file.has_filename()) {
    throw InputError(where(option, file), "expected a file name");
  }
  std::filesystem::path dir = file.parent_path();
  makeWritableFolder(dir.empty() ? std::filesystem::path(".") : dir,
                     where(option, file), false);
}

}  // namespace conftrack::cli

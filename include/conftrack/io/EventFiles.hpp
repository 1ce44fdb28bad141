#pragma once

/// @file EventFiles.hpp
/// Names and discovery of per-event files: `eventNNNNNNNNN-hits.csv`,
/// `-truth.csv`, `-particles.csv`, each optionally with `.gz`.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace conftrack {

/// The three files of an event.
enum class EventFileKind : std::uint8_t { eHits, eTruth, eParticles };

/// File name of an event file, e.g. "event000001001-hits.csv.gz". Event
/// numbers are zero-padded to 9 digits (more digits if needed).
/// "event" plus the event number zero-padded to 9 digits: the stem shared by
/// all per-event files (events, tracks, submissions).
std::string eventFileStem(std::uint64_t eventNumber);

std::string eventFileName(std::uint64_t eventNumber, EventFileKind kind,
                          bool gzip);

/// The files of one event found in a folder.
struct EventFiles {
  /// Event number.
  std::uint64_t number = 0;
  /// Existing hits, truth and particles files (plain or .gz), if any.
  std::optional<std::filesystem::path> hits;
  std::optional<std::filesystem::path> truth;
  std::optional<std::filesystem::path> particles;

  /// Looks for the files of event `number` in `dir`, trying the plain and
  /// the .gz name. Throws InputError if both exist for the same file (which
  /// one is meant would be a guess).
  static EventFiles locate(const std::filesystem::path& dir,
                           std::uint64_t number);
};

/// Sorted event numbers of all `event<digits>-hits.csv[.gz]` in `dir`.
/// Throws InputError if `dir` is not a readable folder.
std::vector<std::uint64_t> listEvents(const std::filesystem::path& dir);

}  // namespace conftrack

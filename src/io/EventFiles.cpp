#include "conftrack/io/EventFiles.hpp"

#include "conftrack/core/Error.hpp"

#include <algorithm>
#include <charconv>
#include <string_view>

namespace conftrack {

namespace {

std::string_view suffix(EventFileKind kind) {
  switch (kind) {
    case EventFileKind::eHits:
      return "-hits.csv";
    case EventFileKind::eTruth:
      return "-truth.csv";
    case EventFileKind::eParticles:
      return "-particles.csv";
  }
  return "";
}

std::optional<std::filesystem::path> findOne(const std::filesystem::path& dir,
                                             std::uint64_t number,
                                             EventFileKind kind) {
  std::filesystem::path plain = dir / eventFileName(number, kind, false);
  std::filesystem::path gz = dir / eventFileName(number, kind, true);
  std::error_code ec;
  bool hasPlain = std::filesystem::exists(plain, ec);
  bool hasGz = std::filesystem::exists(gz, ec);
  if (hasPlain && hasGz) {
    throw InputError(location(plain.string()),
                     "both " + plain.filename().string() + " and " +
                         gz.filename().string() + " exist: remove one of them");
  }
  if (hasPlain) {
    return plain;
  }
  if (hasGz) {
    return gz;
  }
  return std::nullopt;
}

}  // namespace

std::string eventFileStem(std::uint64_t eventNumber) {
  std::string digits = std::to_string(eventNumber);
  std::string name = "event";
  if (digits.size() < 9) {
    name.append(9 - digits.size(), '0');
  }
  return name + digits;
}

std::string eventFileName(std::uint64_t eventNumber, EventFileKind kind,
                          bool gzip) {
  std::string name = eventFileStem(eventNumber);
  name += suffix(kind);
  if (gzip) {
    name += ".gz";
  }
  return name;
}

EventFiles EventFiles::locate(const std::filesystem::path& dir,
                              std::uint64_t number) {
  EventFiles files;
  files.number = number;
  files.hits = findOne(dir, number, EventFileKind::eHits);
  files.truth = findOne(dir, number, EventFileKind::eTruth);
  files.particles = findOne(dir, number, EventFileKind::eParticles);
  return files;
}

std::vector<std::uint64_t> listEvents(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) {
    throw MissingFileError(location(dir.string()), "not a folder");
  }
  if (!std::filesystem::is_directory(dir, ec)) {
    throw InputError(location(dir.string()), "not a folder");
  }
  std::vector<std::uint64_t> numbers;
  std::filesystem::directory_iterator it(dir, ec);
  if (ec) {
    throw InputError(location(dir.string()),
                     "cannot list folder: " + ec.message());
  }
  for (const auto& entry : it) {
    std::string name = entry.path().filename().string();
    std::string_view view = name;
    if (!view.starts_with("event")) {
      continue;
    }
    view.remove_prefix(5);
    if (view.ends_with(".gz")) {
      view.remove_suffix(3);
    }
    if (!view.ends_with("-hits.csv")) {
      continue;
    }
    view.remove_suffix(9);
    std::uint64_t number = 0;
    auto [ptr, err] =
        std::from_chars(view.data(), view.data() + view.size(), number);
    if (view.empty() || err != std::errc{} ||
        ptr != view.data() + view.size()) {
      continue;  // not an event file, e.g. "eventX-hits.csv"
    }
    numbers.push_back(number);
  }
  std::sort(numbers.begin(), numbers.end());
  numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());
  return numbers;
}

}  // namespace conftrack

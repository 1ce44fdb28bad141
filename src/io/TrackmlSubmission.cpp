#include "conftrack/io/TrackmlSubmission.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/io/CsvReader.hpp"
#include "conftrack/io/CsvWriter.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/TrackmlReader.hpp"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

namespace conftrack {

namespace {

constexpr std::string_view kEventId = "event_id";
constexpr std::string_view kHitId = "hit_id";
constexpr std::string_view kTrackId = "track_id";

}  // namespace

std::vector<std::uint64_t> trackmlLabels(
    std::size_t nHits, std::span<const std::vector<HitIndex>> tracks) {
  std::vector<std::uint64_t> labels(nHits, 0);
  // Owner's length per hit; a hit moves to a strictly longer track only,
  // so that ties stay with the earlier track.
  std::vector<std::size_t> ownerLength(nHits, 0);
  for (std::size_t k = 0; k < tracks.size(); ++k) {
    const std::size_t length = tracks[k].size();
    for (HitIndex h : tracks[k]) {
      if (h >= nHits) {
        throw std::invalid_argument(
            "trackmlLabels: track " + std::to_string(k) + " has hit index " +
            std::to_string(h) + " of " + std::to_string(nHits) + " hits");
      }
      if (labels[h] == 0 || length > ownerLength[h]) {
        labels[h] = k + 1;
        ownerLength[h] = length;
      }
    }
  }
  return labels;
}

std::string submissionFileName(std::uint64_t eventNumber, bool gzip) {
  std::string name = eventFileStem(eventNumber);
  name += "-submission.csv";
  if (gzip) {
    name += ".gz";
  }
  return name;
}

void writeSubmission(const std::filesystem::path& file, std::uint64_t eventId,
                     const std::vector<Hit>& hits,
                     std::span<const std::uint64_t> labels, int gzipLevel) {
  if (labels.size() != hits.size()) {
    throw std::invalid_argument(
        "writeSubmission: " + std::to_string(labels.size()) + " labels for " +
        std::to_string(hits.size()) + " hits");
  }
  CsvWriter csv(file.string(), {kEventId, kHitId, kTrackId}, hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    csv.add(eventId);
    csv.add(hits[i].id);
    csv.add(labels[i]);
    csv.endRow();
  }
  csv.write(file, hasGzipExtension(file), gzipLevel);
}

std::filesystem::path writeSubmission(
    const std::filesystem::path& dir, std::uint64_t eventNumber,
    const std::vector<Hit>& hits, std::span<const std::vector<HitIndex>> tracks,
    bool gzip) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw InputError(location(dir.string()),
                     "cannot create folder: " + ec.message());
  }
  std::filesystem::path file = dir / submissionFileName(eventNumber, gzip);
  std::vector<std::uint64_t> labels = trackmlLabels(hits.size(), tracks);
  writeSubmission(file, eventNumber, hits, labels);
  return file;
}

std::vector<std::uint64_t> parseSubmission(
    std::string text, const std::string& source, const std::vector<Hit>& hits,
    std::optional<std::uint64_t> eventId) {
  CsvReader csv(std::move(text), source);
  const auto cEvent = csv.findColumn(kEventId);
  const std::size_t cHit = csv.requireColumn(kHitId);
  const std::size_t cTrack = csv.requireColumn(kTrackId);

  // Hit ids of TrackML events run 1..N in file order: then the index is
  // id - 1 and no map is needed.
  bool contiguous = true;
  for (std::size_t i = 0; i < hits.size() && contiguous; ++i) {
    contiguous = hits[i].id == i + 1;
  }
  std::unordered_map<std::uint64_t, std::size_t> index;
  if (!contiguous) {
    index.reserve(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
      index.emplace(hits[i].id, i);
    }
  }
  std::vector<std::uint64_t> labels(hits.size(), 0);
  std::vector<std::uint8_t> seen(hits.size(), 0);
  while (csv.next()) {
    if (cEvent) {
      const auto id = csv.getInteger<std::uint64_t>(*cEvent);
      if (!eventId) {
        eventId = id;
      } else if (id != *eventId) {
        csv.failField(*cEvent, "differs from the event " +
                                   std::to_string(*eventId) +
                                   " (one event per submission file)");
      }
    }
    const auto hitId = csv.getInteger<std::uint64_t>(cHit);
    std::size_t i = hits.size();
    if (contiguous) {
      if (hitId >= 1 && hitId <= hits.size()) {
        i = static_cast<std::size_t>(hitId - 1);
      }
    } else if (auto it = index.find(hitId); it != index.end()) {
      i = it->second;
    }
    if (i == hits.size()) {
      csv.fail("hit_id " + std::to_string(hitId) +
               " is not a hit of the event");
    }
    if (seen[i] != 0) {
      csv.fail("second row for hit_id " + std::to_string(hitId) +
               " (a hit belongs to one track)");
    }
    seen[i] = 1;
    labels[i] = csv.getInteger<std::uint64_t>(cTrack);
  }
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (seen[i] == 0) {
      const auto missing = static_cast<std::size_t>(
          std::count(seen.begin(), seen.end(), std::uint8_t{0}));
      throw InputError(location(csv.fileName()),
                       "no row for hit_id " + std::to_string(hits[i].id) +
                           " (" + std::to_string(missing) +
                           " hits missing; every hit needs one row, "
                           "track_id 0 for none)");
    }
  }
  return labels;
}

std::vector<std::uint64_t> readSubmission(
    const std::filesystem::path& file, const std::vector<Hit>& hits,
    std::optional<std::uint64_t> eventId) {
  return parseSubmission(readTextFile(file), file.string(), hits, eventId);
}

SubmittedEvent readSubmittedEvent(const std::filesystem::path& submissionFile,
                                  const std::filesystem::path& eventDir,
                                  std::uint64_t eventNumber) {
  EventFiles files = EventFiles::locate(eventDir, eventNumber);
  if (!files.truth) {
    throw MissingFileError(
        location((eventDir /
                  eventFileName(eventNumber, EventFileKind::eTruth, false))
                     .string()),
        "no such file (nor with .gz): scoring needs the truth");
  }
  SubmittedEvent result;
  result.event = readEvent(eventDir, eventNumber, nullptr);
  result.labels =
      readSubmission(submissionFile, result.event.hits, eventNumber);
  return result;
}

}  // namespace conftrack

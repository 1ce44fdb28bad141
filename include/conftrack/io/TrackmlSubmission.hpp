#pragma once

/// @file TrackmlSubmission.hpp
/// TrackML submission files, one per event: `eventNNNNNNNNN-submission.csv`
/// (optionally `.gz`) with the columns event_id,hit_id,track_id, one row
/// per hit of the event with its original hit id; track_id 0 for hits on no
/// track (labels: trackmlLabels). Scoring them is the evaluation's
/// (evaluation/TrackmlScore.hpp; files: frontend/SubmissionScore.hpp).

#include "conftrack/core/Event.hpp"
#include "conftrack/core/Hit.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Types.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace conftrack {

/// Track id per hit for a submission: track k of `tracks` gets id k + 1,
/// hits on no track 0. A hit on several tracks goes to the one with the
/// most hits, the earlier one on a tie (the longer track keeps its hits, so
/// it stays above 50 %). Hit indices out of range throw
/// std::invalid_argument.
std::vector<std::uint64_t> trackmlLabels(
    std::size_t nHits, std::span<const std::vector<HitIndex>> tracks);

/// "event000001001-submission.csv" (with ".gz" if `gzip`); the event number
/// is zero-padded to 9 digits as the other event files.
std::string submissionFileName(std::uint64_t eventNumber, bool gzip = false);

/// Writes one row per hit (in hit order) with `labels[i]` as the track id
/// of hits[i]; gzip if the name ends in ".gz". Throws std::invalid_argument
/// if the sizes differ, InputError if the file cannot be written.
void writeSubmission(const std::filesystem::path& file, std::uint64_t eventId,
                     const std::vector<Hit>& hits,
                     std::span<const std::uint64_t> labels,
                     int gzipLevel = kDefaultGzipLevel);

/// Writes the submission of `tracks` (hit indices into `hits`, labelled by
/// trackmlLabels) as `dir`/submissionFileName(eventNumber, gzip), creating
/// `dir` if needed; returns the file written.
std::filesystem::path writeSubmission(
    const std::filesystem::path& dir, std::uint64_t eventNumber,
    const std::vector<Hit>& hits, std::span<const std::vector<HitIndex>> tracks,
    bool gzip = false);

/// Reads a submission for `hits`: the track ids parallel to `hits`. Columns
/// by header name (hit_id and track_id required, event_id optional). Every
/// hit must appear exactly once; unknown or duplicate hit ids, missing hits
/// and an event_id other than `eventId` (or, without it, than the first
/// row's) are InputErrors "file:line: problem".
std::vector<std::uint64_t> readSubmission(
    const std::filesystem::path& file, const std::vector<Hit>& hits,
    std::optional<std::uint64_t> eventId = std::nullopt);

/// readSubmission on text already in memory (plain, see decompressIfGzip);
/// `source` names it in error messages.
std::vector<std::uint64_t> parseSubmission(
    std::string text, const std::string& source, const std::vector<Hit>& hits,
    std::optional<std::uint64_t> eventId = std::nullopt);

/// An event with truth and a submission's track ids for its hits.
struct SubmittedEvent {
  Event event;
  /// Track id per hit, parallel to event.hits.
  std::vector<std::uint64_t> labels;
};

/// Reads event `eventNumber` of `eventDir` (hits, truth and particles
/// files, without a detector: hits carry raw TrackML volume and layer ids)
/// and `submissionFile` for it. The truth file is required (InputError
/// "file: no such file ..." otherwise); errors as readSubmission.
SubmittedEvent readSubmittedEvent(const std::filesystem::path& submissionFile,
                                  const std::filesystem::path& eventDir,
                                  std::uint64_t eventNumber);

}  // namespace conftrack

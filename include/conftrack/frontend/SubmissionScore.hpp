#pragma once

/// @file SubmissionScore.hpp
/// The TrackML score of a submission file against an event's files: the
/// files read by io, the score computed by the evaluation.

#include "conftrack/evaluation/TrackmlScore.hpp"

#include <cstdint>
#include <filesystem>

namespace conftrack {

/// Scores `submissionFile` against event `eventNumber` of `eventDir`
/// (hits, truth and particles files, read without a detector). The truth
/// file is required; its weight column is used if present, else the
/// weights are computed from truth and particles (scoreTrackml).
TrackmlScore scoreSubmission(const std::filesystem::path& submissionFile,
                             const std::filesystem::path& eventDir,
                             std::uint64_t eventNumber,
                             const TrackmlScoreConfig& config = {});

}  // namespace conftrack

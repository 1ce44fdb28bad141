#include "conftrack/frontend/SubmissionScore.hpp"

#include "conftrack/io/TrackmlSubmission.hpp"

#include <span>

namespace conftrack {

TrackmlScore scoreSubmission(const std::filesystem::path& submissionFile,
                             const std::filesystem::path& eventDir,
                             std::uint64_t eventNumber,
                             const TrackmlScoreConfig& config) {
  const SubmittedEvent submitted =
      readSubmittedEvent(submissionFile, eventDir, eventNumber);
  return scoreTrackml(submitted.event,
                      std::span<const std::uint64_t>(submitted.labels), config);
}

}  // namespace conftrack

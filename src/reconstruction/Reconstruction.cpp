#include "conftrack/reconstruction/Reconstruction.hpp"

#include <algorithm>
#include <chrono>

namespace conftrack {

namespace {
TrackSelector::Config selectorConfig(const Reconstruction::Config& c) {
  TrackSelector::Config s = c.selector;
  s.requireFitted = s.requireFitted && c.fit;
  return s;
}
}  // namespace

FitInput fitInput(const FoundTrack& found) {
  return {found.hits, found.fitBackward};
}

Track withFit(const FoundTrack& found, Track fitted) {
  Track track = toTrack(found);
  // The fit's flags for the hits it was given; further-turn hits follow.
  track.takeFit(fitted);
  return track;
}

Reconstruction::Reconstruction(const Detector& detector, Config config,
                               std::shared_ptr<const ModuleLayout> sensors)
    : m_config(std::move(config)),
      m_finder(detector, {m_config.chain}),
      m_fitter(detector, m_config.fitter, std::move(sensors)),
      m_merger(m_fitter, m_config.merger),
      m_selector(selectorConfig(m_config)) {}

Reconstruction::Result Reconstruction::run(std::span<const Hit> hits) const {
  using Clock = std::chrono::steady_clock;
  Result r;
  FindingResult found = m_finder.run(hits);
  r.findingMs = found.milliseconds;
  r.steps = std::move(found.steps);
  r.vertexRegions = std::move(found.vertexRegions);
  r.candidates = found.tracks.size();
  std::vector<Track> tracks;
  if (m_config.fit) {
    std::vector<FitInput> inputs;
    inputs.reserve(found.tracks.size());
    for (const FoundTrack& f : found.tracks) {
      inputs.push_back(fitInput(f));
    }
    FittingResult fitted = m_fitter.run(hits, inputs);
    r.fittingMs = fitted.milliseconds;
    r.fitFailures = fitted.failures;
    tracks.reserve(found.tracks.size());
    for (std::size_t i = 0; i < found.tracks.size(); ++i) {
      tracks.push_back(withFit(found.tracks[i], std::move(fitted.tracks[i])));
    }
    // The candidates are no longer needed: free them before the selection.
    std::vector<FoundTrack>().swap(found.tracks);
    const auto mergeStart = Clock::now();
    SplitTrackMerger::Result merged = m_merger.run(hits, std::move(tracks));
    tracks = std::move(merged.tracks);
    r.splitMerges = merged.merges;
    r.fittingMs +=
        std::chrono::duration<double, std::milli>(Clock::now() - mergeStart)
            .count();
  } else {
    tracks.reserve(found.tracks.size());
    for (const FoundTrack& f : found.tracks) {
      tracks.push_back(toTrack(f));
    }
  }
  auto t0 = Clock::now();
  r.tracks = m_selector.run(hits, std::move(tracks)).tracks;
  r.selectionMs =
      std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return r;
}

}  // namespace conftrack

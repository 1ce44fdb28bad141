#include "conftrack/reconstruction/Reconstruction.hpp"

#include <chrono>

namespace conftrack {

namespace {
TrackSelector::Config selectorConfig(const Reconstruction::Config& c) {
  TrackSelector::Config s = c.selector;
  s.requireFitted = s.requireFitted && c.fit;
  return s;
}
}  // namespace

Reconstruction::Reconstruction(const Detector& detector, Config config)
    : m_config(std::move(config)),
      m_finder(detector, {m_config.chain}),
      m_fitter(detector, m_config.fitter),
      m_selector(selectorConfig(m_config)) {}

Reconstruction::Result Reconstruction::run(std::span<const Hit> hits) const {
  using Clock = std::chrono::steady_clock;
  Result r;
  FindingResult found = m_finder.run(hits);
  r.findingMs = found.milliseconds;
  r.steps = std::move(found.steps);
  r.candidates = found.tracks.size();
  std::vector<Track> tracks;
  if (m_config.fit) {
    FittingResult fitted = m_fitter.run(hits, found.tracks);
    // The candidates are no longer needed: free them before the selection.
    std::vector<FoundTrack>().swap(found.tracks);
    r.fittingMs = fitted.milliseconds;
    r.fitFailures = fitted.failures;
    tracks = std::move(fitted.tracks);
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

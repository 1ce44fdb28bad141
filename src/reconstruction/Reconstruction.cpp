#include "conftrack/reconstruction/Reconstruction.hpp"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <stdexcept>
#include <string>

namespace conftrack {

namespace {
TrackSelector::Config selectorConfig(const Reconstruction::Config& c) {
  TrackSelector::Config s = c.selector;
  s.requireFitted = s.requireFitted && c.fit;
  return s;
}
}  // namespace

FitInput fitInput(const FoundTrack& found, const Vector2& beamLine) {
  return {found.hits, found.fitBackward, beamLine};
}

Track withFit(const FoundTrack& found, const Track& fitted) {
  Track track = toTrack(found);
  // The fit's flags for the hits it was given; further-turn hits follow.
  track.takeFit(fitted);
  return track;
}

Reconstruction::Reconstruction(
    const Detector& detector, Config config,
    const std::shared_ptr<const ModuleLayout>& sensors)
    : m_config(std::move(config)),
      m_finder(detector, {m_config.chain}),
      m_fitter(detector, m_config.fitter, sensors),
      m_merger(m_fitter, m_config.merger),
      m_reassigner(m_fitter, m_config.reassigner),
      m_selector(selectorConfig(m_config)) {
  if (auto p =
          findSecondPassProblem(m_config.secondPassSteps, m_config.chain)) {
    throw std::invalid_argument("Reconstruction: key 'second_pass." + p->first +
                                "': " + p->second);
  }
}

std::optional<std::pair<std::string, std::string>>
Reconstruction::findSecondPassProblem(
    const std::vector<std::uint16_t>& secondPassSteps,
    const FinderConfig& chain) {
  for (std::size_t i = 0; i < secondPassSteps.size(); ++i) {
    const std::uint16_t k = secondPassSteps[i];
    if (k >= chain.steps.size()) {
      return std::make_pair(std::string("steps"),
                            "step index " + std::to_string(k) +
                                " is not one of the chain's " +
                                std::to_string(chain.steps.size()));
    }
    const FindingStep& step = chain.steps[k];
    // A step without collections searches the pool of the step before
    // it, which need not run in this pass; an extension alone finds no
    // new track.
    if (step.collections.empty() || !(step.build || step.helix)) {
      return std::make_pair(std::string("steps"),
                            "step '" + step.name +
                                "' must build tracks (action build or "
                                "helix) in collections of its own");
    }
    if (i > 0 && secondPassSteps[i - 1] >= k) {
      return std::make_pair(
          std::string("steps"),
          "step '" + step.name + "' listed twice or out of the chain's order");
    }
  }
  return std::nullopt;
}

void Reconstruction::fitAndSelect(std::span<const Hit> hits,
                                  std::vector<FoundTrack> found,
                                  Result& r) const {
  using Clock = std::chrono::steady_clock;
  r.candidates += found.size();
  std::vector<Track> tracks;
  if (m_config.fit) {
    std::vector<FitInput> inputs;
    inputs.reserve(found.size());
    for (const FoundTrack& f : found) {
      // The perigee about the line the finder mapped about: d0 of a
      // prompt track is then its distance from the luminous region.
      inputs.push_back(fitInput(f, r.beamSpot));
    }
    FittingResult fitted = m_fitter.run(hits, inputs);
    r.fittingMs += fitted.milliseconds;
    r.fitFailures += fitted.failures;
    tracks.reserve(found.size());
    for (std::size_t i = 0; i < found.size(); ++i) {
      tracks.push_back(withFit(found[i], fitted.tracks[i]));
    }
    // The candidates are no longer needed: free them before the selection.
    std::vector<FoundTrack>().swap(found);
    const auto mergeStart = Clock::now();
    SplitTrackMerger::Result merged = m_merger.run(hits, std::move(tracks));
    tracks = std::move(merged.tracks);
    r.splitMerges += merged.merges;
    r.fittingMs +=
        std::chrono::duration<double, std::milli>(Clock::now() - mergeStart)
            .count();
  } else {
    tracks.reserve(found.size());
    for (const FoundTrack& f : found) {
      tracks.push_back(toTrack(f));
    }
  }
  auto t0 = Clock::now();
  std::vector<Track> selected = m_selector.run(hits, std::move(tracks)).tracks;
  r.selectionMs +=
      std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  r.tracks.insert(r.tracks.end(), std::make_move_iterator(selected.begin()),
                  std::make_move_iterator(selected.end()));
}

Reconstruction::Result Reconstruction::run(std::span<const Hit> hits) const {
  Result r;
  FindingResult found = m_finder.run(hits);
  r.findingMs = found.milliseconds;
  r.steps = std::move(found.steps);
  r.vertexRegions = std::move(found.vertexRegions);
  r.beamSpot = found.beamSpot;
  fitAndSelect(hits, std::move(found.tracks), r);
  if (!m_config.secondPassSteps.empty()) {
    secondPass(hits, r);
  }
  if (m_config.fit && m_config.reassigner.enabled) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    HitReassigner::Result moved = m_reassigner.run(hits, std::move(r.tracks));
    r.tracks = std::move(moved.tracks);
    r.reassignedHits = moved.outliersMoved + moved.freeHitsAdded;
    r.fittingMs +=
        std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  }
  return r;
}

void Reconstruction::secondPass(std::span<const Hit> hits, Result& r) const {
  // The second pass: the chosen steps over the hits no selected track
  // holds, the dropped candidates' hits among them.
  std::vector<std::uint8_t> taken(hits.size(), 0);
  for (const Track& t : r.tracks) {
    for (HitIndex h : t.hits) {
      taken[h] = 1;
    }
  }
  const ConformalTrackFinder::Pass pass{m_config.secondPassSteps, taken,
                                        r.vertexRegions, r.beamSpot};
  FindingResult second = m_finder.run(hits, pass);
  r.findingMs += second.milliseconds;
  for (StepStats& s : second.steps) {
    s.name += "/2";
    r.steps.push_back(std::move(s));
  }
  const std::size_t before = r.tracks.size();
  fitAndSelect(hits, std::move(second.tracks), r);
  r.secondPassTracks = r.tracks.size() - before;
}

}  // namespace conftrack

// The extension actions of a step (upstream.md 10): ExtendTracks, and the
// completion of newly built tracks. The units that they run are
// TrackExtension, CatchAllExtension, InwardExtension and HoleFilling
// (detail/), which share TrackFollower and LayerCrossingSearch.

#include "conftrack/reconstruction/finding/detail/CatchAllExtension.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/HoleFilling.hpp"
#include "conftrack/reconstruction/finding/detail/InwardExtension.hpp"
#include "conftrack/reconstruction/finding/detail/TrackExtension.hpp"

namespace conftrack::detail {

void completeTrack(FinderState& state, const FindingStep& step,
                   const HitPool& pool, StepStats& stats, std::uint32_t t) {
  if (step.direction == SearchDirection::eInsideOut) {
    const InwardExtension inward(
        InwardExtension::Config::fromStep(step, state.config));
    inward.run(state, pool, stats, t);
  }
  const HoleFilling holes(HoleFilling::Config::fromStep(
      step, state.config, HoleFilling::Residuals::eToFits));
  holes.run(state, pool, stats, t);
}

void extendTracks(FinderState& state, const FindingStep& step,
                  const HitPool& pool, StepStats& stats) {
  // Hits of all tracks are claimed before extending (upstream.md 10.2).
  for (const TrackCandidate& t : state.tracks) {
    for (ConfIndex h : t.hits) {
      state.used[h] = 1;
    }
  }
  const TrackExtension perLayer(
      TrackExtension::Config::fromStep(step, state.config));
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (state.tracks[t].alive && state.tracks[t].pt >= step.highPtCut) {
      perLayer.run(state, pool, stats, t);
    }
  }
  const CatchAllExtension catchAll(
      CatchAllExtension::Config::fromStep(step, state.config));
  for (std::uint32_t t = 0; t < state.tracks.size(); ++t) {
    if (state.tracks[t].alive) {
      catchAll.run(state, pool, stats, t);
    }
  }
}

}  // namespace conftrack::detail

#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"

#include "conftrack/core/Units.hpp"
#include "conftrack/reconstruction/finding/detail/EndExtension.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/OverlapHits.hpp"
#include "conftrack/reconstruction/finding/detail/SharedHitResolution.hpp"
#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

namespace conftrack {

Track toTrack(const FoundTrack& found) {
  Track t;
  // The first half-turn's hits, then those of a looper's further turns.
  t.hits = found.hits;
  t.hits.insert(t.hits.end(), found.turnHits.begin(), found.turnHits.end());
  t.outlier.assign(found.hits.size(), kFittedHit);
  t.outlier.resize(t.hits.size(), kTurnHit);
  t.findingStep = found.step;
  t.ptEstimate = found.pt;
  t.chargeEstimate = found.charge;
  t.chi2Uv = found.uv.chi2;
  t.ndfUv = found.uv.ndf;
  t.chi2Sz = found.sz.chi2;
  t.ndfSz = found.sz.ndf;
  return t;
}

ConformalTrackFinder::ConformalTrackFinder(const Detector& detector,
                                           Config config)
    : m_detector(&detector), m_config(std::move(config)) {
  // A chain built in code is checked like one read from a file (whose
  // reader has already turned the same problem into an InputError).
  if (std::optional<ChainProblem> p =
          findChainProblem(m_config.chain, detector)) {
    throw std::invalid_argument("ConformalTrackFinder: invalid chain: " +
                                p->describe());
  }
  if (m_config.chain.beamSpotPrepass) {
    m_beamSpotPrepass.emplace(detector, *m_config.chain.beamSpotPrepass);
  }
  if (m_config.chain.fieldCorrection && !detector.field().isUniform()) {
    m_bending = std::make_shared<const PromptBending>(
        detector.field(), detector.envelopeR(), detector.envelopeZ());
  }
}

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
}  // namespace

FindingResult ConformalTrackFinder::run(std::span<const Hit> hits) const {
  return find(hits, nullptr);
}

FindingResult ConformalTrackFinder::run(std::span<const Hit> hits,
                                        const Pass& pass) const {
  if (pass.taken.size() != hits.size()) {
    throw std::invalid_argument(
        "ConformalTrackFinder::run: " + std::to_string(pass.taken.size()) +
        " taken flags for " + std::to_string(hits.size()) + " hits");
  }
  // The step loop looks its steps up by binary search.
  if (std::adjacent_find(pass.steps.begin(), pass.steps.end(),
                         std::greater_equal<>()) != pass.steps.end() ||
      (!pass.steps.empty() &&
       pass.steps.back() >= m_config.chain.steps.size())) {
    throw std::invalid_argument(
        "ConformalTrackFinder::run: the pass's steps must be indices of the "
        "chain's steps, ascending without repeats");
  }
  return find(hits, &pass);
}

FindingResult ConformalTrackFinder::find(std::span<const Hit> hits,
                                         const Pass* pass) const {
  const auto tEvent = Clock::now();
  const FinderConfig& chain = m_config.chain;
  FindingResult result;
  // The beam line of the conformal map: the first pass's in a later pass,
  // else the event's own where the pre-pass measures it, else the chain's.
  Vector2 beamSpot(chain.beamSpotX, chain.beamSpotY);
  if (pass != nullptr) {
    beamSpot = pass->beamSpot.value_or(beamSpot);
  } else if (m_beamSpotPrepass) {
    const BeamSpotPrepass::Result measured =
        m_beamSpotPrepass->run(hits, beamSpot);
    beamSpot = measured.position;
    StepStats stats;
    stats.name = "BeamSpot";
    stats.seeds = measured.triplets;
    stats.candidates = measured.inliers;
    stats.milliseconds = measured.milliseconds;
    result.steps.push_back(std::move(stats));
  }
  result.beamSpot = beamSpot;
  ConformalHits conformal =
      makeConformalHits(hits, *m_detector, m_bending.get(), beamSpot);
  double bz = chain.legacyFourTesla ? 4.0 * units::T : m_detector->bz();
  detail::FinderState state(conformal, *m_detector, chain, bz);
  state.bending = m_bending.get();

  if (pass != nullptr) {
    for (ConfIndex h = 0; h < conformal.size(); ++h) {
      if (pass->taken[conformal.original[h]] != 0) {
        state.used[h] = detail::FinderState::kReserved;
      }
    }
    state.vertexRegions.assign(pass->vertexRegions.begin(),
                               pass->vertexRegions.end());
    result.vertexRegions = state.vertexRegions;
  } else if (chain.vertexPrepass) {
    result.steps.push_back(detail::findVertexRegions(state));
    result.vertexRegions = state.vertexRegions;
  }
  std::optional<HitPool> pool;
  // The shared-hit resolution after the steps (finalMinUniqueHits; none
  // if 0), and with sharedHitsEachStep after each of them.
  std::optional<detail::SharedHitResolution> sharedHits;
  if (chain.finalMinUniqueHits > 0) {
    sharedHits.emplace(detail::SharedHitResolution::Config{
        chain.cloneSharedHits, chain.finalMinUniqueHits,
        chain.finalTrimSharedHits});
  }
  const std::size_t lastStep = pass != nullptr && !pass->steps.empty()
                                   ? pass->steps.back()
                                   : chain.steps.size() - 1;
  for (std::size_t i = 0; i < chain.steps.size(); ++i) {
    if (pass != nullptr &&
        !std::binary_search(pass->steps.begin(), pass->steps.end(), i)) {
      continue;
    }
    const FindingStep& step = chain.steps[i];
    const auto tStep = Clock::now();
    StepStats stats;
    stats.name = step.name;
    // The regions this step seeds about: the event's, or those of the hits
    // still free (FindingStep::vertexPrepassFreeHits).
    state.stepVertexRegions = step.vertexPrepassFreeHits
                                  ? detail::findFreeHitVertexRegions(state)
                                  : state.vertexRegions;
    if (!step.collections.empty()) {
      std::vector<ConfIndex> members;
      for (ConfIndex h = 0; h < conformal.size(); ++h) {
        if (state.used[h] == 0 &&
            std::find(step.collections.begin(), step.collections.end(),
                      conformal.subdetector[h]) != step.collections.end()) {
          members.push_back(h);
        }
      }
      pool.emplace(conformal, std::move(members));
    }
    if (step.build) {
      detail::buildTracks(state, step, static_cast<std::uint16_t>(i), *pool,
                          stats);
    }
    if (step.helix) {
      detail::buildHelixTracks(state, step, static_cast<std::uint16_t>(i),
                               *pool, stats);
    }
    state.compact();
    if (step.extend) {
      detail::extendTracks(state, step, *pool, stats);
    }
    if (chain.overlapHits && pool &&
        (step.build || step.helix || step.extend)) {
      detail::addOverlapHits(state, *pool, stats);
    }
    if (step.overlapPairBelowHits > 0) {
      // Counted as dropped, not as accepted: the step's tracks are those
      // it keeps.
      const std::uint32_t dropped = detail::dropUnpairedShortTracks(
          state, static_cast<std::uint16_t>(i), step.overlapPairBelowHits);
      stats.droppedTracks += dropped;
      stats.accepted -= std::min<std::uint64_t>(stats.accepted, dropped);
    }
    if (step.sort) {
      std::sort(state.tracks.begin(), state.tracks.end(),
                [](const TrackCandidate& a, const TrackCandidate& b) {
                  return a.pt != b.pt ? a.pt > b.pt : a.hits < b.hits;
                });
      state.clones.rebuild(state.tracks);
    }
    // End of step: every hit on a track is used.
    for (const TrackCandidate& t : state.tracks) {
      for (ConfIndex h : t.hits) {
        if (state.used[h] == 0) {
          state.used[h] = 1;
        }
      }
    }
    // The tracks the shared-hit resolution drops give their hits back
    // before the next step, not only at the end (sharedHitsEachStep; after
    // the last step the final resolution below runs).
    if (sharedHits && chain.sharedHitsEachStep && i != lastStep &&
        !state.tracks.empty()) {
      stats.droppedTracks += sharedHits->run(state);
    }
    stats.hitsUsed = static_cast<std::uint64_t>(
        std::count(state.used.begin(), state.used.end(), 1));
    stats.milliseconds = msSince(tStep);
    result.steps.push_back(std::move(stats));
  }

  if (sharedHits && !state.tracks.empty()) {
    const auto tStep = Clock::now();
    StepStats stats;
    stats.name = "SharedHits";
    stats.droppedTracks = sharedHits->run(state);
    stats.hitsUsed = static_cast<std::uint64_t>(
        std::count(state.used.begin(), state.used.end(), 1));
    stats.milliseconds = msSince(tStep);
    result.steps.push_back(std::move(stats));
  }

  if ((chain.finalHoleFilling || chain.finalExtension) &&
      !state.tracks.empty()) {
    auto tStep = Clock::now();
    std::vector<std::uint16_t> collections;
    for (const FindingStep& step : chain.steps) {
      collections.insert(collections.end(), step.collections.begin(),
                         step.collections.end());
    }
    std::vector<ConfIndex> members;
    for (ConfIndex h = 0; h < conformal.size(); ++h) {
      if (state.used[h] == 0 &&
          std::find(collections.begin(), collections.end(),
                    conformal.subdetector[h]) != collections.end()) {
        members.push_back(h);
      }
    }
    // One pool of the hits no track holds for both stages: each stage skips
    // the hits the one before claimed (the used flags).
    std::optional<HitPool> all;
    if (!members.empty()) {
      all.emplace(conformal, std::move(members));
    }
    auto finish = [&](StepStats& stats) {
      stats.hitsUsed = static_cast<std::uint64_t>(
          std::count(state.used.begin(), state.used.end(), 1));
      stats.milliseconds = msSince(tStep);
      result.steps.push_back(std::move(stats));
      tStep = Clock::now();
    };
    if (chain.finalExtension) {
      StepStats stats;
      stats.name = "EndExtension";
      if (all) {
        detail::extendTrackEnds(state, *all, stats);
      }
      finish(stats);
    }
    if (chain.finalHoleFilling) {
      StepStats stats;
      stats.name = "HoleFilling";
      if (all) {
        detail::fillHoles(state, *all, stats);
        // Overlap partners among the hits no step's search reached or the
        // shared-hit resolution released.
        if (chain.overlapHits) {
          detail::addOverlapHits(state, *all, stats);
        }
      }
      finish(stats);
    }
  }

  if (chain.trackMerging && state.tracks.size() > 1) {
    const auto tStep = Clock::now();
    StepStats stats;
    stats.name = "Merging";
    detail::mergeTracks(state, stats);
    stats.hitsUsed = static_cast<std::uint64_t>(
        std::count(state.used.begin(), state.used.end(), 1));
    stats.milliseconds = msSince(tStep);
    result.steps.push_back(std::move(stats));
  }

  result.tracks.reserve(state.tracks.size());
  for (const TrackCandidate& t : state.tracks) {
    FoundTrack out;
    out.hits.reserve(t.hits.size());
    for (ConfIndex h : t.hits) {
      out.hits.push_back(conformal.original[h]);
    }
    out.turnHits.reserve(t.turnHits.size());
    for (ConfIndex h : t.turnHits) {
      out.turnHits.push_back(conformal.original[h]);
    }
    out.uv = t.uv;
    out.sz = t.sz;
    out.pt = t.pt;
    out.charge = t.uv.charge();
    out.step = t.step;
    out.fitBackward = t.fitBackward;
    result.tracks.push_back(std::move(out));
  }
  result.milliseconds = msSince(tEvent);
  return result;
}

}  // namespace conftrack

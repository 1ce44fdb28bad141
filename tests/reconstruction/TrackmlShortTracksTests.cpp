/// @file TrackmlShortTracksTests.cpp
/// Prompt particles that end after three pixel layers (a hadronic
/// interaction in the material): three hits and an overlap partner, too
/// short for any step's min_hits but weighed by the TrackML score. The
/// shipped chain's PixelShort step builds three-hit prompt tracks and keeps
/// those that the overlap search gives a pair (overlap_pair_below_hits,
/// docs/algorithm.md 3.20). Event 1001's particles through the module-level
/// simulation with the real noise rate, as `conftrack simulate-trackml`.

#include "conftrack/core/Event.hpp"
#include "conftrack/evaluation/TruthMatching.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/StepStats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "TrackmlSample.hpp"

namespace conftrack {
namespace {

using test::event1001Particles;
using test::simulateTrackml;

/// True if two hits of the track lie on one layer (an overlap pair).
bool holdsAPair(const Event& event, const Track& track) {
  for (std::size_t i = 1; i < track.hits.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (event.hits[track.hits[i]].detId.sameLayer(
              event.hits[track.hits[j]].detId)) {
        return true;
      }
    }
  }
  return false;
}

struct ShortTrackCount {
  std::size_t particles = 0;
  std::size_t found = 0;
  /// Tracks of the PixelShort step with fewer than 5 hits, and those of
  /// them without two hits on one layer.
  std::size_t shortTracks = 0;
  std::size_t unpaired = 0;
  /// The step's counts: tracks kept and dropped by the rule.
  std::uint64_t accepted = 0;
  std::uint64_t dropped = 0;
};

ShortTrackCount countShortTracks(const Event& event, bool withPixelShort) {
  const Detector detector = loadDetector("trackml");
  Reconstruction::Config config =
      readReconstructionConfig(resolveChainPath("trackml"), detector);
  auto& steps = config.chain.steps;
  const auto it =
      std::find_if(steps.begin(), steps.end(),
                   [](const FindingStep& s) { return s.name == "PixelShort"; });
  EXPECT_NE(it, steps.end()) << "the shipped chain has no PixelShort step";
  const auto shortStep = static_cast<std::uint16_t>(it - steps.begin());
  if (!withPixelShort && it != steps.end()) {
    steps.erase(it);
  }
  // The step's own effect: without the second pass after the selection,
  // which runs PixelShort again (SecondPassTests.cpp).
  config.secondPassSteps.clear();
  const Reconstruction::Result result =
      Reconstruction(detector, config).run(event.hits);

  ShortTrackCount c;
  for (const StepStats& s : result.steps) {
    if (s.name == "PixelShort") {
      c.accepted = s.accepted;
      c.dropped = s.droppedTracks;
    }
  }
  for (const Track& t : result.tracks) {
    if (withPixelShort && t.findingStep == shortStep && t.hits.size() < 5) {
      ++c.shortTracks;
      c.unpaired += holdsAPair(event, t) ? 0 : 1;
    }
  }
  // The prompt particles (produced within 1 mm of the beam line) with 4
  // or 5 hits on exactly three layers: a particle that ended after three
  // (pixel) layers and left an overlap pair.
  const EventMatching matching =
      matchTracks(event, test::hitLists(result.tracks));
  std::vector<std::uint8_t> wanted(event.particles.size(), 0);
  for (std::size_t p = 0; p < event.particles.size(); ++p) {
    const ParticleTruth& truth = matching.particles[p];
    const bool threeLayers = event.particles[p].vertex.head<2>().norm() < 1.0 &&
                             truth.nHits >= 4 && truth.nHits <= 5 &&
                             truth.nLayers == 3;
    wanted[p] = threeLayers ? 1 : 0;
    c.particles += wanted[p];
  }
  for (const TrackMatch& m : matching.tracks) {
    if (m.matched && wanted[m.particle] != 0) {
      ++c.found;
    }
  }
  return c;
}

TEST(TrackmlShortTracks, ParticlesEndingAfterThreePixelLayersAreFound) {
  const Event event =
      simulateTrackml(event1001Particles(), test::SampleNoise::eReal);
  const ShortTrackCount with = countShortTracks(event, true);
  const ShortTrackCount without = countShortTracks(event, false);
  std::printf(
      "[ three-layer prompt particles ] %zu: found %zu with PixelShort, %zu "
      "without; PixelShort tracks below 5 hits %zu, without a pair %zu; "
      "the step kept %llu, dropped %llu\n",
      with.particles, with.found, without.found, with.shortTracks,
      with.unpaired, static_cast<unsigned long long>(with.accepted),
      static_cast<unsigned long long>(with.dropped));
  // Premise: such particles are common (measured 61 on this event).
  ASSERT_GE(with.particles, 40u);
  // Measured 33 of 61 found with the step, none without (36 before the
  // final extension, 34 before the shared-hit resolution after every
  // step); guarded at 45 % and 15 %.
  EXPECT_GE(with.found, with.particles * 45 / 100);
  EXPECT_LE(without.found, without.particles * 15 / 100);
  // The rule itself: no short PixelShort track lacks an overlap pair.
  // Measured 33 such tracks, all with a pair.
  EXPECT_GT(with.shortTracks, 15u);
  EXPECT_EQ(with.unpaired, 0u);
  // The step reports the tracks it keeps as accepted and those the rule
  // drops as dropped (measured 62 and 66; 59 and 62 before the resolution
  // after every step).
  EXPECT_GE(with.accepted, with.shortTracks);
  EXPECT_GT(with.dropped, 20u);
}

}  // namespace
}  // namespace conftrack

/// @file TrackmlVertexRegionsTests.cpp
/// The vertex regions of the TrackML chain at the HL-LHC length of the
/// luminous region (sigma_z = 50 mm), on event 1001's particles through
/// the module-level simulation: a prompt build seeded about the regions
/// of a second pre-pass over the hits still free
/// (FindingStep::vertexPrepassFreeHits) finds the particles of vertices
/// that the event's pre-pass missed.

#include "conftrack/evaluation/TruthMatching.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/VertexZPrepass.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "TrackmlSample.hpp"

namespace conftrack {
namespace {

/// Prompt particles (produced < 1 mm from the beam line) with four hits
/// or more that a track holds at least half of, at least half of whose
/// hits are its own, counted apart for those whose vertex lies more than
/// 5 mm from every region of `regions` (`far`).
struct Found {
  std::size_t all = 0;
  std::size_t far = 0;
};
Found promptFound(const Event& event, const FindingResult& result,
                  const std::vector<std::pair<double, double>>& regions) {
  std::vector<std::vector<HitIndex>> lists;
  for (const FoundTrack& t : result.tracks) {
    lists.push_back(t.hits);
  }
  MatchingConfig doubleMatching;
  doubleMatching.purity = 0.5;
  doubleMatching.doubleMatching = true;
  const EventMatching m = matchTracks(event, lists, {}, doubleMatching);
  const ZWindows windows(regions, 0.0);
  Found out;
  for (std::size_t p = 0; p < event.particles.size(); ++p) {
    const Particle& particle = event.particles[p];
    if (particle.vertex.head<2>().norm() >= 1.0 || m.particles[p].nHits < 4 ||
        m.particles[p].nMatchedTracks == 0) {
      continue;
    }
    ++out.all;
    out.far += windows.near(particle.vertex.z(), 5.0) ? 0 : 1;
  }
  return out;
}

TEST(TrackmlVertexRegions, FreeHitPrepassFindsTheVerticesTheFirstMissed) {
  // The shipped chain's PixelPrompt alone, and followed by PixelPrompt2
  // (the same cuts, vertex_prepass_free_hits): measured 2388 prompt
  // particles found (pixel tracks only, no strip extension), 17 of them
  // more than 5 mm from the event's regions, then 2444 and 60 since the
  // seed cells' z0 along the arc (2392, 19, 2449 and 61 before; 2429, 26,
  // 2475 and 62 before the pixel disks' inner ring of docs/validation.md
  // item 13; 2432, 26,
  // 2475 and 60 with 17 % noise instead of the real files' rate per
  // sensor; 2480 and
  // 34, 2526 and 71 before the simulation placed the layers' material where
  // the real files show it, docs/validation.md items 11 and 12). Guarded
  // at +30 and +25.
  const Detector detector = loadDetector("trackml");
  const FinderConfig shipped = readChain(resolveChainPath("trackml"), detector);
  FinderConfig one = shipped;
  FinderConfig two = shipped;
  auto keep = [](FinderConfig& c, const std::vector<std::string>& names) {
    std::erase_if(c.steps, [&](const FindingStep& s) {
      return std::find(names.begin(), names.end(), s.name) == names.end();
    });
  };
  keep(one, {"PixelPrompt"});
  keep(two, {"PixelPrompt", "PixelPrompt2"});
  ASSERT_EQ(two.steps.size(), 2u);
  ASSERT_TRUE(two.steps[1].vertexPrepassFreeHits);
  const LuminousRegion::Preset* hllhc = LuminousRegion::findPreset("hllhc");
  ASSERT_NE(hllhc, nullptr);
  const Event event = test::simulateTrackml(
      test::event1001Particles(), test::SampleNoise::eReal, hllhc->config);
  const FindingResult first =
      ConformalTrackFinder(detector, {one}).run(event.hits);
  const FindingResult second =
      ConformalTrackFinder(detector, {two}).run(event.hits);
  // The event's regions are reported either way (those of the first
  // pre-pass).
  ASSERT_FALSE(first.vertexRegions.empty());
  EXPECT_EQ(second.vertexRegions, first.vertexRegions);
  const Found a = promptFound(event, first, first.vertexRegions);
  const Found b = promptFound(event, second, first.vertexRegions);
  std::printf(
      "[ trackml 1001, sigma_z 50 mm ] prompt particles found: %zu "
      "(%zu far from the regions) with PixelPrompt, %zu (%zu) with "
      "PixelPrompt2\n",
      a.all, a.far, b.all, b.far);
  EXPECT_GE(b.all, a.all + 30);
  EXPECT_GE(b.far, a.far + 25);
}

}  // namespace
}  // namespace conftrack

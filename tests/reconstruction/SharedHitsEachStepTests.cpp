/// @file SharedHitsEachStepTests.cpp
/// The finder's shared-hit resolution after every step ([finder]
/// shared_hits_each_step, docs/algorithm.md 3.13), not only after the
/// last: the tracks it drops held hits while the later steps ran. Event
/// 1001's particles through the module-level TrackML simulation with the
/// real noise rate, as `conftrack simulate-trackml`.

#include "conftrack/core/Error.hpp"
#include "conftrack/evaluation/TrackmlScore.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/StepStats.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "ChainText.hpp"
#include "InputErrorOf.hpp"
#include "TrackmlSample.hpp"

namespace conftrack {
namespace {

TEST(SharedHitsEachStep, ChainKey) {
  const Detector det = loadDetector("clicdet");
  const std::string step = minimalStep("VertexBarrel");
  EXPECT_FALSE(parseChain(step, "c.toml", det).sharedHitsEachStep);
  EXPECT_TRUE(parseChain("[finder]\nfinal_min_unique_hits = 6\n"
                         "shared_hits_each_step = true\n" +
                             step,
                         "c.toml", det)
                  .sharedHitsEachStep);
  // It runs the final resolution's rule, which must be on.
  const std::string what = test::inputErrorOf([&] {
    parseChain("[finder]\nshared_hits_each_step = true\n" + step, "c.toml",
               det);
  });
  EXPECT_NE(what.find("c.toml:2"), std::string::npos) << what;
  EXPECT_NE(what.find("finder.shared_hits_each_step"), std::string::npos)
      << what;
  EXPECT_NE(what.find("needs final_min_unique_hits"), std::string::npos)
      << what;
}

struct Outcome {
  TrackmlScore score;
  std::uint64_t droppedAfterPixelPrompt = 0;
};

Outcome reconstruct(const Event& event, bool eachStep) {
  const Reconstruction::Result result = test::reconstructWithTrackmlChain(
      event, [&](Reconstruction::Config& config) {
        EXPECT_TRUE(config.chain.sharedHitsEachStep)
            << "the shipped chain resolves shared hits after the last step "
               "only";
        config.chain.sharedHitsEachStep = eachStep;
      });
  Outcome out;
  out.score = scoreTrackml(event, test::hitLists(result.tracks));
  for (const StepStats& s : result.steps) {
    if (s.name == "PixelPrompt") {
      out.droppedAfterPixelPrompt = s.droppedTracks;
    }
  }
  return out;
}

TEST(SharedHitsEachStep, LaterStepsFindTheParticlesOfDroppedTracksHits) {
  const Event event = test::simulateTrackml(test::event1001Particles(),
                                            test::SampleNoise::eReal);
  const Outcome with = reconstruct(event, true);
  const Outcome without = reconstruct(event, false);
  std::printf(
      "[ shared hits each step, event 1001 ] TrackML score %.4f with, %.4f "
      "without; fake rate %.4f, %.4f; tracks dropped after PixelPrompt "
      "%llu\n",
      with.score.score, without.score.score, with.score.fakeRate,
      without.score.fakeRate,
      static_cast<unsigned long long>(with.droppedAfterPixelPrompt));
  // Measured: 373 tracks dropped after PixelPrompt (none without: the
  // resolution then runs after the last step only); score 0.8919 ->
  // 0.8954, fake rate 0.0159 -> 0.0157 with the chain of stop 47 (424,
  // 0.8882 -> 0.8929 when added; five events then: +0.0059 at sigma_z
  // 5.5 mm, +0.0153 at 50 mm). Guarded at about half the gain, and the
  // fake rate no higher.
  EXPECT_GT(with.droppedAfterPixelPrompt, 200u);
  EXPECT_EQ(without.droppedAfterPixelPrompt, 0u);
  EXPECT_GE(with.score.score - without.score.score, 0.002);
  EXPECT_LE(with.score.fakeRate, without.score.fakeRate + 0.001);
}

}  // namespace
}  // namespace conftrack

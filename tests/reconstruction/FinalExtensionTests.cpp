/// @file FinalExtensionTests.cpp
/// The final extension of every track's end ([finder] final_extension,
/// docs/algorithm.md 3.23; the unit is tested in ExtensionTests.cpp): its
/// chain keys, and its effect on event 1001's particles through the
/// module-level TrackML simulation with the real noise rate, as
/// `conftrack simulate-trackml`.

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

TEST(FinalExtension, ChainKeys) {
  const Detector det = loadDetector("clicdet");
  const std::string step = minimalStep("VertexBarrel");
  const FinderConfig off = parseChain(step, "c.toml", det);
  EXPECT_FALSE(off.finalExtension);
  EXPECT_DOUBLE_EQ(off.finalExtensionAngleFactor, 3.0);
  EXPECT_DOUBLE_EQ(off.finalExtensionPhiWindow, 0.06);
  const FinderConfig on = parseChain(
      "[finder]\nfinal_extension = true\nfinal_extension_angle_factor = 2.5\n"
      "final_extension_phi_window = 0.08\n" +
          step,
      "c.toml", det);
  EXPECT_TRUE(on.finalExtension);
  EXPECT_DOUBLE_EQ(on.finalExtensionAngleFactor, 2.5);
  EXPECT_DOUBLE_EQ(on.finalExtensionPhiWindow, 0.08 * units::rad);
  for (const auto& [line, key] :
       std::vector<std::pair<std::string, std::string>>{
           {"final_extension_angle_factor = 0.5",
            "finder.final_extension_angle_factor"},
           {"final_extension_phi_window = 0.0",
            "finder.final_extension_phi_window"},
           {"final_extension = 2", "finder.final_extension"}}) {
    const std::string what = test::inputErrorOf(
        [&] { parseChain("[finder]\n" + line + "\n" + step, "c.toml", det); });
    EXPECT_NE(what.find("c.toml:2"), std::string::npos) << what;
    EXPECT_NE(what.find(key), std::string::npos) << what;
  }
}

struct Outcome {
  TrackmlScore score;
  std::uint64_t extendedHits = 0;
  std::vector<std::string> stages;
};

Outcome reconstruct(const Event& event, bool finalExtension) {
  const Reconstruction::Result result = test::reconstructWithTrackmlChain(
      event, [&](Reconstruction::Config& config) {
        EXPECT_TRUE(config.chain.finalExtension)
            << "the shipped chain has no final extension";
        config.chain.finalExtension = finalExtension;
        // The hit reassignment after the fit (algorithm.md 10.2) takes
        // most of the same hits when the final extension is off: event
        // 1001 0.9085 -> 0.9088 with both. The finder's own stage is
        // measured without it.
        config.reassigner.enabled = false;
      });
  Outcome out;
  out.score = scoreTrackml(event, test::hitLists(result.tracks));
  for (const StepStats& s : result.steps) {
    out.stages.push_back(s.name);
    if (s.name == "EndExtension") {
      out.extendedHits = s.extendedHits;
    }
  }
  return out;
}

/// The position of `name` in `stages`, or -1.
int indexOf(const std::vector<std::string>& stages, const std::string& name) {
  for (std::size_t i = 0; i < stages.size(); ++i) {
    if (stages[i] == name) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

TEST(FinalExtension, TakesTheFurtherHitsOfFoundParticles) {
  const Event event = test::simulateTrackml(test::event1001Particles(),
                                            test::SampleNoise::eReal);
  const Outcome with = reconstruct(event, true);
  const Outcome without = reconstruct(event, false);
  std::printf(
      "[ final extension, event 1001 ] TrackML score %.4f with, %.4f "
      "without; fake rate %.4f, %.4f; hits taken %llu\n",
      with.score.score, without.score.score, with.score.fakeRate,
      without.score.fakeRate,
      static_cast<unsigned long long>(with.extendedHits));
  // After the shared-hit resolution, before the final hole filling; only
  // when switched on.
  const int at = indexOf(with.stages, "EndExtension");
  EXPECT_GE(at, 0);
  EXPECT_EQ(at + 1, indexOf(with.stages, "HoleFilling"));
  EXPECT_EQ(at - 1, indexOf(with.stages, "SharedHits"));
  EXPECT_EQ(indexOf(without.stages, "EndExtension"), -1);
  // Measured: 128 hits taken; score 0.8945 -> 0.8954, fake rate 0.0160 ->
  // 0.0157 (five events: +0.0010 at sigma_z 5.5 mm, +0.0008 at 50 mm);
  // at stop 56, without the hit reassignment, 143 hits, 0.9054 -> 0.9062.
  // Guarded at about half the gain, and the fake rate no higher.
  EXPECT_GT(with.extendedHits, 100u);
  EXPECT_GE(with.score.score - without.score.score, 0.0005);
  EXPECT_LE(with.score.fakeRate, without.score.fakeRate + 0.001);
}

}  // namespace
}  // namespace conftrack

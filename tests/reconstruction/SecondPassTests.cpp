/// @file SecondPassTests.cpp
/// The reconstruction's second pass ([second_pass] of a chain file,
/// docs/algorithm.md 3.21): chosen steps run again after the fit and the
/// selection over the hits that no selected track holds. Its settings are
/// checked like the chain's; on event 1001's particles through the
/// module-level TrackML simulation (as `conftrack simulate-trackml`) it
/// finds particles whose hits dropped candidates held while the steps ran.

#include "conftrack/core/Error.hpp"
#include "conftrack/evaluation/TrackmlScore.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/StepStats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "ChainText.hpp"
#include "InputErrorOf.hpp"
#include "TrackmlSample.hpp"

namespace conftrack {
namespace {

/// The message of the InputError that reading `text` as a chain file
/// raises, "(accepted)" if it reads.
std::string configError(const std::string& text) {
  static const Detector det = loadDetector("clicdet");
  return test::inputErrorOf(
      [&] { parseReconstructionConfig(text, "c.toml", det); });
}

TEST(SecondPass, ChainFileTable) {
  const Detector det = loadDetector("clicdet");
  const std::string build = minimalStep("VertexBarrel");
  const std::string extend =
      "[[step]]\nname = \"E1\"\ncollections = [\"VertexBarrel\"]\n"
      "actions = [\"extend\"]\nmax_cell_angle = 0.01\n"
      "max_cell_angle_rz = 0.01\nchi2_cut = 100.0\nmin_hits = 4\n"
      "max_distance = 0.02\nslope_z_range = 10.0\nhigh_pt_cut_GeV = 10.0\n";
  // Without the table: no second pass.
  EXPECT_TRUE(
      parseReconstructionConfig(build, "c.toml", det).secondPassSteps.empty());
  const Reconstruction::Config c = parseReconstructionConfig(
      "[second_pass]\nsteps = [\"S0\"]\n" + build + extend, "c.toml", det);
  EXPECT_EQ(c.secondPassSteps, (std::vector<std::uint16_t>{0}));
  // The finder's own reader accepts the table and leaves it alone.
  EXPECT_EQ(
      parseChain("[second_pass]\nsteps = [\"S0\"]\n" + build, "c.toml", det)
          .steps.size(),
      1u);
  // Bad tables: one line naming the file, the line and the key.
  const std::string unknown =
      configError("[second_pass]\nsteps = [\"Helix\"]\n" + build);
  EXPECT_NE(unknown.find("c.toml:2"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("no step named 'Helix'"), std::string::npos)
      << unknown;
  const std::string twice =
      configError("[second_pass]\nsteps = [\"S0\", \"S0\"]\n" + build);
  EXPECT_NE(twice.find("second_pass.steps"), std::string::npos) << twice;
  EXPECT_NE(twice.find("listed twice"), std::string::npos) << twice;
  const std::string extension =
      configError("[second_pass]\nsteps = [\"E1\"]\n" + build + extend);
  EXPECT_NE(extension.find("must build tracks"), std::string::npos)
      << extension;
  EXPECT_NE(configError("[second_pass]\nstepz = [\"S0\"]\n" + build),
            "(accepted)");
  EXPECT_NE(configError("[second_pass]\nsteps = \"S0\"\n" + build),
            "(accepted)");
  // A configuration built in code is checked by the constructor.
  Reconstruction::Config bad = c;
  bad.secondPassSteps = {1};
  EXPECT_THROW(Reconstruction(det, bad), std::invalid_argument);
  bad.secondPassSteps = {7};
  EXPECT_THROW(Reconstruction(det, bad), std::invalid_argument);
  // The finder refuses taken flags that are not one per hit.
  const ConformalTrackFinder finder(det, {c.chain});
  const std::vector<Hit> hits(3);
  const std::vector<std::uint8_t> taken(2, 0);
  EXPECT_THROW(finder.run(hits, {c.secondPassSteps, taken, {}, {}}),
               std::invalid_argument);
  // ... and steps that are not ascending indices of the chain's.
  const std::vector<std::uint8_t> none(3, 0);
  const std::vector<std::uint16_t> repeated = {0, 0};
  const std::vector<std::uint16_t> outside = {0, 5};
  EXPECT_THROW(finder.run(hits, {repeated, none, {}, {}}),
               std::invalid_argument);
  EXPECT_THROW(finder.run(hits, {outside, none, {}, {}}),
               std::invalid_argument);
  const FindingResult empty =
      finder.run(std::span<const Hit>(), {c.secondPassSteps, {}, {}, {}});
  EXPECT_TRUE(empty.tracks.empty());
}

struct PassResult {
  Reconstruction::Result result;
  TrackmlScore score;
};

PassResult reconstruct(const Event& event, bool secondPass) {
  // The shipped chain, with the finder's shared-hit resolution after the
  // last step only and Helix and PixelShort in the second pass: the
  // configuration where the pass finds most. (The shipped chain resolves
  // shared hits after every step, which frees most of those hits before
  // the later steps, and runs only PixelShort again.)
  const Detector detector = loadDetector("trackml");
  Reconstruction::Config config =
      readReconstructionConfig(resolveChainPath("trackml"), detector);
  EXPECT_FALSE(config.secondPassSteps.empty())
      << "the shipped chain has no second pass";
  config.chain.sharedHitsEachStep = false;
  // The hit reassignment after both passes moves hits between first-pass
  // tracks differently once second-pass tracks are there: off, so that
  // the first pass can be compared track by track.
  config.reassigner.enabled = false;
  config.secondPassSteps.clear();
  if (secondPass) {
    for (std::size_t k = 0; k < config.chain.steps.size(); ++k) {
      const std::string& name = config.chain.steps[k].name;
      if (name == "Helix" || name == "PixelShort") {
        config.secondPassSteps.push_back(static_cast<std::uint16_t>(k));
      }
    }
    EXPECT_EQ(config.secondPassSteps.size(), 2u);
  }
  PassResult out;
  out.result = Reconstruction(detector, config).run(event.hits);
  out.score = scoreTrackml(event, test::hitLists(out.result.tracks));
  return out;
}

TEST(SecondPass, FindsTheParticlesOfDroppedCandidatesHits) {
  const Event event = test::simulateTrackml(test::event1001Particles(),
                                            test::SampleNoise::eReal);
  const PassResult with = reconstruct(event, true);
  const PassResult without = reconstruct(event, false);
  const Reconstruction::Result& r = with.result;
  std::printf(
      "[ second pass, event 1001 ] %zu tracks of %zu from the second pass; "
      "TrackML score %.4f with, %.4f without; fake rate %.4f, %.4f\n",
      r.secondPassTracks, r.tracks.size(), with.score.score,
      without.score.score, with.score.fakeRate, without.score.fakeRate);

  // The first pass is untouched: the same tracks, in the same order.
  const std::size_t first = r.tracks.size() - r.secondPassTracks;
  ASSERT_EQ(first, without.result.tracks.size());
  for (std::size_t i = 0; i < first; ++i) {
    EXPECT_EQ(r.tracks[i].hits, without.result.tracks[i].hits) << i;
  }
  // The second pass takes no hit of a first-pass track (tracks of one
  // pass may share hits, as the selection's min_unique_hits allows), and
  // its tracks come from its steps (Helix, PixelShort), reported as rows
  // "<step>/2".
  std::vector<std::uint8_t> held(event.hits.size(), 0);
  for (std::size_t i = 0; i < first; ++i) {
    for (HitIndex h : r.tracks[i].hits) {
      held[h] = 1;
    }
  }
  for (std::size_t i = first; i < r.tracks.size(); ++i) {
    for (HitIndex h : r.tracks[i].hits) {
      EXPECT_EQ(held[h], 0) << "hit " << h << " of a first-pass track";
    }
  }
  const Detector detector = loadDetector("trackml");
  const Reconstruction::Config config =
      readReconstructionConfig(resolveChainPath("trackml"), detector);
  for (std::size_t i = first; i < r.tracks.size(); ++i) {
    const std::string& name = config.chain.steps[r.tracks[i].findingStep].name;
    EXPECT_TRUE(name == "Helix" || name == "PixelShort") << name;
  }
  for (const char* step : {"Helix", "PixelShort"}) {
    const std::string row = std::string(step) + "/2";
    EXPECT_TRUE(std::any_of(r.steps.begin(), r.steps.end(),
                            [&](const StepStats& s) { return s.name == row; }))
        << row;
  }
  // Measured: 28 tracks; score 0.8872 -> 0.8891, fake rate 0.0180 ->
  // 0.0194 (five events: +0.0025 at sigma_z 5.5 mm, +0.0063 at 50 mm;
  // with the shipped chain's resolution after every step, +0.0007 /
  // +0.0007).
  // Guarded at about half the gain and a fake rate within the goal of
  // issue 15.
  EXPECT_GT(r.secondPassTracks, 15u);
  EXPECT_GE(with.score.score - without.score.score, 0.001);
  EXPECT_LE(with.score.fakeRate, 0.05);
}

}  // namespace
}  // namespace conftrack

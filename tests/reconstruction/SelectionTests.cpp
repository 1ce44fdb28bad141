/// @file SelectionTests.cpp
/// The track selection on hand-made tracks: clone treatment (more hits,
/// then lower chi2/ndf, then hit ids), minimum hits, fit failures, the
/// shared-hit resolution and the [selection] table of chain files.

#include "conftrack/core/Error.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/selection/TrackSelector.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "ChainText.hpp"

namespace conftrack {
namespace {

/// 30 hits whose ids run backwards (id = 1000 - index), so that a tie-break
/// on indices and one on ids would disagree.
std::vector<Hit> makeHits() {
  std::vector<Hit> hits(30);
  for (std::size_t i = 0; i < hits.size(); ++i) {
    hits[i].id = 1000 - i;
  }
  return hits;
}

Track makeTrack(std::vector<HitIndex> hits, double chi2PerNdf,
                std::vector<std::uint8_t> outliers = {}) {
  Track t;
  t.hits = std::move(hits);
  t.outlier = outliers.empty() ? std::vector<std::uint8_t>(t.hits.size(), 0)
                               : std::move(outliers);
  t.fitted = true;
  t.ndf = 2 * static_cast<int>(t.numMeasurements()) - 5;
  t.chi2 = chi2PerNdf * t.ndf;
  return t;
}

std::vector<std::vector<HitIndex>> hitLists(const SelectionResult& r) {
  std::vector<std::vector<HitIndex>> out;
  for (const Track& t : r.tracks) {
    out.push_back(t.hits);
  }
  return out;
}

TEST(Selection, LongerTrackWinsOverLowerChi2) {
  const auto hits = makeHits();
  const TrackSelector selector;
  const auto r = selector.run(
      hits, {makeTrack({1, 2, 3, 4}, 0.5), makeTrack({1, 2, 3, 4, 5}, 9.0)});
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].hits.size(), 5u);
  EXPECT_EQ(r.clones, 1u);
}

TEST(Selection, EqualLengthLowerChi2PerNdfWins) {
  const auto hits = makeHits();
  const TrackSelector selector;
  const auto r = selector.run(
      hits, {makeTrack({1, 2, 3, 4}, 2.0), makeTrack({1, 2, 7, 8}, 1.0)});
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].hits, (std::vector<HitIndex>{1, 2, 7, 8}));
}

TEST(Selection, TieBreakOnHitIds) {
  const auto hits = makeHits();
  const TrackSelector selector;
  // Same length and chi2/ndf: the smaller sorted id list wins. Indices
  // {1,2,3,9} have ids {991,997,998,999}, {1,2,3,8} have {992,...}.
  for (bool swap : {false, true}) {
    std::vector<Track> tracks = {makeTrack({1, 2, 3, 8}, 1.0),
                                 makeTrack({1, 2, 3, 9}, 1.0)};
    if (swap) {
      std::swap(tracks[0], tracks[1]);
    }
    const auto r = selector.run(hits, tracks);
    ASSERT_EQ(r.tracks.size(), 1u);
    EXPECT_EQ(r.tracks[0].hits, (std::vector<HitIndex>{1, 2, 3, 9}));
  }
}

TEST(Selection, SharedHitThreshold) {
  const auto hits = makeHits();
  // One shared hit: no clones with the default of two.
  EXPECT_EQ(TrackSelector()
                .run(hits, {makeTrack({1, 2, 3, 4}, 1.0),
                            makeTrack({4, 5, 6, 7}, 1.0)})
                .tracks.size(),
            2u);
  TrackSelector::Config one;
  one.cloneSharedHits = 1;
  EXPECT_EQ(TrackSelector(one)
                .run(hits, {makeTrack({1, 2, 3, 4}, 1.0),
                            makeTrack({4, 5, 6, 7}, 1.0)})
                .tracks.size(),
            1u);
  TrackSelector::Config off;
  off.cloneSharedHits = 0;
  EXPECT_EQ(TrackSelector(off)
                .run(hits, {makeTrack({1, 2, 3, 4}, 1.0),
                            makeTrack({1, 2, 3, 4}, 1.0)})
                .tracks.size(),
            2u);
}

TEST(Selection, OutliersDoNotCount) {
  const auto hits = makeHits();
  const TrackSelector selector;
  // Hits 1 and 2 are outliers of the second track: not shared.
  const auto r =
      selector.run(hits, {makeTrack({1, 2, 3, 4}, 1.0),
                          makeTrack({1, 2, 5, 6, 7}, 1.0, {1, 1, 0, 0, 0})});
  EXPECT_EQ(r.tracks.size(), 2u);
  // Five hits of which two outliers: three used, fewer than four.
  const auto longer =
      selector.run(hits, {makeTrack({1, 2, 3, 4}, 1.0),
                          makeTrack({1, 2, 3, 6, 7}, 0.1, {0, 0, 0, 1, 1})});
  ASSERT_EQ(longer.tracks.size(), 1u);
  EXPECT_EQ(longer.tracks[0].hits.size(), 4u);
}

TEST(Selection, MinimumHitsAndFitFailures) {
  const auto hits = makeHits();
  Track unfitted = makeTrack({10, 11, 12, 13}, 1.0);
  unfitted.fitted = false;
  std::vector<Track> tracks = {makeTrack({1, 2, 3}, 1.0),
                               makeTrack({4, 5, 6, 7}, 1.0, {0, 0, 1, 1}),
                               unfitted};
  const auto r = TrackSelector().run(hits, tracks);
  EXPECT_EQ(hitLists(r), (std::vector<std::vector<HitIndex>>{{1, 2, 3}}));
  EXPECT_EQ(r.tooFewHits, 1u);
  EXPECT_EQ(r.unfitted, 1u);
  TrackSelector::Config config;
  config.minHits = 4;
  config.requireFitted = false;
  const auto r4 = TrackSelector(config).run(hits, tracks);
  EXPECT_EQ(hitLists(r4),
            (std::vector<std::vector<HitIndex>>{{10, 11, 12, 13}}));
  EXPECT_EQ(r4.tooFewHits, 2u);
}

TEST(Selection, ResultDoesNotDependOnInputOrder) {
  const auto hits = makeHits();
  // A chain: B is a clone of A and of C, A and C share one hit. A is the
  // best, so B goes and C stays; equal-quality tracks exercise the ties.
  std::vector<Track> tracks = {
      makeTrack({1, 2, 3, 4, 5, 6}, 1.0),  // A
      makeTrack({5, 6, 7, 8, 9}, 0.5),     // B
      makeTrack({6, 8, 9, 10, 11}, 0.8),   // C
      makeTrack({20, 21, 22, 23}, 1.0),    // D
      makeTrack({20, 21, 24, 25}, 1.0),    // E, ties with D
      makeTrack({26, 27, 28}, 3.0),        // F
  };
  std::vector<std::size_t> perm(tracks.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::vector<std::vector<HitIndex>> reference;
  do {
    std::vector<Track> shuffled;
    for (std::size_t i : perm) {
      shuffled.push_back(tracks[i]);
    }
    auto kept = hitLists(TrackSelector().run(hits, shuffled));
    std::sort(kept.begin(), kept.end());
    if (reference.empty()) {
      reference = kept;
    }
    ASSERT_EQ(kept, reference);
  } while (std::next_permutation(perm.begin(), perm.end()));
  // E's ids {975..979,...}: indices 24, 25 have the smaller ids.
  EXPECT_EQ(reference, (std::vector<std::vector<HitIndex>>{{1, 2, 3, 4, 5, 6},
                                                           {6, 8, 9, 10, 11},
                                                           {20, 21, 24, 25},
                                                           {26, 27, 28}}));
}

TEST(Selection, KeepsInputOrderOfSurvivors) {
  const auto hits = makeHits();
  const auto r = TrackSelector().run(
      hits, {makeTrack({7, 8, 9}, 1.0), makeTrack({1, 2, 3, 4}, 1.0),
             makeTrack({1, 2, 3}, 1.0)});
  EXPECT_EQ(hitLists(r),
            (std::vector<std::vector<HitIndex>>{{7, 8, 9}, {1, 2, 3, 4}}));
}

TEST(Selection, BadTracksThrow) {
  const auto hits = makeHits();
  Track bad = makeTrack({1, 2, 3}, 1.0);
  bad.outlier.pop_back();
  EXPECT_THROW(TrackSelector().run(hits, {bad}), std::invalid_argument);
  EXPECT_THROW(TrackSelector().run(hits, {makeTrack({1, 2, 99}, 1.0)}),
               std::out_of_range);
  // A hit twice on one track, even as an outlier and on a track the cuts
  // would drop (unfitted): the evaluation would count it twice.
  Track twice = makeTrack({1, 2, 3, 2}, 1.0, {0, 0, 0, 1});
  twice.fitted = false;
  try {
    TrackSelector().run(hits, {makeTrack({5, 6, 7}, 1.0), twice});
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("hit id 998 twice"), std::string::npos)
        << e.what();
  }
}

TEST(Selection, SharedHitResolutionDropsTracksWithFewOwnHits) {
  const auto hits = makeHits();
  TrackSelector::Config config;
  config.minUniqueHits = 3;
  const TrackSelector selector(config);
  // Two good tracks and a third with one hit of each and two of its own:
  // no clone (one shared hit per pair), but only two hits of its own.
  const std::vector<Track> tracks = {makeTrack({1, 2, 3, 4, 5, 6}, 1.0),
                                     makeTrack({10, 11, 12, 13, 14}, 1.0),
                                     makeTrack({6, 14, 20, 21}, 1.0)};
  const auto r = selector.run(hits, tracks);
  EXPECT_EQ(hitLists(r), (std::vector<std::vector<HitIndex>>{
                             {1, 2, 3, 4, 5, 6}, {10, 11, 12, 13, 14}}));
  EXPECT_EQ(r.ambiguous, 1u);
  EXPECT_EQ(r.clones, 0u);
  // Three hits of its own are enough.
  std::vector<Track> enough = tracks;
  enough[2] = makeTrack({6, 14, 20, 21, 22}, 1.0);
  EXPECT_EQ(selector.run(hits, enough).tracks.size(), 3u);
  // Off by default: all three kept.
  EXPECT_EQ(TrackSelector().run(hits, tracks).tracks.size(), 3u);
}

TEST(Selection, SharedHitResolutionSparesTracksSharingNothing) {
  const auto hits = makeHits();
  TrackSelector::Config config;
  config.minUniqueHits = 5;
  // Four hits, none shared: an ambiguity of nobody, kept (minHits 3).
  const auto r = TrackSelector(config).run(
      hits,
      {makeTrack({1, 2, 3, 4, 5, 6}, 1.0), makeTrack({7, 8, 9, 10}, 1.0)});
  EXPECT_EQ(r.tracks.size(), 2u);
  EXPECT_EQ(r.ambiguous, 0u);
}

TEST(Selection, SharedHitResolutionCountsOutliersAndIsOrderFree) {
  const auto hits = makeHits();
  TrackSelector::Config config;
  config.minUniqueHits = 3;
  const TrackSelector selector(config);
  // The second track's own hits 20 and 21 are outliers: they still count
  // as its own (three with 22), so it stays.
  std::vector<Track> tracks = {
      makeTrack({1, 2, 3, 4, 5, 6}, 1.0),
      makeTrack({6, 20, 21, 22, 23, 24}, 2.0, {0, 1, 1, 0, 0, 0})};
  EXPECT_EQ(selector.run(hits, tracks).tracks.size(), 2u);
  // The better track claims first whatever the input order: the longer
  // one keeps its shared hits and the short one with two own hits goes.
  tracks = {makeTrack({1, 2, 3, 7, 8}, 1.0), makeTrack({1, 9, 10, 11}, 0.5),
            makeTrack({3, 9, 12, 13}, 0.7)};
  const auto forward = hitLists(selector.run(hits, tracks));
  std::reverse(tracks.begin(), tracks.end());
  auto backward = hitLists(selector.run(hits, tracks));
  std::sort(backward.begin(), backward.end());
  auto sortedForward = forward;
  std::sort(sortedForward.begin(), sortedForward.end());
  EXPECT_EQ(sortedForward, backward);
  // {1,2,3,7,8} first; {1,9,10,11} (chi2 0.5) has 3 own hits and stays;
  // {3,9,12,13} then has two own hits (12, 13) and goes.
  EXPECT_EQ(forward, (std::vector<std::vector<HitIndex>>{{1, 2, 3, 7, 8},
                                                         {1, 9, 10, 11}}));
}

TEST(Selection, DropOutliersLeavesTheMeasurements) {
  const auto hits = makeHits();
  // The clone treatment runs first (the first track wins with 5 used hits
  // against 4; they share the used hits 1 and 3), then the outliers leave
  // the kept track, and their flags with them.
  const std::vector<Track> tracks = {
      makeTrack({1, 2, 3, 4, 5, 6, 9}, 1.0, {0, 1, 0, 0, 1, 0, 0}),
      makeTrack({1, 2, 3, 8}, 1.0)};
  TrackSelector::Config config;
  config.dropOutliers = true;
  const auto dropped = TrackSelector(config).run(hits, tracks);
  ASSERT_EQ(dropped.tracks.size(), 1u);
  EXPECT_EQ(dropped.clones, 1u);
  EXPECT_EQ(dropped.tracks[0].hits, (std::vector<HitIndex>{1, 3, 4, 6, 9}));
  EXPECT_EQ(dropped.tracks[0].outlier, std::vector<std::uint8_t>(5, 0));
  // Off by default: the hits stay, flagged.
  const auto kept = TrackSelector().run(hits, tracks);
  ASSERT_EQ(kept.tracks.size(), 1u);
  EXPECT_EQ(kept.tracks[0].hits, (std::vector<HitIndex>{1, 2, 3, 4, 5, 6, 9}));
  EXPECT_EQ(kept.tracks[0].numOutliers(), 2u);
}

/// Hits 0-9 on layers 0-9 of one barrel subdetector, hits 10 and 11 on
/// layer 3 (an overlap partner of hit 3: another module).
std::vector<Hit> makeLayeredHits() {
  std::vector<Hit> hits = makeHits();
  for (std::size_t i = 0; i < hits.size(); ++i) {
    hits[i].detId.subdetector = 2;
    hits[i].detId.layer = static_cast<std::uint16_t>(i < 10 ? i : 3);
    hits[i].detId.module = static_cast<std::uint32_t>(i);
  }
  return hits;
}

Track stepTrack(std::vector<HitIndex> hits, double chi2PerNdf,
                std::uint16_t step) {
  Track t = makeTrack(std::move(hits), chi2PerNdf);
  t.findingStep = step;
  return t;
}

TEST(Selection, ShortTrackRuleJudgesShortTracksOfItsSteps) {
  const auto hits = makeLayeredHits();
  TrackSelector::Config c;
  c.shortTrackHits = 6;
  c.shortTrackMaxChi2Ndf = 2.0;
  c.shortTrackSteps = {7};
  const TrackSelector selector(c);
  // Short tracks of step 7: one hit per layer and chi2/ndf <= 2 kept; a
  // worse fit or a second hit on layer 3 (hit 10) dropped.
  const auto r = selector.run(hits, {stepTrack({0, 1, 2, 3, 4}, 1.9, 7),
                                     stepTrack({5, 6, 7, 8, 9}, 2.1, 7),
                                     stepTrack({13, 14, 3, 10, 15}, 0.5, 7)});
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].hits, (std::vector<HitIndex>{0, 1, 2, 3, 4}));
  EXPECT_EQ(r.poorShort, 2u);
  // The same tracks from another step, and six-hit tracks of step 7, are
  // left to the other rules.
  const auto other =
      selector.run(hits, {stepTrack({5, 6, 7, 8, 9}, 2.1, 0),
                          stepTrack({13, 14, 3, 10, 15}, 0.5, 0),
                          stepTrack({20, 21, 22, 23, 24, 25}, 9.0, 7),
                          stepTrack({16, 17, 18, 2, 11, 19}, 0.5, 7)});
  EXPECT_EQ(other.tracks.size(), 4u);
  EXPECT_EQ(other.poorShort, 0u);
  // No steps named: every step's short tracks.
  c.shortTrackSteps.clear();
  EXPECT_EQ(TrackSelector(c)
                .run(hits, {stepTrack({5, 6, 7, 8, 9}, 2.1, 0)})
                .poorShort,
            1u);
  // Off by default.
  EXPECT_EQ(TrackSelector()
                .run(hits, {stepTrack({13, 14, 3, 10, 15}, 9.0, 7)})
                .tracks.size(),
            1u);
}

TEST(Selection, ConfigIsValidated) {
  TrackSelector::Config zero;
  zero.minHits = 0;
  EXPECT_THROW(TrackSelector{zero}, std::invalid_argument);
  TrackSelector::Config huge;
  huge.minUniqueHits = 5000;
  EXPECT_THROW(TrackSelector{huge}, std::invalid_argument);
  // A short-track rule needs a positive, finite chi2/ndf bound.
  TrackSelector::Config shortRule;
  shortRule.shortTrackHits = 6;
  EXPECT_EQ(TrackSelector::findProblem(shortRule)->key,
            "short_track_max_chi2_ndf");
  shortRule.shortTrackMaxChi2Ndf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(TrackSelector{shortRule}, std::invalid_argument);
  shortRule.shortTrackMaxChi2Ndf = 2.0;
  EXPECT_FALSE(TrackSelector::findProblem(shortRule));
  EXPECT_FALSE(TrackSelector::findProblem(TrackSelector::Config{}));
}

TEST(Selection, ChainFileSelectionTable) {
  const Detector det = loadDetector("clicdet");
  const std::string steps = minimalStep("VertexBarrel");
  const Reconstruction::Config c = parseReconstructionConfig(
      "[selection]\nmin_unique_hits = 6\nmin_hits = 4\ndrop_outliers = true\n" +
          steps,
      "c.toml", det);
  EXPECT_EQ(c.selector.minUniqueHits, 6u);
  EXPECT_TRUE(c.selector.dropOutliers);
  EXPECT_EQ(c.selector.minHits, 4u);
  EXPECT_EQ(c.selector.cloneSharedHits, 2u);
  EXPECT_EQ(c.chain.steps.size(), 1u);
  // Without the table: the defaults.
  EXPECT_EQ(parseReconstructionConfig(steps, "c.toml", det).selector.minHits,
            3u);
  EXPECT_FALSE(
      parseReconstructionConfig(steps, "c.toml", det).selector.dropOutliers);
  // Bad values and unknown keys: located at the key.
  for (const char* bad :
       {"[selection]\nmin_hits = 0\n", "[selection]\nmin_unique_hits = -1\n",
        "[selection]\nmin_unique_hitz = 3\n",
        "[selection]\ndrop_outliers = 1\n"}) {
    try {
      parseReconstructionConfig(std::string(bad) + steps, "c.toml", det);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("c.toml:2"), std::string::npos)
          << e.what();
    }
  }
  // The short-track rule names the chain's steps.
  const Reconstruction::Config shortRule = parseReconstructionConfig(
      "[selection]\nshort_track_hits = 6\nshort_track_max_chi2_ndf = 2.0\n"
      "short_track_steps = [\"S0\"]\n" +
          steps,
      "c.toml", det);
  EXPECT_EQ(shortRule.selector.shortTrackHits, 6u);
  EXPECT_DOUBLE_EQ(shortRule.selector.shortTrackMaxChi2Ndf, 2.0);
  EXPECT_EQ(shortRule.selector.shortTrackSteps,
            (std::vector<std::uint16_t>{0}));
  for (const char* bad :
       {"[selection]\nshort_track_hits = 6\nshort_track_max_chi2_ndf = 2.0\n"
        "short_track_steps = [\"Helix\"]\n",
        "[selection]\nshort_track_hits = 6\n",
        "[selection]\nshort_track_hits = 6\nshort_track_max_chi2_ndf = "
        "-1.0\n"}) {
    try {
      parseReconstructionConfig(std::string(bad) + steps, "c.toml", det);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("c.toml:"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("short_track"), std::string::npos)
          << e.what();
    }
  }
  // The finder's own reader accepts the table (and leaves it alone).
  EXPECT_EQ(parseChain("[selection]\nmin_hits = 4\n" + steps, "c.toml", det)
                .steps.size(),
            1u);
}

}  // namespace
}  // namespace conftrack

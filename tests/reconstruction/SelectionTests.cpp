/// @file SelectionTests.cpp
/// The track selection on hand-made tracks: clone treatment (more hits,
/// then lower chi2/ndf, then hit ids), minimum hits, fit failures.

#include "conftrack/reconstruction/selection/TrackSelector.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <vector>

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
}

}  // namespace
}  // namespace conftrack

#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

TrackCandidate candidate(std::vector<ConfIndex> hits, double chi2) {
  TrackCandidate c;
  c.hits = std::move(hits);
  c.uv.chi2 = chi2;
  c.uv.ndf = 1;
  return c;
}

std::size_t alive(const std::vector<TrackCandidate>& ts) {
  std::size_t n = 0;
  for (const auto& t : ts) {
    n += t.alive ? 1 : 0;
  }
  return n;
}

TEST(CloneTreatment, LongerTrackWins) {
  std::vector<TrackCandidate> tracks;
  detail::CloneIndex index(20);
  EXPECT_TRUE(index.offer(tracks, candidate({1, 2, 3, 4}, 1.0), 2));
  // Superset: replaces the shorter track.
  EXPECT_TRUE(index.offer(tracks, candidate({1, 2, 3, 4, 5}, 50.0), 2));
  EXPECT_FALSE(tracks[0].alive);
  // Subset: dropped.
  EXPECT_FALSE(index.offer(tracks, candidate({2, 3, 4}, 0.1), 2));
  // Longer but different: still wins against a shorter one it overlaps.
  EXPECT_FALSE(index.offer(tracks, candidate({1, 2, 8, 9}, 0.1), 2));
  EXPECT_EQ(alive(tracks), 1u);
}

TEST(CloneTreatment, EqualLengthLowerChi2Wins) {
  std::vector<TrackCandidate> tracks;
  detail::CloneIndex index(20);
  EXPECT_TRUE(index.offer(tracks, candidate({1, 2, 3, 4}, 5.0), 2));
  EXPECT_FALSE(index.offer(tracks, candidate({1, 2, 3, 7}, 6.0), 2));
  EXPECT_TRUE(index.offer(tracks, candidate({1, 2, 3, 8}, 4.0), 2));
  EXPECT_EQ(alive(tracks), 1u);
  EXPECT_EQ(tracks.back().hits.back(), 8u);
}

TEST(CloneTreatment, OneSharedHitIsNoClone) {
  std::vector<TrackCandidate> tracks;
  detail::CloneIndex index(20);
  EXPECT_TRUE(index.offer(tracks, candidate({1, 2, 3, 4}, 5.0), 2));
  EXPECT_TRUE(index.offer(tracks, candidate({4, 5, 6, 7}, 5.0), 2));
  EXPECT_EQ(alive(tracks), 2u);
  // With a threshold of one shared hit they are clones.
  EXPECT_FALSE(index.offer(tracks, candidate({7, 9, 10, 11}, 9.0), 1));
}

TEST(CloneTreatment, ReplacesSeveralWorseTracks) {
  std::vector<TrackCandidate> tracks;
  detail::CloneIndex index(20);
  EXPECT_TRUE(index.offer(tracks, candidate({1, 2, 3}, 1.0), 2));
  EXPECT_TRUE(index.offer(tracks, candidate({5, 6, 7}, 1.0), 2));
  EXPECT_TRUE(index.offer(tracks, candidate({1, 2, 5, 6, 9}, 1.0), 2));
  EXPECT_EQ(alive(tracks), 1u);
}

TEST(CloneTreatment, CandidatesOfAStepCompareWithItsTracksAsBuilt) {
  // Two clones from two seeds of one build step: the first accepted has
  // since been completed to more hits (its inward extension and overlap
  // partners), the second has the lower chi2 as built. They are compared
  // as built (TrackCandidate::builtHits, builtQuality), so the better one
  // wins whichever seed came first; compared with the completed track, the
  // first would win by its extra hits alone (TrackML: a forward track
  // taking a neighbour's innermost pixel hit; CLD: 0.1 % more particles
  // found above 1 GeV, docs/algorithm.md 3.3).
  std::vector<TrackCandidate> tracks;
  detail::CloneIndex index(20);
  TrackCandidate first = candidate({1, 2, 3, 4}, 5.0);
  first.builtHits = first.hits.size();
  first.builtQuality = first.quality();
  ASSERT_TRUE(index.offer(tracks, first, 2));
  tracks[0].hits.push_back(10);  // the completion adds two hits
  tracks[0].hits.push_back(11);
  TrackCandidate second = candidate({0, 2, 3, 4}, 4.0);
  EXPECT_TRUE(index.offer(tracks, second, 2));
  EXPECT_FALSE(tracks[0].alive);
  // A worse candidate of the step still loses against the track as built.
  EXPECT_FALSE(index.offer(tracks, candidate({5, 2, 3, 4}, 4.5), 2));
  // After its step (builtHits cleared) a track meets later candidates
  // completed: more hits win, a lower chi2 does not.
  tracks[1].hits.push_back(12);
  tracks[1].builtHits = second.hits.size();
  tracks[1].builtQuality = second.quality();
  EXPECT_TRUE(index.offer(tracks, candidate({6, 2, 3, 4}, 0.1), 2));
  EXPECT_FALSE(tracks[1].alive);
  tracks[2].hits.push_back(13);
  tracks[2].builtHits = 0;
  EXPECT_FALSE(index.offer(tracks, candidate({7, 2, 3, 4}, 0.01), 2));
  EXPECT_EQ(alive(tracks), 1u);
}

/// One step over the synthetic barrel with loose angles.
FinderConfig oneStep(bool recovery) {
  FinderConfig cfg = test::oneBuildStep();
  cfg.steps[0].recovery = recovery;
  return cfg;
}

TEST(Recovery, RemovesOneSpuriousHit) {
  Detector det = test::barrelDetector();
  std::vector<Hit> hits = test::helixHits(det, 3000.0, 0.4, 1, 0.3, 1);
  ASSERT_EQ(hits.size(), 8u);
  // Keep six layers and displace the second hit by 100 um in r-phi: the
  // angles still pass, the chi2 does not. A seeding disc that reaches only
  // the next layer forces every path from the first hit through it (the
  // automaton itself skips spurious hits further out).
  hits.resize(6);
  hits[1].position += 0.1 * hits[1].uAxis;
  FinderConfig cfg = oneStep(false);
  cfg.steps[0].maxDistance = 0.01;
  ConformalTrackFinder plain(det, {cfg});
  EXPECT_TRUE(plain.run(hits).tracks.empty());
  cfg.steps[0].recovery = true;
  ConformalTrackFinder recovering(det, {cfg});
  FindingResult r = recovering.run(hits);
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].hits.size(), 5u);
  for (HitIndex h : r.tracks[0].hits) {
    EXPECT_NE(h, 1u);
  }
  EXPECT_EQ(r.steps[0].recovered, 1u);
}

TEST(CellAngles, KinkAboveTheCutSplitsTheTrack) {
  Detector det = test::barrelDetector();
  std::vector<Hit> hits = test::helixHits(det, 5000.0, 1.0, -1, 0.0, 1);
  FinderConfig cfg = oneStep(false);
  cfg.steps[0].minHits = 4;
  cfg.steps[0].chi2Cut = 1e9;
  // Rotate the outer four hits by 20 mrad around the z axis: a kink of
  // about that size in the conformal plane.
  for (std::size_t k = 4; k < hits.size(); ++k) {
    Eigen::AngleAxisd rot(0.02, Vector3::UnitZ());
    hits[k].position = rot * hits[k].position;
  }
  cfg.steps[0].maxCellAngle = 0.5;
  ConformalTrackFinder loose(det, {cfg});
  EXPECT_EQ(loose.run(hits).tracks[0].hits.size(), 8u);
  cfg.steps[0].maxCellAngle = 0.005;
  ConformalTrackFinder tight(det, {cfg});
  FindingResult r = tight.run(hits);
  ASSERT_FALSE(r.tracks.empty());
  EXPECT_LT(r.tracks[0].hits.size(), 8u);
}

}  // namespace
}  // namespace conftrack

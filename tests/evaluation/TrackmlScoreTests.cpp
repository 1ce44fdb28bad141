/// @file TrackmlScoreTests.cpp
/// The TrackML score on hand-made events with known scores, checked also
/// against a direct transcription of score.py on random submissions.

#include "conftrack/evaluation/TrackmlScore.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <stdexcept>

namespace conftrack {
namespace {

using Labels = std::vector<std::uint64_t>;

/// 12 hits: particle 1 on hits 0-3 (weight 0.1 each), particle 2 on hits
/// 4-7 (0.15 each), particle 3 on hits 8-9 (2 hits: weight 0), noise on
/// hits 10-11. Weights sum to 1.
Event handMadeEvent() {
  Event event;
  event.number = 1;
  const std::uint64_t particleOf[] = {1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 0, 0};
  for (std::size_t i = 0; i < 12; ++i) {
    Hit hit;
    hit.id = i + 1;
    event.hits.push_back(hit);
    HitTruth t;
    t.particleId = particleOf[i];
    t.weight = particleOf[i] == 1 ? 0.1 : particleOf[i] == 2 ? 0.15 : 0.0;
    event.truth.push_back(t);
  }
  for (std::uint64_t id : {1, 2, 3}) {
    Particle p;
    p.id = id;
    p.momentum = Vector3(1.0, 0.0, 0.0);
    event.particles.push_back(p);
  }
  return event;
}

double score(const Event& event, const Labels& labels) {
  return scoreTrackml(event, std::span<const std::uint64_t>(labels)).score;
}

/// score.py, transcribed literally (dictionaries instead of a sort).
double referenceScore(const Event& event, const Labels& labels) {
  std::map<std::uint64_t, std::size_t> particleHits;
  double total = 0.0;
  for (const HitTruth& t : event.truth) {
    ++particleHits[t.particleId];
    total += t.weight;
  }
  std::map<std::uint64_t,
           std::map<std::uint64_t, std::pair<std::size_t, double>>>
      tracks;  // track -> particle -> (hits, weight)
  for (std::size_t i = 0; i < labels.size(); ++i) {
    auto& entry = tracks[labels[i]][event.truth[i].particleId];
    ++entry.first;
    entry.second += event.truth[i].weight;
  }
  double sum = 0.0;
  for (const auto& [track, parts] : tracks) {
    std::size_t nTrack = 0;
    std::uint64_t major = 0;
    std::size_t majorHits = 0;
    double majorWeight = 0.0;
    for (const auto& [particle, hw] : parts) {
      nTrack += hw.first;
      if (hw.first > majorHits) {
        major = particle;
        majorHits = hw.first;
        majorWeight = hw.second;
      }
    }
    if (2 * majorHits > nTrack && 2 * majorHits > particleHits[major]) {
      sum += majorWeight;
    }
  }
  return sum / total;
}

TEST(TrackmlScore, Perfect) {
  Event event = handMadeEvent();
  // Labels = particle ids: noise forms track 0, particle 3 its own track.
  Labels labels = {1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 0, 0};
  TrackmlScore s = scoreTrackml(event, std::span<const std::uint64_t>(labels));
  EXPECT_DOUBLE_EQ(s.score, 1.0);
  EXPECT_DOUBLE_EQ(s.totalWeight, 1.0);
  EXPECT_FALSE(s.weightsComputed);
  EXPECT_EQ(s.nTracks, 4u);
  EXPECT_EQ(s.nGoodTracks, 4u);
  EXPECT_EQ(s.nReconstructable, 2u);  // particle 3 has 2 hits
  EXPECT_EQ(s.nReconstructed, 2u);
  EXPECT_DOUBLE_EQ(s.efficiency, 1.0);
  EXPECT_EQ(s.nSelectedTracks, 2u);  // tracks 1 and 2 (>= 4 hits)
  EXPECT_EQ(s.nFakeTracks, 0u);
  EXPECT_DOUBLE_EQ(s.fakeRate, 0.0);
  // Track ids are arbitrary.
  EXPECT_DOUBLE_EQ(score(event, {7, 7, 7, 7, 9, 9, 9, 9, 0, 0, 0, 0}), 1.0);
}

TEST(TrackmlScore, KnownScores) {
  Event event = handMadeEvent();
  // Nothing submitted: one track 0 with everything, no majority > 50 %.
  EXPECT_DOUBLE_EQ(score(event, Labels(12, 0)), 0.0);
  // Particle 1 split 2 + 2: exactly 50 % is not enough (strict).
  EXPECT_NEAR(score(event, {1, 1, 5, 5, 2, 2, 2, 2, 0, 0, 0, 0}), 0.6, 1e-15);
  // Split 3 + 1: the 3-hit track is good and scores its 3 hits.
  EXPECT_NEAR(score(event, {1, 1, 1, 5, 2, 2, 2, 2, 0, 0, 0, 0}), 0.9, 1e-15);
  // Particle 1 with 3 foreign hits: 4 / 7 > 50 %, good.
  EXPECT_NEAR(score(event, {1, 1, 1, 1, 2, 2, 2, 2, 1, 1, 1, 0}), 1.0, 1e-15);
  // With 4 foreign hits: 4 / 8, not good.
  EXPECT_NEAR(score(event, {1, 1, 1, 1, 2, 2, 2, 2, 1, 1, 1, 1}), 0.6, 1e-15);
  // Particles 1 and 2 merged: 4 / 8 each, not good.
  EXPECT_NEAR(score(event, {1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0}), 0.0, 1e-15);
  // Particle 2's track takes one hit of particle 1: still good (4 / 5), and
  // particle 1's track keeps 3 of 4 hits: 0.3 + 0.6.
  EXPECT_NEAR(score(event, {1, 1, 1, 2, 2, 2, 2, 2, 0, 0, 0, 0}), 0.9, 1e-15);
  // Every hit its own track: each holds 1 of 4 particle hits.
  EXPECT_NEAR(score(event, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}), 0.0,
              1e-15);
}

TEST(TrackmlScore, EfficiencyAndFakes) {
  Event event = handMadeEvent();
  // Particle 1 split 2 + 2 (both tracks fail), particle 2 found with one
  // noise hit, a 3-hit track of particle 3 (2 hits) and noise.
  Labels labels = {1, 1, 5, 5, 2, 2, 2, 2, 6, 6, 6, 2};
  TrackmlScore s = scoreTrackml(event, std::span<const std::uint64_t>(labels));
  EXPECT_EQ(s.nReconstructable, 2u);
  EXPECT_EQ(s.nReconstructed, 1u);
  EXPECT_DOUBLE_EQ(s.efficiency, 0.5);
  // Tracks with >= 4 hits: track 2 (5 hits, good), track 6 (3 hits: not
  // selected); tracks 1 and 5 have 2 hits.
  EXPECT_EQ(s.nSelectedTracks, 1u);
  EXPECT_EQ(s.nFakeTracks, 0u);
  TrackmlScoreConfig all;
  all.minTrackHits = 1;
  s = scoreTrackml(event, std::span<const std::uint64_t>(labels), all);
  // Track 6: particle 3 has 2 of its 3 hits (> 50 %) and both of particle
  // 3's hits: good. Tracks 1 and 5: 2 of 4 hits of particle 1, not good.
  EXPECT_EQ(s.nSelectedTracks, 4u);
  EXPECT_EQ(s.nFakeTracks, 2u);
  EXPECT_DOUBLE_EQ(s.fakeRate, 0.5);
  // pT cut on reconstructable particles.
  all.minPt = 2.0;
  s = scoreTrackml(event, std::span<const std::uint64_t>(labels), all);
  EXPECT_EQ(s.nReconstructable, 0u);
  EXPECT_DOUBLE_EQ(s.efficiency, 0.0);
}

TEST(TrackmlScore, RandomSubmissionsMatchScorePy) {
  // A larger event: 50 particles with 1-15 hits, 20 % noise, weights from
  // computeTrackmlWeights.
  std::mt19937_64 rng(42);
  Event event;
  std::uniform_int_distribution<int> nHits(1, 15);
  for (std::uint64_t p = 1; p <= 50; ++p) {
    Particle particle;
    particle.id = p;
    particle.momentum = Vector3(0.1 * static_cast<double>(p), 0.0, 1.0);
    event.particles.push_back(particle);
    for (int k = nHits(rng); k > 0; --k) {
      HitTruth t;
      t.particleId = p;
      t.position = Vector3(1.0, 0.0, 10.0 * k);
      event.truth.push_back(t);
    }
  }
  const std::size_t nNoise = event.truth.size() / 4;
  for (std::size_t k = 0; k < nNoise; ++k) {
    event.truth.push_back(HitTruth{});
  }
  std::vector<double> w = computeTrackmlWeights(event.truth, event.particles);
  for (std::size_t i = 0; i < w.size(); ++i) {
    event.truth[i].weight = w[i];
    Hit hit;
    hit.id = i + 1;
    event.hits.push_back(hit);
  }
  Labels perfect(event.hits.size());
  for (std::size_t i = 0; i < perfect.size(); ++i) {
    perfect[i] = event.truth[i].particleId;
  }
  EXPECT_NEAR(score(event, perfect), 1.0, 1e-12);
  // Random reassignments of 0 to 60 % of the hits (trackml shuffle_hits).
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uniform_int_distribution<std::uint64_t> anyTrack(0, 60);
  for (double probability : {0.0, 0.05, 0.2, 0.4, 0.6}) {
    Labels labels = perfect;
    for (std::uint64_t& l : labels) {
      if (uniform(rng) < probability) {
        l = anyTrack(rng);
      }
    }
    const double s = score(event, labels);
    EXPECT_NEAR(s, referenceScore(event, labels), 1e-12) << probability;
    EXPECT_LE(s, 1.0 + 1e-12);
  }
  // Fully random labels score far below 1.
  Labels random(event.hits.size());
  for (std::uint64_t& l : random) {
    l = anyTrack(rng);
  }
  EXPECT_LT(score(event, random), 0.2);
  EXPECT_NEAR(score(event, random), referenceScore(event, random), 1e-12);
}

TEST(TrackmlScore, ComputesMissingWeights) {
  Event event = handMadeEvent();
  for (HitTruth& t : event.truth) {
    t.weight = 0.0;
    t.position.z() = 0.0;
  }
  // Give particle 1's hits distinct |z| so that ranks are defined.
  for (std::size_t i = 0; i < 4; ++i) {
    event.truth[i].position.z() = 10.0 * static_cast<double>(i + 1);
  }
  Labels labels = {1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 0, 0};
  TrackmlScore s = scoreTrackml(event, std::span<const std::uint64_t>(labels));
  EXPECT_TRUE(s.weightsComputed);
  EXPECT_NEAR(s.totalWeight, 1.0, 1e-12);
  EXPECT_NEAR(s.score, 1.0, 1e-12);
  // Particle 1 split 3 + 1, losing the farthest hit (rank 3). Both
  // particles have pT 1 GeV; particle 2's hits all tie (rank 2.5 -> 1).
  s = scoreTrackml(event, Labels{1, 1, 1, 5, 2, 2, 2, 2, 3, 3, 0, 0});
  EXPECT_NEAR(
      s.score,
      1.0 - trackmlOrderWeight(3, 4) / (1.0 + 4.0 * trackmlOrderWeight(1, 4)),
      1e-12);
}

TEST(TrackmlScore, LabelsFromTracks) {
  // Hit 2 is on tracks 0 (3 hits) and 1 (4 hits): the longer track gets it;
  // hit 5 on tracks 1 and 2 (4 hits each): the earlier one.
  std::vector<std::vector<HitIndex>> tracks = {
      {0, 1, 2}, {2, 3, 4, 5}, {5, 6, 7, 8}};
  Labels labels = trackmlLabels(10, tracks);
  EXPECT_EQ(labels, (Labels{1, 1, 2, 2, 2, 2, 3, 3, 3, 0}));
  tracks.push_back({10});
  EXPECT_THROW(trackmlLabels(10, tracks), std::invalid_argument);
  Event event = handMadeEvent();
  std::vector<std::vector<HitIndex>> found = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  EXPECT_DOUBLE_EQ(
      scoreTrackml(event, std::span<const std::vector<HitIndex>>(found)).score,
      1.0);
  EXPECT_THROW(scoreTrackml(event, Labels(3, 0)), std::invalid_argument);
  event.truth.clear();
  EXPECT_THROW(scoreTrackml(event, Labels(12, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

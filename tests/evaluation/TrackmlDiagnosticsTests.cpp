/// @file TrackmlDiagnosticsTests.cpp
/// The TrackML truth diagnostics on a hand-made event in which every
/// category is known exactly, and on random submissions: the categories
/// add up to 1 - score with the score of scoreTrackml.

#include "conftrack/evaluation/TrackmlDiagnostics.hpp"
#include "conftrack/evaluation/TrackmlScore.hpp"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

namespace conftrack {
namespace {

using Labels = std::vector<std::uint64_t>;

/// One hit of the hand-made event: particle, layer, weight, track.
struct HitSpec {
  std::uint64_t particle;
  std::uint16_t layer;
  double weight;
  std::uint64_t track;
};

/// Particles (weights per hit, summing to 1):
/// - 1 (8 hits on layers 0,1,2,2,3,4,5,6): track 1 holds 5 of them
///   (layers 0,1,2,4,5; 0.04 each) and a noise hit: matched, found 0.20;
///   the second layer-2 hit on no track (left off, same layer, 0.05), the
///   layer-3 hit on no track (left off, new layer, 0.03), the layer-6 hit
///   on track 2 (other tracks, 0.04);
/// - 2 (4 x 0.0375): one hit on track 2 (a stray), 3 on no track: never
///   found, 0.15;
/// - 3 (6 x 0.02): 3 hits on track 3, 3 on track 4: split, 0.12;
/// - 4 (6 x 0.015): 3 on track 5, 3 on no track: partial, 0.09;
/// - 5 (4 x 0.04): 3 on track 6 with the 4 hits of particle 6, 1 on no
///   track: impure, 0.16;
/// - 6 (4 x 0.04): all on track 6 (4 of its 7 hits): found, 0.16; not in
///   event.particles (binned outside);
/// - 7 (2 hits, weight 0): one on track 7 with a noise hit, one on none.
/// Score 0.36. Tracks 1-7; fakes: 2 (1+1 hits) and 7 (1+1).
const std::vector<HitSpec> kHits = {
    {1, 0, 0.04, 1},   {1, 1, 0.04, 1},   {1, 2, 0.04, 1},   {1, 2, 0.05, 0},
    {1, 3, 0.03, 0},   {1, 4, 0.04, 1},   {1, 5, 0.04, 1},   {1, 6, 0.04, 2},
    {2, 0, 0.0375, 2}, {2, 1, 0.0375, 0}, {2, 2, 0.0375, 0}, {2, 3, 0.0375, 0},
    {3, 0, 0.02, 3},   {3, 1, 0.02, 3},   {3, 2, 0.02, 3},   {3, 3, 0.02, 4},
    {3, 4, 0.02, 4},   {3, 5, 0.02, 4},   {4, 0, 0.015, 5},  {4, 1, 0.015, 5},
    {4, 2, 0.015, 5},  {4, 3, 0.015, 0},  {4, 4, 0.015, 0},  {4, 5, 0.015, 0},
    {5, 0, 0.04, 6},   {5, 1, 0.04, 6},   {5, 2, 0.04, 6},   {5, 3, 0.04, 0},
    {6, 0, 0.04, 6},   {6, 1, 0.04, 6},   {6, 2, 0.04, 6},   {6, 3, 0.04, 6},
    {7, 0, 0.0, 7},    {7, 1, 0.0, 0},    {0, 3, 0.0, 1},    {0, 4, 0.0, 7},
};

Particle makeParticle(std::uint64_t id, double pt, double eta, double r) {
  Particle p;
  p.id = id;
  p.momentum = Vector3(pt, 0.0, pt * std::sinh(eta));
  p.vertex = Vector3(0.0, r, 0.0);
  return p;
}

Event handMadeEvent() {
  Event event;
  event.number = 1;
  for (std::size_t i = 0; i < kHits.size(); ++i) {
    Hit hit;
    hit.id = i + 1;
    hit.detId.subdetector = 7;
    hit.detId.layer = kHits[i].layer;
    event.hits.push_back(hit);
    HitTruth t;
    t.particleId = kHits[i].particle;
    t.weight = kHits[i].weight;
    event.truth.push_back(t);
  }
  // pT, eta, production radius; particle 6 is missing.
  event.particles = {
      makeParticle(1, 0.2, 0.5, 0.0),    makeParticle(2, 1.5, -2.5, 50.0),
      makeParticle(3, 0.7, 1.5, 0.5),    makeParticle(4, 0.7, -1.5, 5.0),
      makeParticle(5, 10.0, 3.5, 500.0), makeParticle(7, 0.2, 0.5, 0.0)};
  return event;
}

Labels handMadeLabels() {
  Labels labels;
  for (const HitSpec& h : kHits) {
    labels.push_back(h.track);
  }
  return labels;
}

TrackmlDiagnostics diagnose(const Event& event, const Labels& labels,
                            const TrackmlDiagnosticsConfig& config = {}) {
  return diagnoseTrackml(event, std::span<const std::uint64_t>(labels), config);
}

void expectSum(const WeightBreakdown& a, const WeightBreakdown& b) {
  EXPECT_NEAR(a.found, b.found, 1e-12);
  EXPECT_NEAR(a.leftOffSameLayer, b.leftOffSameLayer, 1e-12);
  EXPECT_NEAR(a.leftOffNewLayer, b.leftOffNewLayer, 1e-12);
  EXPECT_NEAR(a.otherTracks, b.otherTracks, 1e-12);
  EXPECT_NEAR(a.neverFound, b.neverFound, 1e-12);
  EXPECT_NEAR(a.split, b.split, 1e-12);
  EXPECT_NEAR(a.partial, b.partial, 1e-12);
  EXPECT_NEAR(a.impure, b.impure, 1e-12);
  EXPECT_NEAR(a.noise, b.noise, 1e-12);
}

/// Bins + outside of a histogram.
WeightBreakdown histogramSum(const DiagnosticsHistogram& h) {
  WeightBreakdown sum = h.outside;
  for (const DiagnosticsBin& b : h.bins) {
    sum.add(b.weight);
  }
  return sum;
}

TEST(TrackmlDiagnostics, HandMadeEventEveryCategory) {
  const Event event = handMadeEvent();
  const Labels labels = handMadeLabels();
  const TrackmlDiagnostics d = diagnose(event, labels);
  EXPECT_NEAR(d.totalWeight, 1.0, 1e-12);
  EXPECT_FALSE(d.weightsComputed);
  const WeightBreakdown& w = d.weight;
  EXPECT_NEAR(w.found, 0.36, 1e-12);
  EXPECT_NEAR(w.leftOffSameLayer, 0.05, 1e-12);
  EXPECT_NEAR(w.leftOffNewLayer, 0.03, 1e-12);
  EXPECT_NEAR(w.otherTracks, 0.04, 1e-12);
  EXPECT_NEAR(w.neverFound, 0.15, 1e-12);
  EXPECT_NEAR(w.split, 0.12, 1e-12);
  EXPECT_NEAR(w.partial, 0.09, 1e-12);
  EXPECT_NEAR(w.impure, 0.16, 1e-12);
  EXPECT_EQ(w.noise, 0.0);
  EXPECT_NEAR(w.total(), 1.0, 1e-12);
  EXPECT_NEAR(w.lost(), 0.64, 1e-12);
  EXPECT_NEAR(w.found,
              scoreTrackml(event, std::span<const std::uint64_t>(labels)).score,
              1e-12);

  EXPECT_EQ(d.tracks, 7.0);
  EXPECT_EQ(d.fakeTracks, 2.0);
  EXPECT_NEAR(d.fakeFraction, 2.0 / 7.0, 1e-12);
  EXPECT_EQ(d.foundParticles, 2.0);
  EXPECT_NEAR(d.meanFoundHitFraction, (5.0 / 8.0 + 1.0) / 2.0, 1e-12);
  // Track 1: the noise hit; track 6: the 3 hits of particle 5.
  EXPECT_EQ(d.foreignHitsOnMatched, 4.0);
  EXPECT_NEAR(d.foreignWeightOnMatched, 0.12, 1e-12);
}

TEST(TrackmlDiagnostics, HandMadeEventBins) {
  const TrackmlDiagnostics d = diagnose(handMadeEvent(), handMadeLabels());
  // pT bins 0-0.1-0.3-0.5-1-2-5-inf: particle 1 in 0.1-0.3 (particle 7
  // has no weight), 3 and 4 in 0.5-1, 2 in 1-2, 5 in 5-inf; 6 outside.
  ASSERT_EQ(d.pt.bins.size(), 7u);
  EXPECT_EQ(d.pt.bins[1].particles, 1.0);
  EXPECT_NEAR(d.pt.bins[1].weight.found, 0.20, 1e-12);
  EXPECT_NEAR(d.pt.bins[1].weight.lost(), 0.12, 1e-12);
  EXPECT_EQ(d.pt.bins[3].particles, 2.0);
  EXPECT_NEAR(d.pt.bins[3].weight.split, 0.12, 1e-12);
  EXPECT_NEAR(d.pt.bins[3].weight.partial, 0.09, 1e-12);
  EXPECT_NEAR(d.pt.bins[4].weight.neverFound, 0.15, 1e-12);
  EXPECT_NEAR(d.pt.bins[6].weight.impure, 0.16, 1e-12);
  EXPECT_NEAR(d.pt.outside.found, 0.16, 1e-12);
  EXPECT_NEAR(d.pt.outside.total(), 0.16, 1e-12);
  // |eta| 0-1-2-3-4-inf: 1 | 3, 4 | 2 | 5.
  ASSERT_EQ(d.absEta.bins.size(), 5u);
  EXPECT_NEAR(d.absEta.bins[0].weight.total(), 0.32, 1e-12);
  EXPECT_NEAR(d.absEta.bins[1].weight.total(), 0.21, 1e-12);
  EXPECT_NEAR(d.absEta.bins[2].weight.neverFound, 0.15, 1e-12);
  EXPECT_NEAR(d.absEta.bins[3].weight.impure, 0.16, 1e-12);
  // Production radius 0-1-10-100-inf mm: 1, 3 | 4 | 2 | 5.
  ASSERT_EQ(d.radius.bins.size(), 4u);
  EXPECT_EQ(d.radius.bins[0].particles, 2.0);
  EXPECT_NEAR(d.radius.bins[0].weight.total(), 0.44, 1e-12);
  EXPECT_NEAR(d.radius.bins[1].weight.partial, 0.09, 1e-12);
  EXPECT_NEAR(d.radius.bins[2].weight.neverFound, 0.15, 1e-12);
  EXPECT_NEAR(d.radius.bins[3].weight.impure, 0.16, 1e-12);
  for (const DiagnosticsHistogram* h : {&d.pt, &d.absEta, &d.radius}) {
    expectSum(histogramSum(*h), d.weight);
  }
}

TEST(TrackmlDiagnostics, StrayHitsThreshold) {
  // Without strays, particle 2's single hit on track 2 is a piece: partial.
  TrackmlDiagnosticsConfig config;
  config.maxStrayHits = 0;
  const TrackmlDiagnostics d0 =
      diagnose(handMadeEvent(), handMadeLabels(), config);
  EXPECT_EQ(d0.weight.neverFound, 0.0);
  EXPECT_NEAR(d0.weight.partial, 0.24, 1e-12);
  // With 3 strays, the 3-hit pieces of particles 3 and 4 are strays too;
  // particle 5 stays impure (its track holds more than half of it).
  config.maxStrayHits = 3;
  const TrackmlDiagnostics d3 =
      diagnose(handMadeEvent(), handMadeLabels(), config);
  EXPECT_NEAR(d3.weight.neverFound, 0.36, 1e-12);
  EXPECT_EQ(d3.weight.split, 0.0);
  EXPECT_EQ(d3.weight.partial, 0.0);
  EXPECT_NEAR(d3.weight.impure, 0.16, 1e-12);
}

TEST(TrackmlDiagnostics, PerfectAndEmptySubmissions) {
  const Event event = handMadeEvent();
  Labels perfect;
  for (const HitSpec& h : kHits) {
    perfect.push_back(h.particle);
  }
  const TrackmlDiagnostics p = diagnose(event, perfect);
  EXPECT_NEAR(p.weight.found, 1.0, 1e-12);
  EXPECT_NEAR(p.meanFoundHitFraction, 1.0, 1e-12);
  EXPECT_EQ(p.fakeTracks, 0.0);
  // Every hit on no track: nothing is found, everything never found.
  const TrackmlDiagnostics e = diagnose(event, Labels(kHits.size(), 0));
  EXPECT_EQ(e.weight.found, 0.0);
  EXPECT_NEAR(e.weight.neverFound, 1.0, 1e-12);
  EXPECT_EQ(e.tracks, 0.0);
  EXPECT_EQ(e.fakeFraction, 0.0);
}

TEST(TrackmlDiagnostics, NoiseWeightIsItsOwnCategory) {
  Event event = handMadeEvent();
  // Give the two noise hits weight: neither is credited (no track holds
  // more than half of the noise), so they are lost as noise.
  event.truth[34].weight = 0.5;
  event.truth[35].weight = 0.5;
  const TrackmlDiagnostics d = diagnose(event, handMadeLabels());
  EXPECT_NEAR(d.totalWeight, 2.0, 1e-12);
  EXPECT_NEAR(d.weight.noise, 0.5, 1e-12);
  EXPECT_NEAR(d.weight.found, 0.18, 1e-12);
  EXPECT_NEAR(d.weight.total(), 1.0, 1e-12);
  EXPECT_NEAR(d.pt.outside.noise, 0.5, 1e-12);
}

TEST(TrackmlDiagnostics, CategoriesAddUpToOneMinusTheScore) {
  // Random submissions of random events: score + causes = 1 and found is
  // the score of scoreTrackml; the bins add up to the event.
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    Event event;
    const std::size_t nHits = 1 + rng() % 80;
    const std::uint64_t nParticles = 1 + rng() % 12;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::size_t i = 0; i < nHits; ++i) {
      Hit hit;
      hit.id = i + 1;
      hit.detId.layer = static_cast<std::uint16_t>(rng() % 6);
      event.hits.push_back(hit);
      HitTruth t;
      // Hit 0 is a particle's: the event has weight.
      t.particleId = i == 0 ? 1 : rng() % (nParticles + 1);
      t.weight = t.particleId == 0 && trial % 2 == 0 ? 0.0 : unit(rng);
      event.truth.push_back(t);
    }
    for (std::uint64_t id = 1; id <= nParticles; id += 2) {
      event.particles.push_back(
          makeParticle(id, 5.0 * unit(rng), 5.0 * unit(rng), 200 * unit(rng)));
    }
    const std::uint64_t nTracks = 1 + rng() % 10;
    Labels labels(nHits);
    for (std::size_t i = 0; i < nHits; ++i) {
      // Mostly the particle's own track, sometimes another or none.
      const std::uint64_t r = rng() % 10;
      labels[i] = r < 6   ? event.truth[i].particleId % (nTracks + 1)
                  : r < 8 ? 0
                          : rng() % (nTracks + 1);
    }
    TrackmlDiagnosticsConfig config;
    config.maxStrayHits = static_cast<std::uint32_t>(trial % 3);
    const TrackmlDiagnostics d = diagnose(event, labels, config);
    const double score =
        scoreTrackml(event, std::span<const std::uint64_t>(labels)).score;
    EXPECT_NEAR(d.weight.found, score, 1e-9) << trial;
    EXPECT_NEAR(d.weight.found + d.weight.lost(), 1.0, 1e-9) << trial;
    for (const DiagnosticsHistogram* h : {&d.pt, &d.absEta, &d.radius}) {
      expectSum(histogramSum(*h), d.weight);
    }
    EXPECT_GE(d.meanFoundHitFraction, 0.0);
    EXPECT_LE(d.meanFoundHitFraction, 1.0);
    EXPECT_LE(d.fakeTracks, d.tracks);
    // Every left-off and other-track hit has exactly one place.
    const LostHitPlaces& p = d.places;
    EXPECT_NEAR(p.leftOffBefore + p.leftOffBetween + p.leftOffAfter,
                d.weight.leftOffSameLayer + d.weight.leftOffNewLayer, 1e-9)
        << trial;
    EXPECT_NEAR(p.otherAtHolderEnd + p.otherInsideHolder, d.weight.otherTracks,
                1e-9)
        << trial;
  }
}

TEST(TrackmlDiagnostics, PlacesOfLostHitsAlongTheParticle) {
  // Particle 1 moves out along x with a hit every 10 mm from 10 to 110 mm
  // (0.1 each): track 1 holds those at 30, 40, 60, 70, 80 and 90 mm (6 of
  // 11: matched); 10 and 20 mm are left off before the track's first hit,
  // 50 mm between, 110 mm after its last; 100 mm is on track 2, between
  // that track's hits at 95 and 105 mm (particle 2's, 0.05 each: matched
  // to track 2), whose third hit, at 130 mm, is track 3's only hit.
  Event event;
  event.number = 1;
  auto add = [&](std::uint64_t particle, double x, double weight) {
    Hit hit;
    hit.id = event.hits.size() + 1;
    hit.position = Vector3(x, 0.0, 0.0);
    hit.detId.layer = static_cast<std::uint16_t>(x);
    event.hits.push_back(hit);
    HitTruth t;
    t.particleId = particle;
    t.position = hit.position;
    t.weight = weight;
    event.truth.push_back(t);
  };
  for (int k = 1; k <= 11; ++k) {
    add(1, 10.0 * k, 0.1);
  }
  add(2, 95.0, 0.05);
  add(2, 105.0, 0.05);
  add(2, 130.0, 0.05);
  event.particles = {makeParticle(1, 1.0, 0.0, 0.0),
                     makeParticle(2, 1.0, 0.0, 0.0)};
  const Labels labels = {0, 0, 1, 1, 0, 1, 1, 1, 1, 2, 0, 2, 2, 3};
  TrackmlDiagnostics d = diagnose(event, labels);
  const double total = 1.25;
  EXPECT_NEAR(d.weight.found, 0.7 / total, 1e-12);
  EXPECT_NEAR(d.places.leftOffBefore, 0.2 / total, 1e-12);
  EXPECT_NEAR(d.places.leftOffBetween, 0.1 / total, 1e-12);
  EXPECT_NEAR(d.places.leftOffAfter, 0.1 / total, 1e-12);
  EXPECT_NEAR(d.places.otherInsideHolder, 0.1 / total, 1e-12);
  EXPECT_NEAR(d.places.otherAtHolderEnd, 0.05 / total, 1e-12);

  // With truth times the order is theirs, not the distance from the
  // vertex: particle 1 crossed its hits from 110 mm back to 10 mm.
  for (std::size_t i = 0; i < 11; ++i) {
    event.truth[i].time = 11.0 - static_cast<double>(i);
  }
  d = diagnose(event, labels);
  EXPECT_NEAR(d.places.leftOffBefore, 0.1 / total, 1e-12);  // 110 mm
  EXPECT_NEAR(d.places.leftOffBetween, 0.1 / total, 1e-12);
  EXPECT_NEAR(d.places.leftOffAfter, 0.2 / total, 1e-12);  // 20, 10 mm
}

TEST(TrackmlDiagnostics, AverageOfEvents) {
  const Event event = handMadeEvent();
  const Labels labels = handMadeLabels();
  Labels perfect;
  for (const HitSpec& h : kHits) {
    perfect.push_back(h.particle);
  }
  const std::vector<TrackmlDiagnostics> events = {diagnose(event, labels),
                                                  diagnose(event, perfect)};
  const TrackmlDiagnostics mean =
      averageDiagnostics(std::span<const TrackmlDiagnostics>(events));
  EXPECT_NEAR(mean.weight.found, (0.36 + 1.0) / 2.0, 1e-12);
  EXPECT_NEAR(mean.weight.split, 0.06, 1e-12);
  EXPECT_NEAR(mean.weight.total(), 1.0, 1e-12);
  EXPECT_NEAR(mean.tracks, 7.0, 1e-12);
  EXPECT_NEAR(mean.pt.bins[1].weight.found, (0.20 + 0.32) / 2.0, 1e-12);
  // Particle 1's left-off hits (0.05 + 0.03, all hits at the origin: none
  // before or after its track's) and its hit on track 2, halved.
  EXPECT_NEAR(mean.places.leftOffBetween, 0.04, 1e-12);
  EXPECT_NEAR(mean.places.otherAtHolderEnd + mean.places.otherInsideHolder,
              0.02, 1e-12);
  EXPECT_EQ(averageDiagnostics({}).tracks, 0.0);

  TrackmlDiagnosticsConfig other;
  other.ptEdges = {0.0, 1.0};
  const std::vector<TrackmlDiagnostics> mixed = {
      diagnose(event, labels), diagnose(event, labels, other)};
  EXPECT_THROW(averageDiagnostics(std::span<const TrackmlDiagnostics>(mixed)),
               std::invalid_argument);
}

TEST(TrackmlDiagnostics, BadInputThrows) {
  const Event event = handMadeEvent();
  EXPECT_THROW(diagnose(event, Labels(3, 0)), std::invalid_argument);
  EXPECT_THROW(diagnose(Event{}, Labels{}), std::invalid_argument);
  TrackmlDiagnosticsConfig config;
  config.absEtaEdges = {1.0, 0.0};
  EXPECT_THROW(diagnose(event, handMadeLabels(), config),
               std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

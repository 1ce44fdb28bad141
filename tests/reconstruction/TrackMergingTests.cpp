/// @file TrackMergingTests.cpp
/// Track merging (detail/TrackMerging.hpp): two pieces of one helix become
/// one track, without a hit of another particle that ended one of them,
/// also when the particle was produced off the beam line or scattered
/// between them (below 1 GeV); pieces of two different nearby helices stay
/// apart; the chain keys and cuts. The
/// pieces are made directly (fitted hit lists in a FinderState), as the
/// finder would leave them after a gap; loopers' further half-turns are in
/// TrackMergingTurnsTests.cpp.
///
/// Tolerances: the synthetic hits lie exactly on their helices (5 um
/// errors); "nearby" helices differ by 10 mrad in azimuth (1 mm at the
/// outer layers: inside the 10 mm geometric gate, 200 sigma for the merged
/// fit) or by 0.02 in tanLambda (2 mm in z); the merged pT is checked to
/// 0.05 GeV of 3.6 GeV and tanLambda to 1e-3.

#include "conftrack/core/Error.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/detail/TrackMerging.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "ChainText.hpp"
#include "SyntheticHits.hpp"
#include "TrackMergingFixture.hpp"

namespace conftrack {
namespace {

using test::chain;
using test::Fixture;
using test::kPhi0;
using test::kRho;
using test::kTanL;

TEST(TrackMerging, TwoPiecesOfOneHelixAreMerged) {
  Fixture f;
  f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
  ASSERT_EQ(f.hits.size(), 8u);
  f.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  // All eight hits, along the path.
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_NEAR(f.state->tracks[0].pt, 0.3 * 4.0 * kRho / 1000.0, 0.05);
  EXPECT_NEAR(f.state->tracks[0].sz.tanLambda, kTanL, 1e-3);
}

TEST(TrackMerging, PiecesBeyondTheirStepsCutAreMergedByTheRatio) {
  // Hits 30 um off the helix, alternately on either side (6 sigma): each
  // piece's circle fit has a chi2/ndf of order 100, above a step cut of
  // 10 that the pieces passed when they were built (the extension, not
  // the step, took them past it). The merged fit is as good as the
  // pieces', so they merge; the step's cut is not applied again.
  Fixture f;
  f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
  for (std::size_t i = 0; i < f.hits.size(); ++i) {
    Hit& h = f.hits[i];
    const Vector3 across =
        Vector3(-h.position.y(), h.position.x(), 0.0).normalized();
    h.position += (i % 2 == 0 ? 0.03 : -0.03) * across;
  }
  f.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
  const double pieceChi2 = f.state->tracks[0].uv.chi2PerNdf();
  EXPECT_GT(pieceChi2, 10.0);
  f.cfg.steps[0].chi2Cut = 10.0;
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(TrackMerging, OrderOfHitsAndPiecesDoesNotMatter) {
  Fixture f;
  f.hits = test::helixHits(f.det, kRho, kPhi0, -1, kTanL, 1);
  f.prepare({{1, 2, 3}, {4, 5, 6, 7, 8}});
  ASSERT_EQ(f.merge(), 1u);
  Fixture g;
  g.hits = test::helixHits(g.det, kRho, kPhi0, -1, kTanL, 1);
  std::reverse(g.hits.begin(), g.hits.end());
  g.prepare({{4, 5, 6, 7, 8}, {1, 2, 3}});
  ASSERT_EQ(g.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  ASSERT_EQ(g.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), g.ids(0));
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(TrackMerging, DifferentNearbyHelicesStayApart) {
  for (int which = 0; which < 2; ++which) {
    Fixture f;
    f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
    const double phi = which == 0 ? kPhi0 + 0.01 : kPhi0;
    const double tanL = which == 0 ? kTanL : kTanL + 0.02;
    std::vector<Hit> second = test::helixHits(f.det, kRho, phi, 1, tanL, 101);
    f.hits.insert(f.hits.end(), second.begin(), second.end());
    f.prepare({{1, 2, 3, 4}, {105, 106, 107, 108}});
    EXPECT_EQ(f.merge(), 0u) << "case " << which;
    EXPECT_EQ(f.state->tracks.size(), 2u);
  }
}

TEST(TrackMerging, ScatteredLowMomentumPiecesAreMergedByTheirMomentum) {
  // The outer piece (hits 5-8) is 70 um off in z from the inner piece's
  // line (14 sigma): scattering between them, which each piece's own
  // straight s-z line absorbs. The merged s-z chi2/ndf, about 16, is above
  // 10 times the pieces' own (each exact, counted as 1). At 0.6 GeV
  // (rho = 500 mm, p = 0.63 GeV) the bound grows by (1 GeV / p)^2 = 2.5,
  // as scattering does, and the pieces merge; at 6 GeV they do not, nor
  // at 0.6 GeV without the momentum's allowance.
  constexpr double kOffset = 0.07;  // [mm]
  const auto scattered = [&](const Detector& det, double rho) {
    std::vector<Hit> hits = test::helixHits(det, rho, kPhi0, 1, kTanL, 1);
    for (Hit& h : hits) {
      if (h.id >= 5) {
        h.position.z() += kOffset;
      }
    }
    return hits;
  };
  for (double rho : {500.0, 5000.0}) {
    Fixture f;
    f.hits = scattered(f.det, rho);
    ASSERT_EQ(f.hits.size(), 8u);
    f.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
    EXPECT_EQ(f.merge(), rho < 1000.0 ? 1u : 0u) << rho;
  }
  Fixture g;
  g.hits = scattered(g.det, 500.0);
  g.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
  detail::TrackMerger::Config cfg;
  cfg.scatteringMomentum = 1e-6;
  cfg.dropTurns = false;  // a default circle of 1 m could loop
  EXPECT_EQ(detail::TrackMerger(*g.state, cfg).run(), 0u);
}

TEST(TrackMerging, PieceEndingOnAnotherParticlesHitIsMergedWithoutIt) {
  // The inner piece's extension ended on a hit of a particle 0.1 rad away
  // (12 mm off at 120 mm, 15 mm at 150 mm: beyond the 10 mm gate). That
  // hit is left out and the pieces merge; with no outlier allowed they
  // stay apart.
  for (std::uint64_t foreign : {107u, 108u}) {
    Fixture f;
    f.hits = test::helixHits(f.det, kRho, kPhi0, 1, kTanL, 1);
    std::vector<Hit> second =
        test::helixHits(f.det, kRho, kPhi0 - 0.1, 1, kTanL, 101);
    f.hits.insert(f.hits.end(), second.begin(), second.end());
    f.cfg.steps[0].chi2Cut = 1e9;
    // With 108 (150 mm) the inner piece reaches further out than the outer
    // one (layers 80-120): its circle, bent by that hit, is tried first.
    if (foreign == 107) {
      f.prepare({{1, 2, 3, 4, 107}, {5, 6, 7, 8}});
    } else {
      f.prepare({{1, 2, 3, 4, 108}, {5, 6, 7}});
    }
    EXPECT_EQ(f.merge(), 1u) << foreign;
    ASSERT_EQ(f.state->tracks.size(), 1u) << foreign;
    std::vector<std::uint64_t> expected{1, 2, 3, 4, 5, 6, 7, 8};
    if (foreign == 108) {
      expected.pop_back();
    }
    EXPECT_EQ(f.ids(0), expected) << foreign;

    Fixture g;
    g.hits = f.hits;
    g.cfg.steps[0].chi2Cut = 1e9;
    if (foreign == 107) {
      g.prepare({{1, 2, 3, 4, 107}, {5, 6, 7, 8}});
    } else {
      g.prepare({{1, 2, 3, 4, 108}, {5, 6, 7}});
    }
    detail::TrackMerger::Config cfg;
    cfg.maxOutliers = 0;
    EXPECT_EQ(detail::TrackMerger(*g.state, cfg).run(), 0u) << foreign;
  }
}

TEST(TrackMerging, DisplacedPiecesArePairedByTheirFreeCircles) {
  // A particle that passes 10 mm from the beam line (d0, 1.2 GeV): the
  // conformal fits, circles through the origin, put the centres of its
  // inner (30-65 mm) and outer (80-150 mm) pieces 0.26 rad apart in
  // azimuth, beyond the 0.1 rad sweep; their free circles lie within it.
  constexpr double kDisplacedRho = 1000.0;
  Fixture f;
  f.hits = test::helixHits(f.det, kDisplacedRho, kPhi0, 1, kTanL, 1, 10.0);
  ASSERT_EQ(f.hits.size(), 8u);
  f.cfg.steps[0].chi2Cut = 1e9;
  f.prepare({{1, 2, 3, 4}, {5, 6, 7, 8}});
  const auto azimuth = [&](std::size_t t) {
    const auto& uv = f.state->tracks[t].uv;
    return std::atan2(uv.centreY, uv.centreX);
  };
  EXPECT_GT(std::abs(azimuth(0) - azimuth(1)), 0.1);
  EXPECT_EQ(f.merge(), 1u);
  ASSERT_EQ(f.state->tracks.size(), 1u);
  EXPECT_EQ(f.ids(0), (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(TrackMerging, ChainKeysAreRead) {
  const Detector det = test::barrelDetector();
  const FinderConfig c = parseChain(
      "[finder]\ntrack_merging = false\nmerge_max_dphi = 0.2\n"
      "merge_max_distance_mm = 4.0\nmerge_max_dz_mm = 8.0\n"
      "merge_max_chi2_ratio = 5.0\nmerge_drop_turns = false\n" +
          minimalStep("Barrel"),
      "chain.toml", det);
  EXPECT_FALSE(c.trackMerging);
  EXPECT_FALSE(c.mergeDropTurns);
  EXPECT_TRUE(
      parseChain("[finder]\n" + minimalStep("Barrel"), "chain.toml", det)
          .mergeDropTurns);
  EXPECT_DOUBLE_EQ(c.mergeMaxDeltaPhi, 0.2);
  EXPECT_DOUBLE_EQ(c.mergeMaxDistance, 4.0 * units::mm);
  EXPECT_DOUBLE_EQ(c.mergeMaxDz, 8.0 * units::mm);
  EXPECT_DOUBLE_EQ(c.mergeMaxChi2Ratio, 5.0);
  EXPECT_THROW(
      parseChain("[finder]\nmerge_max_dz_mm = -1.0\n" + minimalStep("Barrel"),
                 "chain.toml", det),
      InputError);
  EXPECT_THROW(
      parseChain("[finder]\nmerge_drop_turns = 3\n" + minimalStep("Barrel"),
                 "chain.toml", det),
      InputError);
}

TEST(TrackMerging, CutsAreValidated) {
  const Detector det = test::barrelDetector();
  FinderConfig cfg = chain();
  cfg.mergeMaxDistance = 0.0;
  auto p = findChainProblem(cfg, det);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->key, "finder.merge_max_distance_mm");
  cfg = chain();
  cfg.mergeMaxChi2Ratio = 0.5;
  p = findChainProblem(cfg, det);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->key, "finder.merge_max_chi2_ratio");

  const ConformalHits none = makeConformalHits({}, det);
  cfg = chain();
  detail::FinderState state(none, det, cfg, 4.0);
  detail::TrackMerger::Config bad;
  bad.maxDz = std::nan("");
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
  bad = {};
  bad.maxDeltaPhi = 4.0;
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
  bad = {};
  bad.turnScaleTanLambda = 0.0;
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
  bad = {};
  bad.maxTurnScore = std::nan("");
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
  bad = {};
  bad.scatteringMomentum = 0.0;
  EXPECT_THROW(detail::TrackMerger(state, bad), std::invalid_argument);
}

}  // namespace
}  // namespace conftrack

// The helix-triplet step for displaced tracks (FindingStep::helix): its
// keys, and what it adds on the CLICdet displaced-muon sample.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/evaluation/TruthMatching.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ChainText.hpp"

namespace conftrack {
namespace {

const Detector& clicdet() {
  static const Detector det = loadDetector("clicdet");
  return det;
}

/// A helix step over `collections` (by default the tracker barrels), with
/// `extra` keys appended.
std::string helixStep(const std::string& extra,
                      const std::string& collections =
                          "\"InnerTrackerBarrel\", \"OuterTrackerBarrel\"") {
  return "[[step]]\nname = \"H\"\ncollections = [" + collections +
         "]\n"
         "actions = [\"helix\"]\nmax_cell_angle = 0.03\n"
         "max_cell_angle_rz = 0.005\nchi2_cut = 12.0\nmin_hits = 4\n"
         "max_distance = 0.02\nslope_z_range = 10.0\nhigh_pt_cut_GeV = 0.0\n" +
         extra;
}

/// A finder of the one helix step helixStep(keys, collections) in CLICdet.
ConformalTrackFinder helixFinder(const std::string& keys,
                                 const std::string& collections) {
  return ConformalTrackFinder(
      clicdet(),
      {parseChain(helixStep(keys, collections), "chain.toml", clicdet())});
}

/// A one-muon gun in CLICdet, charge random, with `keys` (momentum and
/// angle or vertex ranges) appended to its [generator] table.
EventSimulation muonGun(std::uint64_t seed, const std::string& keys) {
  EventSimulation::Config cfg;
  cfg.sample = "muons";
  cfg.seed = seed;
  cfg.generatorToml =
      "[generator]\nsample = \"gun\"\nparticle = \"mu-\"\n"
      "random_charge = true\nmultiplicity = 1\n" +
      keys;
  return EventSimulation(clicdet(), cfg);
}

/// Hits of the event's particles (noise left out) on the subdetectors
/// `names`.
std::size_t particleHitsOn(const Event& ev,
                           std::initializer_list<std::string_view> names) {
  std::vector<std::uint16_t> subdetectors;
  for (std::string_view name : names) {
    const auto sub = clicdet().findSubdetector(name);
    EXPECT_TRUE(sub.has_value()) << name;
    subdetectors.push_back(sub.value_or(0));
  }
  std::size_t n = 0;
  for (HitIndex h = 0; h < ev.hits.size(); ++h) {
    n += ev.truth[h].particleId != 0 &&
                 std::find(subdetectors.begin(), subdetectors.end(),
                           ev.hits[h].detId.subdetector) != subdetectors.end()
             ? 1
             : 0;
  }
  return n;
}

std::string helixError(const std::string& extra) {
  try {
    parseChain(helixStep(extra), "chain.toml", clicdet());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(HelixStep, KeysAreValidated) {
  const FinderConfig ok =
      parseChain(helixStep("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                           "max_d0_mm = 600.0\nmax_missed_layers = 1\n"),
                 "chain.toml", clicdet());
  ASSERT_EQ(ok.steps.size(), 1u);
  EXPECT_TRUE(ok.steps[0].helix);
  EXPECT_DOUBLE_EQ(ok.steps[0].minPt, 0.5);
  EXPECT_DOUBLE_EQ(ok.steps[0].maxD0, 600.0);
  EXPECT_EQ(ok.steps[0].maxMissedLayers, 1u);
  EXPECT_EQ(ok.steps[0].continueMissedLayers, 0u);
  EXPECT_EQ(ok.steps[0].continueChi2Cut, 0.0);
  // The continuation's chi2 cut: 0 (the step's) or at least chi2_cut.
  EXPECT_EQ(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "continue_chi2_cut = 0.0\n"),
            "");
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "continue_chi2_cut = -1.0\n")
                .find("continue_chi2_cut"),
            std::string::npos);
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "continue_chi2_cut = 5.0\n")  // chi2_cut 12
                .find("at least chi2_cut"),
            std::string::npos);
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "continue_missed_layers = 11\n")
                .find("continue_missed_layers"),
            std::string::npos);
  // The seed search needs a bound on the hit-to-hit distance and a pT.
  EXPECT_NE(helixError("min_pt_GeV = 0.5\n").find("max_seed_length_mm"),
            std::string::npos);
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\n").find("min_pt_GeV"),
            std::string::npos);
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "max_missed_layers = 11\n")
                .find("max_missed_layers"),
            std::string::npos);
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "max_d0_mm = 0.0\n")
                .find("max_d0_mm"),
            std::string::npos);
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "max_seed_gap_mm = -1.0\n")
                .find("max_seed_gap_mm"),
            std::string::npos);
  EXPECT_EQ(ok.steps[0].maxSeedGap, 0.0);
  // seed_length_per_gap: 0 or above 1, with a bound above
  // max_seed_length_mm; no bound without it.
  EXPECT_EQ(ok.steps[0].seedLengthPerGap, 0.0);
  const std::string seedKeys = "max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n";
  const std::vector<std::pair<std::string, std::string>> perGapErrors = {
      {"seed_length_per_gap = 2.0\n", "seed_length_per_gap_max_mm"},
      {"seed_length_per_gap = 2.0\nseed_length_per_gap_max_mm = 400.0\n",
       "above max_seed_length_mm"},
      {"seed_length_per_gap_max_mm = 600.0\n", "needs seed_length_per_gap"},
      {"seed_length_per_gap = -1.0\n", "seed_length_per_gap"},
      {"seed_length_per_gap = 0.8\nseed_length_per_gap_max_mm = 600.0\n",
       "above 1"}};
  for (const auto& [keys, mention] : perGapErrors) {
    EXPECT_NE(helixError(seedKeys + keys).find(mention), std::string::npos)
        << keys;
  }
  const FinderConfig perGap =
      parseChain(helixStep("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                           "seed_length_per_gap = 2.0\n"
                           "seed_length_per_gap_max_mm = 600.0\n"),
                 "chain.toml", clicdet());
  EXPECT_DOUBLE_EQ(perGap.steps[0].seedLengthPerGap, 2.0);
  EXPECT_DOUBLE_EQ(perGap.steps[0].maxSeedLengthPerGap, 600.0 * units::mm);
  std::string build = helixStep(
      "max_seed_length_mm = 400.0\nseed_length_per_gap = 2.0\n"
      "seed_length_per_gap_max_mm = 600.0\n");
  build.replace(build.find("\"helix\""), 7, "\"build\"");
  try {
    parseChain(build, "chain.toml", clicdet());
    ADD_FAILURE() << "seed_length_per_gap accepted on a build step";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("only a helix step"),
              std::string::npos)
        << e.what();
  }
  // inward_collections: a helix step's, known subdetectors, once each.
  EXPECT_TRUE(ok.steps[0].inwardCollections.empty());
  const FinderConfig inward = parseChain(
      helixStep("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                "inward_collections = [\"VertexBarrel\", \"VertexEndcap\"]\n"),
      "chain.toml", clicdet());
  EXPECT_EQ(
      inward.steps[0].inwardCollections,
      (std::vector<std::uint16_t>{*clicdet().findSubdetector("VertexBarrel"),
                                  *clicdet().findSubdetector("VertexEndcap")}));
  auto inwardError = [&](const std::string& list) {
    return helixError(
        "max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
        "inward_collections = " +
        list + "\n");
  };
  EXPECT_NE(inwardError("[]").find("inward_collections"), std::string::npos);
  EXPECT_NE(inwardError("[\"Calorimeter\"]").find("inward_collections"),
            std::string::npos);
  EXPECT_NE(
      inwardError("[\"VertexBarrel\", \"VertexBarrel\"]").find("listed twice"),
      std::string::npos);
  std::string notHelix;
  try {
    parseChain(minimalStep("VertexBarrel") +
                   "inward_collections = [\"VertexEndcap\"]\n",
               "chain.toml", clicdet());
  } catch (const InputError& e) {
    notHelix = e.what();
  }
  EXPECT_NE(notHelix.find("only a helix step"), std::string::npos);
  // past_turn_min_hits: 0 (off) by default, only with inward_collections,
  // at most 100.
  EXPECT_EQ(inward.steps[0].pastTurnMinHits, 0u);
  const std::string inwardKeys =
      "max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
      "inward_collections = [\"VertexBarrel\"]\n";
  EXPECT_EQ(parseChain(helixStep(inwardKeys + "past_turn_min_hits = 2\n"),
                       "chain.toml", clicdet())
                .steps[0]
                .pastTurnMinHits,
            2u);
  EXPECT_NE(helixError("max_seed_length_mm = 400.0\nmin_pt_GeV = 0.5\n"
                       "past_turn_min_hits = 2\n")
                .find("only a helix step with inward_collections"),
            std::string::npos);
  EXPECT_NE(helixError(inwardKeys + "past_turn_min_hits = 101\n")
                .find("past_turn_min_hits"),
            std::string::npos);
  EXPECT_NE(helixError(inwardKeys + "past_turn_min_hits = -1\n")
                .find("past_turn_min_hits"),
            std::string::npos);
  // Defaults of a step without the action: no pT floor, no d0 cut.
  const FinderConfig plain =
      parseChain(minimalStep("VertexBarrel"), "chain.toml", clicdet());
  EXPECT_FALSE(plain.steps[0].helix);
  EXPECT_EQ(plain.steps[0].minPt, 0.0);
  EXPECT_TRUE(std::isinf(plain.steps[0].maxD0));
  EXPECT_EQ(plain.steps[0].maxMissedLayers, 1u);
  std::string bad;
  try {
    parseChain(
        "[[step]]\nname = \"S\"\ncollections = [\"VertexBarrel\"]\n"
        "actions = [\"helices\"]\n",
        "chain.toml", clicdet());
  } catch (const InputError& e) {
    bad = e.what();
  }
  EXPECT_NE(bad.find("expected build, extend, sort, helix"), std::string::npos);
}

/// Fraction of displaced 1 GeV muons (theta, phi 80-100 deg, production
/// radius 250-550 mm: beyond the reach of the conformal displaced steps
/// at this momentum) found as a pure track holding >= 75 % of their hits.
double displacedMuonEfficiency(const FinderConfig& chain, std::size_t n,
                               std::size_t& fakes) {
  const ConformalTrackFinder finder(clicdet(), {chain});
  const EventSimulation sim =
      muonGun(5,
              "p_GeV = 1.0\ntheta_min_deg = 80.0\ntheta_max_deg = 100.0\n"
              "phi_min_deg = 80.0\nphi_max_deg = 100.0\n"
              "r_min_mm = 250.0\nr_max_mm = 550.0\n");
  std::size_t particles = 0;
  std::size_t found = 0;
  fakes = 0;
  for (std::size_t e = 0; e < n; ++e) {
    const Event ev = sim.simulate(e + 1);
    const FindingResult r = finder.run(ev.hits);
    std::vector<std::vector<HitIndex>> lists;
    for (const FoundTrack& t : r.tracks) {
      lists.push_back(t.hits);
    }
    const EventMatching m = matchTracks(ev, lists);
    std::vector<bool> hit(ev.particles.size(), false);
    for (const TrackMatch& t : m.tracks) {
      if (t.purity < 0.75) {
        ++fakes;
      } else if (t.matched &&
                 t.nMajority >= 0.75 * m.particles[t.particle].nHits) {
        hit[t.particle] = true;
      }
    }
    for (std::size_t p = 0; p < ev.particles.size(); ++p) {
      if (m.particles[p].reconstructable) {
        ++particles;
        found += hit[p] ? 1 : 0;
      }
    }
  }
  return double(found) / double(std::max<std::size_t>(1, particles));
}

TEST(HelixStep, FindsDisplacedLowMomentumMuons) {
  // With the shipped chain (these 200: 98.0 %; 90.5 % before the step
  // took residuals at the hit and overlap partners and filtered its
  // (s, z) slope, docs/algorithm.md 3.8) against the same
  // chain without its helix steps (about 0 % in this radius range: the
  // impact parameter is comparable to the tracker radii, and the conformal
  // steps need a line or parabola in (u, v)). 200 muons: the binomial
  // error at 90 % is 2 %.
  FinderConfig chain = readChain(resolveChainPath("clicdet"), clicdet());
  std::size_t fakes = 0;
  const double with = displacedMuonEfficiency(chain, 200, fakes);
  const std::size_t fakesWith = fakes;
  ASSERT_TRUE(chain.steps.back().helix);
  std::erase_if(chain.steps, [](const FindingStep& s) { return s.helix; });
  const double without = displacedMuonEfficiency(chain, 200, fakes);
  std::printf(
      "[ displaced 1 GeV muons, R 250-550 mm ] with helix step %.3f "
      "(%zu impure tracks), without %.3f\n",
      with, fakesWith, without);
  EXPECT_GE(with, 0.85);
  EXPECT_LE(without, 0.5);
  EXPECT_LE(fakesWith, 2u);
}

TEST(HelixStep, AcceptedTracksAreFollowedOnPastAGap) {
  // Prompt 5 GeV muons at 80-100 degrees through the vertex and tracker
  // barrels, their hit on the middle inner-tracker layer (IT_B_L1, 340
  // mm) moved to the opposite side: a sensor gap. Built with no missed layer
  // allowed, a track that reaches the first inner-tracker layer (127 mm) ends
  // at the gap; with continue_missed_layers = 1 it is followed on to the hits
  // beyond it. The build itself is unchanged, so no track is gained or lost.
  // Measured: 16 of the 80 tracks reach 127 mm with this step's cuts (the
  // others end in the vertex barrel), none of them passes the gap without
  // the continuation, all 16 with it.
  const Detector& det = clicdet();
  const std::string keys =
      "seed_collections = [\"VertexBarrel\"]\n"
      "max_seed_length_mm = 200.0\nmin_pt_GeV = 0.5\nmax_missed_layers = 0\n";
  const std::string collections =
      "\"VertexBarrel\", \"InnerTrackerBarrel\", \"OuterTrackerBarrel\"";
  const ConformalTrackFinder tight = helixFinder(keys, collections);
  const ConformalTrackFinder continued =
      helixFinder(keys + "continue_missed_layers = 1\n", collections);
  const EventSimulation sim =
      muonGun(13, "p_GeV = 5.0\ntheta_min_deg = 80.0\ntheta_max_deg = 100.0\n");
  const auto innerTracker = det.findSubdetector("InnerTrackerBarrel");
  ASSERT_TRUE(innerTracker.has_value());
  struct Count {
    std::size_t tracks = 0;
    std::size_t atGap = 0;   ///< holding the 127 mm hit
    std::size_t beyond = 0;  ///< holding a hit beyond 400 mm
  };
  auto count = [](const std::vector<Hit>& hits, const FindingResult& r,
                  Count& c) {
    for (const FoundTrack& t : r.tracks) {
      ++c.tracks;
      double rMax = 0.0;
      for (HitIndex h : t.hits) {
        rMax = std::max(rMax, hits[h].position.head<2>().norm());
      }
      c.atGap += rMax > 100.0 ? 1 : 0;
      c.beyond += rMax > 400.0 ? 1 : 0;
    }
  };
  Count before;
  Count after;
  for (std::size_t e = 0; e < 80; ++e) {
    // The layer keeps a hit, on the opposite side of the detector, so
    // that the finder still searches it.
    std::vector<Hit> hits = sim.simulate(e + 1).hits;
    std::size_t moved = 0;
    for (Hit& h : hits) {
      if (h.detId.subdetector == *innerTracker && h.detId.layer == 1) {
        h.position.head<2>() *= -1.0;
        h.uAxis.head<2>() *= -1.0;
        ++moved;
      }
    }
    ASSERT_GT(moved, 0u) << "event " << e + 1;
    count(hits, tight.run(hits), before);
    count(hits, continued.run(hits), after);
  }
  std::printf(
      "[ 5 GeV muons, a gap at 340 mm ] %zu tracks, %zu at the gap, %zu "
      "beyond it; continued: %zu, %zu, %zu\n",
      before.tracks, before.atGap, before.beyond, after.tracks, after.atGap,
      after.beyond);
  ASSERT_GE(before.atGap, 10u);
  EXPECT_EQ(before.beyond, 0u);
  EXPECT_EQ(after.tracks, before.tracks);
  EXPECT_GE(after.beyond, before.atGap - before.atGap / 10);
}

TEST(HelixStep, AdjacentLayersBeyondTheSeedLengthPairWithMaxSeedGap) {
  // Forward 5 GeV muons (12-16 degrees) through CLICdet's inner-tracker
  // disks, 284 mm apart, with 250 mm seeds: no seed can join two disks,
  // so a helix step over those disks alone finds nothing. With
  // max_seed_gap_mm = 300 adjacent disks pair (a seed segment reaching
  // 250 mm beyond their distance) and the muons are found; disks two
  // apart (568 mm) still do not pair, so a seed skips no disk.
  const std::string keys =
      "max_seed_length_mm = 250.0\nmin_pt_GeV = 0.5\nmax_missed_layers = 0\n";
  const std::string collections = "\"InnerTrackerEndcap\"";
  const ConformalTrackFinder plain = helixFinder(keys, collections);
  const ConformalTrackFinder gap =
      helixFinder(keys + "max_seed_gap_mm = 300.0\n", collections);
  const EventSimulation sim =
      muonGun(17, "p_GeV = 5.0\ntheta_min_deg = 12.0\ntheta_max_deg = 16.0\n");
  constexpr std::size_t kEvents = 40;
  std::size_t plainTracks = 0;
  std::size_t gapTracks = 0;
  std::size_t found = 0;
  std::size_t skipped = 0;
  for (std::size_t e = 0; e < kEvents; ++e) {
    const Event ev = sim.simulate(e + 1);
    plainTracks += plain.run(ev.hits).tracks.size();
    const FindingResult r = gap.run(ev.hits);
    const std::size_t muonHits = particleHitsOn(ev, {"InnerTrackerEndcap"});
    gapTracks += r.tracks.size();
    for (const FoundTrack& t : r.tracks) {
      found += t.hits.size() + 1 >= muonHits ? 1 : 0;
      // Consecutive hits on disks at most one apart (284 mm in z).
      for (std::size_t k = 1; k < t.hits.size(); ++k) {
        const double dz = std::abs(ev.hits[t.hits[k]].position.z() -
                                   ev.hits[t.hits[k - 1]].position.z());
        skipped += dz > 400.0 ? 1 : 0;
      }
    }
  }
  std::printf(
      "[ forward 5 GeV muons, disks 284 mm apart, 250 mm seeds ] %zu tracks "
      "without max_seed_gap_mm; with it %zu tracks, %zu of %zu muons found "
      "whole\n",
      plainTracks, gapTracks, found, kEvents);
  EXPECT_EQ(plainTracks, 0u);
  EXPECT_GE(found, kEvents * 9 / 10);
  EXPECT_EQ(skipped, 0u);
}

TEST(HelixStep, SeedLengthPerGapKeepsThePolarReachOfWideLayerPairs) {
  // Prompt 5 GeV muons at 42-46 degrees (|dz/dr| 0.97-1.11) through
  // CLICdet's tracker barrels (127, 340, 554, 817 and 1151 mm) with
  // 280 mm seeds: between layers 213 mm apart such a segment reaches
  // |dz/dr| 0.85 only, so no triplet is made and the step finds nothing.
  // With seed_length_per_gap = 2 up to 450 mm the inner-tracker pairs get
  // 426 and 428 mm (|dz/dr| up to 1.7) and the muons are found; the
  // 263 mm pair (526 mm, beyond the bound) keeps 280 mm. With the bound
  // at 400 mm no pair is scaled and nothing is found again.
  const std::string keys =
      "max_seed_length_mm = 280.0\nmin_pt_GeV = 0.5\nmax_missed_layers = 0\n";
  const std::string collections =
      "\"InnerTrackerBarrel\", \"OuterTrackerBarrel\"";
  const ConformalTrackFinder plain = helixFinder(keys, collections);
  const ConformalTrackFinder scaled = helixFinder(
      keys + "seed_length_per_gap = 2.0\nseed_length_per_gap_max_mm = 450.0\n",
      collections);
  const ConformalTrackFinder bounded = helixFinder(
      keys + "seed_length_per_gap = 2.0\nseed_length_per_gap_max_mm = 400.0\n",
      collections);
  const EventSimulation sim =
      muonGun(23, "p_GeV = 5.0\ntheta_min_deg = 42.0\ntheta_max_deg = 46.0\n");
  constexpr std::size_t kEvents = 40;
  std::size_t plainTracks = 0;
  std::size_t boundedTracks = 0;
  std::size_t scaledTracks = 0;
  std::size_t found = 0;
  for (std::size_t e = 0; e < kEvents; ++e) {
    const Event ev = sim.simulate(e + 1);
    plainTracks += plain.run(ev.hits).tracks.size();
    boundedTracks += bounded.run(ev.hits).tracks.size();
    const std::size_t muonHits =
        particleHitsOn(ev, {"InnerTrackerBarrel", "OuterTrackerBarrel"});
    const FindingResult r = scaled.run(ev.hits);
    scaledTracks += r.tracks.size();
    for (const FoundTrack& t : r.tracks) {
      found += t.hits.size() >= 4 && t.hits.size() + 1 >= muonHits ? 1 : 0;
    }
  }
  std::printf(
      "[ 5 GeV muons at 42-46 degrees, 280 mm seeds ] %zu tracks; with "
      "seed_length_per_gap 2 up to 450 mm %zu tracks, %zu of %zu muons "
      "found whole; up to 400 mm %zu tracks\n",
      plainTracks, scaledTracks, found, kEvents, boundedTracks);
  EXPECT_EQ(plainTracks, 0u);
  EXPECT_EQ(boundedTracks, 0u);
  EXPECT_GE(found, kEvents * 9 / 10);
  EXPECT_LE(scaledTracks, kEvents);
}

TEST(HelixStep, PathsEndAfterHalfATurn) {
  // Prompt 0.3 GeV muons at 90 degrees turn back inside the inner tracker
  // (4 T: radius of curvature 250 mm, largest radius 500 mm): the
  // simulation follows loopers, so each half-turn (leg) crosses the vertex
  // barrel and the 127 and 340 mm layers. A helix path spans at most half
  // a turn from its first hit, so no track joins two legs (before, the
  // follower took the next leg's hits at 340 mm, beyond which the
  // circle's orientation from its first, middle and last hits is
  // ambiguous), and a leg is found whole: 6 vertex hits over 30 mm and
  // the two tracker hits 68 and 250 mm further out (before, the
  // prediction left out the scattering's share of the seed's curvature
  // and missed the 127 mm hit by 4 sigma).
  const std::string chain = helixStep(
      "seed_collections = [\"VertexBarrel\"]\n"
      "max_seed_length_mm = 100.0\nmin_pt_GeV = 0.1\n",
      "\"VertexBarrel\", \"InnerTrackerBarrel\"");
  const ConformalTrackFinder finder(
      clicdet(), {parseChain(chain, "chain.toml", clicdet())});
  const EventSimulation sim =
      muonGun(11, "p_GeV = 0.3\ntheta_min_deg = 75.0\ntheta_max_deg = 80.0\n");
  constexpr std::size_t kEvents = 40;
  std::size_t whole = 0;
  std::size_t mixed = 0;
  for (std::size_t e = 0; e < kEvents; ++e) {
    const Event ev = sim.simulate(e + 1);
    // Legs: the muon's hits in time order, a new leg wherever the sign of
    // its radial motion changes.
    std::vector<HitIndex> byTime;
    for (HitIndex h = 0; h < ev.hits.size(); ++h) {
      if (ev.truth[h].particleId != 0) {
        byTime.push_back(h);
      }
    }
    std::sort(byTime.begin(), byTime.end(), [&](HitIndex a, HitIndex b) {
      return ev.truth[a].time < ev.truth[b].time;
    });
    std::vector<int> leg(ev.hits.size(), -1);
    std::vector<std::size_t> legSize;
    bool lastOut = true;
    for (HitIndex h : byTime) {
      const HitTruth& t = ev.truth[h];
      const bool out = t.position.head<2>().dot(t.momentum.head<2>()) > 0.0;
      if (legSize.empty() || out != lastOut) {
        legSize.push_back(0);
      }
      lastOut = out;
      leg[h] = static_cast<int>(legSize.size()) - 1;
      ++legSize.back();
    }
    ASSERT_GE(legSize.size(), 2u) << "event " << e + 1 << ": no looper";
    const FindingResult r = finder.run(ev.hits);
    bool found = false;
    for (const FoundTrack& t : r.tracks) {
      const int first = leg[t.hits.front()];
      const bool oneLeg =
          first >= 0 &&
          std::all_of(t.hits.begin(), t.hits.end(),
                      [&](HitIndex h) { return leg[h] == first; });
      mixed += oneLeg ? 0 : 1;
      found =
          found || (oneLeg && first < 2 &&
                    t.hits.size() == legSize[static_cast<std::size_t>(first)]);
    }
    whole += found ? 1 : 0;
  }
  std::printf(
      "[ prompt 0.3 GeV loopers ] %zu of %zu with its first or second leg "
      "whole on one track, %zu tracks joining legs\n",
      whole, kEvents, mixed);
  EXPECT_EQ(mixed, 0u);
  EXPECT_GE(whole, kEvents * 9 / 10);
}

}  // namespace
}  // namespace conftrack

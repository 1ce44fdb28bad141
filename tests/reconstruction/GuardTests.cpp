/// @file GuardTests.cpp
/// The combinatorics guards of the finder (FinderConfig, docs/robustness.md)
/// on a synthetic dense event: a narrow jet of helices plus noise hits on
/// the barrelDetector() layers, thousands of hits within 0.1 rad. Each
/// guard must bite there when set low, be counted in the step statistics,
/// and bound the work it guards; with guards that do not bite the tracks
/// must be those of unlimited guards; the cell-cache bound must not change
/// the tracks where no hit is claimed during a build; and the result must
/// not depend on the hit order.

#include "conftrack/core/Error.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "ChainText.hpp"
#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

/// `tracks` helices from the origin in a jet 0.1 rad wide in azimuth and
/// 0.2 in dz/dR, plus `noise` random hits on the eight barrel layers in
/// that jet. Ids are unique, the order is fixed by the seed.
std::vector<Hit> denseJet(const Detector& det, int tracks, int noise) {
  std::mt19937_64 rng(20240613);
  std::uniform_real_distribution<double> phi(0.4, 0.5);
  std::uniform_real_distribution<double> tanL(-0.1, 0.1);
  std::uniform_real_distribution<double> rho(1500.0, 6000.0);
  std::vector<Hit> hits;
  std::uint64_t id = 1;
  for (int t = 0; t < tracks; ++t) {
    const int q = (t % 2 == 0) ? 1 : -1;
    std::vector<Hit> h =
        test::helixHits(det, rho(rng), phi(rng), q, tanL(rng), id);
    id += h.size();
    hits.insert(hits.end(), h.begin(), h.end());
  }
  std::uniform_int_distribution<int> layer(0, 7);
  std::uniform_real_distribution<double> slope(-0.1, 0.1);
  for (int n = 0; n < noise; ++n) {
    const auto l = static_cast<std::uint16_t>(layer(rng));
    const double r = det.layers()[l].r;
    const double p = phi(rng);
    hits.push_back(test::barrelHit(det, l, r * std::cos(p), r * std::sin(p),
                                   r * slope(rng), id++));
  }
  return hits;
}

/// A build step over the barrel with loose cuts (prompt, radial seeding),
/// then an extension step over the same hits.
FinderConfig denseChain() {
  FinderConfig cfg;
  FindingStep s;
  s.name = "Build";
  s.collections = {0};
  s.build = true;
  s.maxCellAngle = 0.02;
  s.maxCellAngleRZ = 0.02;
  s.chi2Cut = 100.0;
  s.minHits = 5;
  s.maxDistance = 0.02;
  s.radialSearch = true;
  s.maxSeedDeltaPhi = 0.1;
  cfg.steps.push_back(s);
  FindingStep e = s;
  e.name = "Extend";
  e.build = false;
  e.extend = true;
  e.highPtCut = 0.0;
  cfg.steps.push_back(e);
  cfg.extensionPhiWindow = 0.05;
  return cfg;
}

/// Guards so large that they never bite.
FinderConfig unlimited(FinderConfig cfg) {
  const auto big = std::numeric_limits<std::uint32_t>::max();
  cfg.maxPathsPerSeed = big;
  cfg.maxCellsPerSeed = big;
  cfg.maxSeedNeighbours = big;
  cfg.maxCellNeighbours = big;
  cfg.maxLeavesPerSeed = big;
  cfg.maxWindowHits = big;
  cfg.maxCachedCells = big;
  cfg.maxCellsPerHit = big;
  cfg.maxTripletsPerSeed = big;
  return cfg;
}

/// The build step of denseChain() alone, without the final hole filling
/// and with no guard biting: the step budget's tests.
FinderConfig unlimitedBuildOnly() {
  FinderConfig cfg = denseChain();
  cfg.steps.resize(1);
  cfg.finalHoleFilling = false;
  return unlimited(cfg);
}

/// The tracks as lists of hit ids (independent of the hit order), sorted.
std::vector<std::vector<std::uint64_t>> trackIds(const FindingResult& r,
                                                 const std::vector<Hit>& hits) {
  std::vector<std::vector<std::uint64_t>> out;
  for (const FoundTrack& t : r.tracks) {
    std::vector<std::uint64_t> ids;
    for (HitIndex h : t.hits) {
      ids.push_back(hits[h].id);
    }
    out.push_back(ids);
  }
  std::sort(out.begin(), out.end());
  return out;
}

StepStats total(const FindingResult& r) {
  StepStats sum;
  for (const StepStats& s : r.steps) {
    sum += s;
  }
  return sum;
}

TEST(Guards, EachBitesOnADenseJetAndIsCounted) {
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = denseJet(det, 150, 750);
  ASSERT_GT(hits.size(), 1800u);
  FinderConfig cfg = denseChain();
  cfg.maxSeedNeighbours = 4;
  cfg.maxCellNeighbours = 2;
  cfg.maxLeavesPerSeed = 2;
  cfg.maxPathsPerSeed = 1;
  cfg.maxWindowHits = 2;
  const FindingResult r = ConformalTrackFinder(det, {cfg}).run(hits);
  const StepStats& build = r.steps.at(0);
  for (Guard g : {Guard::eSeedNeighbours, Guard::eCellNeighbours,
                  Guard::eLeavesPerSeed, Guard::ePathsPerSeed}) {
    EXPECT_GT(build.guard(g).bites, 0u) << guardKey(g);
    EXPECT_GE(build.guard(g).cut, build.guard(g).bites) << guardKey(g);
  }
  // Windows are searched by the completion of built tracks, the extension
  // step and the final hole filling.
  EXPECT_GT(total(r).guard(Guard::eWindowHits).bites, 0u);
  // Bites are counted per seed at most once for the per-seed guards.
  EXPECT_LE(build.guard(Guard::eSeedNeighbours).bites, build.seeds);
  EXPECT_LE(build.guard(Guard::eLeavesPerSeed).bites, build.seeds);
  // The work per seed is bounded: at most maxLeavesPerSeed paths (one per
  // leaf beyond the path budget) and maxCellsPerSeed cells.
  EXPECT_LE(build.paths, build.seeds * cfg.maxLeavesPerSeed);
  EXPECT_TRUE(build.truncated());
  const std::string text = describeTruncation(r.steps);
  for (const char* key :
       {"max_seed_neighbours", "max_cell_neighbours", "max_leaves_per_seed",
        "max_paths_per_seed", "max_window_hits"}) {
    EXPECT_NE(text.find(key), std::string::npos) << key << " in " << text;
  }
  EXPECT_NE(text.find("step Build: "), std::string::npos) << text;

  // The cells of one seed's automaton.
  cfg.maxCellsPerSeed = 10;
  const StepStats capped = ConformalTrackFinder(det, {cfg}).run(hits).steps[0];
  const GuardCount& cells = capped.guard(Guard::eCellsPerSeed);
  EXPECT_GT(cells.bites, 0u);
  EXPECT_LE(cells.bites, capped.seeds);
  EXPECT_LE(capped.cells, capped.seeds * cfg.maxCellsPerSeed);
  EXPECT_LT(capped.cells, build.cells);
}

TEST(Guards, BoundTheCellsPerSeedAsTheDensityGrows) {
  // Four times the hits in the same region: without guards the automaton
  // of a seed grows with the density; with them it may not pass the
  // bound.
  const Detector det = test::barrelDetector();
  FinderConfig cfg = denseChain();
  cfg.steps.resize(1);
  cfg.finalHoleFilling = false;
  cfg.maxSeedNeighbours = 8;
  cfg.maxCellNeighbours = 4;
  const FinderConfig free = unlimited(cfg);
  double cellsPerSeedFree[2] = {0.0, 0.0};
  double cellsPerSeedGuarded[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    const std::vector<Hit> hits =
        denseJet(det, k == 0 ? 25 : 100, k == 0 ? 125 : 500);
    const StepStats a = ConformalTrackFinder(det, {free}).run(hits).steps[0];
    const StepStats b = ConformalTrackFinder(det, {cfg}).run(hits).steps[0];
    cellsPerSeedFree[k] = double(a.cells) / double(a.seeds);
    cellsPerSeedGuarded[k] = double(b.cells) / double(b.seeds);
    EXPECT_EQ(a.guard(Guard::eSeedNeighbours).bites, 0u);
  }
  EXPECT_GT(cellsPerSeedFree[1], 2.0 * cellsPerSeedFree[0]);
  EXPECT_LT(cellsPerSeedGuarded[1], cellsPerSeedFree[1]);
  EXPECT_LT(cellsPerSeedGuarded[1], 1.5 * cellsPerSeedGuarded[0] + 8.0);
}

TEST(Guards, StepBudgetSkipsTheLastSeedsAndBoundsTheCells) {
  // max_cells_per_hit: once a build's automata have held that many cells
  // per pool hit, the remaining seeds are skipped. The cells may pass the
  // budget by at most the last seed's automaton (maxCellsPerSeed).
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = denseJet(det, 100, 500);
  FinderConfig cfg = unlimitedBuildOnly();
  const StepStats free = ConformalTrackFinder(det, {cfg}).run(hits).steps[0];
  EXPECT_EQ(free.guard(Guard::eCellsPerHit).bites, 0u);
  cfg.maxCellsPerHit = 2;
  const StepStats capped = ConformalTrackFinder(det, {cfg}).run(hits).steps[0];
  const GuardCount& budget = capped.guard(Guard::eCellsPerHit);
  EXPECT_EQ(budget.bites, 1u);  // once per step
  EXPECT_GT(budget.cut, 0u);
  EXPECT_LT(capped.seeds, free.seeds);
  // (The last seed's automaton may pass the budget; this one is small.)
  EXPECT_LE(capped.cells, 2 * hits.size() + 10000);
  EXPECT_LT(capped.cells, free.cells);
  // Every seed is either processed, skipped by the budget or on a track.
  EXPECT_LE(capped.seeds + budget.cut, hits.size());
}

TEST(Guards, StepBudgetReplacesTheFindersForItsStep) {
  // A step's own max_cells_per_hit is its budget instead of the finder's
  // (TrackML's LowPt step at sigma_z = 50 mm): with the finder's at 2 the
  // step is cut as above, with its own large enough it is not, and it
  // finds what it finds without any budget.
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = denseJet(det, 100, 500);
  FinderConfig cfg = unlimitedBuildOnly();
  const FindingResult free = ConformalTrackFinder(det, {cfg}).run(hits);
  cfg.maxCellsPerHit = 2;
  const FindingResult capped = ConformalTrackFinder(det, {cfg}).run(hits);
  EXPECT_EQ(capped.steps[0].guard(Guard::eCellsPerHit).bites, 1u);
  cfg.steps[0].maxCellsPerHit = std::numeric_limits<std::uint32_t>::max();
  const FindingResult own = ConformalTrackFinder(det, {cfg}).run(hits);
  EXPECT_EQ(own.steps[0].guard(Guard::eCellsPerHit).bites, 0u);
  EXPECT_EQ(own.steps[0].cells, free.steps[0].cells);
  EXPECT_EQ(trackIds(own, hits), trackIds(free, hits));
  // ... and a step's budget below the finder's cuts that step.
  cfg.maxCellsPerHit = std::numeric_limits<std::uint32_t>::max();
  cfg.steps[0].maxCellsPerHit = 2;
  const FindingResult tighter = ConformalTrackFinder(det, {cfg}).run(hits);
  EXPECT_EQ(tighter.steps[0].guard(Guard::eCellsPerHit).cut,
            capped.steps[0].guard(Guard::eCellsPerHit).cut);
}

TEST(Guards, DefaultsDoNotBiteOnANormalEventAndChangeNothing) {
  const Detector det = test::barrelDetector();
  // Twenty tracks spread over the whole azimuth plus a little noise.
  std::vector<Hit> hits;
  std::uint64_t id = 1;
  for (int t = 0; t < 20; ++t) {
    std::vector<Hit> h =
        test::helixHits(det, 2000.0 + 150.0 * t, 0.3 * t, t % 2 == 0 ? 1 : -1,
                        -0.5 + 0.05 * t, id);
    id += h.size();
    hits.insert(hits.end(), h.begin(), h.end());
  }
  const FinderConfig defaults = denseChain();
  const FindingResult a = ConformalTrackFinder(det, {defaults}).run(hits);
  const FindingResult b =
      ConformalTrackFinder(det, {unlimited(defaults)}).run(hits);
  EXPECT_EQ(a.tracks.size(), 20u);
  EXPECT_EQ(trackIds(a, hits), trackIds(b, hits));
  for (const StepStats& s : a.steps) {
    EXPECT_FALSE(s.truncated()) << s.name;
    EXPECT_EQ(s.cellCacheFlushes, 0u);
  }
  EXPECT_EQ(describeTruncation(a.steps), "");
}

TEST(Guards, CellCacheBoundChangesNothingWhenNoHitIsClaimed) {
  // Cells are cached with the used flags of the time they were made; only
  // the completion of built tracks claims hits during a build. With
  // separate tracks every track is complete when built, nothing is
  // claimed, and emptying the cache must not change anything.
  const Detector det = test::barrelDetector();
  std::vector<Hit> hits;
  std::uint64_t id = 1;
  for (int t = 0; t < 150; ++t) {
    std::vector<Hit> h =
        test::helixHits(det, 1500.0 + 20.0 * t, 0.0419 * t, t % 2 == 0 ? 1 : -1,
                        -0.6 + 0.008 * t, id);
    id += h.size();
    hits.insert(hits.end(), h.begin(), h.end());
  }
  FinderConfig cfg = denseChain();
  cfg.steps.resize(1);
  cfg.steps[0].maxCellAngle = 0.05;
  cfg.steps[0].maxCellAngleRZ = 0.05;
  cfg.steps[0].maxSeedDeltaPhi = 0.5;
  const FindingResult a = ConformalTrackFinder(det, {cfg}).run(hits);
  cfg.maxCachedCells = 1000;  // the smallest allowed
  const FindingResult b = ConformalTrackFinder(det, {cfg}).run(hits);
  EXPECT_GT(b.steps[0].cellCacheFlushes, 0u);
  EXPECT_EQ(a.steps[0].cellCacheFlushes, 0u);
  EXPECT_EQ(a.steps[0].extendedHits, 0u);
  EXPECT_EQ(a.tracks.size(), 150u);
  EXPECT_EQ(trackIds(a, hits), trackIds(b, hits));
  EXPECT_EQ(a.steps[0].cells, b.steps[0].cells);
  EXPECT_EQ(a.steps[0].paths, b.steps[0].paths);
}

TEST(Guards, TruncationDoesNotDependOnTheHitOrder) {
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = denseJet(det, 100, 500);
  FinderConfig cfg = denseChain();
  cfg.maxSeedNeighbours = 5;
  cfg.maxCellNeighbours = 2;
  cfg.maxLeavesPerSeed = 4;
  cfg.maxWindowHits = 3;
  const ConformalTrackFinder finder(det, {cfg});
  const FindingResult a = finder.run(hits);
  std::vector<Hit> shuffled = hits;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
  const FindingResult b = finder.run(shuffled);
  EXPECT_TRUE(total(a).truncated());
  EXPECT_FALSE(a.tracks.empty());
  EXPECT_EQ(trackIds(a, hits), trackIds(b, shuffled));
  for (std::size_t i = 0; i < kGuardCount; ++i) {
    EXPECT_EQ(total(a).guards[i].bites, total(b).guards[i].bites);
    EXPECT_EQ(total(a).guards[i].cut, total(b).guards[i].cut);
  }
}

TEST(Guards, ZeroIsRejected) {
  const Detector det = test::barrelDetector();
  FinderConfig cfg = denseChain();
  cfg.maxCellNeighbours = 0;
  EXPECT_THROW(ConformalTrackFinder(det, {cfg}), std::invalid_argument);
  cfg = denseChain();
  cfg.maxCachedCells = 10;
  const std::optional<ChainProblem> problem = findChainProblem(cfg, det);
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->key, "finder.max_cached_cells");
  for (const char* key :
       {"max_seed_neighbours", "max_cell_neighbours", "max_leaves_per_seed",
        "max_window_hits", "max_cached_cells", "max_cells_per_hit",
        "max_triplets_per_seed"}) {
    const std::string text =
        std::string("[finder]\n") + key + " = 0\n" + minimalStep("Barrel");
    try {
      parseChain(text, "dense.toml", det);
      ADD_FAILURE() << key << " = 0 accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

TEST(Guards, ChainKeysAreRead) {
  const Detector det = test::barrelDetector();
  const FinderConfig cfg = parseChain(
      "[finder]\nmax_seed_neighbours = 7\nmax_cell_neighbours = 6\n"
      "max_leaves_per_seed = 5\nmax_window_hits = 4\n"
      "max_cached_cells = 5000\nmax_cells_per_hit = 3\n"
      "max_triplets_per_seed = 11\n" +
          minimalStep("Barrel") + "max_paths = 9\nmax_cells_per_hit = 8\n",
      "dense.toml", det);
  EXPECT_EQ(cfg.maxSeedNeighbours, 7u);
  EXPECT_EQ(cfg.maxCellNeighbours, 6u);
  EXPECT_EQ(cfg.maxLeavesPerSeed, 5u);
  EXPECT_EQ(cfg.maxWindowHits, 4u);
  EXPECT_EQ(cfg.maxCachedCells, 5000u);
  EXPECT_EQ(cfg.maxCellsPerHit, 3u);
  EXPECT_EQ(cfg.maxTripletsPerSeed, 11u);
  EXPECT_EQ(cfg.steps[0].maxPaths, 9u);
  EXPECT_EQ(cfg.steps[0].maxCellsPerHit, 8u);
  EXPECT_EQ(cfg.cellsPerHitOf(cfg.steps[0]), 8u);
  const FinderConfig defaults =
      parseChain(minimalStep("Barrel"), "dense.toml", det);
  EXPECT_EQ(defaults.maxSeedNeighbours, FinderConfig{}.maxSeedNeighbours);
  EXPECT_EQ(defaults.steps[0].maxPaths, 0u);
  // A step without its own budget has the finder's.
  EXPECT_EQ(defaults.steps[0].maxCellsPerHit, 0u);
  EXPECT_EQ(defaults.cellsPerHitOf(defaults.steps[0]),
            FinderConfig{}.maxCellsPerHit);
  try {
    parseChain(minimalStep("Barrel") + "max_cells_per_hit = -1\n", "dense.toml",
               det);
    ADD_FAILURE() << "step max_cells_per_hit = -1 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_cells_per_hit"),
              std::string::npos)
        << e.what();
  }
}

TEST(Guards, TripletsPerSeedBoundTheHelixFollowing) {
  // max_triplets_per_seed: a helix step follows at most that many of a
  // seed hit's triplets (the straightest first). In the dense jet a seed
  // has tens of triplets; with the guard at 2 each seed follows two.
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = denseJet(det, 100, 500);
  FinderConfig cfg;
  FindingStep s;
  s.name = "Helix";
  s.collections = {0};
  s.helix = true;
  s.maxCellAngle = 0.03;
  s.maxCellAngleRZ = 0.01;
  s.chi2Cut = 12.0;
  s.minHits = 5;
  s.maxDistance = 0.02;
  s.maxSeedLength = 40.0;
  s.minPt = 1.0;
  cfg.steps.push_back(s);
  cfg.finalHoleFilling = false;
  cfg = unlimited(cfg);
  const FindingResult free = ConformalTrackFinder(det, {cfg}).run(hits);
  const StepStats& all = free.steps.at(0);
  EXPECT_EQ(all.guard(Guard::eTriplets).bites, 0u);
  ASSERT_GT(all.paths, 4 * all.seeds);  // the guard below must matter
  EXPECT_GE(free.tracks.size(), 50u);

  cfg.maxTripletsPerSeed = 2;
  const FindingResult capped = ConformalTrackFinder(det, {cfg}).run(hits);
  const StepStats& two = capped.steps.at(0);
  const GuardCount& g = two.guard(Guard::eTriplets);
  EXPECT_GT(g.bites, 0u);
  EXPECT_LE(g.bites, two.seeds);  // once per seed at most
  EXPECT_GE(g.cut, g.bites);
  EXPECT_LE(two.paths, 2 * two.seeds);
  EXPECT_NE(describeTruncation(capped.steps).find("max_triplets_per_seed"),
            std::string::npos);
  // The straightest two of each seed still find most of the jet.
  EXPECT_GE(capped.tracks.size(), free.tracks.size() / 2);
}

TEST(Guards, StepPathLimitIsASettingNotAGuard) {
  // A step's own max_paths truncates like the guard but is not counted;
  // the guard is, where it is the smaller.
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = denseJet(det, 100, 500);
  FinderConfig cfg = denseChain();
  cfg.steps[0].maxPaths = 1;
  const FindingResult setting = ConformalTrackFinder(det, {cfg}).run(hits);
  EXPECT_EQ(setting.steps[0].guard(Guard::ePathsPerSeed).bites, 0u);
  cfg.steps[0].maxPaths = 0;
  cfg.maxPathsPerSeed = 1;
  const FindingResult guard = ConformalTrackFinder(det, {cfg}).run(hits);
  EXPECT_GT(guard.steps[0].guard(Guard::ePathsPerSeed).bites, 0u);
  EXPECT_EQ(trackIds(setting, hits), trackIds(guard, hits));
}

}  // namespace
}  // namespace conftrack

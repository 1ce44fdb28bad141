/// @file VertexZPrepassTests.cpp
/// The vertex-z pre-pass (VertexZPrepass.hpp): its z windows, its config
/// validation, the vertices it finds among synthetic prompt tracks from
/// known z with random hits on top, its independence of the hit order, and
/// the chain keys that switch it on.

#include "conftrack/core/Error.hpp"
#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/VertexZPrepass.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "ChainText.hpp"
#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

TEST(VertexZPrepass, ZWindowsMergeAndContain) {
  const ZWindows w({{10.0, 12.0}, {-5.0, -5.0}, {14.0, 20.0}}, 1.0);
  // [-6, -4] and [9, 13] + [13, 21] merged.
  ASSERT_EQ(w.size(), 2u);
  EXPECT_DOUBLE_EQ(w.lowest(), -6.0);
  EXPECT_DOUBLE_EQ(w.highest(), 21.0);
  EXPECT_DOUBLE_EQ(w.length(), 2.0 + 12.0);
  for (double z : {-6.0, -4.0, 9.0, 13.0, 21.0}) {
    EXPECT_TRUE(w.contains(z)) << z;
  }
  for (double z : {-7.0, -3.9, 0.0, 8.9, 21.1}) {
    EXPECT_FALSE(w.contains(z)) << z;
  }
  // Within a margin of an interval.
  EXPECT_TRUE(w.near(-3.5, 0.5));
  EXPECT_FALSE(w.near(-3.4, 0.5));
  EXPECT_TRUE(w.near(0.0, 4.0));
  EXPECT_TRUE(w.near(25.0, 4.0));
  EXPECT_FALSE(w.near(25.1, 4.0));
  EXPECT_TRUE(ZWindows({}, 5.0).empty());
  EXPECT_FALSE(ZWindows({}, 5.0).contains(0.0));
}

TEST(VertexZPrepass, ConfigIsValidated) {
  const Detector det = test::barrelDetector();
  VertexZPrepass::Config ok;
  ok.collections = {*det.findSubdetector("Barrel")};
  EXPECT_NO_THROW(VertexZPrepass(det, ok));
  EXPECT_EQ(VertexZPrepass(det, ok).layers(),
            (std::vector<std::uint32_t>{0, 1, 2}));
  auto problem = [&](auto change) {
    VertexZPrepass::Config c = ok;
    change(c);
    auto p = VertexZPrepass::findProblem(c, det);
    return p ? p->first : std::string();
  };
  using C = VertexZPrepass::Config;
  EXPECT_EQ(problem([](C& c) { c.maxAbsZ = 0.0; }), "max_z_mm");
  EXPECT_EQ(problem([](C& c) { c.binWidth = 400.0; }), "bin_width_mm");
  EXPECT_EQ(problem([](C& c) { c.maxDeltaPhi = 2.0; }), "max_dphi");
  EXPECT_EQ(problem([](C& c) { c.confirmPhi = -1.0; }), "confirm_dphi");
  EXPECT_EQ(problem([](C& c) { c.confirmZ = 0.0; }), "confirm_dz_mm");
  EXPECT_EQ(problem([](C& c) { c.minExcess = 0.5; }), "min_excess");
  EXPECT_EQ(problem([](C& c) { c.minSignificance = -1.0; }),
            "min_significance");
  EXPECT_EQ(problem([](C& c) { c.collections.clear(); }), "collections");
  EXPECT_EQ(problem([&](C& c) { c.collections.push_back(c.collections[0]); }),
            "collections");
  // The endcap has one disk and no barrel layer.
  EXPECT_EQ(
      problem([&](C& c) { c.collections = {*det.findSubdetector("Endcap")}; }),
      "collections");
  VertexZPrepass::Config bad = ok;
  bad.binWidth = -1.0;
  try {
    VertexZPrepass p(det, bad);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bin_width_mm"), std::string::npos);
  }
}

/// Prompt tracks (pT 0.4-5 GeV in the 4 T of barrelDetector, |tanL| < 1.5)
/// from each of `vertices`, `perVertex` each, plus `noise` random hits on
/// each of the three innermost layers.
std::vector<Hit> syntheticEvent(const Detector& det,
                                const std::vector<double>& vertices,
                                int perVertex, int noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Hit> hits;
  for (double zv : vertices) {
    for (int t = 0; t < perVertex; ++t) {
      const double pt = 0.4 + 4.6 * u(rng);
      const double rho = pt / (0.3 * 4.0) * 1000.0;  // mm
      const double phi0 = std::numbers::pi * (2.0 * u(rng) - 1.0);
      const double tanL = 3.0 * u(rng) - 1.5;
      const int q = u(rng) < 0.5 ? -1 : 1;
      for (Hit h : test::helixHits(det, rho, phi0, q, tanL, 0)) {
        h.position.z() += zv;
        if (std::abs(h.position.z()) < 500.0) {
          h.id = hits.size() + 1;
          hits.push_back(h);
        }
      }
    }
  }
  for (std::uint16_t l = 0; l < 3; ++l) {
    const double r = det.layers()[l].r;
    for (int k = 0; k < noise; ++k) {
      const double phi = std::numbers::pi * (2.0 * u(rng) - 1.0);
      hits.push_back(test::barrelHit(det, l, r * std::cos(phi),
                                     r * std::sin(phi), 1000.0 * u(rng) - 500.0,
                                     hits.size() + 1));
    }
  }
  return hits;
}

TEST(VertexZPrepass, FindsTheVerticesOfPromptTracks) {
  const Detector det = test::barrelDetector();
  VertexZPrepass::Config config;
  config.collections = {*det.findSubdetector("Barrel")};
  const VertexZPrepass prepass(det, config);
  // Ten vertices 12-80 mm apart, out to 150 mm (HL-LHC-like tails), 15
  // tracks each, and 1000 random hits on each of the three layers.
  const std::vector<double> truth = {-150.0, -70.0, -40.0, -21.3, -3.1,
                                     9.0,    25.0,  60.0,  100.0, 140.0};
  std::vector<Hit> hits = syntheticEvent(det, truth, 15, 1000, 3);
  const VertexZPrepass::Result r = prepass.run(makeConformalHits(hits, det));
  // Every vertex found within 0.5 mm (one bin), none elsewhere: each found
  // vertex within 2 mm of a generated one.
  for (double z : truth) {
    double best = 1e9;
    for (double v : r.vertices) {
      best = std::min(best, std::abs(v - z));
    }
    EXPECT_LT(best, 0.5) << "vertex at " << z;
  }
  for (double v : r.vertices) {
    double best = 1e9;
    for (double z : truth) {
      best = std::min(best, std::abs(v - z));
    }
    EXPECT_LT(best, 2.0) << "found " << v;
  }
  EXPECT_TRUE(std::is_sorted(r.vertices.begin(), r.vertices.end()));
  // The regions hold every vertex and little else: at most 3 mm each.
  const ZWindows w(r.regions, 0.0);
  for (double z : truth) {
    EXPECT_TRUE(w.contains(z)) << z;
  }
  EXPECT_LE(w.length(), 3.0 * truth.size());
  EXPECT_GT(r.triplets, r.background);

  // The same result for any order of the hits.
  std::mt19937_64 rng(5);
  std::shuffle(hits.begin(), hits.end(), rng);
  const VertexZPrepass::Result s = prepass.run(makeConformalHits(hits, det));
  EXPECT_EQ(s.vertices, r.vertices);
  EXPECT_EQ(s.regions, r.regions);
  EXPECT_EQ(s.triplets, r.triplets);
  EXPECT_EQ(s.background, r.background);

  // Random hits alone make no vertex.
  const VertexZPrepass::Result noise =
      prepass.run(makeConformalHits(syntheticEvent(det, {}, 0, 1000, 4), det));
  EXPECT_TRUE(noise.vertices.empty());
  EXPECT_TRUE(noise.regions.empty());
}

TEST(VertexZPrepass, ExcludedHitsMakeNoVertex) {
  // Two vertices of 15 tracks and random hits: both found; with the hits
  // of the first vertex's tracks excluded (as those that tracks hold,
  // FindingStep::vertexPrepassFreeHits), only the second.
  const Detector det = test::barrelDetector();
  VertexZPrepass::Config config;
  config.collections = {*det.findSubdetector("Barrel")};
  const VertexZPrepass prepass(det, config);
  std::vector<Hit> hits = syntheticEvent(det, {-40.0}, 15, 0, 21);
  const std::size_t first = hits.size();
  for (const std::vector<Hit>& more : {syntheticEvent(det, {60.0}, 15, 0, 22),
                                       syntheticEvent(det, {}, 0, 1000, 23)}) {
    for (Hit h : more) {
      h.id = hits.size() + 1;
      hits.push_back(h);
    }
  }
  const ConformalHits conformal = makeConformalHits(hits, det);
  const ZWindows all(prepass.run(conformal).regions, 0.0);
  EXPECT_TRUE(all.contains(-40.0));
  EXPECT_TRUE(all.contains(60.0));
  std::vector<std::uint8_t> held(conformal.size(), 0);
  for (ConfIndex h = 0; h < conformal.size(); ++h) {
    held[h] = conformal.original[h] < first ? 1 : 0;
  }
  const VertexZPrepass::Result free = prepass.run(conformal, &held);
  const ZWindows rest(free.regions, 0.0);
  EXPECT_FALSE(rest.near(-40.0, 5.0));
  EXPECT_TRUE(rest.contains(60.0));
  // Nothing excluded: the same as without the flags.
  std::vector<std::uint8_t> none(conformal.size(), 0);
  EXPECT_EQ(prepass.run(conformal, &none).regions,
            prepass.run(conformal).regions);
}

TEST(VertexZPrepass, DenseVerticesFormOneRegion) {
  // 150 vertices with sigma_z = 5.5 mm (the Kaggle events): not resolved,
  // but one region covers them all but the outermost few.
  const Detector det = test::barrelDetector();
  VertexZPrepass::Config config;
  config.collections = {*det.findSubdetector("Barrel")};
  const VertexZPrepass prepass(det, config);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> gauss(0.0, 5.5);
  std::vector<double> truth(150);
  for (double& z : truth) {
    z = gauss(rng);
  }
  const VertexZPrepass::Result r = prepass.run(
      makeConformalHits(syntheticEvent(det, truth, 6, 1000, 8), det));
  const ZWindows w(r.regions, 0.0);
  std::size_t inside = 0;
  for (double z : truth) {
    inside += w.contains(z) ? 1 : 0;
  }
  EXPECT_GE(inside, 140u);
  // With a step's window of 10 mm, all of them.
  const ZWindows wide(r.regions, 10.0);
  for (double z : truth) {
    EXPECT_TRUE(wide.contains(z)) << z;
  }
}

std::string chainWith(const std::string& prepass, const std::string& step) {
  return prepass + minimalStep("Barrel") + step;
}

std::string chainError(const std::string& text) {
  try {
    parseChain(text, "chain.toml", test::barrelDetector());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(VertexZPrepass, ChainKeys) {
  const Detector det = test::barrelDetector();
  const std::string table =
      "[vertex_prepass]\ncollections = [\"Barrel\"]\nbin_width_mm = 1.0\n"
      "max_z_mm = 250.0\nsmooth_bins = 3\nmax_dphi = 0.04\n"
      "confirm_dphi = 0.004\nconfirm_dz_mm = 1.5\nmin_excess = 5\n"
      "min_significance = 2.5\n";
  const FinderConfig c = parseChain(
      chainWith(table, "vertex_window_mm = 12.0\n"), "chain.toml", det);
  ASSERT_TRUE(c.vertexPrepass.has_value());
  EXPECT_EQ(c.vertexPrepass->collections,
            std::vector<std::uint16_t>{*det.findSubdetector("Barrel")});
  EXPECT_DOUBLE_EQ(c.vertexPrepass->binWidth, 1.0);
  EXPECT_DOUBLE_EQ(c.vertexPrepass->maxAbsZ, 250.0);
  EXPECT_EQ(c.vertexPrepass->smoothBins, 3u);
  EXPECT_DOUBLE_EQ(c.vertexPrepass->maxDeltaPhi, 0.04);
  EXPECT_DOUBLE_EQ(c.vertexPrepass->confirmPhi, 0.004);
  EXPECT_DOUBLE_EQ(c.vertexPrepass->confirmZ, 1.5);
  EXPECT_DOUBLE_EQ(c.vertexPrepass->minExcess, 5.0);
  EXPECT_DOUBLE_EQ(c.vertexPrepass->minSignificance, 2.5);
  EXPECT_DOUBLE_EQ(c.steps[0].vertexWindow, 12.0);
  // Off by default.
  const FinderConfig plain =
      parseChain(minimalStep("Barrel"), "chain.toml", det);
  EXPECT_FALSE(plain.vertexPrepass.has_value());
  EXPECT_FALSE(std::isfinite(plain.steps[0].vertexWindow));

  EXPECT_FALSE(c.steps[0].vertexPrepassFreeHits);
  EXPECT_TRUE(parseChain(chainWith(table,
                                   "vertex_window_mm = 12.0\n"
                                   "vertex_prepass_free_hits = true\n"),
                         "chain.toml", det)
                  .steps[0]
                  .vertexPrepassFreeHits);
  EXPECT_NE(chainError(chainWith(table, "vertex_prepass_free_hits = true\n"))
                .find("vertex_prepass_free_hits"),
            std::string::npos);

  EXPECT_EQ(chainError(chainWith(table, "")), "");
  EXPECT_NE(chainError(chainWith("", "vertex_window_mm = 10.0\n"))
                .find("vertex_prepass"),
            std::string::npos);
  EXPECT_NE(chainError(chainWith(table, "vertex_window_mm = 0.0\n"))
                .find("vertex_window_mm"),
            std::string::npos);
  EXPECT_NE(chainError(chainWith("[vertex_prepass]\ncollections = "
                                 "[\"Barrel\"]\nmax_dphi = 0.0\n",
                                 ""))
                .find("max_dphi"),
            std::string::npos);
  EXPECT_NE(chainError(chainWith("[vertex_prepass]\ncollections = "
                                 "[\"Endcap\"]\n",
                                 ""))
                .find("three barrel layers"),
            std::string::npos);
  EXPECT_NE(chainError(chainWith("[vertex_prepass]\ncollections = "
                                 "[\"Barrel\"]\nbogus = 1\n",
                                 ""))
                .find("bogus"),
            std::string::npos);
}

TEST(VertexZPrepass, SeedsFollowTheVertices) {
  // Tracks from z = 120 mm: a fixed 20 mm cut about 0 finds none, vertex
  // windows of 10 mm find them all, and the result does not depend on the
  // hit order.
  const Detector det = test::barrelDetector();
  const std::string step =
      "max_seed_dphi = 0.2\nradial_search = true\n"
      "straight_line_fit = true\n";
  const std::string base = "[finder]\nfinal_hole_filling = false\n";
  const std::vector<Hit> hits = syntheticEvent(det, {120.0}, 10, 0, 12);
  auto found = [&](const std::string& text, std::vector<Hit> h) {
    ConformalTrackFinder::Config c{parseChain(text, "chain.toml", det)};
    return ConformalTrackFinder(det, c).run(h).tracks;
  };
  EXPECT_TRUE(
      found(base + minimalStep("Barrel") + step + "max_seed_z0_mm = 20.0\n",
            hits)
          .empty());
  const std::string vertexChain =
      base + "[vertex_prepass]\ncollections = [\"Barrel\"]\n" +
      minimalStep("Barrel") + step +
      "max_seed_z0_mm = 300.0\nvertex_window_mm = 10.0\n";
  const std::vector<FoundTrack> tracks = found(vertexChain, hits);
  EXPECT_EQ(tracks.size(), 10u);
  std::vector<Hit> shuffled = hits;
  std::mt19937_64 rng(1);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const std::vector<FoundTrack> again = found(vertexChain, shuffled);
  ASSERT_EQ(again.size(), tracks.size());
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    ASSERT_EQ(again[i].hits.size(), tracks[i].hits.size());
    for (std::size_t k = 0; k < tracks[i].hits.size(); ++k) {
      EXPECT_EQ(shuffled[again[i].hits[k]].id, hits[tracks[i].hits[k]].id);
    }
  }
}

TEST(VertexZPrepass, FinderReportsTheVertexRegions) {
  // The finder passes on the regions its steps seeded about: those of the
  // pre-pass run alone on the same hits, holding the vertex at 120 mm;
  // none without a pre-pass.
  const Detector det = test::barrelDetector();
  const std::vector<Hit> hits = syntheticEvent(det, {120.0}, 10, 0, 12);
  const std::string step =
      "max_seed_dphi = 0.2\nradial_search = true\n"
      "straight_line_fit = true\nmax_seed_z0_mm = 300.0\n";
  const std::string text = "[vertex_prepass]\ncollections = [\"Barrel\"]\n" +
                           minimalStep("Barrel") + step +
                           "vertex_window_mm = 10.0\n";
  const FinderConfig chain = parseChain(text, "chain.toml", det);
  const FindingResult r = ConformalTrackFinder(det, {chain}).run(hits);
  const VertexZPrepass::Result alone = VertexZPrepass(det, *chain.vertexPrepass)
                                           .run(makeConformalHits(hits, det));
  ASSERT_FALSE(r.vertexRegions.empty());
  EXPECT_EQ(r.vertexRegions, alone.regions);
  EXPECT_TRUE(ZWindows(r.vertexRegions, 0.0).contains(120.0));
  const FindingResult none =
      ConformalTrackFinder(
          det, {parseChain(minimalStep("Barrel") + step, "chain.toml", det)})
          .run(hits);
  EXPECT_TRUE(none.vertexRegions.empty());
  EXPECT_EQ(none.tracks.size(), 10u);
}

}  // namespace
}  // namespace conftrack

/// @file HitPoolTests.cpp
/// The HitPool's orders: the per-layer lists (built by a counting sort of
/// the azimuth order) must be those of sorting by (layer, azimuth, index),
/// and an azimuth window filtered by `keep` the window filtered afterwards.

#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/HitPool.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

/// Random hits on the eight barrel layers of test::barrelDetector(), some
/// of them sharing an azimuth (ties broken by index).
std::vector<Hit> randomHits(const Detector& det, std::size_t n,
                            std::mt19937_64& rng) {
  std::uniform_real_distribution<double> phi(-std::numbers::pi,
                                             std::numbers::pi);
  std::uniform_real_distribution<double> z(-400.0, 400.0);
  std::uniform_int_distribution<std::uint16_t> layer(0, 7);
  std::vector<Hit> hits;
  double last = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t l = layer(rng);
    const double a = i % 9 == 0 && i > 0 ? last : phi(rng);
    last = a;
    const double r = det.layers()[l].r;
    hits.push_back(test::barrelHit(det, l, r * std::cos(a), r * std::sin(a),
                                   z(rng), i + 1));
  }
  return hits;
}

TEST(HitPool, LayerListsFollowLayerThenAzimuth) {
  const Detector det = test::barrelDetector();
  std::mt19937_64 rng(5);
  const std::vector<Hit> hits = randomHits(det, 3000, rng);
  const ConformalHits conf = makeConformalHits(hits, det);
  // A pool of every third hit and of the hits of layer 4, in no order.
  std::vector<ConfIndex> members;
  for (ConfIndex i = 0; i < conf.size(); ++i) {
    if (i % 3 == 0 || conf.layer[i] == 4) {
      members.push_back(i);
    }
  }
  std::shuffle(members.begin(), members.end(), rng);
  const HitPool pool(conf, members);
  std::sort(members.begin(), members.end(), [&](ConfIndex a, ConfIndex b) {
    if (conf.layer[a] != conf.layer[b]) {
      return conf.layer[a] < conf.layer[b];
    }
    return conf.phi[a] != conf.phi[b] ? conf.phi[a] < conf.phi[b] : a < b;
  });
  // Each layer's whole azimuth range, through the public window search.
  std::vector<ConfIndex> got;
  for (std::uint32_t l : pool.layers()) {
    std::vector<ConfIndex> window;
    pool.layerWindow(l, 0.0, 2.0 * std::numbers::pi, window);
    got.insert(got.end(), window.begin(), window.end());
  }
  EXPECT_EQ(got, members);
}

TEST(HitPool, AzimuthWindowFiltersBeforeItsOrder) {
  const Detector det = test::barrelDetector();
  std::mt19937_64 rng(6);
  const std::vector<Hit> hits = randomHits(det, 2000, rng);
  const ConformalHits conf = makeConformalHits(hits, det);
  std::vector<ConfIndex> all(conf.size());
  for (ConfIndex i = 0; i < conf.size(); ++i) {
    all[i] = i;
  }
  const HitPool pool(conf, all);
  std::uniform_real_distribution<double> centre(-std::numbers::pi,
                                                std::numbers::pi);
  std::size_t kept = 0;
  for (int i = 0; i < 500; ++i) {
    const double phi = i % 5 == 0 ? std::numbers::pi - 0.01 : centre(rng);
    const double half = i % 7 == 0 ? 0.5 : 0.05;
    const auto keep = [&](ConfIndex h) {
      return conf.layer[h] % 2 == 0 || h % 5 == 0;
    };
    std::vector<ConfIndex> expected;
    pool.azimuthWindow(phi, half, expected);
    // The window's order: by |dphi|, then index.
    for (std::size_t k = 1; k < expected.size(); ++k) {
      auto dphi = [&](ConfIndex h) {
        const double d = std::abs(conf.phi[h] - phi);
        return std::min(d, 2.0 * std::numbers::pi - d);
      };
      const double a = dphi(expected[k - 1]);
      const double b = dphi(expected[k]);
      EXPECT_TRUE(a < b || (a == b && expected[k - 1] < expected[k]));
    }
    std::erase_if(expected, [&](ConfIndex h) { return !keep(h); });
    std::vector<ConfIndex> got;
    pool.azimuthWindow(phi, half, got, keep);
    EXPECT_EQ(got, expected) << "phi " << phi << ", half-width " << half;
    kept += got.size();
  }
  EXPECT_GT(kept, 1000U);  // the windows are not empty
}

TEST(HitPool, SparseLayersAreSearchedAlongTheirOwnCoordinate) {
  // Few hits left on a layer: two on the disk (z = 600 mm) on sensors
  // mounted 2.5 and 3 mm off it, at nearly one radius, and two on the
  // barrel layer at R = 50 mm at one z on staves 1.5 and 2 mm out. A box
  // about the disk's nominal z (its R bounds the hits) and one about the
  // barrel's nominal R (its z bounds them) must hold them: the pool
  // searches a disk along R and a barrel along z, whatever the spread of
  // the hits it holds (by their spread both layers were searched along the
  // other coordinate, and both boxes came back empty).
  const Detector det = test::barrelDetector();
  const std::uint16_t disk = 8;
  const std::uint16_t barrel = 2;  // R = 50 mm
  ASSERT_TRUE(det.layers()[disk].isDisk());
  std::vector<Hit> hits;
  hits.push_back(test::barrelHit(det, disk, 100.0, 0.0, 602.5, 1));
  hits.push_back(test::barrelHit(det, disk, 100.2, 1.0, 603.0, 2));
  hits.push_back(test::barrelHit(det, barrel, 0.0, 51.5, 120.0, 3));
  hits.push_back(test::barrelHit(det, barrel, 0.0, 52.0, 120.0, 4));
  const ConformalHits conf = makeConformalHits(hits, det);
  const HitPool pool(conf, {0, 1, 2, 3});
  // The hit ids found in a box.
  auto ids = [&](std::uint32_t layer, double phi, double zLo, double zHi,
                 double rLo, double rHi) {
    std::vector<ConfIndex> found;
    pool.layerBox(layer, phi, 0.1, zLo, zHi, rLo, rHi, found);
    std::vector<std::uint64_t> out;
    for (ConfIndex h : found) {
      out.push_back(conf.id[h]);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(ids(disk, 0.0, 599.0, 601.0, 95.0, 105.0),
            (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(ids(barrel, 0.5 * std::numbers::pi, 110.0, 130.0, 49.0, 51.0),
            (std::vector<std::uint64_t>{3, 4}));
}

}  // namespace
}  // namespace conftrack

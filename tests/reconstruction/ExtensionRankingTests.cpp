// How extensions choose among the compatible hits of a layer crossing
// (detail/TrackFollower.hpp): on TrackML's long strips, which measure z to
// 3 mm only, a noise hit beside a track's own must not win on its
// transverse residual alone; and a hit far beyond a track's own fit
// quality is no candidate, so that it does not end the track.

#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>
#include <vector>

#include "TrackmlSample.hpp"

namespace conftrack {
namespace {

/// Hits that the tracks of the shipped TrackML chain's finder hold of their
/// majority particle (own) and the others (foreign, noise included), the
/// chain changed by `change`.
struct OwnForeign {
  std::size_t own = 0;
  std::size_t foreign = 0;
};
OwnForeign countOwnForeign(const Event& event, const Detector& detector,
                           const std::function<void(FinderConfig&)>& change) {
  FinderConfig chain =
      readReconstructionConfig(resolveChainPath("trackml"), detector).chain;
  change(chain);
  const ConformalTrackFinder finder(detector, {chain});
  const FindingResult found = finder.run(event.hits);
  OwnForeign c;
  c.own = test::majorityHits(event, found);
  for (const FoundTrack& t : found.tracks) {
    c.foreign += t.hits.size();
  }
  c.foreign -= c.own;
  return c;
}

/// countOwnForeign on event 1001 with the real noise rate, with the shipped
/// chain (which must have `key` on) and with `key` off; prints both.
std::pair<OwnForeign, OwnForeign> ownForeignWithAndWithout(
    const char* what, bool FinderConfig::*key) {
  const Event event = test::simulateTrackml(test::event1001Particles(),
                                            test::SampleNoise::eReal);
  const Detector detector = loadDetector("trackml");
  const OwnForeign on = countOwnForeign(
      event, detector, [&](FinderConfig& c) { EXPECT_TRUE(c.*key); });
  const OwnForeign off = countOwnForeign(
      event, detector, [&](FinderConfig& c) { c.*key = false; });
  std::printf(
      "[ trackml 1001, %zu hits ] own hits on tracks %zu with %s, %zu "
      "without; foreign %zu with, %zu without\n",
      event.hits.size(), on.own, what, off.own, on.foreign, off.foreign);
  return {on, off};
}

TEST(ExtensionRanking, ScatteringRanksLongStripDecoysBelowTheTracksHits) {
  // Central prompt particles of 0.5-1.5 GeV from event 1001 on the real
  // sensors, no noise. Next to each of their long-strip barrel hits a
  // decoy on the same sensor: 0.2 mm aside across the strips (alternately
  // on either side) and 4 sigma (12.5 mm) along them. Below a few GeV the
  // scattering in the last layer moves a track by more than 0.2 mm at the
  // next long-strip layer, so a ranking by the hits' own errors takes the
  // decoy whenever it lies on the side of the prediction, whatever its z;
  // ranked with that scattering in the variances, z decides. Measured:
  // 2.6 % of the long-strip hits on tracks are decoys (29 of 1106) since
  // z is ranked against the tracks' (s, z) filter and (u, v) with every
  // crossed layer's scattering (extension_sz_filter,
  // extension_uv_scattering; SzFilterKeepsLowMomentumTracksOnTheirOwnHits;
  // 2.9 %, 32 of 1107, with the filter alone); 6.3 % before (70 of
  // 1105, with and
  // without the second pass after the selection; 7.9 % when the test was
  // written, 32.3 % when candidates were ranked without the scattering).
  // Guarded at 15 %.
  std::vector<Particle> particles;
  for (const Particle& p : test::event1001Particles()) {
    const double pt = p.momentum.head<2>().norm();
    const double eta = std::asinh(p.momentum.z() / pt);
    if (p.vertex.head<2>().norm() < 1.0 && pt > 0.5 && pt < 1.5 &&
        std::abs(eta) < 0.8) {
      particles.push_back(p);
    }
  }
  ASSERT_GT(particles.size(), 300u);
  Event event = test::simulateTrackml(particles, test::SampleNoise::eNone);
  const Detector detector = loadDetector("trackml");
  const auto longStrips = detector.findSubdetector("LongStripBarrel");
  ASSERT_TRUE(longStrips.has_value());
  const std::size_t nTrue = event.hits.size();
  std::size_t decoys = 0;
  for (std::size_t k = 0; k < nTrue; ++k) {
    const Hit hit = event.hits[k];
    if (hit.detId.subdetector != *longStrips) {
      continue;
    }
    const double side = k % 2 == 0 ? 1.0 : -1.0;
    Hit decoy = hit;
    decoy.id = 1000000 + k;
    decoy.position += side * 0.2 * hit.uAxis + 4.0 * hit.sigmaV * hit.vAxis;
    event.hits.push_back(decoy);
    event.truth.push_back(HitTruth{});
    ++decoys;
  }
  ASSERT_GT(decoys, 500u);

  Reconstruction::Config config =
      readReconstructionConfig(resolveChainPath("trackml"), detector);
  const Reconstruction reco(detector, config);
  const Reconstruction::Result result = reco.run(event.hits);
  std::size_t onTracks = 0;
  std::size_t decoysOnTracks = 0;
  for (const Track& t : result.tracks) {
    for (HitIndex h : t.hits) {
      if (event.hits[h].detId.subdetector == *longStrips) {
        ++onTracks;
        decoysOnTracks += h >= nTrue ? 1 : 0;
      }
    }
  }
  const double fraction =
      double(decoysOnTracks) / double(std::max<std::size_t>(1, onTracks));
  std::printf(
      "[ long-strip decoys ] %zu decoys; of %zu long-strip hits on tracks "
      "%zu decoys (%.3f)\n",
      decoys, onTracks, decoysOnTracks, fraction);
  EXPECT_GT(onTracks, 400u);
  EXPECT_LE(fraction, 0.15);
}

TEST(ExtensionRanking, HitsFarBeyondTheFitQualityDoNotEndTracks) {
  // Event 1001 on the real sensors with noise, found by the shipped
  // chain with and without its hit chi2 cut (extension_hit_chi2_ratio).
  // The steps' chi2_cut bounds only the rise of chi2/ndf, which a long
  // track meets with one hit at chi2 2000: where a particle crossed no
  // module the extension took a neighbour's hit, and its own further hits
  // then failed. Counted over all tracks: hits of the track's majority
  // particle (own) and the others (foreign, noise included). Measured: own
  // 69392 with the cut against 69333 without, foreign 3896 against 3999
  // (-2.6 %) with the chain of stop 54 (the extensions' scattering models,
  // the ratio 20); 69045 / 68996,
  // 4068 / 4181 (-2.7 %) with the chain of stop 53 (the TrackML score of the
  // five events 0.8946 / 0.8877 without the cut, 0.8954 / 0.8885 with it,
  // sigma_z 5.5 / 50 mm); 68873 / 68824, 3791 / 3904 (-2.9 %) with the
  // cuts of stop 52 (0.8917 / 0.8843 and 0.8925 / 0.8850); 68459 / 68331, 3462
  // / 3651 (-5.2 %) before them, with the shared-hit resolution after every
  // step (68135 /
  // 67990, 3468 / 3650 before it, with the PixelShort step; 67940 / 67795,
  // 3454 / 3635 before
  // it, since the seed cells' z0 along the arc; 67919 / 67768, 3450 / 3631
  // before that) and the pixel disks' inner ring of docs/validation.md item 13
  // (67858 / 67647, 3585 / 3825 before it) and the real files' noise rate
  // per sensor (before that, with
  // 17 % noise and an older chain: 66792 / 66591, 2650 / 2852, -7.1 %; after
  // the fit and selection the TrackML score of the five events rises 0.8448 ->
  // 0.8469). Guarded at +25 own and -2 % foreign (-3 % before stop 52).
  const Event event = test::simulateTrackml(test::event1001Particles(),
                                            test::SampleNoise::eReal);
  const Detector detector = loadDetector("trackml");
  const OwnForeign on = countOwnForeign(event, detector, [](FinderConfig& c) {
    EXPECT_GT(c.extensionHitChi2Ratio, 0.0);
  });
  const OwnForeign off = countOwnForeign(
      event, detector, [](FinderConfig& c) { c.extensionHitChi2Ratio = 0.0; });
  std::printf(
      "[ trackml 1001, %zu hits ] own hits on tracks %zu with the hit chi2 "
      "cut, %zu without; foreign %zu with, %zu without\n",
      event.hits.size(), on.own, off.own, on.foreign, off.foreign);
  EXPECT_GE(on.own, off.own + 25);
  EXPECT_LE(static_cast<double>(on.foreign), 0.98 * off.foreign);
}

TEST(ExtensionRanking, SzFilterKeepsLowMomentumTracksOnTheirOwnHits) {
  // Event 1001 on the real sensors with noise, found by the shipped chain
  // with and without extension_sz_filter: candidates ranked in z against
  // the (s, z) filter of the track's hits (each crossed layer's
  // scattering) or against the straight line through all of them, whose
  // slope, the mean over the track, misses a low-momentum track's hit
  // 200 mm further by 10-20 mm. Counted as in
  // HitsFarBeyondTheFitQualityDoNotEndTracks. Measured: own 69392 with the
  // filter against 69003 without, foreign 3896 against 4150 (-6.1 %; the
  // shipped chain, with extension_uv_scattering; the filter alone, with
  // the hit chi2 ratio 30 and skip chi2 300 of before: 69331 / 69091, 3957
  // / 4104); the TrackML score of the five events 0.8960 / 0.8890 ->
  // 0.8988 / 0.8913 (sigma_z 5.5 / 50 mm). Guarded at +120 own and -1.5 %
  // foreign.
  const auto [on, off] = ownForeignWithAndWithout(
      "the (s, z) filter", &FinderConfig::extensionSzFilter);
  EXPECT_GE(on.own, off.own + 120);
  EXPECT_LE(static_cast<double>(on.foreign), 0.985 * off.foreign);
}

TEST(ExtensionRanking, UvScatteringOfEveryLayerKeepsTracksOnTheirOwnHits) {
  // As SzFilterKeepsLowMomentumTracksOnTheirOwnHits, for the transverse
  // part of the ranking: with extension_uv_scattering the residual to the
  // track's conformal fit carries the scattering of every layer the track
  // crossed (HelixPredictionError), not only the last one's. Measured: own
  // 69392 with it against 69337 without, foreign 3896 against 3917; the
  // TrackML score of the five events 0.8990 / 0.8918 -> 0.8999 / 0.8928
  // (sigma_z 5.5 / 50 mm). On the chain of stop 55 (PixelStrip from 8
  // hits, build clones compared as built): own 69524 against 69491,
  // foreign 3747 against 3746. Guarded at +25 own and foreign hits within
  // 0.5 % of those without it (one hit either way is chance).
  const auto [on, off] =
      ownForeignWithAndWithout("every layer's scattering in (u, v)",
                               &FinderConfig::extensionUvScattering);
  EXPECT_GE(on.own, off.own + 25);
  EXPECT_LE(double(on.foreign), 1.005 * double(off.foreign));
}

}  // namespace
}  // namespace conftrack

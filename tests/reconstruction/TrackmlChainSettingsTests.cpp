/// @file TrackmlChainSettingsTests.cpp
/// The shipped TrackML chain's settings (chains/trackml.toml: its steps,
/// their keys and the selection) and the chain keys added for it, their
/// defaults and their validation.

#include "conftrack/core/Error.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ChainText.hpp"

namespace conftrack {
namespace {

TEST(TrackmlChain, ShippedChainSettings) {
  const Detector detector = loadDetector("trackml");
  const FinderConfig c = readChain(resolveChainPath("trackml"), detector);
  ASSERT_EQ(c.steps.size(), 11u);
  // A step by name; a missing one fails the test (and reads as a default
  // step instead of past the end).
  static const FindingStep kMissing;
  auto step = [&](const std::string& name) -> const FindingStep& {
    auto it =
        std::find_if(c.steps.begin(), c.steps.end(),
                     [&](const FindingStep& s) { return s.name == name; });
    if (it == c.steps.end()) {
      ADD_FAILURE() << "no step " << name;
      return kMissing;
    }
    return *it;
  };
  EXPECT_TRUE(c.overlapHits);
  // Extensions without the scattering allowance, the inward completion
  // with it (two keys).
  EXPECT_FALSE(c.scatteringAllowance);
  EXPECT_TRUE(c.inwardScatteringAllowance);
  const FinderConfig off =
      parseChain("[finder]\ninward_scattering_allowance = false\n" +
                     minimalStep("PixelBarrel"),
                 "chain.toml", detector);
  EXPECT_FALSE(off.inwardScatteringAllowance);
  EXPECT_TRUE(off.scatteringAllowance);
  // The extensions' hit chi2 cut, relative to the track's chi2/ndf (off
  // unless a chain sets it).
  EXPECT_DOUBLE_EQ(c.extensionHitChi2Ratio, 20.0);
  EXPECT_DOUBLE_EQ(c.extensionHitChi2Floor, 100.0);
  EXPECT_DOUBLE_EQ(off.extensionHitChi2Ratio, 0.0);
  // The displaced step last: real-space helices seeded in the pixels, cut
  // against random helices through noise (d0, pT, no missed layer).
  const FindingStep& helix = step("Helix");
  EXPECT_TRUE(helix.helix && !helix.build && !helix.extend);
  EXPECT_EQ(helix.seedCollections.size(), 2u);
  EXPECT_EQ(helix.collections.size(), 6u);
  EXPECT_DOUBLE_EQ(helix.maxD0, 200.0);
  EXPECT_DOUBLE_EQ(helix.minPt, 0.15);
  EXPECT_DOUBLE_EQ(helix.chi2Cut, 8.0);  // 6 before stop 52's re-scan
  EXPECT_DOUBLE_EQ(helix.maxSeedLength, 150.0);
  EXPECT_DOUBLE_EQ(helix.maxSeedGap, 200.0);  // the outer pixel disks' gaps
  EXPECT_EQ(helix.maxMissedLayers, 0u);
  EXPECT_EQ(helix.continueMissedLayers, 1u);
  EXPECT_DOUBLE_EQ(helix.continueChi2Cut, 18.0);
  EXPECT_EQ(helix.firstPassMinHits, 8u);
  // Seed triplets kinked in (s, z) by at most 1 mrad beyond 3 sigma of
  // scattering and resolution: a quarter fewer triplets to follow than
  // with 5 mrad, at the same score (stop 47).
  EXPECT_DOUBLE_EQ(helix.maxCellAngleRZ, 0.001);
  // The files' particles end after half a turn.
  EXPECT_DOUBLE_EQ(c.maxTrackTurns, 0.5);
  // Every conformal track followed outwards once more at the end, with
  // loosened cuts (algorithm.md 3.23).
  EXPECT_TRUE(c.finalExtension);
  EXPECT_DOUBLE_EQ(c.finalExtensionAngleFactor, 3.0);
  EXPECT_DOUBLE_EQ(c.finalExtensionPhiWindow, 0.06);
  // ... so no track is a further half-turn of another.
  EXPECT_TRUE(c.trackMerging);
  EXPECT_FALSE(c.mergeDropTurns);
  EXPECT_EQ(c.finalMinUniqueHits, 6u);
  EXPECT_TRUE(c.finalTrimSharedHits);
  EXPECT_EQ(helix.minHits, 6u);
  // ... and the displaced tracks beyond the pixels, seeded in the
  // short-strip barrel with a tighter chi2 (strip z is coarse) and
  // followed through all strips.
  const FindingStep& strips = step("HelixStrips");
  EXPECT_TRUE(strips.helix);
  EXPECT_EQ(strips.seedCollections,
            std::vector<std::uint16_t>{
                *detector.findSubdetector("ShortStripBarrel")});
  EXPECT_EQ(strips.collections.size(), 4u);
  EXPECT_EQ(strips.minHits, 5u);  // 5-hit tracks: the short-track rule
  EXPECT_DOUBLE_EQ(strips.chi2Cut, helix.chi2Cut);
  EXPECT_DOUBLE_EQ(strips.minPt, 0.15);
  EXPECT_EQ(strips.continueMissedLayers, 1u);
  EXPECT_DOUBLE_EQ(strips.continueChi2Cut, 18.0);
  EXPECT_DOUBLE_EQ(strips.maxCellAngleRZ, helix.maxCellAngleRZ);
  // The selection judges the strip helix step's 5-hit tracks.
  const Reconstruction::Config reconstruction =
      readReconstructionConfig(resolveChainPath("trackml"), detector);
  const TrackSelector::Config& selection = reconstruction.selector;
  // Hits of no track and outliers given to the track whose end they
  // continue, with the class's windows and cuts (docs/algorithm.md 10.2).
  EXPECT_TRUE(reconstruction.reassigner.enabled);
  EXPECT_TRUE(reconstruction.reassigner.freeHits);
  EXPECT_DOUBLE_EQ(reconstruction.reassigner.maxTransverse, 5.0);
  EXPECT_DOUBLE_EQ(reconstruction.reassigner.maxLongitudinal, 10.0);
  EXPECT_DOUBLE_EQ(reconstruction.reassigner.maxPredictedChi2, 12.0);
  EXPECT_DOUBLE_EQ(reconstruction.reassigner.maxChi2Increase, 12.0);
  EXPECT_EQ(reconstruction.reassigner.refitsPerHit, 1);
  EXPECT_EQ(selection.minUniqueHits, 6u);
  EXPECT_EQ(selection.shortTrackHits, 6u);
  EXPECT_DOUBLE_EQ(selection.shortTrackMaxChi2Ndf, 2.0);
  EXPECT_EQ(selection.shortTrackSteps, std::vector<std::uint16_t>{9});
  // The low-momentum build and its extension.
  EXPECT_TRUE(step("LowPt").build && step("LowPt").minHits == 6 &&
              step("LowPt").chi2Cut == 3000.0);
  // Its cells bend by at most 0.03 rad in (u, v), re-scanned at stop 55
  // (0.04 before: 18 % more cells, a 0.0005 lower score at sigma_z 50 mm).
  EXPECT_DOUBLE_EQ(step("LowPt").maxCellAngle, 0.03);
  EXPECT_TRUE(step("Strips3").extend && !step("Strips3").build);
  // The prompt builds seed cells bending by at most 0.04 rad (about 0.3
  // GeV from L0 to L1) and leave the slower tracks to LowPt, whose cells
  // may bend by 0.1 rad (0.13 GeV): cheaper and fewer fakes than 0.1 and
  // 0.15 (stop 47).
  EXPECT_DOUBLE_EQ(step("PixelPrompt").maxSeedDeltaPhi, 0.04);
  EXPECT_DOUBLE_EQ(step("PixelPrompt2").maxSeedDeltaPhi, 0.04);
  EXPECT_DOUBLE_EQ(step("LowPt").maxSeedDeltaPhi, 0.10);
  EXPECT_GT(step("LowPt").maxSeedDeltaPhi, step("PixelPrompt").maxSeedDeltaPhi);
  EXPECT_TRUE(step("PixelPrompt").build &&
              step("PixelPrompt").straightLineFit &&
              step("PixelPrompt").radialSearch);
  // Seeds about the vertices of the event, not about a fixed beam spot.
  ASSERT_TRUE(c.vertexPrepass.has_value());
  EXPECT_EQ(
      c.vertexPrepass->collections,
      std::vector<std::uint16_t>{*detector.findSubdetector("PixelBarrel")});
  EXPECT_DOUBLE_EQ(step("PixelPrompt").vertexWindow, 1.0);
  // PixelPrompt again, about the vertices of the hits it left free.
  EXPECT_FALSE(step("PixelPrompt").vertexPrepassFreeHits);
  EXPECT_TRUE(step("PixelPrompt2").vertexPrepassFreeHits);
  EXPECT_TRUE(step("PixelStrip").vertexPrepassFreeHits);
  EXPECT_FALSE(step("LowPt").vertexPrepassFreeHits);
  // Four-hit pixel tracks from the leftovers, with looser cell cuts.
  EXPECT_EQ(step("PixelLoose").minHits, 4u);
  EXPECT_GT(step("PixelLoose").maxCellAngleRZ,
            step("PixelPrompt").maxCellAngleRZ);
  EXPECT_DOUBLE_EQ(step("PixelPrompt2").vertexWindow, 1.0);
  EXPECT_DOUBLE_EQ(step("PixelPrompt2").chi2Cut, step("PixelPrompt").chi2Cut);
  // Last, three-hit prompt pixel tracks, kept below five hits only with an
  // overlap pair (algorithm.md 3.20); the other steps have no such rule.
  EXPECT_EQ(c.steps.back().name, "PixelShort");
  EXPECT_TRUE(step("PixelShort").build);
  EXPECT_EQ(step("PixelShort").minHits, 3u);
  EXPECT_EQ(step("PixelShort").overlapPairBelowHits, 5u);
  // Cuts re-scanned at stop 52 (their effect:
  // TrackmlChain.CutsRescannedAtStop52GainAtTheHlLhcLength): PixelShort
  // looser, PixelStrip tighter (its fakes at sigma_z 50 mm).
  EXPECT_DOUBLE_EQ(step("PixelShort").chi2Cut, 3000.0);
  EXPECT_DOUBLE_EQ(step("PixelShort").maxCellAngle, 0.03);
  EXPECT_DOUBLE_EQ(step("PixelShort").maxCellAngleRZ, 0.015);
  EXPECT_DOUBLE_EQ(step("PixelStrip").chi2Cut, 1500.0);
  // PixelStrip keeps tracks of 8 or more hits and leaves the shorter ones
  // to LowPt (stop 55;
  // TrackmlChain.PixelStripLeavesItsShortTracksToLowPtAtTheHlLhcLength).
  EXPECT_EQ(step("PixelStrip").minHits, 8u);
  EXPECT_GT(step("PixelStrip").minHits, step("LowPt").minHits);
  EXPECT_DOUBLE_EQ(step("PixelShort").vertexWindow, 1.0);
  // Strip seeds reach twice the distance of layers up to 300 mm apart
  // (TrackmlChain.StripSeedsBetweenWiderLayersReachTheSamePolarAngles);
  // the pixel helix step keeps one length.
  EXPECT_DOUBLE_EQ(step("HelixStrips").maxSeedLength, 200.0);
  EXPECT_DOUBLE_EQ(step("HelixStrips").seedLengthPerGap, 2.0);
  EXPECT_DOUBLE_EQ(step("HelixStrips").maxSeedLengthPerGap, 300.0);
  // The extensions rank z against the tracks' (s, z) filter
  // (ExtensionRanking.SzFilterKeepsLowMomentumTracksOnTheirOwnHits).
  EXPECT_TRUE(c.extensionSzFilter);
  // ... and in (u, v) with every crossed layer's scattering
  // (ExtensionRanking.UvScatteringOfEveryLayerKeepsTracksOnTheirOwnHits).
  EXPECT_TRUE(c.extensionUvScattering);
  // Its 6-hit candidates claim in the first pass (Helix: 8 hits).
  EXPECT_EQ(step("HelixStrips").firstPassMinHits, 6u);
  // It follows its tracks past the turn, taking incoming legs of two hits
  // or more (TrackmlChain.StripTracksTakeTheirIncomingLegsHits); no other
  // step follows inwards.
  for (const FindingStep& s : c.steps) {
    EXPECT_EQ(s.pastTurnMinHits, s.name == "HelixStrips" ? 2u : 0u) << s.name;
  }
  EXPECT_DOUBLE_EQ(step("Helix").seedLengthPerGap, 0.0);
  for (const FindingStep& s : c.steps) {
    EXPECT_TRUE(s.name == "PixelShort" || s.overlapPairBelowHits == 0)
        << s.name;
  }
  EXPECT_DOUBLE_EQ(step("PixelStrip").vertexWindow, 4.0);
  for (const FindingStep& s : c.steps) {
    EXPECT_EQ(s.maxSeedZ0, std::numeric_limits<double>::infinity());
  }
  EXPECT_TRUE(step("PixelPrompt").seedCollections.empty());
  EXPECT_TRUE(step("Strips1").extend && !step("Strips1").build);
  EXPECT_DOUBLE_EQ(step("Strips1").chi2PtScale, 1.0);
  EXPECT_DOUBLE_EQ(step("Strips1").chi2CutAt(2.0), 300.0);
  EXPECT_DOUBLE_EQ(step("Strips1").chi2CutAt(0.5), 1200.0);
  EXPECT_EQ(step("PixelStrip").collections.size(), 4u);
  ASSERT_EQ(step("PixelStrip").seedCollections.size(), 2u);
  EXPECT_EQ(step("PixelStrip").seedCollections[0],
            *detector.findSubdetector("PixelBarrel"));
  // The builds' path limit of 50 is a step setting; the finder's guard
  // keeps its default.
  EXPECT_EQ(step("PixelPrompt").maxPaths, 50u);
  EXPECT_EQ(step("PixelStrip").maxPaths, 50u);
  EXPECT_EQ(c.maxPathsPerSeed, FinderConfig{}.maxPathsPerSeed);

  // The step additions default to upstream's behaviour; the CLICdet chain
  // uses the seed caps, the vertex windows and tracker seeds in the
  // displaced steps.
  const Detector clic = loadDetector("clicdet");
  const FinderConfig minimal =
      parseChain(minimalStep("VertexBarrel"), "minimal.toml", clic);
  const FindingStep& d = minimal.steps.at(0);
  EXPECT_EQ(d.maxSeedZ0, std::numeric_limits<double>::infinity());
  EXPECT_EQ(d.vertexWindow, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(minimal.vertexPrepass.has_value());
  EXPECT_EQ(d.maxSeedLength, std::numeric_limits<double>::infinity());
  EXPECT_EQ(d.maxSeedCells, 0u);
  EXPECT_TRUE(d.seedCollections.empty());
  EXPECT_EQ(d.chi2PtScale, 0.0);
  EXPECT_EQ(d.chi2CutAt(0.1), d.chi2Cut);
  EXPECT_TRUE(minimal.finalHoleFilling && minimal.scatteringAllowance);
  const FinderConfig clicChain = readChain(resolveChainPath("clicdet"), clic);
  // The vertex builds seed about the event's vertices (algorithm.md 3.16),
  // found with thresholds for the overlay's small interactions.
  ASSERT_TRUE(clicChain.vertexPrepass.has_value());
  EXPECT_EQ(clicChain.vertexPrepass->minExcess, 2.0);
  EXPECT_EQ(clicChain.vertexPrepass->minSignificance, 2.0);
  EXPECT_EQ(clicChain.vertexPrepass->collections.size(), 1u);
  for (const FindingStep& s : clicChain.steps) {
    const bool displaced = s.name.starts_with("Displaced");
    // LowPtHelix seeds in the vertex barrel and endcap, 80 mm long;
    // ForwardPrompt builds prompt tracks in the tracker disks, its cells
    // as long as the displaced steps'.
    const bool lowPtHelix = s.name == "LowPtHelix";
    const bool forward = s.name == "ForwardPrompt";
    EXPECT_EQ(s.seedCollections.size(),
              lowPtHelix || (displaced && !s.helix) ? 2u : (s.helix ? 4u : 0u))
        << s.name;
    EXPECT_EQ(s.chi2PtScale, 0.0);
    const bool vertexBuild = s.build && !displaced;
    EXPECT_EQ(s.maxSeedZ0,
              vertexBuild ? 200.0 : std::numeric_limits<double>::infinity())
        << s.name;
    EXPECT_EQ(s.maxSeedCells, s.build && s.radialSearch ? 30u : 0u) << s.name;
    EXPECT_EQ(s.vertexWindow, vertexBuild
                                  ? (forward ? 5.0 : 1.0)
                                  : std::numeric_limits<double>::infinity())
        << s.name;
    EXPECT_FALSE(s.vertexPrepassFreeHits) << s.name;
    EXPECT_EQ(s.maxSeedLength,
              lowPtHelix
                  ? 80.0
                  : (s.helix ? 400.0
                             : (displaced || forward
                                    ? 800.0
                                    : std::numeric_limits<double>::infinity())))
        << s.name;
  }
}

/// The error of a one-step chain with `stepKeys` added to its step and
/// `finderTable` before it, empty if it parses.
std::string chainError(const std::string& stepKeys,
                       const std::string& finderTable = "") {
  static const Detector det = loadDetector("trackml");
  const std::string text = finderTable + minimalStep("PixelBarrel") + stepKeys;
  try {
    parseChain(text, "chain.toml", det);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TrackmlChain, NewKeysAreValidated) {
  EXPECT_EQ(chainError("max_seed_z0_mm = 20.0\n"
                       "seed_collections = [\"PixelBarrel\"]\n"
                       "chi2_cut_pt_scale_GeV = 1.0\n"),
            "");
  EXPECT_NE(chainError("max_seed_z0_mm = 0.0\n"), "");
  EXPECT_NE(
      chainError("max_seed_length_mm = -5.0\n").find("max_seed_length_mm"),
      std::string::npos);
  EXPECT_NE(chainError("max_seed_cells = -1\n").find("max_seed_cells"),
            std::string::npos);
  EXPECT_NE(chainError("chi2_cut_pt_scale_GeV = -1.0\n"), "");
  EXPECT_NE(chainError("seed_collections = []\n").find("must not be empty"),
            std::string::npos);
  EXPECT_NE(chainError("seed_collections = [\"Pixel\"]\n")
                .find("no subdetector 'Pixel'"),
            std::string::npos);
  EXPECT_NE(chainError("seed_collections = [\"PixelEndcap\"]\n")
                .find("not among the step's collections"),
            std::string::npos);
  // The overlap-pair rule: above min_hits (4 here), and only with the
  // overlap search that adds the pairs.
  EXPECT_EQ(chainError("overlap_pair_below_hits = 5\n"), "");
  EXPECT_EQ(chainError("overlap_pair_below_hits = 0\n"), "");
  EXPECT_NE(chainError("overlap_pair_below_hits = 4\n").find("above min_hits"),
            std::string::npos);
  EXPECT_NE(chainError("overlap_pair_below_hits = -1\n")
                .find("overlap_pair_below_hits"),
            std::string::npos);
  EXPECT_NE(chainError("overlap_pair_below_hits = 5\n",
                       "[finder]\noverlap_hits = false\n")
                .find("needs the overlap search"),
            std::string::npos);
  // The extensions' (s, z) filter: a boolean of [finder], off by default.
  EXPECT_EQ(chainError("", "[finder]\nextension_sz_filter = true\n"), "");
  EXPECT_NE(chainError("", "[finder]\nextension_sz_filter = 2\n")
                .find("extension_sz_filter"),
            std::string::npos);
  const FinderConfig defaults = parseChain(
      minimalStep("PixelBarrel"), "chain.toml", loadDetector("trackml"));
  EXPECT_FALSE(defaults.extensionSzFilter);
  EXPECT_FALSE(defaults.extensionUvScattering);
  EXPECT_NE(chainError("", "[finder]\nextension_uv_scattering = \"yes\"\n")
                .find("extension_uv_scattering"),
            std::string::npos);
}

}  // namespace
}  // namespace conftrack

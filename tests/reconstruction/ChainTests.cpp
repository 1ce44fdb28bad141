#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/FindingChain.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "ChainText.hpp"
#include "InputErrorOf.hpp"

namespace conftrack {
namespace {

const std::string kStep = minimalStep("VertexBarrel", "0.005");

std::string errorOf(const std::string& text) {
  static const Detector det = loadDetector("clicdet");
  return test::inputErrorOf([&] { parseChain(text, "chain.toml", det); });
}

std::string with(const std::string& from, const std::string& to) {
  std::string s = kStep;
  auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos);
  return s.replace(pos, from.size(), to);
}

TEST(Chain, ShippedChainsMatchTheReference) {
  Detector clic = loadDetector("clicdet");
  FinderConfig c = readChain(resolveChainPath("clicdet"), clic);
  ASSERT_EQ(c.steps.size(), 10u);
  // upstream.md 13.1 (CLICPerformance at HEAD).
  EXPECT_EQ(c.steps[0].name, "VXDBarrel");
  EXPECT_DOUBLE_EQ(c.steps[0].maxCellAngle, 0.005);
  EXPECT_TRUE(c.steps[0].build && !c.steps[0].radialSearch);
  EXPECT_TRUE(c.steps[1].extend && !c.steps[1].build);
  EXPECT_DOUBLE_EQ(c.steps[1].highPtCut, 0.0);
  EXPECT_TRUE(c.steps[3].collections.empty() && c.steps[3].sort);
  EXPECT_DOUBLE_EQ(c.steps[3].chi2Cut, 2000.0);
  EXPECT_EQ(c.steps[4].collections.size(), 4u);
  // conftrack's sixth step: prompt tracks of the tracker disks, seeded
  // about the event's vertices (chains/clicdet.toml gives the
  // measurements).
  EXPECT_EQ(c.steps[5].name, "ForwardPrompt");
  EXPECT_TRUE(c.steps[5].build && c.steps[5].radialSearch);
  EXPECT_EQ(c.steps[5].collections.size(), 2u);
  EXPECT_DOUBLE_EQ(c.steps[5].vertexWindow, 5.0);
  EXPECT_EQ(c.steps[5].direction, SearchDirection::eInsideOut);
  EXPECT_EQ(c.steps[6].name, "Displaced");
  EXPECT_EQ(c.steps[6].minHits, 5u);
  EXPECT_DOUBLE_EQ(c.steps[6].maxDistance, 0.015);
  EXPECT_EQ(c.steps[6].direction, SearchDirection::eOutsideIn);
  // Its seeds in the outer tracker only, since ForwardPrompt.
  EXPECT_EQ(c.steps[6].seedCollections.size(), 2u);
  // conftrack applies the displaced step's chi2 cut to both fits
  // (docs/algorithm.md §3.6).
  EXPECT_TRUE(!c.steps[6].onlySzChi2Cut && !c.steps[6].straightLineFit);
  // conftrack's four-hit displaced tracks (§3.7).
  EXPECT_EQ(c.steps[7].name, "Displaced4");
  EXPECT_EQ(c.steps[7].minHits, 4u);
  EXPECT_EQ(c.steps[7].direction, SearchDirection::eOutsideIn);
  // ... helix triplets for displaced tracks (§3.8).
  EXPECT_EQ(c.steps[8].name, "DisplacedHelix");
  EXPECT_TRUE(c.steps[8].helix && !c.steps[8].build && !c.steps[8].extend);
  EXPECT_EQ(c.steps[8].minHits, 4u);
  EXPECT_DOUBLE_EQ(c.steps[8].minPt, 0.5);
  EXPECT_DOUBLE_EQ(c.steps[8].maxSeedLength, 400.0);
  EXPECT_EQ(c.steps[8].maxMissedLayers, 0u);
  // ... and low-momentum helix triplets from the vertex detector.
  EXPECT_EQ(c.steps[9].name, "LowPtHelix");
  EXPECT_TRUE(c.steps[9].helix);
  EXPECT_DOUBLE_EQ(c.steps[9].minPt, 0.1);
  EXPECT_DOUBLE_EQ(c.steps[9].maxSeedLength, 80.0);
  EXPECT_EQ(c.steps[9].seedCollections.size(), 2u);
  EXPECT_DOUBLE_EQ(c.thetaRange, 0.05);

  Detector cld = loadDetector("cld");
  FinderConfig d = readChain(resolveChainPath("cld"), cld);
  // Ten steps: CLDConfig's six plus the CLICdet chain's ForwardPrompt,
  // Displaced4, DisplacedHelix and LowPtHelix (chains/cld.toml gives the
  // measurements; CldChainTests checks their effect).
  ASSERT_EQ(d.steps.size(), 10u);
  // upstream.md 13.2 (CLDConfig).
  EXPECT_DOUBLE_EQ(d.steps[0].maxDistance, 0.05);
  EXPECT_DOUBLE_EQ(d.steps[3].maxCellAngle, 0.1);
  EXPECT_DOUBLE_EQ(d.steps[4].highPtCut, 1.0);
  EXPECT_EQ(d.steps[5].name, "ForwardPrompt");
  EXPECT_DOUBLE_EQ(d.steps[5].vertexWindow, 5.0);
  EXPECT_DOUBLE_EQ(d.steps[6].maxDistance, 0.015);
  EXPECT_EQ(d.steps[6].direction, SearchDirection::eOutsideIn);
  EXPECT_EQ(d.steps[6].seedCollections.size(), 2u);
  // The CLICdet treatment, with CLD's layer spacing (outer-tracker barrel
  // layers 570 mm apart against CLICdet's 330 mm).
  EXPECT_DOUBLE_EQ(d.steps[6].maxSeedLength, 1000.0);
  EXPECT_EQ(d.steps[7].name, "Displaced4");
  EXPECT_EQ(d.steps[7].minHits, 4u);
  EXPECT_EQ(d.steps[7].direction, SearchDirection::eOutsideIn);
  EXPECT_EQ(d.steps[8].name, "DisplacedHelix");
  EXPECT_TRUE(d.steps[8].helix && !d.steps[8].build && !d.steps[8].extend);
  EXPECT_DOUBLE_EQ(d.steps[8].maxSeedLength, 700.0);
  EXPECT_EQ(d.steps[8].maxMissedLayers, 0u);
}

TEST(Chain, MinimalStepParses) { EXPECT_EQ(errorOf(kStep), "(accepted)"); }

TEST(Chain, UnknownKey) {
  std::string msg = errorOf(with("min_hits = 4", "min_hits = 4\nspeed = 3"));
  EXPECT_EQ(msg, "chain.toml:9: key 'step[0].speed': unknown key");
}

TEST(Chain, UnknownCollection) {
  std::string msg = errorOf(with("\"VertexBarrel\"", "\"Calorimeter\""));
  EXPECT_NE(msg.find("chain.toml:3: key 'step[0].collections': detector "
                     "'CLICdet' has no subdetector 'Calorimeter'"),
            std::string::npos)
      << msg;
}

TEST(Chain, NonsenseValues) {
  EXPECT_NE(errorOf(with("chi2_cut = 100.0", "chi2_cut = -1.0"))
                .find("chain.toml:7: key 'step[0].chi2_cut': value -1 out "
                      "of range"),
            std::string::npos);
  EXPECT_NE(errorOf(with("min_hits = 4", "min_hits = 2")).find("min_hits"),
            std::string::npos);
  EXPECT_NE(errorOf(with("max_distance = 0.02", "max_distance = 0.0"))
                .find("max_distance"),
            std::string::npos);
  EXPECT_NE(errorOf(with("max_cell_angle = 0.005", "max_cell_angle = nan"))
                .find("finite"),
            std::string::npos);
}

TEST(Chain, BadActionsAndFlags) {
  EXPECT_NE(errorOf(with("[\"build\"]", "[\"fly\"]")).find("unknown action"),
            std::string::npos);
  EXPECT_NE(errorOf(with("[\"build\"]", "[]")).find("actions"),
            std::string::npos);
  EXPECT_NE(errorOf(kStep + "direction = \"sideways\"\n").find("direction"),
            std::string::npos);
  EXPECT_NE(errorOf(kStep + "radial_search = 1\n").find("true or false"),
            std::string::npos);
}

TEST(Chain, MissingParameter) {
  std::string msg = errorOf(with("slope_z_range = 10.0\n", ""));
  EXPECT_NE(msg.find("'step[0].slope_z_range': missing"), std::string::npos)
      << msg;
}

TEST(Chain, FirstStepNeedsCollections) {
  std::string msg = errorOf(with("[\"VertexBarrel\"]", "[]"));
  EXPECT_NE(msg.find("first step"), std::string::npos) << msg;
}

TEST(Chain, DuplicateStepAndEmptyChain) {
  EXPECT_NE(errorOf(kStep + kStep).find("duplicate step name"),
            std::string::npos);
  EXPECT_NE(errorOf("[finder]\ntheta_range = 0.05\n").find("[[step]]"),
            std::string::npos);
  EXPECT_NE(errorOf("[finder]\nfoo = 1\n" + kStep).find("finder.foo"),
            std::string::npos);
}

TEST(Chain, MinHitsZeroAndUnknownKeysNameTheKey) {
  EXPECT_NE(errorOf(with("min_hits = 4", "min_hits = 0"))
                .find("chain.toml:8: key 'step[0].min_hits': value 0 out of "
                      "range [3, 100]"),
            std::string::npos);
  EXPECT_NE(errorOf(with("min_hits = 4", "min_hits = -1")).find("min_hits"),
            std::string::npos);
  EXPECT_NE(errorOf("[finder]\ntheta_range = -0.1\n" + kStep)
                .find("chain.toml:2: key 'finder.theta_range': value -0.1 out "
                      "of range (0, 3.14159]"),
            std::string::npos);
}

TEST(Chain, ValuesTakeTheUnitsOfTheirKeys) {
  const FinderConfig c =
      parseChain(kStep +
                     "max_seed_z0_mm = 200.0\nmax_seed_length_mm = 800\n"
                     "min_pt_GeV = 0.5\nmax_d0_mm = 50\n",
                 "chain.toml", loadDetector("clicdet"));
  const FindingStep& s = c.steps.at(0);
  EXPECT_DOUBLE_EQ(s.maxSeedZ0, 200.0 * units::mm);
  EXPECT_DOUBLE_EQ(s.maxSeedLength, 800.0 * units::mm);
  EXPECT_DOUBLE_EQ(s.minPt, 0.5 * units::GeV);
  EXPECT_DOUBLE_EQ(s.maxD0, 50.0 * units::mm);
  EXPECT_DOUBLE_EQ(s.maxCellAngle, 0.005 * units::rad);
  EXPECT_DOUBLE_EQ(s.maxDistance, 0.02 / units::mm);
  EXPECT_DOUBLE_EQ(s.highPtCut, 10.0 * units::GeV);
}

TEST(Chain, BeamSpotKeys) {
  const Detector det = loadDetector("clicdet");
  const FinderConfig axis = parseChain(kStep, "chain.toml", det);
  EXPECT_EQ(axis.beamSpotX, 0.0);
  EXPECT_EQ(axis.beamSpotY, 0.0);
  const FinderConfig off = parseChain(
      "[finder]\nbeam_spot_x_mm = 0.7\nbeam_spot_y_mm = -0.25\n" + kStep,
      "chain.toml", det);
  EXPECT_DOUBLE_EQ(off.beamSpotX, 0.7 * units::mm);
  EXPECT_DOUBLE_EQ(off.beamSpotY, -0.25 * units::mm);
  EXPECT_EQ(errorOf("[finder]\nbeam_spot_y_mm = 12\n" + kStep),
            "chain.toml:2: key 'finder.beam_spot_y_mm': value 12 out of "
            "range [-10, 10]");
  EXPECT_NE(errorOf("[finder]\nbeam_spot_x_mm = nan\n" + kStep)
                .find("chain.toml:2: key 'finder.beam_spot_x_mm'"),
            std::string::npos);
}

/// A valid chain built in code: one build step over the vertex barrel.
FinderConfig codeChain(const Detector& det) {
  FinderConfig c;
  FindingStep s;
  s.name = "S0";
  s.collections = {det.findSubdetector("VertexBarrel").value()};
  s.build = true;
  c.steps.push_back(s);
  return c;
}

/// The message of the std::invalid_argument of the finder's constructor.
std::string constructorError(const Detector& det, const FinderConfig& chain) {
  try {
    ConformalTrackFinder finder(det, {chain});
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Chain, ChainBuiltInCodeIsValidatedLikeAFile) {
  const Detector det = loadDetector("clicdet");
  EXPECT_EQ(constructorError(det, codeChain(det)), "");
  // An empty first step would reuse a pool that does not exist.
  FinderConfig c = codeChain(det);
  c.steps[0].collections.clear();
  EXPECT_NE(constructorError(det, c).find(
                "key 'step[0].collections': the first step must name its "
                "collections"),
            std::string::npos);
  c = codeChain(det);
  c.steps[0].minHits = 0;
  EXPECT_NE(constructorError(det, c).find("key 'step[0].min_hits': value 0"),
            std::string::npos);
  c = codeChain(det);
  c.steps[0].chi2Cut = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(constructorError(det, c).find("chi2_cut': must not be NaN"),
            std::string::npos);
  c = codeChain(det);
  c.steps[0].collections.push_back(99);
  EXPECT_NE(constructorError(det, c).find("subdetector index 99"),
            std::string::npos);
  c = codeChain(det);
  c.steps[0].build = false;
  EXPECT_NE(constructorError(det, c).find("'step[0].actions'"),
            std::string::npos);
  c = codeChain(det);
  c.steps.push_back(c.steps[0]);
  EXPECT_NE(constructorError(det, c).find("duplicate step name 'S0'"),
            std::string::npos);
  c = codeChain(det);
  c.steps[0].helix = true;  // needs max_seed_length_mm and min_pt_GeV
  EXPECT_NE(constructorError(det, c).find("max_seed_length_mm"),
            std::string::npos);
  c = codeChain(det);
  c.steps.clear();
  EXPECT_NE(constructorError(det, c).find("key 'step': missing"),
            std::string::npos);
  c = codeChain(det);
  c.extensionLookahead = -1;
  EXPECT_NE(constructorError(det, c).find("key 'finder.extension_lookahead'"),
            std::string::npos);
}

}  // namespace
}  // namespace conftrack

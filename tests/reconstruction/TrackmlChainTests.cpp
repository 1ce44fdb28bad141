/// @file TrackmlChainTests.cpp
/// The shipped TrackML chain (chains/trackml.toml) on one TrackML-like
/// event with truth: the particles of Kaggle event 1001 through the fast
/// simulation of the TrackML detector with the real files' noise rate per
/// sensor and pT > 0.15 GeV, as
/// `conftrack simulate-trackml` makes it, then finding, fit and selection
/// as `conftrack reconstruct --detector trackml`, scored with the TrackML
/// score (truth used only to score), at the Kaggle events' length of the
/// luminous region and at HL-LHC's. Also the hit-pool searches added for
/// it: the (z, R)-restricted searches against the unrestricted ones on
/// random hits of the TrackML layers (they must return the same hits after
/// the finder's exact cuts). The chain's settings and keys:
/// TrackmlChainSettingsTests.cpp.

#include "conftrack/core/Error.hpp"
#include "conftrack/evaluation/TrackmlScore.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"
#include "conftrack/geometry/TrackmlModuleLayout.hpp"
#include "conftrack/reconstruction/Reconstruction.hpp"
#include "conftrack/reconstruction/finding/ConformalHits.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/reconstruction/finding/HitPool.hpp"
#include "conftrack/reconstruction/finding/StepStats.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"
#include "conftrack/simulation/TrackmlEvents.hpp"
#include "conftrack/simulation/generators/HepMCText.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "ChainText.hpp"
#include "TrackmlSample.hpp"

namespace conftrack {
namespace {

namespace fs = std::filesystem;
using test::event1001Particles;
using test::kTrackmlData;
using test::simulateTrackml;

/// Random hits uniform over the surfaces of all TrackML layers.
std::vector<Hit> randomHits(const Detector& det, std::size_t perLayer) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Hit> hits;
  for (const SensitiveLayer& l : det.layers()) {
    for (std::size_t k = 0; k < perLayer; ++k) {
      const double phi = std::numbers::pi * (2.0 * u(rng) - 1.0);
      Hit h;
      h.id = hits.size() + 1;
      if (l.isDisk()) {
        const double r = std::sqrt(
            l.rMin * l.rMin + (l.rMax * l.rMax - l.rMin * l.rMin) * u(rng));
        h.position = Vector3(r * std::cos(phi), r * std::sin(phi), l.z());
      } else {
        const double z = l.zMin + (l.zMax - l.zMin) * u(rng);
        h.position = Vector3(l.r * std::cos(phi), l.r * std::sin(phi), z);
      }
      h.detId = l.id;
      h.detId.module = l.moduleAt(h.position);
      l.localAxes(h.position, h.uAxis, h.vAxis);
      h.sigmaU = l.sigmaU;
      h.sigmaV = l.sigmaV;
      hits.push_back(h);
    }
  }
  return hits;
}

/// The finder's exact (z, R) angle cut of a cell from the cone's apex.
bool insideRz(const ConformalHits& ch, ConfIndex h, const HitPool::RzCone& c) {
  const double dz = ch.z[h] - c.z;
  const double dr = ch.radius[h] - c.r;
  const double l = std::hypot(dz, dr);
  if (!(l > 0.0)) {
    return true;
  }
  const double ax = dz / l;
  const double ay = dr / l;
  return std::atan2(std::abs(ax * c.dr - ay * c.dz), ax * c.dz + ay * c.dr) <=
         c.halfAngle;
}

TEST(TrackmlChain, RzRestrictedSearchesFindTheSameHits) {
  const Detector det = loadDetector("trackml");
  const std::vector<Hit> hits = randomHits(det, 400);
  const ConformalHits ch = makeConformalHits(hits, det);
  std::vector<ConfIndex> all(ch.size());
  for (ConfIndex i = 0; i < ch.size(); ++i) {
    all[i] = i;
  }
  const HitPool pool(ch, all);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t nonEmpty = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const auto a = static_cast<ConfIndex>(u(rng) * (ch.size() - 1));
    // A cone around a random direction from hit a, half-angle 1 mrad to
    // 0.5 rad (the (z, R) cuts of the chains).
    const double psi = std::numbers::pi * (2.0 * u(rng) - 1.0);
    const double half = std::exp(std::log(1e-3) * u(rng) + std::log(0.5));
    const HitPool::RzCone rz{ch.z[a], ch.radius[a], std::cos(psi),
                             std::sin(psi), half * (0.002 + u(rng))};
    auto keep = [&](ConfIndex h) { return h != a && insideRz(ch, h, rz); };
    const double dphiCut = 0.05 + 0.3 * u(rng);
    auto keepPhi = [&](ConfIndex h) {
      double d = std::abs(ch.phi[h] - ch.phi[a]);
      return keep(h) && std::min(d, 2.0 * std::numbers::pi - d) <= dphiCut;
    };

    // Seeding: the disc in a window, with and without the cone.
    std::vector<ConfIndex> withRz;
    std::vector<ConfIndex> reference;
    pool.discWindow(ch.u[a], ch.v[a], 0.01, ch.phi[a], dphiCut, withRz, keepPhi,
                    &rz);
    pool.disc(ch.u[a], ch.v[a], 0.01, reference);
    std::erase_if(reference, [&](ConfIndex h) { return !keepPhi(h); });
    EXPECT_EQ(withRz, reference) << "discWindow, trial " << trial;

    // Cell growth: the (u, v) cone, with and without the (z, R) cone.
    const double t = std::numbers::pi * (2.0 * u(rng) - 1.0);
    const double du = std::cos(t);
    const double dv = std::sin(t);
    const double d = 0.005 + 0.015 * u(rng);
    const double cu = ch.u[a] + 0.5 * d * du;
    const double cv = ch.v[a] + 0.5 * d * dv;
    std::vector<ConfIndex> coneRz;
    std::vector<ConfIndex> cone;
    pool.cone(ch.u[a], ch.v[a], du, dv, 0.05, cu, cv, 0.625 * d, coneRz, keep,
              &rz);
    pool.cone(ch.u[a], ch.v[a], du, dv, 0.05, cu, cv, 0.625 * d, cone, keep);
    EXPECT_EQ(coneRz, cone) << "cone, trial " << trial;
    // ... and both against brute force: every hit inside the disc and the
    // (u, v) cone, short of the origin (cone() ends the cone at 0.995 of
    // the distance to it, measured along the edges), nearest to the disc
    // centre first.
    const double towardsOrigin = -(ch.u[a] * du + ch.v[a] * dv);
    const double maxAlong = towardsOrigin > 0.0
                                ? 0.995 * towardsOrigin * std::cos(0.05)
                                : std::numeric_limits<double>::infinity();
    std::vector<std::pair<double, ConfIndex>> brute;
    for (ConfIndex h = 0; h < ch.size(); ++h) {
      const double au = ch.u[h] - ch.u[a];
      const double av = ch.v[h] - ch.v[a];
      const double along = au * du + av * dv;
      const double eu = ch.u[h] - cu;
      const double ev = ch.v[h] - cv;
      const double dist2 = eu * eu + ev * ev;
      if (keep(h) && along > 0.0 && along <= maxAlong &&
          along >= std::cos(0.05) * std::sqrt(au * au + av * av) &&
          dist2 <= 0.625 * d * 0.625 * d) {
        brute.emplace_back(dist2, h);
      }
    }
    std::sort(brute.begin(), brute.end());
    std::vector<ConfIndex> bruteIds;
    for (const auto& b : brute) {
      bruteIds.push_back(b.second);
    }
    EXPECT_EQ(cone, bruteIds) << "cone vs brute force, trial " << trial;

    // Extension: one layer's azimuth window.
    for (std::uint32_t layer : pool.layers()) {
      std::vector<ConfIndex> windowRz;
      std::vector<ConfIndex> window;
      pool.layerWindow(layer, ch.phi[a], 0.2, windowRz, &rz);
      pool.layerWindow(layer, ch.phi[a], 0.2, window);
      for (auto* v : {&windowRz, &window}) {
        std::erase_if(*v, [&](ConfIndex h) { return !keep(h); });
        std::sort(v->begin(), v->end());
      }
      EXPECT_EQ(windowRz, window) << "layerWindow, trial " << trial;
    }
    nonEmpty += reference.empty() ? 0 : 1;
  }
  EXPECT_GT(nonEmpty, 30u);
}

/// Event 1001 simulated as `conftrack simulate-trackml` (defaults: the
/// real files' noise rate per sensor, pT > 0.15 GeV, seed 1, the real sensors
/// of detectors.csv; with `region`, --luminous-region), reconstructed as
/// `conftrack reconstruct
/// --detector trackml` (the shipped detector file and its chain, changed
/// by `adjust` if given) and scored. `truncation`, if given, receives
/// describeTruncation() of the finding steps: empty if no combinatorics
/// guard bit.
TrackmlScore scoreEvent1001(
    const char* label, std::optional<LuminousRegion::Config> region,
    const std::function<void(Reconstruction::Config&)>& adjust = {},
    std::string* truncation = nullptr) {
  const Event event = simulateTrackml(
      event1001Particles(), test::SampleNoise::eReal, std::move(region));
  EXPECT_GT(event.hits.size(), 90000u);

  const Detector detector = loadDetector("trackml");
  Reconstruction::Config recoConfig =
      readReconstructionConfig(resolveChainPath("trackml"), detector);
  if (adjust) {
    adjust(recoConfig);
  }
  const Reconstruction reco(detector, recoConfig);
  const auto t0 = std::chrono::steady_clock::now();
  const Reconstruction::Result result = reco.run(event.hits);
  const double ms = std::chrono::duration<double, std::milli>(
                        std::chrono::steady_clock::now() - t0)
                        .count();

  const TrackmlScore score = scoreTrackml(event, test::hitLists(result.tracks));
  if (truncation != nullptr) {
    *truncation = describeTruncation(result.steps);
  }
  std::printf(
      "[ trackml 1001 %s ] %zu hits, %zu tracks: TrackML score %.4f, "
      "efficiency %.4f, fake rate %.4f; finding %.0f ms, fitting %.0f ms, "
      "total %.0f ms\n",
      label, event.hits.size(), result.tracks.size(), score.score,
      score.efficiency, score.fakeRate, result.findingMs, result.fittingMs, ms);
  return score;
}

/// A change of one named step of the shipped chain (checking its shipped
/// value first).
struct StepChange {
  std::string step;
  std::function<void(FindingStep&)> change;
};

/// scoreEvent1001 with `changes` applied; each named step must exist once,
/// or the comparison would measure less than the change.
TrackmlScore scoreEvent1001WithSteps(
    const char* label, std::optional<LuminousRegion::Config> region,
    const std::vector<StepChange>& changes) {
  std::vector<std::size_t> applied(changes.size(), 0);
  const TrackmlScore score =
      scoreEvent1001(label, std::move(region), [&](Reconstruction::Config& c) {
        for (FindingStep& step : c.chain.steps) {
          for (std::size_t k = 0; k < changes.size(); ++k) {
            if (step.name == changes[k].step) {
              changes[k].change(step);
              ++applied[k];
            }
          }
        }
      });
  for (std::size_t k = 0; k < changes.size(); ++k) {
    EXPECT_EQ(applied[k], 1u) << changes[k].step;
  }
  return score;
}

/// Event 1001 scored with the shipped chain (`label`) and with `changes`,
/// the chain before a change (`beforeLabel`): the shipped chain must score
/// at least `minGain` more, its fake rate within issue 15's 5 %.
void expectGainOver(const char* label, const char* beforeLabel,
                    const std::optional<LuminousRegion::Config>& region,
                    const std::vector<StepChange>& changes, double minGain) {
  const TrackmlScore now = scoreEvent1001(label, region);
  const TrackmlScore before =
      scoreEvent1001WithSteps(beforeLabel, region, changes);
  EXPECT_GE(now.score, before.score + minGain);
  EXPECT_LE(now.fakeRate, 0.05);
}

TEST(TrackmlChain, ScoreOnSimulatedEvent1001) {
  const TrackmlScore score = scoreEvent1001("sigma_z 5.5 mm", std::nullopt);
  // Measured 0.9062, fake rate 0.0207 since a build's clones are compared
  // as built (CloneTreatment.CandidatesOfAStepCompareWithItsTracksAsBuilt);
  // 0.9068, fake rate 0.0206 since LowPt's cells bend by at most
  // 0.03 rad; 0.9064, fake rate 0.0211 since PixelStrip keeps tracks of 8
  // hits or more (PixelStripLeavesItsShortTracksToLowPtAtTheHlLhcLength);
  // 0.9051, fake rate 0.0232 since the extensions rank (u, v) with
  // every crossed layer's scattering (extension_uv_scattering;
  // ExtensionRanking.UvScatteringOfEveryLayerKeepsTracksOnTheirOwnHits);
  // 0.9044 and 0.0241 since they rank z against
  // the tracks' (s, z) filter (extension_sz_filter, with the hit chi2
  // ratio 20 and skip chi2 150; ExtensionRanking.
  // SzFilterKeepsLowMomentumTracksOnTheirOwnHits); 0.9015 and 0.0241 since
  // HelixStrips follows its tracks
  // past the turn (StripTracksTakeTheirIncomingLegsHits); 0.9007, fake rate
  // 0.0238 since HelixStrips' 6-hit candidates
  // claim in the first pass (SixHitStripCandidatesClaimInTheFirstPass;
  // 0.9003 and 0.0225 before); 0.9003 since its seeds reach
  // twice the distance of layers up to 300 mm apart (seed_length_per_gap,
  // StripSeedsBetweenWiderLayersReachTheSamePolarAngles below; 0.8977 and
  // 0.019 before, with the changes of docs/algorithm.md 8 since the
  // following); 0.8929, fake rate 0.017 since the finder's shared-hit
  // resolution runs after every step and the second pass after the
  // selection runs PixelShort again (docs/algorithm.md 3.13, 3.21; 0.8891
  // and 0.019 with the resolution after the last step only and Helix too
  // in the second pass); 0.8872, fake rate 0.018 since the PixelShort step
  // keeps three-hit prompt tracks with an overlap pair
  // (docs/algorithm.md 3.20); 0.8810, fake rate 0.018 since the first
  // pixel-disk sensor crossed below r = 35 mm carries the extra material that
  // the real files show (docs/validation.md item 13); 0.8796 and 0.019 since
  // the noise is the real files' rate per sensor (17,796 noise hits here;
  // 0.8800 and 0.017 with 15,588, 17 % of the hits); 0.8800 since the
  // simulation places the layers' material where the real files show it and can
  // end particles between the sensors of a layer (docs/validation.md items 11
  // and 12; 0.8766 and 0.013 before, 0.8760 before PixelLoose; 0.8763 and 0.012
  // before the helix steps' inward following ended at the closest approach and
  // the prompt builds after the first seeded about the vertices of the free
  // hits; 0.8757 and 0.011 before the shared-hit resolution trimmed tracks
  // instead of dropping them, final_trim_shared_hits; 0.8727 and 0.012 before
  // the helix steps' predictions carried every crossed layer's scattering, the
  // hits' errors through the fitted parabola and the field ahead, and the strip
  // helix step followed its tracks back into the pixels; 0.8717 and 0.011
  // before the strip
  // helix step took pT from 0.15 GeV; 0.8705 and 0.013 before long helix
  // candidates claimed their hits first, first_pass_min_hits; 0.8677 and
  // 0.011 before the pixel
  // helix step took pT from 0.15 GeV with a chi2 cut of 6; 0.8659 before
  // the pixel helix step's
  // seeds crossed the 200 mm gaps between the outer disks; 0.8581 and
  // 0.013 before extensions
  // ended half a turn from a track's first hit, max_track_turns; 0.8558
  // and 0.011 before the strip
  // helix step's 5-hit tracks judged by the selection's short-track rule;
  // 0.8533 and 0.012 before the finder's shared-hit resolution and final
  // overlap search; 0.8503 and 0.012 before overlap pairs allowed for the
  // scattering between their sensors, released hits of replaced clones and the
  // helix continuation's looser chi2 cut; 0.8471 and 0.014 before the
  // extensions' hit chi2 cut and the helix continuation; 0.8450 and 0.015
  // before the inward completion allowed for scattering, 0.8408 and 0.015
  // before arc lengths of field-mapped hits were those of their mapped points,
  // 0.8399 and 0.015 before extensions ranked their candidates with the
  // scattering, 0.8328 and 0.014 before the strip helix step took 6 hits from
  // pT 0.2 GeV on, into the strip endcaps; 0.8233 and 0.013 before the helix
  // step took its seed hits' overlap partners, 0.8186 and 0.016 before
  // helix paths ended after half a turn and their predictions carried the
  // scattering's share of the fitted curvature); 0.7922 and 0.009 before
  // the chain
  // had its helix steps for displaced particles (chains/trackml.toml), which
  // finds beam-pipe and pixel secondaries at the cost of some random
  // helices through noise hits. The simulation follows the real
  // events' solenoid field, which weakens towards |z| = 3 m
  // (docs/validation.md item 9); the finder maps the hits for it and the
  // fit follows it (field_correction: 0.7547 and 0.025 without,
  // FieldCorrectionRecoversTheForwardHits below).
  // Before: 0.7901 before the extensions stopped where tracks leave the
  // tracker, fake rate 0.024 before the selection's shared-hit
  // resolution. On the module-level simulation a particle leaves a second
  // hit where sensors overlap (a quarter of its hits, as in the real
  // files); before the finder took those overlap hits
  // (detail/OverlapHits.hpp) and the fit measured them on their own
  // sensor planes it scored 0.5596 with a fake rate of 0.255. Guarded with
  // a margin of 0.02 (fake rate 0.013).
  EXPECT_GE(score.score, 0.859);
  EXPECT_LE(score.fakeRate, 0.03);
}

TEST(TrackmlChain, ScoreOnSimulatedEvent1001WithHlLhcLength) {
  // The same event with its interactions moved to sigma_z = 50 mm
  // (--luminous-region hllhc): the seeds' z windows follow the vertices
  // found by the vertex-z pre-pass (docs/algorithm.md 3.16), so the score
  // stays near that of the Kaggle length (measured 0.9025 against 0.9062,
  // fake rate 0.024 against 0.021 since a build's clones are compared as
  // built; 0.9017 against 0.9068,
  // fake rate 0.024 against 0.021 since LowPt's cells bend by at most 0.03
  // rad; 0.9014 against 0.9064,
  // fake rate 0.025 against 0.021 since PixelStrip keeps tracks of 8 hits
  // or more; 0.8985 against 0.9051,
  // fake rate 0.030 against 0.023 with the extensions' scattering models;
  // 0.8973 against 0.9044,
  // fake rate 0.031 against 0.024 with the extensions' (s, z) filter alone;
  // 0.8943 against 0.9015,
  // fake rate 0.033 against 0.024 since HelixStrips follows its tracks past
  // the turn; 0.8866 against 0.8929,
  // fake rate 0.024 against 0.017 with the shared-hit resolution after
  // every step; 0.8810 against 0.8891, fake rate 0.029 against 0.019 with
  // Helix in the second pass; 0.8748 against 0.8872,
  // fake rate 0.028 against 0.018 with the PixelShort step; 0.8701 against
  // 0.8810, 0.027 against 0.018 with the disks' inner ring of item 13;
  // 0.8690 against 0.8796, 0.025 against 0.019 with the real files' noise
  // rate per sensor; 0.8717 against 0.8800, 0.022 against 0.017 with 17 %
  // noise; 0.8722 and 0.023 before the simulation placed the layers' material,
  // docs/validation.md items 11 and 12; 0.8700 before the prompt builds after
  // the first seeded about the vertices of the free hits and the inward
  // following ended at the closest approach; 0.8688 before trimming; 0.8668
  // before the helix steps' prediction errors, field and inward following;
  // 0.8666 before the LowPt step had its
  // own work budget, 0.8640 before the strip helix step's
  // pT 0.15 GeV, 0.8630 and 0.025 before long helix
  // candidates claimed first, 0.8600 and 0.022 before the pixel
  // helix step's pT 0.15 GeV, 0.8579 before the seeds crossed the
  // outer pixel disks' gaps, 0.8510 and 0.023 before extensions
  // ended half a turn from a track's first hit, 0.8491 and 0.022 before
  // the short-track
  // rule, 0.8456 before the finder's shared-hit resolution, 0.8434 before
  // overlap pairs allowed for the scattering, released hits of replaced clones
  // and the helix continuation's chi2 cut, 0.8402 and 0.025 before the
  // extensions' hit chi2 cut and the continuation, 0.8393 and 0.026 before the
  // inward completion allowed for scattering, 0.8347 and 0.029 before the
  // mapped arc lengths, 0.8257 and 0.027 before the strip helix step's new
  // cuts, 0.8161 and 0.028 before the helix step's seed partners, 0.8123 and
  // 0.029 before helix paths ended after half a turn; 0.7840 and 0.024 before
  // the helix steps; in the solenoid field with the finder's field correction;
  // 0.28 with the fixed window of +-20 mm about 0, before the overlap hits).
  // Guarded at 0.02 below the measured score; the fake rate at the goal of
  // issue 15 (5 %). No combinatorics guard may bite: the vertex windows
  // cover 130-150 mm of z here instead of about 30, and with the guards of
  // the Kaggle length (256 seed cells per seed, 25 cells per hit) the
  // LowPt step dropped 2,947 of its seeds and 2,018 seed cells of 116
  // others in this event.
  const LuminousRegion::Preset* hllhc = LuminousRegion::findPreset("hllhc");
  ASSERT_NE(hllhc, nullptr);
  std::string truncation;
  const TrackmlScore score =
      scoreEvent1001("sigma_z 50 mm", hllhc->config, {}, &truncation);
  EXPECT_GE(score.score, 0.851);
  EXPECT_LE(score.fakeRate, 0.05);
  EXPECT_EQ(truncation, "");
}

TEST(TrackmlChain, CutsRescannedAtStop52GainAtTheHlLhcLength) {
  // The chain's cuts were scanned one at a time, each against the chain
  // of its day; later steps changed what earlier ones leave, and at stop
  // 52 five were scanned again on the five simulated events: the helix
  // steps' chi2 cut per added hit 6 -> 8, PixelStrip's chi2 cut 3000 ->
  // 1500 (at sigma_z = 50 mm it built 46 fake tracks per event against 10
  // at 5.5 mm), PixelShort's chi2 cut 1000 -> 3000 and cell angles 0.02 /
  // 0.005 -> 0.03 / 0.015. Five events, sigma_z 5.5 / 50 mm: 0.8902 /
  // 0.8815 -> 0.8925 / 0.8850 (chains/trackml.toml has each scan). Here
  // event 1001 at the HL-LHC length, the shipped chain against those
  // cuts put back: measured 0.8872 -> 0.8894, fake rate 0.0245 -> 0.0297
  // (on the chain of stop 53: 0.8900 -> 0.8933, 0.0264 -> 0.0324; on that
  // of stop 54, with the extensions' scattering models: 0.8956 -> 0.8985,
  // 0.0249 -> 0.0304; of stop 55, PixelStrip from 8 hits: 0.8987 ->
  // 0.9014, 0.0203 -> 0.0251; with all of stop 55: 0.8996 -> 0.9025,
  // 0.0191 -> 0.0237).
  // Guarded: +0.001, and the fake rate within issue 15's 5 %.
  const LuminousRegion::Preset* hllhc = LuminousRegion::findPreset("hllhc");
  ASSERT_NE(hllhc, nullptr);
  auto helixChi2 = [](FindingStep& step) {
    ASSERT_DOUBLE_EQ(step.chi2Cut, 8.0);
    step.chi2Cut = 6.0;
  };
  expectGainOver("sigma_z 50 mm", "sigma_z 50 mm, the cuts before stop 52",
                 hllhc->config,
                 {{"Helix", helixChi2},
                  {"HelixStrips", helixChi2},
                  {"PixelStrip",
                   [](FindingStep& step) {
                     ASSERT_DOUBLE_EQ(step.chi2Cut, 1500.0);
                     step.chi2Cut = 3000.0;
                   }},
                  {"PixelShort",
                   [](FindingStep& step) {
                     ASSERT_DOUBLE_EQ(step.chi2Cut, 3000.0);
                     step.chi2Cut = 1000.0;
                     step.maxCellAngle = 0.02;
                     step.maxCellAngleRZ = 0.005;
                   }}},
                 0.001);
}

TEST(TrackmlChain, StripSeedsBetweenWiderLayersReachTheSamePolarAngles) {
  // HelixStrips seeds are at most 200 mm long, which between the
  // short-strip barrel layers at 360 and 500 mm allows |dz/dr| up to 1.0
  // only (1.7 between 260 and 360 mm): the first strip triplet of a
  // secondary from the pixel volume was cut at |eta| 0.9. With
  // seed_length_per_gap = 2 up to 300 mm that pair reaches 280 mm. Five
  // events, sigma_z 5.5 / 50 mm: 0.8925 / 0.8850 -> 0.8946 / 0.8874.
  // Here event 1001 at 5.5 mm without the key: measured 0.8975 -> 0.9007,
  // fake rate 0.0213 -> 0.0238 (0.8977 -> 0.9003, 0.0194 -> 0.0225 with
  // first_pass_min_hits 7; 0.9016 -> 0.9051, 0.0201 -> 0.0232 on the chain
  // of stop 54).
  // Guarded: +0.001, and the fake rate within issue 15's 5 %.
  expectGainOver("sigma_z 5.5 mm",
                 "sigma_z 5.5 mm, 200 mm strip seeds on every pair",
                 std::nullopt,
                 {{"HelixStrips",
                   [](FindingStep& step) {
                     ASSERT_DOUBLE_EQ(step.seedLengthPerGap, 2.0);
                     step.seedLengthPerGap = 0.0;
                     step.maxSeedLengthPerGap = 0.0;
                   }}},
                 0.001);
}

TEST(TrackmlChain, SixHitStripCandidatesClaimInTheFirstPass) {
  // HelixStrips' candidates of first_pass_min_hits or more claim their
  // hits as they are found, the shorter ones (min_hits 5) in a second
  // pass. Scanned at stop 53 on the five events (sigma_z 5.5 / 50 mm):
  // 7 (min_hits + 2, as Helix) 0.8946 / 0.8874, 6 0.8954 / 0.8885, with
  // 13 % fewer triplets. Here event 1001 at the HL-LHC length against 7:
  // measured 0.8926 -> 0.8933, fake rate 0.0322 -> 0.0324 (on the chain of
  // stop 54: 0.8977 -> 0.8985, 0.0306 -> 0.0304). Guarded:
  // +0.0004, the fake rate within issue 15's 5 %.
  const LuminousRegion::Preset* hllhc = LuminousRegion::findPreset("hllhc");
  ASSERT_NE(hllhc, nullptr);
  expectGainOver("sigma_z 50 mm",
                 "sigma_z 50 mm, strip candidates of 7 hits first",
                 hllhc->config,
                 {{"HelixStrips",
                   [](FindingStep& step) {
                     ASSERT_EQ(step.firstPassMinHits, 6u);
                     step.firstPassMinHits = 7;
                   }}},
                 0.0004);
}

TEST(TrackmlChain, PixelStripLeavesItsShortTracksToLowPtAtTheHlLhcLength) {
  // PixelStrip keeps its tracks of 8 or more hits in the pixels and short
  // strips (stop 55; 5 before). At sigma_z = 50 mm its 5- to 7-hit tracks
  // were most of its fakes (2-3 pixel hits of different particles where
  // the vertex regions admit 130-150 mm of z0, 36 fake tracks per event),
  // and the true ones among them are built by LowPt after it, with more of
  // their hits. Five events, sigma_z 5.5 / 50 mm: 0.8999 / 0.8928 ->
  // 0.9015 / 0.8960, fake rate 0.025 / 0.033 -> 0.022 / 0.027. Here event
  // 1001 at the HL-LHC length against 5: measured 0.8985 -> 0.9014, fake
  // rate 0.0304 -> 0.0251 (0.8985 -> 0.9017, 0.0301 -> 0.0243 with LowPt's
  // cell angle of stop 55; 0.8997 -> 0.9025, 0.0296 -> 0.0237 with a
  // build's clones compared as built).
  // Guarded: +0.0015, the fake rate within issue 15's 5 %.
  const LuminousRegion::Preset* hllhc = LuminousRegion::findPreset("hllhc");
  ASSERT_NE(hllhc, nullptr);
  expectGainOver("sigma_z 50 mm", "sigma_z 50 mm, PixelStrip from 5 hits",
                 hllhc->config,
                 {{"PixelStrip",
                   [](FindingStep& step) {
                     ASSERT_EQ(step.minHits, 8u);
                     step.minHits = 5;
                   }}},
                 0.0015);
}

TEST(TrackmlChain, StripTracksTakeTheirIncomingLegsHits) {
  // HelixStrips follows its tracks past the closest approach, along the
  // incoming leg of a secondary produced off the beam line moving inwards,
  // and takes the hits there if they are two or more (past_turn_min_hits;
  // TrackmlHelix.PastTurnFollowingTakesTheIncomingLegsPixelHits). Five
  // events, sigma_z 5.5 / 50 mm: 0.8954 / 0.8885 -> 0.8960 / 0.8890. Here
  // event 1001 at the HL-LHC length without it: measured 0.8974 ->
  // 0.8985, fake rate 0.0302 -> 0.0304 (0.8933 -> 0.8943, 0.0324 -> 0.0329
  // before the extensions' scattering models). Guarded: +0.0005, the fake
  // rate
  // within issue 15's 5 %.
  const LuminousRegion::Preset* hllhc = LuminousRegion::findPreset("hllhc");
  ASSERT_NE(hllhc, nullptr);
  expectGainOver("sigma_z 50 mm", "sigma_z 50 mm, no past-turn following",
                 hllhc->config,
                 {{"HelixStrips",
                   [](FindingStep& step) {
                     ASSERT_EQ(step.pastTurnMinHits, 2u);
                     step.pastTurnMinHits = 0;
                   }}},
                 0.0005);
}

TEST(TrackmlChain, FieldCorrectionRecoversTheForwardHits) {
  // The simulation follows the real events' solenoid field, whose bending
  // weakens towards |z| = 3 m; the finder maps the hits so that tracks
  // from the beam line stay straight lines in the conformal plane and
  // predicts their layer crossings the same way (finder key
  // field_correction, PromptBending). Without it the strip extensions
  // leave forward hits off and take wrong ones: measured 0.8623 without,
  // 0.9051 with on the chain of stop 54 (0.8459 and 0.8929 on that of
  // stop 45; 0.8412 and 0.8891 before the shared-hit resolution after
  // every step; 0.8393 and 0.8872 before the second pass after the
  // selection; 0.8332 and 0.8810 before the PixelShort step; 0.8336 and
  // 0.8796 before the disks' inner ring of
  // docs/validation.md item 13; 0.8346 and 0.8800 with 17 % noise instead
  // of the real files' rate per sensor; 0.8316 and 0.8766 before the simulation
  // placed the layers' material, docs/validation.md items 11 and 12; 0.8280 and
  // 0.8727 before this session's inward-following fix, PixelPrompt2 and
  // PixelLoose; 0.8272 and 0.8717 before the strip helix step's pT 0.15 GeV,
  // 0.8260 and 0.8705 before long helix candidates claimed their hits first,
  // 0.8208 and 0.8659 before the seeds crossed the outer pixel disks' gaps and
  // the pixel helix step took pT from 0.15 GeV, 0.8128 and 0.8581 before
  // extensions ended half a turn from a track's first hit, 0.8061 and 0.8471
  // before the helix continuation, the shared-hit resolution and the
  // short-track rule; 0.7547 and 0.7922 before the chain's helix steps).
  const TrackmlScore with = scoreEvent1001("sigma_z 5.5 mm", std::nullopt);
  const TrackmlScore without = scoreEvent1001(
      "sigma_z 5.5 mm, no field correction", std::nullopt,
      [](Reconstruction::Config& c) { c.chain.fieldCorrection = false; });
  EXPECT_GE(with.score - without.score, 0.015);
}

TEST(TrackmlChain, LongHelixCandidatesClaimTheirHitsFirst) {
  // The helix steps take their seeds innermost first. When each seed's
  // best candidate claimed its hits at once, a short random helix through
  // noise and left-over hits, met early, took a hit of a long track met
  // later, which then fell short of its hits or was never built. With
  // first_pass_min_hits (8 and 6 in the shipped chain; 8 and 7 until stop
  // 53) the long candidates claim first. Measured on event 1001: fake rate
  // 0.0252 without, 0.0232 with; score 0.9016 and 0.9051 (the chain of
  // stop 54; 0.0258, 0.0238, 0.8973 and 0.9007 at stop 53; 0.0191, 0.0168,
  // 0.8916 and 0.8929 at stop 47; 0.0215, 0.0194,
  // 0.8878 and 0.8891 before the shared-hit resolution after every step;
  // 0.0201, 0.0180, 0.8858 and 0.8872 before the second pass after the
  // selection; 0.0198, 0.0177, 0.8796 and 0.8810 before the PixelShort step;
  // 0.0206, 0.0191, 0.8789 and 0.8796 before the disks' inner ring of
  // docs/validation.md item 13; 0.0193, 0.0172, 0.8790 and 0.8800 with 17 %
  // noise instead of the real files' rate per sensor; 0.0150, 0.0129, 0.8755
  // and 0.8766 before the simulation placed the layers' material; 0.0142,
  // 0.0118, 0.8712 and 0.8727 before PixelPrompt2 and PixelLoose; five events,
  // before the strip helix step took pT from 0.15 GeV: fake rate 0.021
  // -> 0.019, score +0.0011). Guarded: fewer fakes by 0.001, the score no
  // lower.
  const TrackmlScore with = scoreEvent1001("sigma_z 5.5 mm", std::nullopt);
  const TrackmlScore without =
      scoreEvent1001("sigma_z 5.5 mm, helix candidates claiming at once",
                     std::nullopt, [](Reconstruction::Config& c) {
                       for (FindingStep& step : c.chain.steps) {
                         step.firstPassMinHits = 0;
                       }
                     });
  EXPECT_LE(with.fakeRate, without.fakeRate - 0.001);
  EXPECT_GE(with.score, without.score);
}

TEST(TrackmlChain, InwardCompletionTakesTheInnermostHitsOfForwardTracks) {
  // Prompt particles of event 1001 at 0.2-0.6 GeV and |eta| 1.8-2.6 (they
  // cross the first pixel barrel layers, then the pixel disks), simulated
  // on the real sensors without noise and found by the shipped chain. Such
  // a track scatters in the pixel layers, and its innermost hit lies
  // millimetres off the s-z line of the others ((1 + tan^2 lambda) times
  // the kink): the inward completion takes it only with its scattering
  // allowance (inward_scattering_allowance). Counted: hits on a track of
  // their own particle (the track's majority). Measured 7394 with the
  // allowance against 7281 without (748 particles, 7820 hits; with the
  // extensions' scattering models of stop 54; 7261 and 7126 before them;
  // 7241 and 7117
  // before the shared-hit resolution after every step, 7187 and 7070
  // before the second pass after the selection; 7618 and 7502
  // of 8066 hits before the simulation placed the layers' material, 7589 and
  // 7473 before PixelLoose and the trimmed tracks' chi2 cuts; the TrackML score
  // of the five events 0.8433 -> 0.8448 with a lower fake rate). Guarded at
  // +50.
  const std::vector<Particle> forward = test::forwardLowPtParticles();
  ASSERT_GT(forward.size(), 300u);
  const Event event = simulateTrackml(forward, test::SampleNoise::eNone);
  const Detector detector = loadDetector("trackml");
  auto ownHits = [&](bool allowance) {
    FinderConfig chain =
        readReconstructionConfig(resolveChainPath("trackml"), detector).chain;
    chain.inwardScatteringAllowance = allowance;
    const ConformalTrackFinder finder(detector, {chain});
    return test::majorityHits(event, finder.run(event.hits));
  };
  const std::size_t with = ownHits(true);
  const std::size_t without = ownHits(false);
  std::printf(
      "[ trackml 1001, %zu forward low-pT particles, %zu hits ] hits on "
      "their particle's track: %zu with the inward allowance, %zu without\n",
      forward.size(), event.hits.size(), with, without);
  EXPECT_GE(with, without + 50);
}

}  // namespace
}  // namespace conftrack

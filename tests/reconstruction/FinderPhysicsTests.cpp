// Physics checks of the conformal finder on simulated events (truth is
// used only here, to score the result). The sample sizes are the CI ones;
// the full-statistics checks are documented in docs/algorithm.md
// (§7) and run with the same code through `conftrack run`.

#include "conftrack/core/Random.hpp"
#include "conftrack/evaluation/TruthMatching.hpp"
#include "conftrack/geometry/DetectorReader.hpp"
#include "conftrack/geometry/LayoutFile.hpp"
#include "conftrack/reconstruction/finding/ConformalTrackFinder.hpp"
#include "conftrack/simulation/EventSimulation.hpp"
#include "conftrack/simulation/LuminousRegion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>

namespace conftrack {
namespace {

struct Score {
  std::size_t particles = 0;  // selected reconstructable particles
  std::size_t found = 0;      // ... with a matched (pure) track
  // The same with the selection of the CLICdp efficiency plots
  // (evaluation.md A1): 10 < theta < 170 deg, production radius < 50 mm,
  // proximity dR > 0.02.
  std::size_t clicdpParticles = 0;
  std::size_t clicdpFound = 0;
  std::size_t tracks = 0;
  std::size_t impure = 0;  // tracks with purity < 75 %
  // Matched tracks of particles with two or more (the CLICdp duplicates,
  // all members counted).
  std::size_t duplicates = 0;
  double findMs = 0.0;
  std::size_t events = 0;
};

std::vector<std::vector<HitIndex>> hitLists(const FindingResult& r) {
  std::vector<std::vector<HitIndex>> v;
  for (const FoundTrack& t : r.tracks) {
    v.push_back(t.hits);
  }
  return v;
}

/// Simulates and reconstructs `n` events; scores particles with pT above
/// minPt (and, with minHitFraction, requires the matched track to hold
/// that fraction of the particle's hits).
Score score(const Detector& det, const ConformalTrackFinder& finder,
            EventSimulation::Config cfg, std::size_t n, double minPt,
            double minHitFraction = 0.0) {
  EventSimulation sim(det, cfg);
  Score s;
  for (std::size_t e = 0; e < n; ++e) {
    Event ev = sim.simulate(e + 1);
    FindingResult r = finder.run(ev.hits);
    s.findMs += r.milliseconds;
    ++s.events;
    auto lists = hitLists(r);
    EventMatching m = matchTracks(ev, lists);
    std::vector<std::uint32_t> bestHits(ev.particles.size(), 0);
    for (const TrackMatch& t : m.tracks) {
      ++s.tracks;
      if (t.purity < 0.75) {
        ++s.impure;
      }
      if (t.matched && m.particles[t.particle].nMatchedTracks >= 2) {
        ++s.duplicates;
      }
      if (t.matched) {
        bestHits[t.particle] = std::max(bestHits[t.particle], t.nMajority);
      }
    }
    for (std::size_t p = 0; p < ev.particles.size(); ++p) {
      const Particle& part = ev.particles[p];
      if (!m.particles[p].reconstructable || part.pt() < minPt ||
          part.isBackground()) {
        continue;
      }
      ++s.particles;
      bool found = bestHits[p] > 0 &&
                   bestHits[p] >= minHitFraction * m.particles[p].nHits;
      s.found += found ? 1 : 0;
      double theta = std::acos(part.momentum.z() / part.momentum.norm());
      if (theta > 10.0 * units::degree && theta < 170.0 * units::degree &&
          part.vertex.head<2>().norm() < 50.0 * units::mm &&
          m.particles[p].proximity > 0.02) {
        ++s.clicdpParticles;
        s.clicdpFound += found ? 1 : 0;
      }
    }
  }
  return s;
}

class FinderPhysics : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_detector = new Detector(loadDetector("clicdet"));
    s_finder = new ConformalTrackFinder(
        *s_detector, {readChain(resolveChainPath("clicdet"), *s_detector)});
  }
  static void TearDownTestSuite() {
    delete s_finder;
    delete s_detector;
  }
  static Detector* s_detector;
  static ConformalTrackFinder* s_finder;
};
Detector* FinderPhysics::s_detector = nullptr;
ConformalTrackFinder* FinderPhysics::s_finder = nullptr;

double ratio(std::size_t a, std::size_t b) {
  return double(a) / double(std::max<std::size_t>(1, b));
}

void report(const char* name, const Score& s) {
  std::printf(
      "[ %s ] efficiency %.4f (%zu/%zu), CLICdp selection %.4f (%zu/%zu), "
      "impure tracks %.4f (%zu/%zu), finding %.1f ms/event\n",
      name, ratio(s.found, s.particles), s.found, s.particles,
      ratio(s.clicdpFound, s.clicdpParticles), s.clicdpFound, s.clicdpParticles,
      ratio(s.impure, s.tracks), s.impure, s.tracks,
      s.findMs / std::max<std::size_t>(1, s.events));
}

TEST_F(FinderPhysics, SingleMuons) {
  // One muon per event; pT 1, 10, 100 GeV; theta from 10 to 90 degrees;
  // both charges. Goal: >= 99.9 % of 10,000 muons per point with a pure
  // track holding >= 90 % of their hits. CI runs 1,000 per point and
  // allows 2 sigma of a 99.9 % binomial below the goal (99.7 %); the full
  // check (docs/algorithm.md §7) sets CONFTRACK_MUONS_PER_POINT=10000 and
  // then requires the goal itself.
  const char* env = std::getenv("CONFTRACK_MUONS_PER_POINT");
  const std::size_t n = env != nullptr ? std::strtoul(env, nullptr, 10) : 1000;
  ASSERT_GT(n, 0u);
  const double goal = 0.999;
  const double required =
      n >= 10000 ? goal
                 : goal - 2.0 * std::sqrt(goal * (1.0 - goal) / double(n));
  for (double pt : {1.0, 10.0, 100.0}) {
    EventSimulation::Config cfg;
    cfg.sample = "muons";
    cfg.seed = 11;
    cfg.generatorToml =
        "[generator]\nsample = \"gun\"\nparticle = \"mu-\"\n"
        "random_charge = true\nmultiplicity = 1\npt_GeV = " +
        std::to_string(pt) +
        "\ntheta_min_deg = 10.0\ntheta_max_deg = 90.0\n"
        "theta_sampling = \"theta\"\n";
    Score s = score(*s_detector, *s_finder, cfg, n, 0.0, 0.9);
    report(("muons pT " + std::to_string(int(pt)) + " GeV").c_str(), s);
    EXPECT_EQ(s.particles, n);
    EXPECT_GE(double(s.found), required * double(s.particles))
        << s.found << " of " << s.particles;
    EXPECT_EQ(s.impure, 0u);
  }
}

TEST_F(FinderPhysics, LongitudinalCellAngleFollowsTheHelix) {
  // 0.1 GeV muons at 30-60 degrees in the vertex barrel (R 31-60 mm, 4 T:
  // R / 2Rc = 0.19-0.36), without scattering or energy loss, so that only
  // the helix geometry bends the cells: in (z, R) consecutive chords differ
  // by about 0.01 rad, twice the VXDBarrel cut; in (s, z) they are
  // straight. Measured 100 % with the (s, z) angle, 38 % with (z, R)
  // chords.
  const std::string chain =
      "[[step]]\nname = \"VXDBarrel\"\ncollections = [\"VertexBarrel\"]\n"
      "actions = [\"build\"]\nmax_cell_angle = 0.005\n"
      "max_cell_angle_rz = 0.005\nchi2_cut = 100.0\nmin_hits = 4\n"
      "max_distance = 0.02\nslope_z_range = 10.0\nmax_seed_z0_mm = 200.0\n"
      "high_pt_cut_GeV = 10.0\nstraight_line_fit = true\n"
      "direction = \"inside-out\"\n[finder]\nfinal_hole_filling = false\n";
  const ConformalTrackFinder finder(
      *s_detector, {parseChain(chain, "test chain", *s_detector)});
  EventSimulation::Config cfg;
  cfg.sample = "muons";
  cfg.seed = 13;
  cfg.simulator.multipleScattering = false;
  cfg.simulator.energyLoss = false;
  cfg.simulator.bremsstrahlung = false;
  cfg.generatorToml =
      "[generator]\nsample = \"gun\"\nparticle = \"mu-\"\n"
      "random_charge = true\nmultiplicity = 1\npt_GeV = 0.1\n"
      "theta_min_deg = 30.0\ntheta_max_deg = 60.0\n"
      "theta_sampling = \"theta\"\n";
  Score s = score(*s_detector, finder, cfg, 300, 0.0);
  report("muons pT 0.1 GeV, vertex barrel only", s);
  ASSERT_GE(s.particles, 200u);
  EXPECT_GE(ratio(s.found, s.particles), 0.97);
  EXPECT_EQ(s.impure, 0u);
}

TEST_F(FinderPhysics, ForwardPromptFindsTheTrackerDiskTracks) {
  // Prompt muons of pT 0.3 GeV at 7-10 degrees pass inside the vertex
  // endcap's inner edge (33 mm at z = 180 mm) and cross only the
  // inner-tracker disks: the ForwardPrompt step builds them (the forward
  // overlay particles of chains/clicdet.toml's step 5). Measured 100 % of
  // 189 (300 events) with the shipped chain, 90.5 % without the step (the
  // Displaced step, seeded in the outer tracker only, finds the others).
  EventSimulation::Config cfg;
  cfg.sample = "muons";
  cfg.seed = 17;
  cfg.generatorToml =
      "[generator]\nsample = \"gun\"\nparticle = \"mu-\"\n"
      "random_charge = true\nmultiplicity = 1\npt_GeV = 0.3\n"
      "theta_min_deg = 7.0\ntheta_max_deg = 10.0\n"
      "theta_sampling = \"theta\"\n";
  Score s = score(*s_detector, *s_finder, cfg, 300, 0.0);
  report("muons pT 0.3 GeV, theta 7-10 deg", s);
  ASSERT_GE(s.particles, 150u);
  EXPECT_GE(ratio(s.found, s.particles), 0.99);
  EXPECT_EQ(s.impure, 0u);
}

TEST_F(FinderPhysics, TtbarWithoutBackground) {
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.seed = 21;
  Score s = score(*s_detector, *s_finder, cfg, 40, 1.0);
  report("ttbar pT > 1 GeV", s);
  EXPECT_GE(ratio(s.clicdpFound, s.clicdpParticles), 0.995);
  EXPECT_LE(ratio(s.impure, s.tracks), 0.01);
  // Without the selection, daughters of B hadrons that decay far out in
  // the tracker dominate the losses (measured 99.3 %, 2151 of 2166; 97.8 %
  // before the four-hit displaced step).
  EXPECT_GE(ratio(s.found, s.particles), 0.985);
}

TEST_F(FinderPhysics, TtbarWith30BunchCrossings) {
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = 30;
  cfg.seed = 31;
  Score s = score(*s_detector, *s_finder, cfg, 10, 1.0);
  report("ttbar + 30 BX pT > 1 GeV", s);
  EXPECT_GE(ratio(s.clicdpFound, s.clicdpParticles), 0.99);
  EXPECT_LE(ratio(s.impure, s.tracks), 0.02);
  EXPECT_GE(ratio(s.found, s.particles), 0.98);  // measured 99.2 %
}

TEST_F(FinderPhysics, FewDuplicatesWith30BunchCrossings) {
  // CLICdp duplicate rate (every matched track of a particle with two or
  // more, over all tracks) of the finder's tracks, before the fit and
  // selection, tt-bar + 30 BX, 20 events: 0.67 % (78 of 11,617; 0.62 %
  // before the ForwardPrompt step; 1.77 % before the looper rule's turn
  // circles left a foreign end hit out, 2.79 % before the s-z fit's turn
  // choice, the track merging's outlier hits, both pieces as reference,
  // free-circle pairing and the mirror test). The bound was set 2.7
  // standard deviations (0.09 %) above the 0.96 % measured when it was
  // written.
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = 30;
  cfg.seed = 1;
  Score s = score(*s_detector, *s_finder, cfg, 20, 1.0);
  std::printf("[ ttbar + 30 BX duplicates ] %.4f (%zu/%zu)\n",
              ratio(s.duplicates, s.tracks), s.duplicates, s.tracks);
  EXPECT_LE(ratio(s.duplicates, s.tracks), 0.012);
}

TEST_F(FinderPhysics, BeamsCollidingOffTheAxis) {
  // The beams collide 0.7 mm beside and 0.5 mm below the detector axis.
  // With the conformal map about that beam line (finder keys
  // beam_spot_x_mm, beam_spot_y_mm) the finder does as well as on the same
  // events with the beams on the axis; with the map about the axis, prompt
  // tracks are no straight lines in the conformal plane and break into
  // pieces. tt-bar, 20 events, pT > 1 GeV, the finder's tracks (before
  // fit and selection), measured: on the axis efficiency 0.9843, impure
  // tracks 1.77 %, duplicates 2.06 %; off it, map about the beams 0.9852,
  // 1.83 %, 1.95 %; map about the axis 0.8983, 16.2 %, 14.5 %. The
  // tolerance, 0.5 % on each rate, is about 1.5 standard deviations of
  // one rate over these 1,700 tracks and 1,150 particles.
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.seed = 41;
  const LuminousRegion::Preset* clic = LuminousRegion::findPreset("clic3tev");
  ASSERT_NE(clic, nullptr);
  LuminousRegion::Config region = clic->config;
  EventSimulation::Config onAxis = cfg;
  onAxis.luminousRegion = region;
  region.position = Vector3(0.7 * units::mm, -0.5 * units::mm, 0.0);
  cfg.luminousRegion = region;
  FinderConfig chain = readChain(resolveChainPath("clicdet"), *s_detector);
  chain.beamSpotX = 0.7 * units::mm;
  chain.beamSpotY = -0.5 * units::mm;
  const ConformalTrackFinder atBeam(*s_detector, {chain});
  const Score centred = score(*s_detector, *s_finder, onAxis, 20, 1.0);
  const Score s = score(*s_detector, atBeam, cfg, 20, 1.0);
  const Score axis = score(*s_detector, *s_finder, cfg, 20, 1.0);
  for (const auto& [name, x] :
       {std::pair<const char*, const Score&>{"beams on the axis", centred},
        {"beams off it, map about them", s},
        {"beams off it, map about the axis", axis}}) {
    report(name, x);
    std::printf("[ %s ] duplicates %.4f (%zu/%zu)\n", name,
                ratio(x.duplicates, x.tracks), x.duplicates, x.tracks);
  }
  constexpr double kTolerance = 0.005;
  EXPECT_GE(ratio(s.clicdpFound, s.clicdpParticles), 0.995);
  EXPECT_GE(ratio(s.found, s.particles),
            ratio(centred.found, centred.particles) - kTolerance);
  EXPECT_LE(ratio(s.impure, s.tracks),
            ratio(centred.impure, centred.tracks) + kTolerance);
  EXPECT_LE(ratio(s.duplicates, s.tracks),
            ratio(centred.duplicates, centred.tracks) + kTolerance);
  // Premise: the sample shows what the beam spot is for.
  EXPECT_LT(ratio(axis.found, axis.particles), 0.95);
  EXPECT_GE(ratio(axis.duplicates, axis.tracks), 0.05);
}

TEST_F(FinderPhysics, NoTrackHoldsAHitTwiceWithSensors) {
  // A hit is on a track once, fitted or as a further-turn hit. With
  // CLICdet's sensors a looper's incoming half-turn could end on the first
  // half-turn's hit near the apex, and joining the turn put that hit on
  // the track twice (tt-bar + 30 BX, 100 events: 36 hits on 13 events;
  // 17 on 3 of the 15 here; the track files were refused on reading).
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = 30;
  cfg.seed = 1;
  const auto layout = std::filesystem::path(CONFTRACK_TEST_DATA_DIR) /
                      "layouts" / "clicdet_layout.json.gz";
  cfg.modules = std::make_shared<const ModuleLayout>(
      readLayoutModules(layout, *s_detector));
  EventSimulation sim(*s_detector, cfg);
  std::size_t turnHits = 0;
  std::size_t repeated = 0;
  for (std::uint64_t e = 1; e <= 15; ++e) {
    const Event ev = sim.simulate(e);
    for (const FoundTrack& t : s_finder->run(ev.hits).tracks) {
      std::vector<HitIndex> all = t.hits;
      all.insert(all.end(), t.turnHits.begin(), t.turnHits.end());
      turnHits += t.turnHits.size();
      std::sort(all.begin(), all.end());
      repeated += static_cast<std::size_t>(all.end() -
                                           std::unique(all.begin(), all.end()));
    }
  }
  EXPECT_GT(turnHits, 100u);  // premise: loopers' turns were joined
  EXPECT_EQ(repeated, 0u);
}

TEST_F(FinderPhysics, IndependentOfHitOrder) {
  EventSimulation::Config cfg;
  cfg.sample = "ttbar3tev";
  cfg.overlayBx = 10;
  cfg.seed = 41;
  EventSimulation sim(*s_detector, cfg);
  Event ev = sim.simulate(1);
  auto asIds = [&](const std::vector<Hit>& hits, const FindingResult& r) {
    std::vector<std::vector<std::uint64_t>> ids;
    for (const FoundTrack& t : r.tracks) {
      std::vector<std::uint64_t> v;
      for (HitIndex h : t.hits) {
        v.push_back(hits[h].id);
      }
      ids.push_back(v);
    }
    return ids;
  };
  auto reference = asIds(ev.hits, s_finder->run(ev.hits));
  ASSERT_GT(reference.size(), 50u);
  std::vector<Hit> shuffled = ev.hits;
  std::mt19937_64 rng(5);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  EXPECT_EQ(asIds(shuffled, s_finder->run(shuffled)), reference);
}

}  // namespace
}  // namespace conftrack

// Counting tests of the performance collector on a hand-made event
// (EvaluationTestEvents.hpp documents the expected matches), and the
// determinism of merging.

#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/PerformanceReport.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <random>
#include <thread>

#include "EvaluationTestEvents.hpp"

namespace conftrack {
namespace {

/// The reference event's expectations count its background particle P3.
PerformanceConfig withBackground() {
  PerformanceConfig c;
  c.includeBackground = true;
  return c;
}

using test::EventWithTracks;

void expectRatio(const Ratio& r, std::uint64_t passed, std::uint64_t total,
                 const char* what) {
  EXPECT_EQ(r.passed, passed) << what;
  EXPECT_EQ(r.total, total) << what;
}

/// The bin of `h` that contains x.
Ratio binAt(const RatioHistogram& h, double x) {
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (x >= h.lowerEdge(i) && x < h.upperEdge(i)) {
      return h.bin(i);
    }
  }
  return {};
}

PerformanceData analyse(const PerformanceCollector& c,
                        const EventWithTracks& e) {
  return c.analyseEvent(e.event, e.tracks, 4.0, {}, {});
}

TEST(PerformanceCollector, ReferenceEventCountsClicdp) {
  const EventWithTracks e = test::referenceEvent();
  PerformanceCollector collector(withBackground());
  const PerformanceData d = analyse(collector, e);

  EXPECT_EQ(d.events, 1u);
  EXPECT_EQ(d.eventsWithoutTruth, 0u);
  EXPECT_EQ(d.reconstructableParticles, 3u);
  EXPECT_EQ(d.tracks, 5u);
  EXPECT_EQ(d.fittedTracks, 0u);
  EXPECT_EQ(d.selectedTracks, 4u);

  expectRatio(d.efficiency.all, 2, 3, "efficiency");
  expectRatio(d.efficiency.ptAbove1GeV, 1, 2, "efficiency pT > 1");
  expectRatio(d.efficiency.ptBelow1GeV, 1, 1, "efficiency pT <= 1");
  expectRatio(d.signalEfficiency.all, 2, 2, "signal");
  expectRatio(d.signalEfficiency.ptAbove1GeV, 1, 1, "signal pT > 1");
  expectRatio(d.backgroundEfficiency.all, 0, 1, "background");
  expectRatio(d.backgroundEfficiency.ptAbove1GeV, 0, 1, "background pT > 1");

  // P3 has R_vtx = 100 mm, P2 pT = 0.5 GeV.
  expectRatio(d.efficiencyThetaPlotCuts, 1, 1, "theta plot cuts");
  expectRatio(d.efficiencyPtPlotCuts, 2, 2, "pT plot cuts");
  expectRatio(d.efficiencyAllPlotCuts, 1, 1, "all plot cuts");

  expectRatio(d.fakes, 2, 5, "fakes");
  expectRatio(d.duplicates, 2, 5, "duplicates");
  expectRatio(d.selectedFakes, 1, 4, "selected fakes");
  expectRatio(d.selectedDuplicates, 2, 4, "selected duplicates");

  // ACTS: T0, T1 (4/5 and 4/6) and T2 (3/4 and 3/5) match; T3 (2/4, 2/5)
  // does not; one extra track of P1.
  expectRatio(d.actsEfficiency, 2, 3, "ACTS efficiency");
  expectRatio(d.actsFakes, 2, 5, "ACTS fakes");
  expectRatio(d.actsDuplicates, 1, 5, "ACTS duplicates");
}

TEST(PerformanceCollector, ReferenceEventDistributions) {
  const EventWithTracks e = test::referenceEvent();
  PerformanceCollector collector(withBackground());
  const PerformanceData d = analyse(collector, e);

  expectRatio(d.efficiencyVsPt.total(), 2, 2, "eff vs pT");
  expectRatio(binAt(d.efficiencyVsPt, 5.0), 1, 1, "eff vs pT at 5 GeV");
  expectRatio(binAt(d.efficiencyVsPt, 0.5), 1, 1, "eff vs pT at 0.5 GeV");
  expectRatio(d.efficiencyVsPtAll.total(), 2, 3, "eff vs pT, no cuts");
  expectRatio(binAt(d.efficiencyVsPtAll, 2.0), 0, 1, "P3 at 2 GeV");
  expectRatio(d.efficiencyVsTheta.total(), 1, 1, "eff vs theta");
  expectRatio(binAt(d.efficiencyVsTheta, 91.0 * units::degree), 1, 1,
              "eff vs theta at 90 deg");
  expectRatio(d.efficiencyVsPhi.total(), 1, 1, "eff vs phi");
  expectRatio(d.efficiencyVsVertexRadius.total(), 1, 2, "eff vs R");
  expectRatio(binAt(d.efficiencyVsVertexRadius, 100.0), 0, 1, "eff at 100 mm");
  expectRatio(d.efficiencyVsProximity.total(), 1, 1, "eff vs proximity");

  expectRatio(d.fakeRateVsPt.total(), 1, 4, "fake vs pT");
  expectRatio(binAt(d.fakeRateVsPt, 2.0), 1, 1, "fake at 2 GeV");
  expectRatio(d.duplicateRateVsPt.total(), 2, 4, "duplicate vs pT");
  // T2 (0.5 GeV) fails pT > 1 GeV.
  expectRatio(d.fakeRateVsTheta.total(), 1, 3, "fake vs theta");
  expectRatio(d.duplicateRateVsTheta.total(), 2, 3, "duplicate vs theta");
}

TEST(PerformanceCollector, PurityThresholdIsConfigurable) {
  const EventWithTracks e = test::referenceEvent();
  PerformanceConfig config;
  config.matching.purity = 0.8;  // T2 (0.75) becomes a fake, P2 is lost
  config.includeBackground = true;
  PerformanceCollector collector(config);
  const PerformanceData d = analyse(collector, e);
  expectRatio(d.fakes, 3, 5, "fakes at 0.8");
  expectRatio(d.efficiency.all, 1, 3, "efficiency at 0.8");
  // Duplicates have no purity cut.
  expectRatio(d.duplicates, 2, 5, "duplicates at 0.8");
}

TEST(PerformanceCollector, ActsMatchingAsHeadline) {
  const EventWithTracks e = test::referenceEvent();
  PerformanceConfig config;
  config.matching.purity = 0.5;
  config.matching.doubleMatching = true;
  config.includeBackground = true;
  PerformanceCollector collector(config);
  const PerformanceData d = analyse(collector, e);
  expectRatio(d.efficiency.all, 2, 3, "efficiency");
  expectRatio(d.fakes, 2, 5, "fakes");
}

TEST(PerformanceCollector, SingleParticleTrackSelection) {
  const EventWithTracks e = test::referenceEvent();
  PerformanceCollector collector(PerformanceConfig::singleParticleSample());
  const PerformanceData d = analyse(collector, e);
  // nHits >= 3: T4 (noise, 3 hits) enters the selected rates.
  EXPECT_EQ(d.selectedTracks, 5u);
  expectRatio(d.selectedFakes, 2, 5, "selected fakes");
  // No pT cut in the theta plot: P1 and P2 (P3 fails R_vtx).
  expectRatio(d.efficiencyThetaPlotCuts, 2, 2, "theta plot cuts");
}

TEST(PerformanceCollector, EventWithoutTruthCountsOnlyTracksAndTimes) {
  EventWithTracks e = test::referenceEvent();
  e.event.truth.clear();
  PerformanceCollector collector(withBackground());
  const auto steps = test::twoSteps(1.5, 2.5);
  const PerformanceData d = collector.analyseEvent(
      e.event, e.tracks, 4.0, steps, EventTimes{10.0, 4.0, 3.0});
  EXPECT_EQ(d.eventsWithoutTruth, 1u);
  EXPECT_EQ(d.tracks, 5u);
  EXPECT_EQ(d.reconstructableParticles, 0u);
  EXPECT_EQ(d.fakes.total, 0u);
  EXPECT_DOUBLE_EQ(d.findingMs, 4.0);
  ASSERT_EQ(d.steps.size(), 2u);
  EXPECT_EQ(d.steps[1].name, "displaced");
}

TEST(PerformanceCollector, MergesCountsTimesAndSteps) {
  const EventWithTracks e = test::referenceEvent();
  PerformanceCollector collector(withBackground());
  for (std::size_t i = 0; i < 3; ++i) {
    collector.addEvent(i, e.event, e.tracks, 4.0, test::twoSteps(1.0 + i, 2.0),
                       EventTimes{10.0, 4.0 + i, 1.0});
  }
  const PerformanceSummary s = collector.summary();
  EXPECT_EQ(s.data.events, 3u);
  expectRatio(s.data.efficiency.all, 6, 9, "merged efficiency");
  expectRatio(s.data.fakes, 6, 15, "merged fakes");
  ASSERT_EQ(s.data.steps.size(), 2u);
  EXPECT_EQ(s.data.steps[0].name, "vertex_barrel");
  EXPECT_EQ(s.data.steps[0].seeds, 30u);
  EXPECT_DOUBLE_EQ(s.data.steps[0].milliseconds, 6.0);
  EXPECT_DOUBLE_EQ(s.findingMsPerEvent(), 5.0);
  EXPECT_DOUBLE_EQ(s.reconstructionMsPerEvent(), 6.0);
  EXPECT_DOUBLE_EQ(s.simulationMsPerEvent(), 10.0);
  std::uint64_t timed = 0;
  for (int i = 0; i < s.data.reconstructionMsPerEvent.axis().size(); ++i) {
    timed += s.data.reconstructionMsPerEvent.at(i);
  }
  EXPECT_EQ(timed, 3u);
  EXPECT_TRUE(s.resolutions.empty());
  EXPECT_TRUE(s.pulls.empty());
  EXPECT_THROW(collector.add(1, PerformanceData{}), std::invalid_argument);
}

std::string summaryText(const PerformanceCollector& collector) {
  nlohmann::ordered_json j =
      makeSummaryJson(RunMetadata{}, collector.summary());
  j.erase("peak_rss_mb");  // the process's memory, not a result
  return j.dump();
}

TEST(PerformanceCollector, MergeOrderDoesNotChangeResults) {
  PerformanceConfig config = PerformanceConfig::singleParticleSample();
  config.minFitEntries = 5;
  const std::size_t n = 60;
  PerformanceCollector reference(config);
  const std::vector<PerformanceData> events = test::mixedRun(reference, n);

  for (std::size_t i = 0; i < n; ++i) {
    reference.add(i, events[i]);
  }
  const std::string expected = summaryText(reference);

  PerformanceCollector reversed(config);
  for (std::size_t i = n; i-- > 0;) {
    reversed.add(i, events[i]);
  }
  EXPECT_EQ(summaryText(reversed), expected);

  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) {
    order[i] = i;
  }
  std::shuffle(order.begin(), order.end(), std::mt19937_64(7));
  PerformanceCollector shuffled(config);
  for (std::size_t i : order) {
    shuffled.add(i, events[i]);
  }
  EXPECT_EQ(summaryText(shuffled), expected);

  // Four threads, each adding a strided subset as it goes.
  PerformanceCollector threaded(config);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < n; i += 4) {
        threaded.add(i, events[i]);
      }
    });
  }
  for (std::thread& t : threads) {
    t.join();
  }
  EXPECT_EQ(summaryText(threaded), expected);
}

}  // namespace
}  // namespace conftrack

namespace conftrack {
namespace {

TEST(PerformanceCollector, HeadlineExcludesBackgroundByDefault) {
  const test::EventWithTracks e = test::referenceEvent();
  PerformanceCollector collector;
  const PerformanceData d =
      collector.analyseEvent(e.event, e.tracks, 4.0, {}, {});
  // P3, the background particle, is left out of the headline...
  EXPECT_EQ(d.reconstructableParticles, 2u);
  EXPECT_EQ(d.efficiency.all.total, 2u);
  // ...and reported on its own.
  EXPECT_EQ(d.backgroundEfficiency.all.total, 1u);
}

}  // namespace
}  // namespace conftrack

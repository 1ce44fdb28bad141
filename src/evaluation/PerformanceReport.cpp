#include "conftrack/evaluation/PerformanceReport.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <ostream>

namespace conftrack {

namespace {

using Json = nlohmann::ordered_json;

std::string versionOf(const RunMetadata& m) {
#ifdef CONFTRACK_VERSION
  return m.version.empty() ? std::string(CONFTRACK_VERSION) : m.version;
#else
  return m.version;
#endif
}

std::size_t eventsOf(const RunMetadata& m, const PerformanceSummary& s) {
  return m.events > 0 ? m.events : static_cast<std::size_t>(s.data.events);
}

/// A number, or null for NaN and infinities (JSON has neither).
Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json ratioJson(const Ratio& r) {
  Json j;
  j["passed"] = r.passed;
  j["total"] = r.total;
  j["value"] = number(r.value());
  j["uncertainty"] = number(r.uncertainty());
  return j;
}

Json efficiencyJson(const EfficiencyRatios& e) {
  Json j;
  j["all"] = number(e.all.value());
  j["pt_above_1GeV"] = number(e.ptAbove1GeV.value());
  j["pt_0p1_to_1GeV"] = number(e.ptBelow1GeV.value());
  return j;
}

Json fitJson(const GaussianFit& f) {
  Json j;
  j["mean"] = number(f.mean);
  j["width"] = number(f.sigma);
  j["mean_error"] = number(f.meanError);
  j["width_error"] = number(f.sigmaError);
  j["entries"] = f.entries;
  return j;
}

/// "97.12 +- 0.15 %  (passed/total)" or "n/a".
std::string percent(const Ratio& r, int digits = 2) {
  if (r.total == 0) {
    return "n/a";
  }
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "%.*f +- %.*f %%  (%llu/%llu)", digits,
                100.0 * r.value(), digits, 100.0 * r.uncertainty(),
                static_cast<unsigned long long>(r.passed),
                static_cast<unsigned long long>(r.total));
  return buffer;
}

std::string fixed(double x, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, x);
  return buffer;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> summaryTableRows(
    const RunMetadata& m, const PerformanceSummary& s) {
  const PerformanceData& d = s.data;
  std::vector<std::pair<std::string, std::string>> rows;
  rows.emplace_back(
      "sample",
      m.sample + (m.overlayBx > 0
                      ? " + " + std::to_string(m.overlayBx) + " BX overlay"
                      : ""));
  rows.emplace_back("detector",
                    m.detector + "  (Bz = " + fixed(d.bz, 2) + " T)");
  rows.emplace_back("events", std::to_string(d.events) + "  (seed " +
                                  std::to_string(m.seed) + ", " +
                                  std::to_string(m.threads) + " threads)");
  rows.emplace_back("reconstructable particles",
                    std::to_string(d.reconstructableParticles));
  rows.emplace_back("reconstructed tracks",
                    std::to_string(d.tracks) + "  (fitted " +
                        std::to_string(d.fittedTracks) + ")");
  rows.emplace_back("efficiency", percent(d.efficiency.all));
  rows.emplace_back("  pT > 1 GeV", percent(d.efficiency.ptAbove1GeV));
  rows.emplace_back("  0.1 <= pT <= 1 GeV", percent(d.efficiency.ptBelow1GeV));
  if (d.backgroundEfficiency.all.total > 0) {
    rows.emplace_back("  signal", percent(d.signalEfficiency.all));
    rows.emplace_back("  background", percent(d.backgroundEfficiency.all));
  }
  rows.emplace_back("  CLICdp cuts (vs theta)",
                    percent(d.efficiencyThetaPlotCuts));
  rows.emplace_back("  CLICdp cuts (vs pT)", percent(d.efficiencyPtPlotCuts));
  rows.emplace_back("fake rate", percent(d.fakes, 3));
  rows.emplace_back("duplicate rate (CLICdp)", percent(d.duplicates, 3));
  rows.emplace_back("ACTS efficiency / fake / dup.",
                    fixed(100.0 * d.actsEfficiency.value(), 2) + " / " +
                        fixed(100.0 * d.actsFakes.value(), 3) + " / " +
                        fixed(100.0 * d.actsDuplicates.value(), 3) + " %");
  rows.emplace_back("time per event [ms]",
                    "simulation " + fixed(s.simulationMsPerEvent(), 1) +
                        ", finding " + fixed(s.findingMsPerEvent(), 1) +
                        ", fitting " + fixed(s.fittingMsPerEvent(), 1));
  const double finding = d.findingMs > 0.0 ? d.findingMs : 1.0;
  for (const StepStats& step : d.steps) {
    rows.emplace_back(
        "  step " + step.name,
        fixed(d.events > 0 ? step.milliseconds / d.events : 0.0, 2) + " ms  (" +
            fixed(100.0 * step.milliseconds / finding, 1) + " % of finding)");
    for (std::size_t i = 0; i < kGuardCount; ++i) {
      const GuardCount& g = step.guards[i];
      if (g.bites > 0) {
        const auto guard = static_cast<Guard>(i);
        rows.emplace_back("    guard " + std::string(guardKey(guard)),
                          std::to_string(g.cut) + " " + guardCutUnit(guard) +
                              " cut in " + std::to_string(g.bites) + " " +
                              guardBiteUnit(guard));
      }
    }
  }
  rows.emplace_back("peak RSS", fixed(s.peakRssMb, 1) + " MiB");
  for (const PullResult& p : s.pulls) {
    rows.emplace_back("pull " + std::string(pullName(p.quantity)),
                      "mean " + fixed(p.fit.mean, 3) + ", width " +
                          fixed(p.fit.sigma, 3) + "  (" +
                          std::to_string(p.fit.entries) + " tracks)");
  }
  return rows;
}

Json makeSummaryJson(const RunMetadata& m, const PerformanceSummary& s) {
  const PerformanceData& d = s.data;
  const PerformanceConfig& c = s.config;
  Json j;
  j["version"] = versionOf(m);
  j["detector"] = m.detector;
  j["sample"] = m.sample;
  j["overlay_bx"] = m.overlayBx;
  j["events"] = eventsOf(m, s);
  j["seed"] = m.seed;
  j["threads"] = m.threads;
  if (m.shard.count > 1) {
    Json shard;
    shard["index"] = m.shard.index;
    shard["count"] = m.shard.count;
    shard["first_event"] = m.shard.firstEvent;
    j["shard"] = shard;
  }
  if (m.mergedShards > 0) {
    j["merged_shards"] = m.mergedShards;
  }
  j["bz_T"] = number(d.bz / units::T);
  j["events_evaluated"] = d.events;
  j["reconstructable_particles"] = d.reconstructableParticles;
  j["reconstructed_tracks"] = d.tracks;
  j["fitted_tracks"] = d.fittedTracks;
  j["efficiency"] = efficiencyJson(d.efficiency);
  j["fake_rate"] = number(d.fakes.value());
  j["duplicate_rate"] = number(d.duplicates.value());

  Json time;
  time["simulation"] = s.simulationMsPerEvent();
  time["finding"] = s.findingMsPerEvent();
  time["fitting"] = s.fittingMsPerEvent();
  time["reconstruction"] = s.reconstructionMsPerEvent();
  Json steps = Json::object();
  for (const StepStats& step : d.steps) {
    steps[step.name] =
        d.events > 0 ? step.milliseconds / double(d.events) : 0.0;
  }
  time["steps"] = steps;
  j["time_ms_per_event"] = time;
  Json total;
  total["simulation"] = d.simulationMs;
  total["finding"] = d.findingMs;
  total["fitting"] = d.fittingMs;
  j["time_ms_total"] = total;
  if (m.mergedShards > 0) {
    j["timing_note"] =
        "merged from " + std::to_string(m.mergedShards) +
        " shards: time_ms_total sums the shards' wall times, "
        "time_ms_per_event divides it by all events, peak_rss_mb is the "
        "largest shard's; threads is each shard's";
  }
  j["peak_rss_mb"] = number(s.peakRssMb);

  if (!s.pulls.empty()) {
    Json pulls;
    for (const PullResult& p : s.pulls) {
      pulls[std::string(pullName(p.quantity))] = fitJson(p.fit);
    }
    j["pulls"] = pulls;
    Json resolutions = Json::array();
    for (const ResolutionPoint& p : s.resolutions) {
      const double scale = residualScale(p.quantity);
      Json r;
      r["quantity"] = residualName(p.quantity);
      r["unit"] = residualUnit(p.quantity);
      r["theta_deg"] = number(p.theta / units::degree);
      r["pt_GeV"] = number(p.ptMean / units::GeV);
      r["entries"] = p.fit.entries;
      r["sigma"] = number(p.fit.sigma * scale);
      r["sigma_error"] = number(p.fit.sigmaError * scale);
      r["mean"] = number(p.fit.mean * scale);
      resolutions.push_back(r);
    }
    j["resolutions"] = resolutions;
  }

  // Extras.
  Json def;
  def["matching"] = c.matching.doubleMatching ? "double" : "CLICdp one-way";
  def["purity"] = c.matching.purity;
  def["min_track_hits"] = c.minTrackHits;
  def["reconstructable"] =
      "stable, charged, pT >= " + fixed(c.particles.minPt / units::GeV, 2) +
      " GeV, |cos theta| < " + fixed(c.particles.maxAbsCosTheta, 3) +
      ", >= " + std::to_string(c.particles.minLayers) + " distinct layers";
  Json cuts;
  cuts["min_pt_GeV"] = c.plotSelection.minPt / units::GeV;
  cuts["theta_range_deg"] = {c.plotSelection.minTheta / units::degree,
                             c.plotSelection.maxTheta / units::degree};
  cuts["max_vertex_radius_mm"] = c.plotSelection.maxVertexRadius / units::mm;
  cuts["min_proximity"] = c.plotSelection.minProximity;
  def["plot_cuts"] = cuts;
  def["single_particle"] = c.singleParticle;
  j["definitions"] = def;
  j["efficiency_signal"] = efficiencyJson(d.signalEfficiency);
  j["efficiency_background"] = efficiencyJson(d.backgroundEfficiency);
  Json plotCuts;
  plotCuts["theta_plot"] = number(d.efficiencyThetaPlotCuts.value());
  plotCuts["pt_plot"] = number(d.efficiencyPtPlotCuts.value());
  plotCuts["all_cuts"] = number(d.efficiencyAllPlotCuts.value());
  j["efficiency_plot_cuts"] = plotCuts;
  j["fake_rate_selected"] = number(d.selectedFakes.value());
  j["duplicate_rate_selected"] = number(d.selectedDuplicates.value());
  Json acts;
  acts["matching_ratio"] = c.actsMatchingRatio;
  acts["efficiency"] = number(d.actsEfficiency.value());
  acts["fake_rate"] = number(d.actsFakes.value());
  acts["duplicate_rate"] = number(d.actsDuplicates.value());
  j["acts"] = acts;

  Json counts;
  counts["efficiency_all"] = ratioJson(d.efficiency.all);
  counts["efficiency_pt_above_1GeV"] = ratioJson(d.efficiency.ptAbove1GeV);
  counts["efficiency_pt_0p1_to_1GeV"] = ratioJson(d.efficiency.ptBelow1GeV);
  counts["efficiency_signal"] = ratioJson(d.signalEfficiency.all);
  counts["efficiency_signal_pt_above_1GeV"] =
      ratioJson(d.signalEfficiency.ptAbove1GeV);
  counts["efficiency_signal_pt_0p1_to_1GeV"] =
      ratioJson(d.signalEfficiency.ptBelow1GeV);
  counts["efficiency_background"] = ratioJson(d.backgroundEfficiency.all);
  counts["efficiency_theta_plot_cuts"] = ratioJson(d.efficiencyThetaPlotCuts);
  counts["efficiency_pt_plot_cuts"] = ratioJson(d.efficiencyPtPlotCuts);
  counts["efficiency_all_plot_cuts"] = ratioJson(d.efficiencyAllPlotCuts);
  counts["fake_rate"] = ratioJson(d.fakes);
  counts["duplicate_rate"] = ratioJson(d.duplicates);
  counts["fake_rate_selected"] = ratioJson(d.selectedFakes);
  counts["duplicate_rate_selected"] = ratioJson(d.selectedDuplicates);
  counts["acts_efficiency"] = ratioJson(d.actsEfficiency);
  counts["acts_fake_rate"] = ratioJson(d.actsFakes);
  counts["acts_duplicate_rate"] = ratioJson(d.actsDuplicates);
  j["counts"] = counts;

  Json stepList = Json::array();
  for (const StepStats& step : d.steps) {
    Json st;
    st["name"] = step.name;
    st["ms_per_event"] =
        d.events > 0 ? step.milliseconds / double(d.events) : 0.0;
    st["seeds"] = step.seeds;
    st["cells"] = step.cells;
    st["paths"] = step.paths;
    st["candidates"] = step.candidates;
    st["accepted"] = step.accepted;
    st["extended_hits"] = step.extendedHits;
    st["overlap_hits"] = step.overlapHits;
    st["merged_tracks"] = step.mergedTracks;
    st["dropped_tracks"] = step.droppedTracks;
    st["hits_used"] = step.hitsUsed;
    // (Kept for readers of older summaries: the bites of two guards.)
    st["path_overflows"] = step.guard(Guard::ePathsPerSeed).bites;
    st["cell_overflows"] = step.guard(Guard::eCellsPerSeed).bites;
    st["recovered"] = step.recovered;
    st["cell_cache_flushes"] = step.cellCacheFlushes;
    Json guards;
    for (std::size_t i = 0; i < kGuardCount; ++i) {
      Json g;
      g["bites"] = step.guards[i].bites;
      g["cut"] = step.guards[i].cut;
      guards[guardKey(static_cast<Guard>(i))] = g;
    }
    st["guards"] = guards;
    stepList.push_back(st);
  }
  j["steps"] = stepList;
  return j;
}

void printSummaryTable(std::ostream& out, const RunMetadata& metadata,
                       const PerformanceSummary& summary) {
  const auto rows = summaryTableRows(metadata, summary);
  std::size_t width = 0;
  for (const auto& [label, value] : rows) {
    width = std::max(width, label.size());
  }
  out << "conftrack " << versionOf(metadata) << " performance summary\n";
  for (const auto& [label, value] : rows) {
    out << "  " << std::left << std::setw(static_cast<int>(width) + 2) << label
        << value << '\n';
  }
  out << std::right;
}

}  // namespace conftrack

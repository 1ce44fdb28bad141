#include "conftrack/evaluation/PerformanceDataJson.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/JsonEntry.hpp"
#include "conftrack/core/Units.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace conftrack {

namespace {

using Json = nlohmann::ordered_json;

/// Largest count accepted when reading (2^53: exact as a double too).
constexpr std::uint64_t kMaxCount = std::uint64_t{1} << 53;

/// A number, or null for NaN and infinities (JSON has neither).
Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

// One table per kind of field, so that writing and reading cannot drift
// apart: a field added to PerformanceData is added here once.

struct CountField {
  const char* key;
  std::uint64_t PerformanceData::*member;
};
constexpr std::array<CountField, 6> kCountFields{{
    {"events", &PerformanceData::events},
    {"events_without_truth", &PerformanceData::eventsWithoutTruth},
    {"reconstructable_particles", &PerformanceData::reconstructableParticles},
    {"tracks", &PerformanceData::tracks},
    {"fitted_tracks", &PerformanceData::fittedTracks},
    {"selected_tracks", &PerformanceData::selectedTracks},
}};

struct RatioField {
  const char* key;
  Ratio& (*get)(PerformanceData&);
};
#define CONFTRACK_RATIO(key, expr)                         \
  RatioField {                                             \
    key, [](PerformanceData& d) -> Ratio& { return expr; } \
  }
const std::array<RatioField, 19> kRatioFields{{
    CONFTRACK_RATIO("efficiency_all", d.efficiency.all),
    CONFTRACK_RATIO("efficiency_pt_above_1GeV", d.efficiency.ptAbove1GeV),
    CONFTRACK_RATIO("efficiency_pt_0p1_to_1GeV", d.efficiency.ptBelow1GeV),
    CONFTRACK_RATIO("signal_efficiency_all", d.signalEfficiency.all),
    CONFTRACK_RATIO("signal_efficiency_pt_above_1GeV",
                    d.signalEfficiency.ptAbove1GeV),
    CONFTRACK_RATIO("signal_efficiency_pt_0p1_to_1GeV",
                    d.signalEfficiency.ptBelow1GeV),
    CONFTRACK_RATIO("background_efficiency_all", d.backgroundEfficiency.all),
    CONFTRACK_RATIO("background_efficiency_pt_above_1GeV",
                    d.backgroundEfficiency.ptAbove1GeV),
    CONFTRACK_RATIO("background_efficiency_pt_0p1_to_1GeV",
                    d.backgroundEfficiency.ptBelow1GeV),
    CONFTRACK_RATIO("efficiency_theta_plot_cuts", d.efficiencyThetaPlotCuts),
    CONFTRACK_RATIO("efficiency_pt_plot_cuts", d.efficiencyPtPlotCuts),
    CONFTRACK_RATIO("efficiency_all_plot_cuts", d.efficiencyAllPlotCuts),
    CONFTRACK_RATIO("fakes", d.fakes),
    CONFTRACK_RATIO("duplicates", d.duplicates),
    CONFTRACK_RATIO("selected_fakes", d.selectedFakes),
    CONFTRACK_RATIO("selected_duplicates", d.selectedDuplicates),
    CONFTRACK_RATIO("acts_efficiency", d.actsEfficiency),
    CONFTRACK_RATIO("acts_fakes", d.actsFakes),
    CONFTRACK_RATIO("acts_duplicates", d.actsDuplicates),
}};
#undef CONFTRACK_RATIO

struct HistogramField {
  const char* key;
  RatioHistogram PerformanceData::*member;
};
constexpr std::array<HistogramField, 10> kHistogramFields{{
    {"efficiency_vs_pt", &PerformanceData::efficiencyVsPt},
    {"efficiency_vs_pt_all", &PerformanceData::efficiencyVsPtAll},
    {"efficiency_vs_theta", &PerformanceData::efficiencyVsTheta},
    {"efficiency_vs_phi", &PerformanceData::efficiencyVsPhi},
    {"efficiency_vs_vertex_radius", &PerformanceData::efficiencyVsVertexRadius},
    {"efficiency_vs_proximity", &PerformanceData::efficiencyVsProximity},
    {"fake_rate_vs_pt", &PerformanceData::fakeRateVsPt},
    {"fake_rate_vs_theta", &PerformanceData::fakeRateVsTheta},
    {"duplicate_rate_vs_pt", &PerformanceData::duplicateRateVsPt},
    {"duplicate_rate_vs_theta", &PerformanceData::duplicateRateVsTheta},
}};

struct StepCounter {
  const char* key;
  std::uint64_t StepStats::*member;
  /// Absent from files written before the counter existed (read as 0).
  bool optional = false;
};
constexpr std::array<StepCounter, 12> kStepCounters{{
    {"seeds", &StepStats::seeds},
    {"cells", &StepStats::cells},
    {"paths", &StepStats::paths},
    {"candidates", &StepStats::candidates},
    {"accepted", &StepStats::accepted},
    {"extended_hits", &StepStats::extendedHits},
    {"overlap_hits", &StepStats::overlapHits},
    {"merged_tracks", &StepStats::mergedTracks},
    {"dropped_tracks", &StepStats::droppedTracks, true},
    {"hits_used", &StepStats::hitsUsed},
    {"recovered", &StepStats::recovered},
    {"cell_cache_flushes", &StepStats::cellCacheFlushes},
}};

/// Bin edges of a histogram axis (native units).
template <class Axis>
std::vector<double> edgesOf(const Axis& axis) {
  std::vector<double> edges;
  for (int i = 0; i <= axis.size(); ++i) {
    edges.push_back(axis.value(i));
  }
  return edges;
}

Json metadataJson(const RunMetadata& m) {
  Json j;
  j["version"] = m.version;
  j["detector"] = m.detector;
  j["sample"] = m.sample;
  j["overlay_bx"] = m.overlayBx;
  j["events"] = m.events;
  j["seed"] = m.seed;
  j["threads"] = m.threads;
  j["shard_index"] = m.shard.index;
  j["shard_count"] = m.shard.count;
  j["first_event"] = m.shard.firstEvent;
  j["merged_shards"] = m.mergedShards;
  return j;
}

}  // namespace

Json makePerformanceConfigJson(const PerformanceConfig& c) {
  Json j;
  j["particles_min_pt_GeV"] = c.particles.minPt / units::GeV;
  j["particles_max_abs_cos_theta"] = c.particles.maxAbsCosTheta;
  j["particles_min_layers"] = c.particles.minLayers;
  j["include_background"] = c.includeBackground;
  j["matching_purity"] = c.matching.purity;
  j["matching_double"] = c.matching.doubleMatching;
  j["acts_matching_ratio"] = c.actsMatchingRatio;
  j["min_track_hits"] = c.minTrackHits;
  j["plot_min_pt_GeV"] = c.plotSelection.minPt / units::GeV;
  j["plot_min_theta_rad"] = c.plotSelection.minTheta / units::rad;
  j["plot_max_theta_rad"] = c.plotSelection.maxTheta / units::rad;
  j["plot_max_vertex_radius_mm"] = c.plotSelection.maxVertexRadius / units::mm;
  j["plot_min_proximity"] = c.plotSelection.minProximity;
  j["single_particle"] = c.singleParticle;
  Json thetas = Json::array();
  for (double t : c.resolutionThetas) {
    thetas.push_back(t / units::rad);
  }
  j["resolution_thetas_rad"] = thetas;
  j["resolution_theta_window_rad"] = c.resolutionThetaWindow / units::rad;
  Json edges = Json::array();
  for (double e : c.resolutionPtEdges) {
    edges.push_back(e / units::GeV);
  }
  j["resolution_pt_edges_GeV"] = edges;
  j["min_fit_entries"] = c.minFitEntries;
  return j;
}

namespace {

Json dataJson(const PerformanceData& constData) {
  // The field tables hand out mutable references; nothing is changed.
  auto& d = const_cast<PerformanceData&>(constData);
  Json j;
  for (const CountField& f : kCountFields) {
    j[f.key] = d.*f.member;
  }
  j["bz_T"] = d.bz / units::T;
  Json ratios;
  for (const RatioField& f : kRatioFields) {
    const Ratio& r = f.get(d);
    ratios[f.key] = Json::array({r.passed, r.total});
  }
  j["ratios"] = ratios;
  Json histograms;
  for (const HistogramField& f : kHistogramFields) {
    const RatioHistogram& h = d.*f.member;
    Json passed = Json::array();
    Json total = Json::array();
    for (int i = -1; i <= static_cast<int>(h.size()); ++i) {
      passed.push_back(h.counts(i).passed);
      total.push_back(h.counts(i).total);
    }
    Json one;
    one["edges"] = edgesOf(h.denominator().axis());
    one["passed"] = passed;
    one["total"] = total;
    histograms[f.key] = one;
  }
  j["histograms"] = histograms;
  Json timeHistogram;
  const auto& th = d.reconstructionMsPerEvent;
  timeHistogram["edges"] = edgesOf(th.axis());
  Json counts = Json::array();
  for (int i = -1; i <= th.axis().size(); ++i) {
    counts.push_back(th.at(i));
  }
  timeHistogram["counts"] = counts;
  j["reconstruction_ms_per_event"] = timeHistogram;

  Json residuals = Json::array();
  for (const TrackResidual& r : d.residuals) {
    Json row = Json::array(
        {number(r.truePt / units::GeV), number(r.trueTheta / units::rad)});
    for (double x : r.residuals) {
      row.push_back(number(x));
    }
    for (double x : r.pulls) {
      row.push_back(number(x));
    }
    residuals.push_back(row);
  }
  j["residuals"] = residuals;

  // Wall-time sums, in ms as PerformanceData keeps them.
  Json time;
  time["simulation"] = d.simulationMs;
  time["finding"] = d.findingMs;
  time["fitting"] = d.fittingMs;
  j["time_ms"] = time;
  Json steps = Json::array();
  for (const StepStats& s : d.steps) {
    Json step;
    step["name"] = s.name;
    for (const StepCounter& c : kStepCounters) {
      step[c.key] = s.*c.member;
    }
    Json guards;
    for (std::size_t g = 0; g < kGuardCount; ++g) {
      guards[guardKey(static_cast<Guard>(g))] =
          Json::array({s.guards[g].bites, s.guards[g].cut});
    }
    step["guards"] = guards;
    step["ms"] = s.milliseconds;
    steps.push_back(step);
  }
  j["steps"] = steps;
  return j;
}

RunMetadata readMetadata(const JsonEntry& e) {
  RunMetadata m;
  m.version = e.text("version");
  m.detector = e.text("detector");
  m.sample = e.text("sample");
  m.overlayBx = e.count("overlay_bx", 0, kMaxCount);
  m.events = e.count("events", 0, kMaxCount);
  m.seed = e.count("seed", 0, std::numeric_limits<std::uint64_t>::max());
  m.threads = e.count("threads", 0, kMaxCount);
  m.shard.count = e.count("shard_count", 1, kMaxCount);
  m.shard.index = e.count("shard_index", 0, m.shard.count - 1);
  m.shard.firstEvent = e.count("first_event", 0, kMaxCount);
  m.mergedShards = e.count("merged_shards", 0, kMaxCount);
  return m;
}

PerformanceConfig readConfig(const JsonEntry& e) {
  PerformanceConfig c;
  c.particles.minPt = e.nonNegative("particles_min_pt_GeV") * units::GeV;
  c.particles.maxAbsCosTheta = e.nonNegative("particles_max_abs_cos_theta");
  c.particles.minLayers =
      static_cast<std::uint32_t>(e.count("particles_min_layers", 0, 1000));
  c.includeBackground = e.boolean("include_background");
  c.matching.purity = e.nonNegative("matching_purity");
  c.matching.doubleMatching = e.boolean("matching_double");
  c.actsMatchingRatio = e.nonNegative("acts_matching_ratio");
  c.minTrackHits =
      static_cast<std::uint32_t>(e.count("min_track_hits", 0, 100000));
  c.plotSelection.minPt = e.nonNegative("plot_min_pt_GeV") * units::GeV;
  c.plotSelection.minTheta = e.number("plot_min_theta_rad") * units::rad;
  c.plotSelection.maxTheta = e.number("plot_max_theta_rad") * units::rad;
  c.plotSelection.maxVertexRadius =
      e.nonNegative("plot_max_vertex_radius_mm") * units::mm;
  c.plotSelection.minProximity = e.nonNegative("plot_min_proximity");
  c.singleParticle = e.boolean("single_particle");
  c.resolutionThetas.clear();
  for (double t : e.numbers("resolution_thetas_rad")) {
    c.resolutionThetas.push_back(t * units::rad);
  }
  c.resolutionThetaWindow =
      e.nonNegative("resolution_theta_window_rad") * units::rad;
  c.resolutionPtEdges.clear();
  for (double p : e.numbers("resolution_pt_edges_GeV")) {
    c.resolutionPtEdges.push_back(p * units::GeV);
  }
  c.minFitEntries = e.count("min_fit_entries", 0, kMaxCount);
  return c;
}

/// Refuses a histogram whose "edges" are not `edges` (this version's).
void checkEdges(const JsonEntry& e, const std::vector<double>& edges) {
  if (e.numbers("edges") != edges) {
    e.fail("edges", "bin edges differ from this version's (" +
                        std::to_string(edges.size()) + " edges from " +
                        std::to_string(edges.front()) + " to " +
                        std::to_string(edges.back()) + ")");
  }
}

/// The counts of `key`: one per bin of a histogram with `edges` edges, plus
/// under- and overflow.
std::vector<std::uint64_t> histogramCounts(const JsonEntry& e,
                                           std::string_view key,
                                           std::size_t edges) {
  std::vector<std::uint64_t> counts = e.counts(key, edges + 1);
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] > kMaxCount) {
      e.fail(std::string(key) + "[" + std::to_string(i) + "]",
             "count too large");
    }
  }
  return counts;
}

Ratio readRatio(const JsonEntry& e, std::string_view key) {
  const std::vector<std::uint64_t> v = e.counts(key, 2);
  if (v[0] > v[1] || v[1] > kMaxCount) {
    e.fail(key, "expected [passed, total] with passed <= total");
  }
  return Ratio{v[0], v[1]};
}

void readData(const JsonEntry& e, PerformanceData& d) {
  for (const CountField& f : kCountFields) {
    d.*f.member = e.count(f.key, 0, kMaxCount);
  }
  d.bz = e.number("bz_T") * units::T;
  const JsonEntry ratios = e.object("ratios");
  for (const RatioField& f : kRatioFields) {
    f.get(d) = readRatio(ratios, f.key);
  }
  const JsonEntry histograms = e.object("histograms");
  for (const HistogramField& f : kHistogramFields) {
    RatioHistogram& h = d.*f.member;
    const JsonEntry one = histograms.object(f.key);
    const std::vector<double> edges = edgesOf(h.denominator().axis());
    checkEdges(one, edges);
    const std::vector<std::uint64_t> passed =
        histogramCounts(one, "passed", edges.size());
    const std::vector<std::uint64_t> total =
        histogramCounts(one, "total", edges.size());
    for (std::size_t i = 0; i < total.size(); ++i) {
      if (passed[i] > total[i]) {
        one.fail("passed[" + std::to_string(i) + "]",
                 "more passed than total entries");
      }
      h.setCounts(static_cast<int>(i) - 1, Ratio{passed[i], total[i]});
    }
  }
  auto& th = d.reconstructionMsPerEvent;
  const JsonEntry timeHistogram = e.object("reconstruction_ms_per_event");
  const std::vector<double> timeEdges = edgesOf(th.axis());
  checkEdges(timeHistogram, timeEdges);
  const std::vector<std::uint64_t> counts =
      histogramCounts(timeHistogram, "counts", timeEdges.size());
  for (std::size_t i = 0; i < counts.size(); ++i) {
    th.at(static_cast<int>(i) - 1) = counts[i];
  }

  const nlohmann::json& rows = e.get("residuals");
  if (!rows.is_array()) {
    e.fail("residuals", "expected an array");
  }
  constexpr std::size_t kColumns =
      2 + eNumResidualQuantities + eNumPullQuantities;
  d.residuals.clear();
  d.residuals.reserve(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const nlohmann::json& row = rows[r];
    const std::string key = "residuals[" + std::to_string(r) + "]";
    if (!row.is_array() || row.size() != kColumns) {
      e.fail(key, "expected an array of " + std::to_string(kColumns) +
                      " numbers or nulls");
    }
    std::array<double, kColumns> values{};
    for (std::size_t c = 0; c < kColumns; ++c) {
      if (row[c].is_null()) {
        values[c] = std::numeric_limits<double>::quiet_NaN();
      } else if (row[c].is_number() && std::isfinite(row[c].get<double>())) {
        values[c] = row[c].get<double>();
      } else {
        e.fail(key, "expected numbers or nulls");
      }
    }
    TrackResidual residual;
    residual.truePt = values[0] * units::GeV;
    residual.trueTheta = values[1] * units::rad;
    for (std::size_t q = 0; q < eNumResidualQuantities; ++q) {
      residual.residuals[q] = values[2 + q];
    }
    for (std::size_t q = 0; q < eNumPullQuantities; ++q) {
      residual.pulls[q] = values[2 + eNumResidualQuantities + q];
    }
    d.residuals.push_back(residual);
  }

  const JsonEntry time = e.object("time_ms");
  d.simulationMs = time.nonNegative("simulation");
  d.findingMs = time.nonNegative("finding");
  d.fittingMs = time.nonNegative("fitting");
  d.steps.clear();
  for (const JsonEntry& s : e.objects("steps")) {
    StepStats step;
    step.name = s.text("name");
    for (const StepCounter& c : kStepCounters) {
      if (c.optional && !s.has(c.key)) {
        continue;
      }
      step.*c.member = s.count(c.key, 0, kMaxCount);
    }
    const JsonEntry guards = s.object("guards");
    for (std::size_t g = 0; g < kGuardCount; ++g) {
      const char* key = guardKey(static_cast<Guard>(g));
      if (!guards.has(key)) {
        continue;  // written before this guard existed: it never bit
      }
      const std::vector<std::uint64_t> v = guards.counts(key, 2);
      step.guards[g] = GuardCount{v[0], v[1]};
    }
    step.milliseconds = s.nonNegative("ms");
    d.steps.push_back(std::move(step));
  }
}

}  // namespace

Json makePerformanceDataJson(const RunMetadata& metadata,
                             const PerformanceSummary& summary) {
  Json j;
  j["format"] = "conftrack performance data";
  j["format_version"] = kPerformanceDataFormatVersion;
  RunMetadata m = metadata;
#ifdef CONFTRACK_VERSION
  if (m.version.empty()) {
    m.version = CONFTRACK_VERSION;
  }
#endif
  j["metadata"] = metadataJson(m);
  j["peak_rss_mb"] = number(summary.peakRssMb);
  j["config"] = makePerformanceConfigJson(summary.config);
  j["data"] = dataJson(summary.data);
  return j;
}

SavedPerformance parsePerformanceDataJson(const nlohmann::json& json,
                                          std::string_view source) {
  const std::string name(source);
  if (!json.is_object()) {
    throw InputError(name, "expected a JSON object");
  }
  const JsonEntry root(json, "", name);
  if (root.text("format") != "conftrack performance data") {
    root.fail("format", "expected \"conftrack performance data\"");
  }
  const std::uint64_t version = root.count("format_version", 0, 1000000);
  if (version != kPerformanceDataFormatVersion) {
    root.fail("format_version",
              "version " + std::to_string(version) + " is not the " +
                  std::to_string(kPerformanceDataFormatVersion) +
                  " this conftrack reads");
  }
  SavedPerformance saved;
  saved.metadata = readMetadata(root.object("metadata"));
  saved.peakRssMb = root.numberOrNull("peak_rss_mb");
  saved.config = readConfig(root.object("config"));
  readData(root.object("data"), saved.data);
  return saved;
}

}  // namespace conftrack

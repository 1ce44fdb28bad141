/// @file EvaluationBindings.cpp
/// Evaluation for Python: the performance summary of events and their
/// reconstruction (the numbers of summary.json and the histograms as
/// arrays) and the TrackML score of a submission.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/evaluation/PerformanceCollector.hpp"
#include "conftrack/evaluation/PerformanceReport.hpp"
#include "conftrack/evaluation/TrackmlScore.hpp"

#include <nlohmann/json.hpp>

#include <pybind11/stl.h>
#include <string>
#include <vector>

#include "Bindings.hpp"
#include "Columns.hpp"
#include "Handles.hpp"

namespace conftrack::python {

namespace {

/// A ratio histogram: edges (in `unit`), passed and total per bin, their
/// ratio and its binomial uncertainty.
py::dict ratioHistogram(const RatioHistogram& h, double unit) {
  const std::size_t n = h.size();
  py::dict d;
  d["edges"] = column<double>(n + 1, [&](auto i) {
    return (i < n ? h.lowerEdge(i) : h.upperEdge(n - 1)) / unit;
  });
  d["passed"] =
      column<std::int64_t>(n, [&](auto i) { return h.bin(i).passed; });
  d["total"] = column<std::int64_t>(n, [&](auto i) { return h.bin(i).total; });
  d["value"] = column<double>(n, [&](auto i) { return h.bin(i).value(); });
  d["uncertainty"] =
      column<double>(n, [&](auto i) { return h.bin(i).uncertainty(); });
  return d;
}

py::dict countHistogram(const CountHistogram& h, double unit) {
  const auto n = static_cast<std::size_t>(h.axis().size());
  py::dict d;
  d["edges"] = column<double>(n + 1, [&](auto i) {
    const int b = static_cast<int>(i < n ? i : n - 1);
    return (i < n ? h.axis().bin(b).lower() : h.axis().bin(b).upper()) / unit;
  });
  d["counts"] = column<std::int64_t>(
      n, [&](auto i) { return h.at(static_cast<int>(i)); });
  return d;
}

/// The distributions of the report (the CSV files of `conftrack run`), in
/// the same units: GeV, degrees, mm, rad, ms.
py::dict histograms(const PerformanceSummary& s) {
  const PerformanceData& d = s.data;
  py::dict h;
  h["efficiency_vs_pt"] = ratioHistogram(d.efficiencyVsPt, units::GeV);
  h["efficiency_vs_pt_all"] = ratioHistogram(d.efficiencyVsPtAll, units::GeV);
  h["efficiency_vs_theta"] = ratioHistogram(d.efficiencyVsTheta, units::degree);
  h["efficiency_vs_phi"] = ratioHistogram(d.efficiencyVsPhi, units::degree);
  h["efficiency_vs_vertex_radius"] =
      ratioHistogram(d.efficiencyVsVertexRadius, units::mm);
  h["efficiency_vs_proximity"] = ratioHistogram(d.efficiencyVsProximity, 1.0);
  h["fake_rate_vs_pt"] = ratioHistogram(d.fakeRateVsPt, units::GeV);
  h["fake_rate_vs_theta"] = ratioHistogram(d.fakeRateVsTheta, units::degree);
  h["duplicate_rate_vs_pt"] = ratioHistogram(d.duplicateRateVsPt, units::GeV);
  h["duplicate_rate_vs_theta"] =
      ratioHistogram(d.duplicateRateVsTheta, units::degree);
  h["time_per_event"] = countHistogram(d.reconstructionMsPerEvent, 1.0);
  return h;
}

/// The summary of the events and their results, and summary.json as text.
std::pair<PerformanceSummary, std::string> evaluate(
    const std::vector<const EventHandle*>& events,
    const std::vector<const ResultHandle*>& results, bool singleParticle,
    const std::string& sample) {
  if (events.size() != results.size()) {
    throw InputError("evaluate: " + std::to_string(events.size()) +
                     " events but " + std::to_string(results.size()) +
                     " results");
  }
  PerformanceCollector collector(singleParticle
                                     ? PerformanceConfig::singleParticleSample()
                                     : PerformanceConfig{});
  std::string detector;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const Event& event = *events[i]->event;
    const ResultHandle& r = *results[i];
    if (!event.hasTruth()) {
      throw InputError("evaluate: event " + std::to_string(event.number) +
                       " has no truth: nothing to evaluate against");
    }
    if (event.hits.size() != r.hits.size()) {
      throw InputError("evaluate: event " + std::to_string(event.number) +
                       " has " + std::to_string(event.hits.size()) +
                       " hits, its result " + std::to_string(r.hits.size()) +
                       ": results must be in the order of the events");
    }
    if (events[i]->detector) {
      detector = events[i]->detector->name();
    }
    collector.addEvent(
        i, event, r.result.tracks, r.bz, r.result.steps,
        {0.0, r.result.findingMs, r.result.fittingMs + r.result.selectionMs});
  }
  PerformanceSummary summary = collector.summary();
  RunMetadata meta;
  meta.detector = detector;
  meta.sample = sample;
  meta.events = events.size();
  std::string json = makeSummaryJson(meta, summary).dump();
  return {std::move(summary), std::move(json)};
}

py::dict score(const py::handle& truth, const py::handle& submission,
               const py::object& particles) {
  Event event;
  // The hits are the truth's rows: the score needs only their ids.
  event.hits = hitIdsFromColumns(truth, "truth");
  event.truth = truthFromColumns(truth, event.hits);
  if (!particles.is_none()) {
    event.particles = particlesFromColumns(particles);
  }
  const std::vector<std::uint64_t> labels =
      labelsFromColumns(submission, event.hits);
  TrackmlScore s;
  {
    py::gil_scoped_release release;
    s = scoreTrackml(event, labels);
  }
  py::dict d;
  d["score"] = s.score;
  d["total_weight"] = s.totalWeight;
  d["weights_computed"] = s.weightsComputed;
  d["tracks"] = s.nTracks;
  d["good_tracks"] = s.nGoodTracks;
  d["reconstructable"] = s.nReconstructable;
  d["reconstructed"] = s.nReconstructed;
  d["efficiency"] = s.efficiency;
  d["selected_tracks"] = s.nSelectedTracks;
  d["fake_tracks"] = s.nFakeTracks;
  d["fake_rate"] = s.fakeRate;
  return d;
}

}  // namespace

void bindEvaluation(py::module_& m) {
  m.def(
      "evaluate",
      [](const std::vector<const EventHandle*>& events,
         const std::vector<const ResultHandle*>& results, bool singleParticle,
         const std::string& sample) {
        std::pair<PerformanceSummary, std::string> r;
        {
          py::gil_scoped_release release;
          r = evaluate(events, results, singleParticle, sample);
        }
        return py::make_tuple(r.second, histograms(r.first));
      },
      py::arg("events"), py::arg("results"), py::arg("single_particle"),
      py::arg("sample"));
  m.def("trackml_score", &score, py::arg("truth"), py::arg("submission"),
        py::arg("particles") = py::none());
}

}  // namespace conftrack::python

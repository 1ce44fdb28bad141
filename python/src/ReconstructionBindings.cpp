/// @file ReconstructionBindings.cpp
/// Reconstruction for Python: a configured Reconstruction run on one event
/// or on many in parallel (the GIL released), and the tables of a result.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/evaluation/TrackmlScore.hpp"
#include "conftrack/frontend/ReconstructionSetup.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <pybind11/stl.h>
#include <string>
#include <utility>
#include <vector>

#include "Bindings.hpp"
#include "Columns.hpp"
#include "Handles.hpp"
#include "Parallel.hpp"

namespace conftrack::python {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// A detector's reconstruction as the CLI sets it up.
class Reconstructor {
 public:
  /// `beamSpot`: (x, y) [mm] of the beam line, or none (the chain's).
  Reconstructor(const DetectorHandle& detector, const std::string& chain,
                bool fit, int fitPdg, bool moduleLevel,
                std::optional<std::pair<double, double>> beamSpot)
      : m_detector(detector.detector) {
    ReconstructionChoice choice;
    choice.detector = detector.source;
    choice.chain = chain;
    choice.fit = fit;
    choice.fitPdg = fitPdg;
    if (beamSpot) {
      choice.beamSpot =
          Vector2(beamSpot->first * units::mm, beamSpot->second * units::mm);
    }
    m_reco = std::make_unique<Reconstruction>(
        *m_detector, makeReconstructionConfig(choice, *m_detector),
        loadSensorLayout(*m_detector, moduleLevel));
  }

  /// Needs the GIL.
  ResultHandle convert(const py::handle& hits) const {
    ResultHandle r;
    r.bz = m_detector->bz();
    auto t0 = Clock::now();
    r.hits = hitsFromColumns(hits, m_detector.get());
    r.conversionMs = millisecondsSince(t0);
    return r;
  }

  ResultHandle run(const py::handle& hits) const {
    ResultHandle r = convert(hits);
    py::gil_scoped_release release;
    r.result = m_reco->run(r.hits);
    return r;
  }

  std::vector<ResultHandle> runMany(const py::list& events,
                                    std::size_t threads) const {
    std::vector<ResultHandle> results;
    results.reserve(events.size());
    for (const py::handle& hits : events) {
      try {
        results.push_back(convert(hits));
      } catch (const InputError& e) {
        // Name the event: "events[3]: hits row 12: ...".
        throw InputError("events[" + std::to_string(results.size()) +
                         "]: " + e.what());
      }
    }
    // Largest events first (cost grows faster than the hit count), so that
    // the last events to start are short ones and the threads finish
    // together; each event's result does not depend on the order.
    std::vector<std::size_t> order(results.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) {
                       return results[a].hits.size() > results[b].hits.size();
                     });
    py::gil_scoped_release release;
    forEachIndex(results.size(), threads, [&](std::size_t k) {
      ResultHandle& r = results[order[k]];
      r.result = m_reco->run(r.hits);
    });
    return results;
  }

 private:
  std::shared_ptr<const Detector> m_detector;
  std::unique_ptr<Reconstruction> m_reco;
};

/// pT of a track [GeV]: from the fitted curvature, else the finder's.
double trackPt(const Track& t, double bz) {
  const double omega = t.atIp.parameters[eOmega];
  if (t.fitted && omega != 0.0) {
    return std::abs(constants::kPtPerTeslaMm * bz / omega) / units::GeV;
  }
  return t.ptEstimate / units::GeV;
}

py::dict trackColumns(const ResultHandle& r) {
  const auto& tracks = r.result.tracks;
  const std::size_t n = tracks.size();
  auto par = [&](int k, double unit) {
    return column<double>(
        n, [&](auto i) { return tracks[i].atIp.parameters[k] / unit; });
  };
  py::dict c;
  c["track_id"] = column<std::int64_t>(n, [](auto i) { return i + 1; });
  c["d0"] = par(eD0, units::mm);
  c["phi0"] = par(ePhi0, 1.0);
  c["omega"] = par(eOmega, 1.0 / units::mm);
  c["z0"] = par(eZ0, units::mm);
  c["tan_lambda"] = par(eTanLambda, 1.0);
  c["pt"] = column<double>(n, [&](auto i) { return trackPt(tracks[i], r.bz); });
  c["chi2"] = column<double>(n, [&](auto i) { return tracks[i].chi2; });
  c["ndf"] = column<std::int64_t>(n, [&](auto i) { return tracks[i].ndf; });
  c["n_hits"] =
      column<std::int64_t>(n, [&](auto i) { return tracks[i].hits.size(); });
  c["n_outliers"] =
      column<std::int64_t>(n, [&](auto i) { return tracks[i].numOutliers(); });
  c["fitted"] = column<bool>(n, [&](auto i) { return tracks[i].fitted; });
  c["step"] =
      column<std::int64_t>(n, [&](auto i) { return tracks[i].findingStep; });
  c["pt_estimate"] = column<double>(
      n, [&](auto i) { return tracks[i].ptEstimate / units::GeV; });
  // The perigee's reference: the beam line the fit took it about.
  c["ref_x"] = column<double>(
      n, [&](auto i) { return tracks[i].atIp.reference.x() / units::mm; });
  c["ref_y"] = column<double>(
      n, [&](auto i) { return tracks[i].atIp.reference.y() / units::mm; });
  return c;
}

/// The covariances of the tracks at the IP, shape (n, 5, 5), in the units
/// of the parameters (mm, rad, 1/mm).
py::array_t<double> covariances(const ResultHandle& r) {
  const auto& tracks = r.result.tracks;
  py::array_t<double> a({static_cast<py::ssize_t>(tracks.size()),
                         py::ssize_t{5}, py::ssize_t{5}});
  double* data = a.mutable_data();
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    for (int row = 0; row < 5; ++row) {
      for (int col = 0; col < 5; ++col) {
        data[i * 25 + static_cast<std::size_t>(row * 5 + col)] =
            tracks[i].atIp.covariance(row, col);
      }
    }
  }
  return a;
}

/// One row per hit of a track, in track order and along the path.
py::dict trackHitColumns(const ResultHandle& r) {
  std::vector<std::int64_t> track;
  std::vector<std::int64_t> hit;
  std::vector<std::int64_t> outlier;  // HitUse, as in the track files
  const auto& tracks = r.result.tracks;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    for (std::size_t k = 0; k < tracks[t].hits.size(); ++k) {
      track.push_back(static_cast<std::int64_t>(t + 1));
      hit.push_back(static_cast<std::int64_t>(r.hits[tracks[t].hits[k]].id));
      outlier.push_back(tracks[t].outlier.empty() ? 0 : tracks[t].outlier[k]);
    }
  }
  py::dict c;
  c["track_id"] =
      column<std::int64_t>(track.size(), [&](auto i) { return track[i]; });
  c["hit_id"] =
      column<std::int64_t>(hit.size(), [&](auto i) { return hit[i]; });
  c["outlier"] =
      column<std::int64_t>(outlier.size(), [&](auto i) { return outlier[i]; });
  return c;
}

/// The TrackML submission: every hit with its track (0: none).
py::dict hitTrackColumns(const ResultHandle& r) {
  std::vector<std::vector<HitIndex>> lists;
  lists.reserve(r.result.tracks.size());
  for (const Track& t : r.result.tracks) {
    lists.push_back(t.hits);
  }
  std::vector<std::uint64_t> labels = trackmlLabels(r.hits.size(), lists);
  py::dict c;
  c["hit_id"] =
      column<std::int64_t>(r.hits.size(), [&](auto i) { return r.hits[i].id; });
  c["track_id"] =
      column<std::int64_t>(labels.size(), [&](auto i) { return labels[i]; });
  return c;
}

/// The finder's statistics, one dict per step.
py::list stepRows(const ResultHandle& r) {
  py::list rows;
  for (const StepStats& s : r.result.steps) {
    py::dict d;
    d["step"] = s.name;
    d["ms"] = s.milliseconds;
    d["seeds"] = s.seeds;
    d["cells"] = s.cells;
    d["paths"] = s.paths;
    d["candidates"] = s.candidates;
    d["accepted"] = s.accepted;
    d["extended_hits"] = s.extendedHits;
    d["overlap_hits"] = s.overlapHits;
    d["merged_tracks"] = s.mergedTracks;
    d["dropped_tracks"] = s.droppedTracks;
    d["hits_used"] = s.hitsUsed;
    d["recovered"] = s.recovered;
    d["cell_cache_flushes"] = s.cellCacheFlushes;
    d["truncated"] = s.truncated();
    rows.append(d);
  }
  return rows;
}

py::dict statistics(const ResultHandle& r) {
  py::dict d;
  d["hits"] = r.hits.size();
  d["tracks"] = r.result.tracks.size();
  d["candidates"] = r.result.candidates;
  d["fit_failures"] = r.result.fitFailures;
  d["second_pass_tracks"] = r.result.secondPassTracks;
  d["reassigned_hits"] = r.result.reassignedHits;
  d["finding_ms"] = r.result.findingMs;
  d["fitting_ms"] = r.result.fittingMs;
  d["selection_ms"] = r.result.selectionMs;
  d["conversion_ms"] = r.conversionMs;
  return d;
}

}  // namespace

void bindReconstruction(py::module_& m) {
  py::class_<ResultHandle>(m, "Result")
      .def("track_columns", &trackColumns)
      .def("covariances", &covariances)
      .def("track_hit_columns", &trackHitColumns)
      .def("hit_track_columns", &hitTrackColumns)
      .def("step_rows", &stepRows)
      .def("statistics", &statistics);

  py::class_<Reconstructor>(m, "Reconstructor")
      .def(py::init<const DetectorHandle&, const std::string&, bool, int, bool,
                    std::optional<std::pair<double, double>>>(),
           py::arg("detector"), py::arg("chain"), py::arg("fit"),
           py::arg("fit_pdg"), py::arg("module_level"), py::arg("beam_spot"))
      .def("run", &Reconstructor::run, py::arg("hits"))
      .def("run_many", &Reconstructor::runMany, py::arg("events"),
           py::arg("threads"));
}

}  // namespace conftrack::python

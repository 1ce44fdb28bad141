/// @file EventBindings.cpp
/// Events for Python: TrackML files read, samples simulated (in parallel,
/// the GIL released), and their tables.

#include "conftrack/core/Error.hpp"
#include "conftrack/frontend/ReconstructionSetup.hpp"
#include "conftrack/io/TrackmlReader.hpp"
#include "conftrack/simulation/EventSimulation.hpp"

#include <limits>
#include <optional>
#include <pybind11/stl.h>
#include <string>
#include <vector>

#include "Bindings.hpp"
#include "Columns.hpp"
#include "Handles.hpp"
#include "Parallel.hpp"

namespace conftrack::python {

namespace {

std::shared_ptr<const Detector> detectorOf(const DetectorHandle* handle) {
  return handle != nullptr ? handle->detector : nullptr;
}

/// Everything simulate() takes besides the detector.
struct SimulationRequest {
  std::string sample;
  std::size_t events = 0;
  std::uint64_t firstEvent = 1;
  std::uint64_t seed = 1;
  std::size_t overlayBx = 0;
  std::string generatorToml;
  bool multipleScattering = true;
  bool energyLoss = true;
  bool timeWindow = true;
  bool moduleLevel = false;
  std::size_t threads = 0;
};

std::vector<EventHandle> simulate(const DetectorHandle& detector,
                                  const SimulationRequest& r) {
  if (r.events > 0 && r.firstEvent > std::numeric_limits<std::uint64_t>::max() -
                                         (r.events - 1)) {
    throw InputError("first_event " + std::to_string(r.firstEvent) +
                     " with events " + std::to_string(r.events) +
                     ": the last event number would exceed 2^64 - 1");
  }
  EventSimulation::Config config;
  config.sample = r.sample;
  config.overlayBx = r.overlayBx;
  config.seed = r.seed;
  config.generatorToml = r.generatorToml;
  config.generatorTomlSource = "simulate() settings";
  config.simulator.multipleScattering = r.multipleScattering;
  config.simulator.energyLoss = r.energyLoss;
  config.applyTimeWindow = r.timeWindow;
  if (r.moduleLevel) {
    config.modules = loadShippedLayout(*detector.detector);
  }
  EventSimulation sim(*detector.detector, config);
  std::vector<EventHandle> events(r.events);
  {
    py::gil_scoped_release release;
    forEachIndex(r.events, r.threads, [&](std::size_t i) {
      events[i].event =
          std::make_shared<const Event>(sim.simulate(r.firstEvent + i));
      events[i].detector = detector.detector;
    });
  }
  return events;
}

}  // namespace

void bindEvents(py::module_& m) {
  py::class_<EventHandle>(m, "Event")
      .def_property_readonly(
          "number", [](const EventHandle& e) { return e.event->number; })
      .def_property_readonly(
          "has_truth", [](const EventHandle& e) { return e.event->hasTruth(); })
      .def_property_readonly(
          "has_particles",
          [](const EventHandle& e) { return !e.event->particles.empty(); })
      .def("hit_columns",
           [](const EventHandle& e) {
             return hitColumns(e.event->hits, e.detector.get());
           })
      .def("truth_columns",
           [](const EventHandle& e) {
             return truthColumns(e.event->hits, e.event->truth);
           })
      .def("particle_columns", [](const EventHandle& e) {
        return particleColumns(e.event->particles);
      });

  m.def(
      "read_hits",
      [](const std::string& path, const DetectorHandle* detector) {
        auto d = detectorOf(detector);
        std::vector<Hit> hits;
        {
          py::gil_scoped_release release;
          hits = readHits(path, trackmlLayerMapOf(d.get()));
        }
        return hitColumns(hits, d.get());
      },
      py::arg("path"), py::arg("detector") = nullptr);

  m.def(
      "read_event",
      [](const std::string& folder, std::uint64_t number,
         const DetectorHandle* detector) {
        EventHandle e;
        e.detector = detectorOf(detector);
        py::gil_scoped_release release;
        e.event = std::make_shared<const Event>(
            readEvent(folder, number, trackmlLayerMapOf(e.detector.get())));
        return e;
      },
      py::arg("folder"), py::arg("event_number"),
      py::arg("detector") = nullptr);

  m.def(
      "simulate",
      [](const DetectorHandle& detector, const std::string& sample,
         std::size_t events, std::uint64_t firstEvent, std::uint64_t seed,
         std::size_t overlayBx, const std::string& generatorToml,
         bool multipleScattering, bool energyLoss, bool timeWindow,
         bool moduleLevel, std::size_t threads) {
        return simulate(
            detector,
            {sample, events, firstEvent, seed, overlayBx, generatorToml,
             multipleScattering, energyLoss, timeWindow, moduleLevel, threads});
      },
      py::arg("detector"), py::arg("sample"), py::arg("events"),
      py::arg("first_event"), py::arg("seed"), py::arg("overlay_bx"),
      py::arg("generator_toml"), py::arg("multiple_scattering"),
      py::arg("energy_loss"), py::arg("time_window"), py::arg("module_level"),
      py::arg("threads"));
}

}  // namespace conftrack::python

#pragma once

/// @file Bindings.hpp
/// The parts of the extension module, one per concept.

#include <pybind11/pybind11.h>

namespace conftrack::python {

/// Detector: load a detector, its numbers and its layers table.
void bindDetector(pybind11::module_& m);
/// Events: read TrackML files, simulate samples.
void bindEvents(pybind11::module_& m);
/// Reconstruction of one or many events (the GIL released).
void bindReconstruction(pybind11::module_& m);
/// Evaluation: performance summary and histograms, TrackML score.
void bindEvaluation(pybind11::module_& m);

}  // namespace conftrack::python

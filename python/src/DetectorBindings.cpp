/// @file DetectorBindings.cpp
/// conftrack._conftrack.Detector: a detector loaded by name or TOML file.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"

#include <string>

#include "Bindings.hpp"
#include "Columns.hpp"
#include "Handles.hpp"

namespace conftrack::python {

namespace {

/// One row per sensitive layer.
py::dict layerColumns(const Detector& d) {
  const auto& layers = d.layers();
  const std::size_t n = layers.size();
  py::list names;
  py::list subdetectors;
  py::list shapes;
  for (const SensitiveLayer& l : layers) {
    names.append(l.name);
    subdetectors.append(d.subdetectors()[l.id.subdetector].name);
    shapes.append(l.isDisk() ? "disk" : "cylinder");
  }
  py::dict c;
  c["name"] = names;
  c["subdetector"] = subdetectors;
  c["side"] = column<std::int64_t>(
      n, [&](auto i) { return static_cast<int>(layers[i].id.side); });
  c["layer"] =
      column<std::int64_t>(n, [&](auto i) { return layers[i].id.layer; });
  c["shape"] = shapes;
  c["r"] = column<double>(n, [&](auto i) { return layers[i].r / units::mm; });
  c["z_min"] =
      column<double>(n, [&](auto i) { return layers[i].zMin / units::mm; });
  c["z_max"] =
      column<double>(n, [&](auto i) { return layers[i].zMax / units::mm; });
  c["r_min"] =
      column<double>(n, [&](auto i) { return layers[i].rMin / units::mm; });
  c["r_max"] =
      column<double>(n, [&](auto i) { return layers[i].rMax / units::mm; });
  c["thickness_x0"] =
      column<double>(n, [&](auto i) { return layers[i].thicknessX0; });
  c["sigma_u"] =
      column<double>(n, [&](auto i) { return layers[i].sigmaU / units::mm; });
  c["sigma_v"] =
      column<double>(n, [&](auto i) { return layers[i].sigmaV / units::mm; });
  c["n_phi_modules"] =
      column<std::int64_t>(n, [&](auto i) { return layers[i].nPhiModules; });
  c["n_z_modules"] =
      column<std::int64_t>(n, [&](auto i) { return layers[i].nZModules; });
  c["volume_id"] =
      column<std::int64_t>(n, [&](auto i) { return layers[i].trackmlVolume; });
  c["layer_id"] =
      column<std::int64_t>(n, [&](auto i) { return layers[i].trackmlLayer; });
  return c;
}

}  // namespace

void bindDetector(py::module_& m) {
  py::class_<DetectorHandle>(m, "Detector")
      .def(py::init([](const std::string& nameOrToml) {
             return DetectorHandle{
                 std::make_shared<const Detector>(loadDetector(nameOrToml)),
                 nameOrToml};
           }),
           py::arg("name_or_toml"))
      .def_property_readonly(
          "name", [](const DetectorHandle& h) { return h.detector->name(); })
      .def_property_readonly(
          "model", [](const DetectorHandle& h) { return h.detector->model(); })
      .def_property_readonly(
          "field",
          [](const DetectorHandle& h) { return h.detector->bz() / units::T; })
      .def_property_readonly("envelope_r",
                             [](const DetectorHandle& h) {
                               return h.detector->envelopeR() / units::mm;
                             })
      .def_property_readonly("envelope_z",
                             [](const DetectorHandle& h) {
                               return h.detector->envelopeZ() / units::mm;
                             })
      .def_readonly("source", &DetectorHandle::source)
      .def("layer_columns",
           [](const DetectorHandle& h) { return layerColumns(*h.detector); });
}

}  // namespace conftrack::python

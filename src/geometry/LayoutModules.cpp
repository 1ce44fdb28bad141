#include "conftrack/geometry/LayoutModules.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/JsonEntry.hpp"
#include "conftrack/core/Units.hpp"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace conftrack {

namespace {

using nlohmann::json;

constexpr double kPi = std::numbers::pi;
/// Upper limit on a count in the file (sensors per ring, row or layer).
constexpr std::uint64_t kMaxCount = 100000;

/// What every sensor of a layer shares.
struct SensorTemplate {
  double thickness = 0.0;
  double thicknessX0 = 0.0;
  double sigmaU = 0.0;
  double sigmaV = 0.0;
};

/// Rotation with u = (-sin phi, cos phi, 0) (the +phi direction) and v:
/// +z on barrels, radial on disks; w = u x v.
Matrix3 frame(double phi, bool disk) {
  const Vector3 u(-std::sin(phi), std::cos(phi), 0.0);
  const Vector3 v =
      disk ? Vector3(std::cos(phi), std::sin(phi), 0.0) : Vector3::UnitZ();
  Matrix3 rotation;
  rotation.col(0) = u;
  rotation.col(1) = v;
  rotation.col(2) = u.cross(v);
  return rotation;
}

PlanarModule makeSensor(std::uint32_t layer, std::uint32_t number,
                        const Vector3& center, const Matrix3& rotation,
                        double minHalfU, double maxHalfU, double halfV,
                        const SensorTemplate& t) {
  PlanarModule m;
  m.layer = layer;
  m.module = number;
  m.center = center;
  m.rotation = rotation;
  m.minHalfU = minHalfU;
  m.maxHalfU = maxHalfU;
  m.halfV = halfV;
  m.thickness = t.thickness;
  m.thicknessX0 = t.thicknessX0;
  m.sigmaU = t.sigmaU;
  m.sigmaV = t.sigmaV;
  return m;
}

/// Flat staves of the vertex barrel (ZPlanarTracker).
void addStaves(const JsonEntry& e, std::uint32_t layer, const SensorTemplate& t,
               std::vector<PlanarModule>& out) {
  const auto n = static_cast<std::uint32_t>(e.count("n_staves", 3, kMaxCount));
  const double width = e.positive("stave_width_mm") * units::mm;
  const double offset = e.number("stave_offset_mm") * units::mm;
  const double distance = e.positive("r_mm") * units::mm;
  const double halfZ = e.positive("half_z_mm") * units::mm;
  for (std::uint32_t j = 0; j < n; ++j) {
    const double phi = 2.0 * kPi * j / n;
    const Matrix3 rotation = frame(phi, false);
    const Vector3 center =
        distance * rotation.col(2) + offset * rotation.col(0);
    out.push_back(makeSensor(layer, j, center, rotation, 0.5 * width,
                             0.5 * width, halfZ, t));
  }
}

/// Staggered modules of a tracker barrel layer (TrackerBarrel driver).
void addBarrelModules(const JsonEntry& e, std::uint32_t layer,
                      const SensorTemplate& t, std::vector<PlanarModule>& out) {
  const auto nPhi =
      static_cast<std::uint32_t>(e.count("n_phi_modules", 3, kMaxCount));
  const auto nZ =
      static_cast<std::uint32_t>(e.count("n_z_modules", 1, kMaxCount));
  const std::vector<double> size = e.numbers("module_size_mm", 2);
  if (!(size[0] > 0.0 && size[1] > 0.0)) {
    e.fail("module_size_mm", "sizes must be positive");
  }
  const double width = size[0] * units::mm;
  const double length = size[1] * units::mm;
  const double r = e.positive("r_mm") * units::mm;
  const double rAlt = e.positive("r_alt_mm") * units::mm;
  const double halfZ = e.positive("half_z_mm") * units::mm;
  if (length > 2.0 * halfZ * (1.0 + 1e-9)) {
    e.fail("module_size_mm", "module longer than 2 * half_z_mm");
  }
  // Rows from -halfZ + length/2 to halfZ - length/2: they cover |z| <
  // halfZ exactly (the driver's z0 = half length - module length / 2).
  const double pitch = nZ > 1 ? (2.0 * halfZ - length) / (nZ - 1) : 0.0;
  for (std::uint32_t k = 0; k < nZ; ++k) {
    const double z = nZ > 1 ? -halfZ + 0.5 * length + k * pitch : 0.0;
    for (std::uint32_t i = 0; i < nPhi; ++i) {
      const double phi = 2.0 * kPi * i / nPhi;
      const Matrix3 rotation = frame(phi, false);
      const Vector3 center =
          (i % 2 == 0 ? r : rAlt) * rotation.col(2) + z * Vector3::UnitZ();
      out.push_back(makeSensor(layer, i + nPhi * k, center, rotation,
                               0.5 * width, 0.5 * width, 0.5 * length, t));
    }
  }
}

/// Rings of rectangular modules of a tracker disk (TrackerEndcap driver);
/// `sign` is +1 for the +z disk, -1 for its mirror.
void addDiskModules(const JsonEntry& e, std::uint32_t layer, double sign,
                    const SensorTemplate& t, std::vector<PlanarModule>& out) {
  const double z = e.positive("z_mm") * units::mm;
  const std::vector<double> offsets = e.numbers("module_z_offsets_mm", 2);
  const double sensorOffset =
      e.number("sensor_z_offset_in_module_mm") * units::mm;
  std::uint32_t number = 0;
  for (const JsonEntry& ring : e.objects("rings")) {
    const double rMin = ring.positive("r_min_mm") * units::mm;
    const double rMax = ring.positive("r_max_mm") * units::mm;
    if (!(rMax > rMin)) {
      ring.fail("r_max_mm", "must be larger than r_min_mm");
    }
    const auto n =
        static_cast<std::uint32_t>(ring.count("n_modules", 3, kMaxCount));
    const double width = ring.positive("module_width_mm") * units::mm;
    for (std::uint32_t k = 0; k < n; ++k) {
      const double phi = 2.0 * kPi * k / n;
      const Matrix3 rotation = frame(phi, true);
      const double zSensor =
          sign * (z + offsets[k % 2] * units::mm + sensorOffset);
      const Vector3 center =
          0.5 * (rMin + rMax) * rotation.col(1) + zSensor * Vector3::UnitZ();
      out.push_back(makeSensor(layer, number++, center, rotation, 0.5 * width,
                               0.5 * width, 0.5 * (rMax - rMin), t));
    }
  }
}

/// Trapezoidal petals of a vertex disk (VertexEndcap driver).
void addPetals(const JsonEntry& e, std::uint32_t layer, double sign,
               const SensorTemplate& t, std::vector<PlanarModule>& out) {
  const auto n = static_cast<std::uint32_t>(e.count("n_petals", 3, kMaxCount));
  const double rMin = e.positive("r_min_mm") * units::mm;
  const double rMax = e.positive("r_max_mm") * units::mm;
  if (!(rMax > rMin)) {
    e.fail("r_max_mm", "must be larger than r_min_mm");
  }
  std::vector<double> zPetals;
  if (e.has("z_petals_mm")) {
    zPetals = e.numbers("z_petals_mm", n);
    for (std::size_t k = 0; k < n; ++k) {
      if (!(zPetals[k] > 0.0)) {
        e.fail("z_petals_mm[" + std::to_string(k) + "]", "must be positive");
      }
      zPetals[k] *= units::mm;
    }
  } else {
    zPetals.assign(n, e.positive("z_mm") * units::mm);
  }
  std::vector<double> phis(n);
  if (e.has("petal_phi_center_rad")) {
    phis = e.numbers("petal_phi_center_rad", n);
    for (double& phi : phis) {
      phi *= units::rad;
    }
  } else {
    for (std::uint32_t k = 0; k < n; ++k) {
      phis[k] = kPi + kPi / n + 2.0 * kPi * k / n;
    }
  }
  // Edges on the radial lines bounding the sector: the petals tile it.
  const double tangent = std::tan(kPi / n);
  for (std::uint32_t k = 0; k < n; ++k) {
    const Matrix3 rotation = frame(phis[k], true);
    const double z = sign > 0.0 ? zPetals[k] : -zPetals[n - 1 - k];
    const Vector3 center =
        0.5 * (rMin + rMax) * rotation.col(1) + z * Vector3::UnitZ();
    out.push_back(makeSensor(layer, k, center, rotation, rMin * tangent,
                             rMax * tangent, 0.5 * (rMax - rMin), t));
  }
}

/// The sensor properties of a layer entry; `support` receives the
/// layer's material besides the sensors [X0].
SensorTemplate readTemplate(const JsonEntry& e, bool disk, double& support) {
  SensorTemplate t;
  t.thickness = e.positive("sensor_thickness_um") * units::um;
  t.sigmaU = e.positive("resolution_rphi_um") * units::um;
  t.sigmaV =
      e.positive(disk ? "resolution_r_um" : "resolution_z_um") * units::um;
  if (e.has("module_X0")) {
    t.thicknessX0 = e.nonNegative("module_X0");
    support = e.has("support_X0") ? e.nonNegative("support_X0") : 0.0;
  } else {
    t.thicknessX0 = e.nonNegative("thickness_X0");
    support = 0.0;
  }
  return t;
}

/// Index of the detector layer of an entry on `side`.
std::uint32_t matchLayer(const JsonEntry& e, const Detector& detector,
                         SubdetectorKind kind, Side side) {
  const std::string name = e.text("subdetector");
  const std::optional<std::uint16_t> sub = detector.findSubdetector(name);
  if (!sub || detector.subdetectors()[*sub].kind != kind) {
    e.fail("subdetector",
           "'" + name + "' is not " +
               (kind == SubdetectorKind::eBarrel ? "a barrel" : "an endcap") +
               " subdetector of detector " + detector.name());
  }
  const auto number =
      static_cast<std::uint32_t>(e.count("layer_id", 0, kMaxCount));
  std::optional<std::uint32_t> layer;
  if (number <= 0xffff) {
    DetectorId id;
    id.subdetector = *sub;
    id.side = side;
    id.layer = static_cast<std::uint16_t>(number);
    layer = detector.findLayer(id);
  }
  if (!layer) {
    e.fail("layer_id", "layer " + std::to_string(number) + " of " + name +
                           " is not in detector " + detector.name());
  }
  return *layer;
}

}  // namespace

ModuleLayout buildLayoutModules(std::string_view jsonText,
                                const Detector& detector,
                                const std::string& source) {
  const json document = parseJsonObject(jsonText, source);
  const JsonEntry root(document, "", source);
  std::vector<PlanarModule> sensors;
  std::vector<double> support(detector.layers().size(), 0.0);
  std::vector<bool> filled(detector.layers().size(), false);
  const auto claim = [&](const JsonEntry& e, std::uint32_t layer) {
    if (filled[layer]) {
      e.fail("layer_id",
             "layer " + detector.layers()[layer].name + " is given twice");
    }
    filled[layer] = true;
  };

  for (const JsonEntry& e : root.objects("barrel_layers")) {
    const std::uint32_t layer =
        matchLayer(e, detector, SubdetectorKind::eBarrel, Side::eBarrel);
    claim(e, layer);
    const SensitiveLayer& surface = detector.layers()[layer];
    const double r = e.positive("r_mm") * units::mm;
    if (std::abs(r - surface.r) > kMaxLayoutLayerDistance) {
      e.fail("r_mm", std::to_string(r) + " mm is far from the radius " +
                         std::to_string(surface.r) + " mm of layer " +
                         surface.name + " of detector " + detector.name());
    }
    const SensorTemplate t = readTemplate(e, false, support[layer]);
    if (e.has("n_staves")) {
      addStaves(e, layer, t, sensors);
    } else {
      addBarrelModules(e, layer, t, sensors);
    }
  }

  for (const JsonEntry& e : root.objects("endcap_disks")) {
    for (const Side side : {Side::ePositive, Side::eNegative}) {
      const std::uint32_t layer =
          matchLayer(e, detector, SubdetectorKind::eEndcap, side);
      claim(e, layer);
      const SensitiveLayer& surface = detector.layers()[layer];
      const double z = e.positive("z_mm") * units::mm;
      if (std::abs(z - std::abs(surface.z())) > kMaxLayoutLayerDistance) {
        e.fail("z_mm", std::to_string(z) + " mm is far from the z " +
                           std::to_string(surface.z()) + " mm of layer " +
                           surface.name + " of detector " + detector.name());
      }
      const SensorTemplate t = readTemplate(e, true, support[layer]);
      const double sign = side == Side::ePositive ? 1.0 : -1.0;
      if (e.has("n_petals")) {
        addPetals(e, layer, sign, t, sensors);
      } else {
        addDiskModules(e, layer, sign, t, sensors);
      }
    }
  }
  return ModuleLayout(detector, std::move(sensors), std::move(support));
}

}  // namespace conftrack

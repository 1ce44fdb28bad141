#include "conftrack/simulation/LuminousRegion.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"

#include <array>
#include <cmath>
#include <sstream>

namespace conftrack {

namespace {

using namespace conftrack::units;

LuminousRegion::Config region(double sigmaX, double sigmaY, double sigmaZ,
                              double sigmaT = 0.0) {
  LuminousRegion::Config c;
  c.sigmaX = sigmaX;
  c.sigmaY = sigmaY;
  c.sigmaZ = sigmaZ;
  c.sigmaT = sigmaT;
  return c;
}

// Every number is explained, with its source, in docs/luminous-region.md.
const std::array<LuminousRegion::Preset, 6> kPresets = {{
    {"clic3tev", "CLIC, 3 TeV", region(0.0, 0.0, 44.0 * um),
     "CLIC 3 TeV parameter list (CLIC Note 764, 2010 update): bunch length "
     "44 um, taken as the length; transverse 45 nm x 1 nm neglected"},
    {"fccee-z", "FCC-ee, Z pole (91.2 GeV)",
     region(4.5 * um, 20.0 * nm, 0.30 * mm, 28.6 * ps),
     "FCC-ee CDR beam parameters via HEP-FCC/FCCeePhysicsPerformance "
     "General/README.md, vertex distribution table"},
    {"fccee-ttbar", "FCC-ee, tt threshold (365 GeV)",
     region(27.0 * um, 48.2 * nm, 1.27 * mm, 6.0 * ps),
     "FCC-ee CDR beam parameters via HEP-FCC/FCCeePhysicsPerformance "
     "General/README.md, vertex distribution table"},
    {"hllhc", "HL-LHC, 14 TeV pp", region(12.5 * um, 12.5 * um, 50.0 * mm),
     "transverse: ACTS full_chain_odd.py; length: 45-55 mm of HL-LHC "
     "conditions, 50 mm taken [unverified against the HL-LHC TDR]"},
    {"trackml-kaggle", "TrackML Kaggle events (pp, pile-up 200)",
     region(15.0 * um, 15.0 * um, 5.5 * mm),
     "Kaggle TrackML accuracy-phase events; measured on the five shipped "
     "events: 14.7 um, 15.0 um, 5.31 mm"},
    {"point", "none: a point at the origin", region(0.0, 0.0, 0.0),
     "definition (the particle gun's default)"},
}};

std::string str(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

/// Problem of one field: not finite, or |v| (v for a width) above `max`.
std::optional<LuminousRegionProblem> fieldProblem(const char* field, double v,
                                                  double max, bool width,
                                                  const char* unit) {
  if (!std::isfinite(v)) {
    return LuminousRegionProblem{field, "must be finite (got " + str(v) + ")"};
  }
  if (width ? !(v >= 0.0 && v <= max) : !(std::abs(v) <= max)) {
    return LuminousRegionProblem{
        field, "must lie in [" + (width ? std::string("0") : "-" + str(max)) +
                   ", " + str(max) + "] " + unit + " (got " + str(v) + ")"};
  }
  return std::nullopt;
}

}  // namespace

std::optional<LuminousRegionProblem> findLuminousRegionProblem(
    const LuminousRegion::Config& c) {
  using R = LuminousRegion;
  for (auto problem :
       {fieldProblem("position.x", c.position.x(), R::kMaxLength, false, "mm"),
        fieldProblem("position.y", c.position.y(), R::kMaxLength, false, "mm"),
        fieldProblem("position.z", c.position.z(), R::kMaxLength, false, "mm"),
        fieldProblem("time", c.time, R::kMaxTime, false, "ns"),
        fieldProblem("sigmaX", c.sigmaX, R::kMaxLength, true, "mm"),
        fieldProblem("sigmaY", c.sigmaY, R::kMaxLength, true, "mm"),
        fieldProblem("sigmaZ", c.sigmaZ, R::kMaxLength, true, "mm"),
        fieldProblem("sigmaT", c.sigmaT, R::kMaxTime, true, "ns")}) {
    if (problem) {
      return problem;
    }
  }
  return std::nullopt;
}

const LuminousRegion::Config& requireValidRegion(
    std::string_view owner, std::string_view field,
    const LuminousRegion::Config& config) {
  if (const auto p = findLuminousRegionProblem(config)) {
    throw InputError(std::string(owner) + ": config field '" +
                     std::string(field) + "." + p->field + "': " + p->problem);
  }
  return config;
}

LuminousRegion::LuminousRegion(const Config& config) : m_cfg(config) {
  if (const auto p = findLuminousRegionProblem(m_cfg)) {
    throw InputError("LuminousRegion: config field '" + p->field +
                     "': " + p->problem);
  }
}

LuminousRegion::Vertex LuminousRegion::sample(RandomEngine& rng) const {
  std::normal_distribution<double> normal(0.0, 1.0);
  return sample(rng, normal);
}

LuminousRegion::Vertex LuminousRegion::sample(
    RandomEngine& rng, std::normal_distribution<double>& normal) const {
  // z first and no draw for a zero width: see the class comment.
  auto draw = [&](double sigma) {
    return sigma > 0.0 ? sigma * normal(rng) : 0.0;
  };
  Vertex v;
  const double dz = draw(m_cfg.sigmaZ);
  const double dx = draw(m_cfg.sigmaX);
  const double dy = draw(m_cfg.sigmaY);
  const double dt = draw(m_cfg.sigmaT);
  v.position = m_cfg.position + Vector3(dx, dy, dz);
  v.time = m_cfg.time + dt;
  return v;
}

std::span<const LuminousRegion::Preset> LuminousRegion::presets() {
  return kPresets;
}

const LuminousRegion::Preset* LuminousRegion::findPreset(
    std::string_view name) {
  for (const Preset& p : kPresets) {
    if (p.name == name) {
      return &p;
    }
  }
  return nullptr;
}

std::string LuminousRegion::presetNames() {
  std::string names;
  for (const Preset& p : kPresets) {
    names += (names.empty() ? "" : ", ") + std::string(p.name);
  }
  return names;
}

LuminousRegion::Config LuminousRegion::clic3TeV() {
  return findPreset("clic3tev")->config;
}

}  // namespace conftrack

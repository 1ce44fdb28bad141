#include "conftrack/geometry/TrackmlDetector.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/DetectorReader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

namespace conftrack {

namespace {

constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------
// Geometry helpers.

/// A module lies in a disk (its normal along z) or on a barrel.
bool isDiskModule(const TrackmlModule& m) {
  return std::abs(m.rotation(2, 2)) > 0.5;
}

double moduleArea(const TrackmlModule& m) {
  return (m.minHalfU + m.maxHalfU) * 2.0 * m.halfV;
}

/// Distance of the z axis from the module in the transverse plane (disk
/// modules): 0 if the module covers the axis, else the nearest edge.
double minRadius(const TrackmlModule& m) {
  std::array<Vector3, 4> c = m.corners();
  double best = std::numeric_limits<double>::infinity();
  int nLeft = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Vector2 a = c[i].head<2>();
    const Vector2 ab = c[(i + 1) % 4].head<2>() - a;
    const double t = std::clamp(-a.dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * ab).norm());
    // The origin is inside the convex polygon iff it lies on the same side
    // of all four edges.
    nLeft += (ab.x() * a.y() - ab.y() * a.x()) < 0.0 ? 1 : 0;
  }
  return (nLeft == 0 || nLeft == 4) ? 0.0 : best;
}

double maxRadius(const TrackmlModule& m) {
  double best = 0.0;
  for (const Vector3& c : m.corners()) {
    best = std::max(best, c.head<2>().norm());
  }
  return best;
}

/// Number of distinct values, merging values closer than `tolerance`.
template <typename Key>
std::map<long long, std::uint32_t> countRows(
    const std::vector<const TrackmlModule*>& ms, Key key, double tolerance) {
  std::map<long long, std::uint32_t> rows;
  for (const TrackmlModule* m : ms) {
    ++rows[std::llround(key(*m) / tolerance)];
  }
  return rows;
}

// ---------------------------------------------------------------------------
// TOML writing.

/// A double rounded to `decimals` in TOML float syntax (always with a '.').
std::string fmt(double value, int decimals) {
  double scale = std::pow(10.0, decimals);
  double rounded = std::round(value * scale) / scale;
  if (rounded == 0.0) {
    rounded = 0.0;  // no "-0"
  }
  char buffer[64];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, rounded);
  std::string s(buffer, ptr);
  if (s.find_first_of(".e") == std::string::npos) {
    s += ".0";
  }
  return s;
}

struct SubdetectorSpec {
  const char* name;
  const char* prefix;
  bool barrel;
  std::uint32_t volumeNeg;  // barrel: the volume
  std::uint32_t volumePos;
};

/// The TrackML volumes: pixels, short strips, long strips.
constexpr std::array<SubdetectorSpec, 6> kSubdetectors = {{
    {"PixelBarrel", "PXB", true, 8, 8},
    {"PixelEndcap", "PXE", false, 7, 9},
    {"ShortStripBarrel", "SSB", true, 13, 13},
    {"ShortStripEndcap", "SSE", false, 12, 14},
    {"LongStripBarrel", "LSB", true, 17, 17},
    {"LongStripEndcap", "LSE", false, 16, 18},
}};

/// One conftrack layer (an endcap layer covers both sides).
struct PlannedLayer {
  std::string name;
  double position = 0.0;  // r (barrel) or |z| (disk)
  double halfZ = 0.0;
  double rMin = 0.0;
  double rMax = 0.0;
  double xOverX0 = 0.0;
  double sigmaU = 0.0;
  double sigmaV = 0.0;
  std::uint32_t nPhi = 1;
  std::uint32_t nSlow = 1;
  std::uint32_t trackmlLayer = 0;     // positive side (or barrel)
  std::uint32_t trackmlLayerNeg = 0;  // negative side (endcaps)
  std::size_t nModules = 0;           // per side
};

struct PlannedSubdetector {
  const SubdetectorSpec* spec = nullptr;
  std::vector<PlannedLayer> layers;
};

struct Plan {
  std::vector<PlannedSubdetector> subdetectors;
  double envelopeR = 0.0;
  double envelopeZ = 0.0;
};

const SubdetectorSpec* specOfVolume(std::uint32_t volume) {
  for (const SubdetectorSpec& s : kSubdetectors) {
    if (s.volumeNeg == volume || s.volumePos == volume) {
      return &s;
    }
  }
  return nullptr;
}

Plan planDetector(const std::vector<TrackmlModule>& modules,
                  const TrackmlDetectorOptions& options) {
  Plan plan;
  double maxR = 0.0;
  double maxZ = 0.0;
  for (const TrackmlModule& m : modules) {
    if (specOfVolume(m.volume) == nullptr) {
      throw InputError(location(options.source),
                       "volume_id " + std::to_string(m.volume) +
                           " is not a TrackML volume (7, 8, 9, 12, 13, 14, "
                           "16, 17, 18)");
    }
    maxR = std::max(maxR, maxRadius(m));
    for (const Vector3& c : m.corners()) {
      maxZ = std::max(maxZ, std::abs(c.z()) + 0.5 * m.thickness);
    }
  }
  // One millimetre beyond the outermost module corner: the simulation stops
  // at the envelope and must not cut the last layers.
  plan.envelopeR = std::ceil(maxR) + 1.0;
  plan.envelopeZ = std::ceil(maxZ) + 1.0;

  std::vector<TrackmlLayerSummary> summaries = summarizeTrackmlLayers(modules);
  auto byVolume = [&](std::uint32_t volume) {
    std::vector<TrackmlLayerSummary> out;
    for (const TrackmlLayerSummary& s : summaries) {
      if (s.volume == volume) {
        out.push_back(s);
      }
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
      return a.position < b.position;
    });
    return out;
  };
  auto material = [&](const TrackmlLayerSummary& s) {
    double x = s.coverage * s.thickness / options.moduleX0;
    if (options.supportThickness > 0.0) {
      x += options.supportThickness / options.supportX0;
    }
    return x;
  };
  const double sqrt12 = std::sqrt(12.0);
  auto segment = [](PlannedLayer& l, std::uint32_t nPhi,
                    std::uint32_t maxModuleId) {
    // TrackML ids run 1..N; conftrack needs id < nPhi * nSlow.
    l.nPhi = std::max<std::uint32_t>(nPhi, 1);
    l.nSlow = maxModuleId / l.nPhi + 1;
  };

  for (const SubdetectorSpec& spec : kSubdetectors) {
    PlannedSubdetector sub;
    sub.spec = &spec;
    if (spec.barrel) {
      std::vector<TrackmlLayerSummary> layers = byVolume(spec.volumePos);
      for (std::size_t i = 0; i < layers.size(); ++i) {
        const TrackmlLayerSummary& s = layers[i];
        if (!s.barrel) {
          throw InputError(location(options.source),
                           "volume " + std::to_string(s.volume) + " layer " +
                               std::to_string(s.layer) +
                               ": disk modules in a barrel volume");
        }
        PlannedLayer l;
        l.name = std::string(spec.prefix) + "_L" + std::to_string(i);
        l.position = s.position;
        l.halfZ = s.halfZ;
        l.xOverX0 = material(s);
        l.sigmaU = s.pitchU / sqrt12;
        l.sigmaV = s.pitchV / sqrt12;
        segment(l, s.nPhi, s.maxModuleId);
        l.trackmlLayer = l.trackmlLayerNeg = s.layer;
        l.nModules = s.nModules;
        sub.layers.push_back(l);
      }
    } else {
      std::vector<TrackmlLayerSummary> neg = byVolume(spec.volumeNeg);
      std::vector<TrackmlLayerSummary> pos = byVolume(spec.volumePos);
      if (neg.size() != pos.size()) {
        throw InputError(location(options.source),
                         "endcap volumes " + std::to_string(spec.volumeNeg) +
                             " and " + std::to_string(spec.volumePos) +
                             " have different numbers of layers (" +
                             std::to_string(neg.size()) + ", " +
                             std::to_string(pos.size()) +
                             "); conftrack endcaps are mirror-symmetric");
      }
      for (std::size_t i = 0; i < pos.size(); ++i) {
        const TrackmlLayerSummary& n = neg[i];
        const TrackmlLayerSummary& p = pos[i];
        // Sides must mirror each other (1 mm: the module staggering is
        // +-2.5..5.5 mm around the same mean on both sides).
        if (n.barrel || p.barrel || !(n.meanZ < 0.0 && p.meanZ > 0.0) ||
            std::abs(n.position - p.position) > 1.0 * units::mm) {
          throw InputError(
              location(options.source),
              "endcap layers (" + std::to_string(n.volume) + ", " +
                  std::to_string(n.layer) + ") at z = " + fmt(n.meanZ, 3) +
                  " mm and (" + std::to_string(p.volume) + ", " +
                  std::to_string(p.layer) + ") at z = " + fmt(p.meanZ, 3) +
                  " mm are not mirror images (negative side at z < 0, "
                  "|z| within 1 mm)");
        }
        PlannedLayer l;
        l.name = std::string(spec.prefix) + "_D" + std::to_string(i);
        l.position = 0.5 * (n.position + p.position);
        l.rMin = std::min(n.rMin, p.rMin);
        l.rMax = std::max(n.rMax, p.rMax);
        l.xOverX0 = 0.5 * (material(n) + material(p));
        l.sigmaU = 0.5 * (n.pitchU + p.pitchU) / sqrt12;
        l.sigmaV = 0.5 * (n.pitchV + p.pitchV) / sqrt12;
        segment(l, std::max(n.nPhi, p.nPhi),
                std::max(n.maxModuleId, p.maxModuleId));
        l.trackmlLayer = p.layer;
        l.trackmlLayerNeg = n.layer;
        l.nModules = p.nModules;
        sub.layers.push_back(l);
      }
    }
    if (!sub.layers.empty()) {
      plan.subdetectors.push_back(std::move(sub));
    }
  }
  return plan;
}

}  // namespace

// ---------------------------------------------------------------------------

std::vector<TrackmlLayerSummary> summarizeTrackmlLayers(
    const std::vector<TrackmlModule>& modules) {
  std::map<std::pair<std::uint32_t, std::uint32_t>,
           std::vector<const TrackmlModule*>>
      groups;
  for (const TrackmlModule& m : modules) {
    groups[{m.volume, m.layer}].push_back(&m);
  }
  std::vector<TrackmlLayerSummary> out;
  for (const auto& [key, ms] : groups) {
    TrackmlLayerSummary s;
    s.volume = key.first;
    s.layer = key.second;
    s.nModules = ms.size();
    // The layer is a disk if most of its modules are.
    std::size_t nDisk = static_cast<std::size_t>(
        std::count_if(ms.begin(), ms.end(),
                      [](const TrackmlModule* m) { return isDiskModule(*m); }));
    s.barrel = 2 * nDisk < ms.size();
    const double n = static_cast<double>(ms.size());
    double area = 0.0;
    s.rMin = std::numeric_limits<double>::infinity();
    s.rMax = 0.0;
    for (const TrackmlModule* m : ms) {
      s.maxModuleId = std::max(s.maxModuleId, m->module);
      s.thickness += m->thickness / n;
      s.pitchU += m->pitchU / n;
      s.pitchV += m->pitchV / n;
      s.meanZ += m->center.z() / n;
      area += moduleArea(*m);
      const double rc = m->center.head<2>().norm();
      if (s.barrel) {
        s.position += rc / n;
        s.halfZ = std::max(s.halfZ, std::abs(m->center.z()) + m->halfV);
        s.rMin = std::min(s.rMin, rc);
        s.rMax = std::max(s.rMax, rc);
      } else {
        s.rMin = std::min(s.rMin, minRadius(*m));
        s.rMax = std::max(s.rMax, maxRadius(*m));
      }
    }
    // Rows: module centres closer than 1 mm in z (barrel) or radius (disk)
    // belong to one row; staggering is well below the row spacing.
    std::map<long long, std::uint32_t> rows =
        s.barrel ? countRows(
                       ms, [](const TrackmlModule& m) { return m.center.z(); },
                       1.0 * units::mm)
                 : countRows(
                       ms,
                       [](const TrackmlModule& m) {
                         return m.center.head<2>().norm();
                       },
                       1.0 * units::mm);
    s.nRows = static_cast<std::uint32_t>(rows.size());
    for (const auto& [k, count] : rows) {
      s.nPhi = std::max(s.nPhi, count);
    }
    if (s.barrel) {
      s.coverage = area / (2.0 * kPi * s.position * 2.0 * s.halfZ);
    } else {
      s.position = std::abs(s.meanZ);
      s.coverage = area / (kPi * (s.rMax * s.rMax - s.rMin * s.rMin));
    }
    out.push_back(s);
  }
  return out;
}

std::string buildTrackmlDetectorToml(const std::vector<TrackmlModule>& modules,
                                     const TrackmlDetectorOptions& options) {
  Plan plan = planDetector(modules, options);
  std::ostringstream o;
  o << "# TrackML challenge detector (Kaggle 2018): conftrack detector file.\n"
    << "# Generated from " << options.source << " by buildTrackmlDetectorToml\n"
    << "# (src/geometry/TrackmlDetector.cpp; `conftrack detector "
       "import-trackml`). Do not edit:\n"
    << "# regenerate. Units are in the key names (_mm, _um, _T).\n"
    << "# - Barrel layers: cylinders at the mean module-centre radius, half "
       "length\n"
    << "#   max |cz| + module half length (staggering and tilts "
       "ignored).\n"
    << "# - Disks: at the mean module-centre |z| of both sides; r range "
       "from the\n"
    << "#   module corners.\n"
    << "# - sigma = pitch / sqrt(12) along u (r-phi) and v (z on barrels, r "
       "on disks),\n"
    << "#   also for the strip volumes 12-18, whose Kaggle hits sit on "
       "pitch_v cells.\n"
    << "# - x_over_x0 = module coverage * t / " << fmt(options.moduleX0, 3)
    << " mm (silicon)";
  if (options.supportThickness > 0.0) {
    o << " + " << fmt(options.supportThickness, 3) << " mm / "
      << fmt(options.supportX0, 3)
      << " mm\n#   support per layer (ACTS TrackML configuration, "
         "GenericDetectorML.ipp).\n";
  } else {
    o << ".\n";
  }
  o << "# - Module ids: TrackML module_id 1..N; n_phi_modules = modules per "
       "phi ring,\n"
    << "#   n_z_modules / n_rings = smallest count with n_phi * n > N.\n"
    << "# - trackml_layer is the TrackML layer_id; on endcaps that of the "
       "+z side\n"
    << "#   (TrackML numbers endcap layers by increasing z on both sides: "
       "the -z side\n"
    << "#   id is 2 * (n_layers + 1) - trackml_layer"
    << (options.perSideLayerIds ? ", written as trackml_layer_neg).\n"
                                : "; buildTrackmlDetector() applies it).\n")
    << "\n[detector]\n"
    << "name = \"TrackML\"\n"
    << "model = \"TrackML_Kaggle_2018\"\n"
    << "bz_T = 2.0\n"
    << "# The challenge's solenoid: its bending weakens towards |z| = 3 m;\n"
    << "# radius and half-length fitted to the real events' track curvature\n"
    << "# along z (scripts/field_profile.py, docs/validation.md item 9). The\n"
    << "# simulation follows it, and so do the finder (PromptBending) and\n"
    << "# the fit.\n"
    << "solenoid_radius_mm = " << fmt(kTrackmlSolenoidRadius, 1) << "\n"
    << "solenoid_half_length_mm = " << fmt(kTrackmlSolenoidHalfLength, 1)
    << "\n"
    << "envelope_r_mm = " << fmt(plan.envelopeR, 3) << "\n"
    << "envelope_z_mm = " << fmt(plan.envelopeZ, 3) << "\n";
  for (const PlannedSubdetector& sub : plan.subdetectors) {
    const SubdetectorSpec& spec = *sub.spec;
    o << "\n[[subdetector]]\n"
      << "name = \"" << spec.name << "\"\n"
      << "kind = \"" << (spec.barrel ? "barrel" : "endcap") << "\"\n";
    if (spec.barrel) {
      o << "trackml_volume = " << spec.volumePos << "\n";
    } else {
      o << "trackml_volumes = [" << spec.volumeNeg << ", " << spec.volumePos
        << "]  # -z, +z\n";
    }
    for (const PlannedLayer& l : sub.layers) {
      o << "\n  [[subdetector.layer]]\n"
        << "  name = \"" << l.name << "\"\n";
      if (spec.barrel) {
        o << "  r_mm = " << fmt(l.position, 3) << "\n"
          << "  half_z_mm = " << fmt(l.halfZ, 3) << "\n";
      } else {
        o << "  z_mm = " << fmt(l.position, 3) << "\n"
          << "  r_min_mm = " << fmt(l.rMin, 3) << "\n"
          << "  r_max_mm = " << fmt(l.rMax, 3) << "\n";
      }
      o << "  x_over_x0 = " << fmt(l.xOverX0, 6) << "\n"
        << "  sigma_rphi_um = " << fmt(l.sigmaU / units::um, 2) << "\n"
        << (spec.barrel ? "  sigma_z_um = " : "  sigma_r_um = ")
        << fmt(l.sigmaV / units::um, 2) << "\n"
        << "  n_phi_modules = " << l.nPhi << "\n"
        << (spec.barrel ? "  n_z_modules = " : "  n_rings = ") << l.nSlow
        << "  # " << l.nModules << " modules"
        << (spec.barrel ? "" : " per side") << "\n"
        << "  trackml_layer = " << l.trackmlLayer << "\n";
      if (!spec.barrel && options.perSideLayerIds &&
          l.trackmlLayerNeg != l.trackmlLayer) {
        o << "  trackml_layer_neg = " << l.trackmlLayerNeg << "\n";
      }
    }
  }
  if (options.passives) {
    // ACTS TrackML configuration: beryllium (X0 = 352.8 mm) beam pipe and
    // pixel support tube; only what lies inside the envelope (a partial
    // table may describe a smaller tracker).
    const double beX0 = 352.8 * units::mm;
    struct Tube {
      const char* name;
      double r;
      double halfZ;
      double thickness;
    };
    for (const Tube& t : {Tube{"BeamPipe", 19.0, plan.envelopeZ, 0.8},
                          Tube{"PixelSupportTube", 200.0, 2800.0, 1.8}}) {
      if (t.r >= plan.envelopeR) {
        continue;
      }
      o << "\n[[passive.cylinder]]\n"
        << "name = \"" << t.name << "\"\n"
        << "r_mm = " << fmt(t.r, 3) << "\n"
        << "z_max_mm = " << fmt(std::min(t.halfZ, plan.envelopeZ), 3) << "\n"
        << "x_over_x0 = " << fmt(t.thickness * units::mm / beX0, 6) << "  # "
        << fmt(t.thickness, 3) << " mm Be\n";
    }
    // Two material surfaces that detectors.csv (sensors only) lacks but
    // the real files' production vertices of secondaries show, sharply in
    // |z| (docs/validation.md item 12): in front of the first pixel disks
    // (316 vertices at |z| = 570.6 mm, r = 25-190 mm, 2.2 times as many as
    // on the pixel disk at 600 mm behind it) and of the strip disks (151
    // at |z| = 1182 mm, r = 200-1000 mm, 0.6 times the strip disk at 1220
    // mm). The thickness is that ratio times the disk's own material.
    struct Disk {
      const char* name;
      double z;
      double rMin;
      double rMax;
      double xOverX0;
    };
    for (const Disk& d :
         {Disk{"PixelEndcapFrontMaterial", 570.6, 25.0, 199.0, 0.03},
          Disk{"StripEndcapFrontMaterial", 1182.3, 201.0, 1025.0, 0.01}}) {
      if (d.z >= plan.envelopeZ || d.rMin >= plan.envelopeR) {
        continue;
      }
      o << "\n[[passive.disk]]\n"
        << "name = \"" << d.name << "\"\n"
        << "z_mm = " << fmt(d.z, 3) << "\n"
        << "r_min_mm = " << fmt(d.rMin, 3) << "\n"
        << "r_max_mm = " << fmt(std::min(d.rMax, plan.envelopeR), 3) << "\n"
        << "x_over_x0 = " << fmt(d.xOverX0, 6)
        << "  # from the real files' secondaries\n";
    }
  }
  return o.str();
}

Detector buildTrackmlDetector(const std::vector<TrackmlModule>& modules,
                              const TrackmlDetectorOptions& options) {
  TrackmlDetectorOptions perSide = options;
  perSide.perSideLayerIds = true;
  return parseDetector(buildTrackmlDetectorToml(modules, perSide),
                       options.source + " (TrackML detector)");
}

}  // namespace conftrack

#include "conftrack/geometry/DetectorReader.hpp"

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"

#include <cmath>
#include <map>
#include <sstream>

namespace conftrack {

namespace {

/// Two sensitive surfaces closer than this are considered to overlap.
constexpr double kMinimumGap = 0.1 * units::mm;

/// TrackML volume and layer ids: positive, and they fit the uint32 of the
/// files (the next free volume must fit too).
const Range kTrackmlIdRange{0.0, 4294967294.0, false, true};

/// Material fractions at or above one X0 per surface are not a tracker.
const Range kX0Range{0.0, 1.0, true, false};

struct NamedLine {
  std::string name;
  const ConfigTable* table;
};

class Builder {
 public:
  explicit Builder(const ConfigTable& root) : m_root(root) {}

  Detector build() {
    ConfigTable det = m_root.getTable("detector");
    std::string name = det.getString("name");
    std::string model = det.getString("model", name);
    MagneticField::Config field;
    field.centralBz = det.getDouble("bz_T", Range::positive()) * units::T;
    // Optional: a solenoid's field instead of a uniform one (MagneticField).
    field.solenoidRadius =
        det.getDouble("solenoid_radius_mm", 0.0, Range::nonNegative()) *
        units::mm;
    field.solenoidHalfLength =
        det.getDouble("solenoid_half_length_mm", 0.0, Range::nonNegative()) *
        units::mm;
    if ((field.solenoidRadius > 0.0) != (field.solenoidHalfLength > 0.0)) {
      det.fail(field.solenoidRadius > 0.0 ? "solenoid_half_length_mm"
                                          : "solenoid_radius_mm",
               "a solenoid needs both solenoid_radius_mm and "
               "solenoid_half_length_mm");
    }
    m_envelopeR = det.getDouble("envelope_r_mm", Range::positive()) * units::mm;
    m_envelopeZ = det.getDouble("envelope_z_mm", Range::positive()) * units::mm;
    det.rejectUnknownKeys();

    std::vector<ConfigTable> subs = m_root.getTableArray("subdetector");
    if (subs.empty()) {
      m_root.fail("subdetector", "missing: at least one [[subdetector]]");
    }
    std::uint32_t nextVolume = 1;
    for (std::size_t k = 0; k < subs.size(); ++k) {
      readSubdetector(subs[k], static_cast<std::uint16_t>(k), nextVolume);
    }
    if (auto passive = m_root.findTable("passive")) {
      for (const ConfigTable& t : passive->getTableArray("cylinder")) {
        readPassiveCylinder(t);
      }
      for (const ConfigTable& t : passive->getTableArray("disk")) {
        readPassiveDisk(t);
      }
      for (const ConfigTable& t : passive->getTableArray("cone")) {
        readPassiveCone(t);
      }
      passive->rejectUnknownKeys();
    }
    m_root.rejectUnknownKeys();
    checkOverlaps();
    return Detector(name, model, MagneticField(field), m_envelopeR, m_envelopeZ,
                    std::move(m_subdetectors), std::move(m_layers),
                    std::move(m_passives));
  }

 private:
  void claimName(const ConfigTable& t, const std::string& name) {
    if (name.empty()) {
      t.fail("name", "must not be empty");
    }
    auto [it, inserted] = m_names.emplace(name, t.lineOf("name"));
    if (!inserted) {
      t.fail("name", "duplicate name '" + name + "' (first used on line " +
                         std::to_string(it->second) + ")");
    }
  }

  void readSubdetector(const ConfigTable& t, std::uint16_t index,
                       std::uint32_t& nextVolume) {
    Subdetector sub;
    sub.name = t.getString("name");
    claimName(t, sub.name);
    std::string kind = t.getString("kind");
    if (kind == "barrel") {
      sub.kind = SubdetectorKind::eBarrel;
    } else if (kind == "endcap") {
      sub.kind = SubdetectorKind::eEndcap;
    } else {
      t.fail("kind", "expected \"barrel\" or \"endcap\", got \"" + kind + "\"");
    }
    bool barrel = sub.kind == SubdetectorKind::eBarrel;
    std::uint32_t volNeg = 0;
    std::uint32_t volPos = 0;
    std::uint32_t volBarrel = 0;
    if (barrel) {
      volBarrel = static_cast<std::uint32_t>(
          t.getInt("trackml_volume", nextVolume, kTrackmlIdRange));
      nextVolume = std::max(nextVolume, volBarrel + 1);
    } else if (t.has("trackml_volumes")) {
      std::vector<double> v =
          t.getDoubleArray("trackml_volumes", kTrackmlIdRange);
      if (v.size() != 2 || v[0] != std::floor(v[0]) ||
          v[1] != std::floor(v[1]) || v[0] == v[1]) {
        t.fail("trackml_volumes",
               "expected two different integers [negative z, positive z]");
      }
      volNeg = static_cast<std::uint32_t>(v[0]);
      volPos = static_cast<std::uint32_t>(v[1]);
      nextVolume = std::max({nextVolume, volNeg + 1, volPos + 1});
    } else {
      volNeg = nextVolume++;
      volPos = nextVolume++;
    }

    // A TrackML volume is one subdetector (one side of an endcap): shared,
    // the hits of one would be read onto the layers of the other.
    if (barrel) {
      claimVolume(t, "trackml_volume", volBarrel, sub.name);
    } else {
      claimVolume(t, "trackml_volumes", volNeg, sub.name + " (-z)");
      claimVolume(t, "trackml_volumes", volPos, sub.name + " (+z)");
    }

    std::vector<ConfigTable> layers = t.getTableArray("layer");
    if (layers.empty()) {
      t.fail("layer", "missing: a subdetector needs at least one [[" +
                          t.qualified("layer") + "]]");
    }
    sub.nLayers = static_cast<std::uint16_t>(layers.size());
    // Endcap layers of the negative side first, then the positive side.
    std::vector<SensitiveLayer> positive;
    for (std::size_t i = 0; i < layers.size(); ++i) {
      const ConfigTable& l = layers[i];
      SensitiveLayer layer;
      layer.name = l.getString("name");
      claimName(l, layer.name);
      layer.id.subdetector = index;
      layer.id.layer = static_cast<std::uint16_t>(i);
      layer.trackmlLayer = static_cast<std::uint32_t>(
          l.getInt("trackml_layer", static_cast<std::int64_t>(2 * (i + 1)),
                   kTrackmlIdRange));
      layer.thicknessX0 = l.getDouble("x_over_x0", kX0Range);
      layer.sigmaU =
          l.getDouble("sigma_rphi_um", Range::positive()) * units::um;
      layer.nPhiModules = static_cast<std::uint32_t>(
          l.getInt("n_phi_modules", 1, Range::closed(1, 1e6)));
      if (barrel) {
        layer.shape = SurfaceShape::eCylinder;
        layer.r = l.getDouble("r_mm", Range::positive()) * units::mm;
        double halfZ = l.getDouble("half_z_mm", Range::positive()) * units::mm;
        layer.zMin = -halfZ;
        layer.zMax = halfZ;
        layer.rMin = layer.rMax = layer.r;
        layer.sigmaV = l.getDouble("sigma_z_um", Range::positive()) * units::um;
        layer.nZModules = static_cast<std::uint32_t>(
            l.getInt("n_z_modules", 1, Range::closed(1, 1e6)));
        layer.trackmlVolume = volBarrel;
        claimTrackmlLayer(l, "trackml_layer", volBarrel, layer.trackmlLayer,
                          layer.name);
        layer.id.side = Side::eBarrel;
        checkInside(l, "r_mm", layer.r, halfZ);
        l.rejectUnknownKeys();
        sub.layers.push_back(static_cast<std::uint32_t>(m_layers.size()));
        m_layers.push_back(layer);
        m_layerTables.push_back(l);
      } else {
        layer.shape = SurfaceShape::eDisk;
        double z = l.getDouble("z_mm", Range::positive()) * units::mm;
        layer.rMin = l.getDouble("r_min_mm", Range::nonNegative()) * units::mm;
        layer.rMax = l.getDouble("r_max_mm", Range::positive()) * units::mm;
        if (!(layer.rMax > layer.rMin)) {
          l.fail("r_max_mm", "must be larger than r_min_mm");
        }
        layer.sigmaV = l.getDouble("sigma_r_um", Range::positive()) * units::um;
        layer.nZModules = static_cast<std::uint32_t>(
            l.getInt("n_rings", 1, Range::closed(1, 1e6)));
        // TrackML numbers endcap layers by increasing z on both sides, so
        // the -z side may need its own layer_id.
        const auto trackmlLayerNeg = static_cast<std::uint32_t>(l.getInt(
            "trackml_layer_neg", static_cast<std::int64_t>(layer.trackmlLayer),
            kTrackmlIdRange));
        checkInside(l, "z_mm", layer.rMax, z);
        claimTrackmlLayer(l, "trackml_layer_neg", volNeg, trackmlLayerNeg,
                          layer.name + "_neg");
        claimTrackmlLayer(l, "trackml_layer", volPos, layer.trackmlLayer,
                          layer.name + "_pos");
        l.rejectUnknownKeys();
        SensitiveLayer neg = layer;
        neg.name = layer.name + "_neg";
        neg.zMin = neg.zMax = -z;
        neg.id.side = Side::eNegative;
        neg.trackmlVolume = volNeg;
        neg.trackmlLayer = trackmlLayerNeg;
        SensitiveLayer pos = layer;
        pos.name = layer.name + "_pos";
        pos.zMin = pos.zMax = z;
        pos.id.side = Side::ePositive;
        pos.trackmlVolume = volPos;
        sub.layers.push_back(static_cast<std::uint32_t>(m_layers.size()));
        m_layers.push_back(neg);
        m_layerTables.push_back(l);
        positive.push_back(pos);
      }
    }
    for (SensitiveLayer& pos : positive) {
      sub.layers.push_back(static_cast<std::uint32_t>(m_layers.size()));
      m_layerTables.push_back(m_layerTables[sub.layers.front() + pos.id.layer]);
      m_layers.push_back(std::move(pos));
    }
    t.rejectUnknownKeys();
    m_subdetectors.push_back(std::move(sub));
  }

  void claimVolume(const ConfigTable& t, std::string_view key,
                   std::uint32_t volume, const std::string& owner) {
    auto [it, inserted] =
        m_volumes.emplace(volume, std::make_pair(owner, t.lineOf(key)));
    if (!inserted) {
      t.fail(key, "TrackML volume " + std::to_string(volume) +
                      " is already that of " + it->second.first + " (line " +
                      std::to_string(it->second.second) +
                      "): each subdetector (endcap side) needs its own");
    }
  }

  void claimTrackmlLayer(const ConfigTable& t, std::string_view key,
                         std::uint32_t volume, std::uint32_t layer,
                         const std::string& owner) {
    const std::uint64_t id = (std::uint64_t{volume} << 32) | layer;
    auto [it, inserted] = m_trackmlLayers.emplace(id, owner);
    if (!inserted) {
      t.fail(key, "TrackML (volume, layer) = (" + std::to_string(volume) +
                      ", " + std::to_string(layer) +
                      ") is already that of layer '" + it->second + "'");
    }
  }

  void checkInside(const ConfigTable& t, std::string_view key, double r,
                   double z) const {
    if (r > m_envelopeR || z > m_envelopeZ) {
      t.fail(key,
             "outside the tracker envelope (envelope_r_mm, "
             "envelope_z_mm)");
    }
  }

  void readPassiveCylinder(const ConfigTable& t) {
    PassiveSurface s;
    s.name = t.getString("name");
    claimName(t, s.name);
    s.shape = SurfaceShape::eCylinder;
    s.r = t.getDouble("r_mm", Range::positive()) * units::mm;
    s.rMin = s.rMax = s.r;
    double zMin = t.getDouble("z_min_mm", 0.0, Range::nonNegative());
    double zMax = t.getDouble("z_max_mm", Range::positive());
    if (!(zMax > zMin)) {
      t.fail("z_max_mm", "must be larger than z_min_mm");
    }
    s.thicknessX0 = t.getDouble("x_over_x0", kX0Range);
    t.rejectUnknownKeys();
    // Symmetric in z: one surface through the centre, or two mirrored.
    if (zMin == 0.0) {
      s.zMin = -zMax;
      s.zMax = zMax;
      m_passives.push_back(s);
    } else {
      PassiveSurface neg = s;
      neg.name += "_neg";
      neg.zMin = -zMax;
      neg.zMax = -zMin;
      s.name += "_pos";
      s.zMin = zMin;
      s.zMax = zMax;
      m_passives.push_back(neg);
      m_passives.push_back(s);
    }
  }

  void readPassiveDisk(const ConfigTable& t) {
    PassiveSurface s;
    s.name = t.getString("name");
    claimName(t, s.name);
    s.shape = SurfaceShape::eDisk;
    double z = t.getDouble("z_mm", Range::positive()) * units::mm;
    s.rMin = t.getDouble("r_min_mm", Range::nonNegative()) * units::mm;
    s.rMax = t.getDouble("r_max_mm", Range::positive()) * units::mm;
    if (!(s.rMax > s.rMin)) {
      t.fail("r_max_mm", "must be larger than r_min_mm");
    }
    s.thicknessX0 = t.getDouble("x_over_x0", kX0Range);
    t.rejectUnknownKeys();
    PassiveSurface neg = s;
    neg.name += "_neg";
    neg.zMin = neg.zMax = -z;
    s.name += "_pos";
    s.zMin = s.zMax = z;
    m_passives.push_back(neg);
    m_passives.push_back(s);
  }

  void readPassiveCone(const ConfigTable& t) {
    PassiveSurface s;
    s.name = t.getString("name");
    claimName(t, s.name);
    s.shape = SurfaceShape::eCone;
    double z1 = t.getDouble("z1_mm", Range::nonNegative()) * units::mm;
    double z2 = t.getDouble("z2_mm", Range::positive()) * units::mm;
    if (!(z2 > z1)) {
      t.fail("z2_mm", "must be larger than z1_mm");
    }
    s.coneR1 = t.getDouble("r1_mm", Range::positive()) * units::mm;
    s.coneR2 = t.getDouble("r2_mm", Range::positive()) * units::mm;
    s.rMin = std::min(s.coneR1, s.coneR2);
    s.rMax = std::max(s.coneR1, s.coneR2);
    s.thicknessX0 = t.getDouble("x_over_x0", kX0Range);
    t.rejectUnknownKeys();
    PassiveSurface neg = s;
    neg.name += "_neg";
    // Mirrored: at z = -z1 the radius is r1, at -z2 it is r2; keep
    // zMin < zMax and swap the radii accordingly.
    neg.zMin = -z2;
    neg.zMax = -z1;
    neg.coneR1 = s.coneR2;
    neg.coneR2 = s.coneR1;
    s.name += "_pos";
    s.zMin = z1;
    s.zMax = z2;
    m_passives.push_back(neg);
    m_passives.push_back(s);
  }

  /// Sensitive surfaces must not intersect or coincide: cylinders closer
  /// than kMinimumGap with overlapping z ranges, disks of one side closer
  /// than kMinimumGap with overlapping r ranges, or a disk cutting through
  /// a cylinder.
  void checkOverlaps() const {
    for (std::size_t j = 0; j < m_layers.size(); ++j) {
      for (std::size_t i = 0; i < j; ++i) {
        const SensitiveLayer& a = m_layers[i];
        const SensitiveLayer& b = m_layers[j];
        bool overlap = false;
        if (!a.isDisk() && !b.isDisk()) {
          overlap = std::abs(a.r - b.r) < kMinimumGap && a.zMin < b.zMax &&
                    b.zMin < a.zMax;
        } else if (a.isDisk() && b.isDisk()) {
          overlap = std::abs(a.z() - b.z()) < kMinimumGap && a.rMin < b.rMax &&
                    b.rMin < a.rMax;
        } else {
          const SensitiveLayer& cyl = a.isDisk() ? b : a;
          const SensitiveLayer& disk = a.isDisk() ? a : b;
          overlap = disk.z() > cyl.zMin - kMinimumGap &&
                    disk.z() < cyl.zMax + kMinimumGap &&
                    cyl.r > disk.rMin - kMinimumGap &&
                    cyl.r < disk.rMax + kMinimumGap;
        }
        if (overlap) {
          m_layerTables[j].fail(
              "name", "layer '" + b.name + "' overlaps layer '" + a.name + "'");
        }
      }
    }
  }

  const ConfigTable& m_root;
  double m_envelopeR = 0.0;
  double m_envelopeZ = 0.0;
  std::vector<Subdetector> m_subdetectors;
  std::vector<SensitiveLayer> m_layers;
  std::vector<ConfigTable> m_layerTables;  // parallel to m_layers
  std::vector<PassiveSurface> m_passives;
  std::map<std::string, std::size_t> m_names;
  /// TrackML volume -> (owner, line).
  std::map<std::uint32_t, std::pair<std::string, std::size_t>> m_volumes;
  /// (volume << 32 | layer) -> layer name.
  std::map<std::uint64_t, std::string> m_trackmlLayers;
};

}  // namespace

Detector parseDetector(std::string_view text, const std::string& sourceName) {
  std::shared_ptr<toml::table> table = ConfigTable::parse(text, sourceName);
  ConfigTable root(*table, sourceName, "");
  return Builder(root).build();
}

Detector readDetector(const std::filesystem::path& file) {
  return parseDetector(readConfigText(file, "detector"), file.string());
}

std::filesystem::path resolveDetectorPath(const std::string& nameOrPath) {
  return resolveShippedFile("detectors", nameOrPath, "detector");
}

Detector loadDetector(const std::string& nameOrPath) {
  return readDetector(resolveDetectorPath(nameOrPath));
}

}  // namespace conftrack

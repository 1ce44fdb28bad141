#include "conftrack/io/TrackmlReader.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/io/CsvReader.hpp"
#include "conftrack/io/EventFiles.hpp"
#include "conftrack/io/HitRows.hpp"
#include "conftrack/io/TrackmlFormat.hpp"
#include "conftrack/io/TrackmlIds.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace conftrack {

namespace {

/// The columns of a three-vector (x, y, z), read in one go.
struct VectorColumns {
  std::size_t x;
  std::size_t y;
  std::size_t z;

  static VectorColumns require(const CsvReader& csv, std::string_view x,
                               std::string_view y, std::string_view z) {
    return {csv.requireColumn(x), csv.requireColumn(y), csv.requireColumn(z)};
  }
  /// The row's vector, in the given unit.
  Vector3 read(CsvReader& csv, double unit) const {
    return Vector3(csv.getDouble(x) * unit, csv.getDouble(y) * unit,
                   csv.getDouble(z) * unit);
  }
};

/// Maps hit ids to hit indices. TrackML ids run 1..N in file order, which
/// makes the map an identity; other orders use a hash map.
class HitIdMap {
 public:
  explicit HitIdMap(const std::vector<Hit>& hits) {
    for (std::size_t i = 0; i < hits.size(); ++i) {
      if (hits[i].id != i + 1) {
        m_contiguous = false;
        break;
      }
    }
    m_size = hits.size();
    if (!m_contiguous) {
      m_map.reserve(hits.size());
      for (std::size_t i = 0; i < hits.size(); ++i) {
        m_map.emplace(hits[i].id, static_cast<HitIndex>(i));
      }
    }
  }

  /// Index of the hit with this id, or kInvalidIndex.
  HitIndex find(std::uint64_t id) const {
    if (m_contiguous) {
      return (id >= 1 && id <= m_size) ? static_cast<HitIndex>(id - 1)
                                       : kInvalidIndex;
    }
    auto it = m_map.find(id);
    return it == m_map.end() ? kInvalidIndex : it->second;
  }

 private:
  bool m_contiguous = true;
  std::size_t m_size = 0;
  std::unordered_map<std::uint64_t, HitIndex> m_map;
};

/// The problems of a hits row, located at the reader's line.
class CsvRowErrors : public HitRowErrors {
 public:
  explicit CsvRowErrors(const CsvReader& csv) : m_csv(csv) {}
  [[noreturn]] void fail(std::string_view what) const override {
    m_csv.fail(what);
  }
  [[noreturn]] void failField(std::string_view column,
                              std::string_view what) const override {
    auto index = m_csv.findColumn(column);
    if (!index) {
      m_csv.fail("column '" + std::string(column) + "' " + std::string(what));
    }
    m_csv.failField(*index, what);
  }

 private:
  const CsvReader& m_csv;
};

double nonNegative(const CsvReader& csv, std::size_t column) {
  double value = csv.getDouble(column);
  if (value < 0.0) {
    csv.failField(column, "is negative");
  }
  return value;
}

}  // namespace

std::vector<Hit> parseHits(std::string text, const std::string& source,
                           const TrackmlLayerMap* layers) {
  namespace c = trackml::hits;
  CsvReader csv(std::move(text), source);
  const std::size_t cId = csv.requireColumn(c::kHitId);
  const auto cPos = VectorColumns::require(csv, c::kX, c::kY, c::kZ);
  const std::size_t cVolume = csv.requireColumn(c::kVolumeId);
  const std::size_t cLayer = csv.requireColumn(c::kLayerId);
  const std::size_t cModule = csv.requireColumn(c::kModuleId);
  const auto cSigmaU = csv.findColumn(c::kSigmaU);
  const auto cSigmaV = csv.findColumn(c::kSigmaV);

  HitRowBuilder builder(layers);
  const CsvRowErrors errors(csv);
  std::vector<Hit> hits;
  hits.reserve(csv.estimateRows());
  while (csv.next()) {
    HitRow row;
    row.id = csv.getInteger<std::uint64_t>(cId);
    row.position = cPos.read(csv, 1.0);
    row.trackml = {csv.getInteger<std::uint32_t>(cVolume),
                   csv.getInteger<std::uint32_t>(cLayer),
                   csv.getInteger<std::uint32_t>(cModule)};
    if (cSigmaU) {
      row.sigmaU = nonNegative(csv, *cSigmaU);
    }
    if (cSigmaV) {
      row.sigmaV = nonNegative(csv, *cSigmaV);
    }
    hits.push_back(builder.build(row, errors));
  }
  return hits;
}

std::vector<HitTruth> parseTruth(std::string text, const std::string& source,
                                 const std::vector<Hit>& hits) {
  namespace c = trackml::truth;
  CsvReader csv(std::move(text), source);
  const std::size_t cHitId = csv.requireColumn(c::kHitId);
  const std::size_t cParticle = csv.requireColumn(c::kParticleId);
  const auto cPos = VectorColumns::require(csv, c::kTx, c::kTy, c::kTz);
  const auto cMom = VectorColumns::require(csv, c::kTpx, c::kTpy, c::kTpz);
  const auto cWeight = csv.findColumn(c::kWeight);
  const auto cTime = csv.findColumn(c::kTime);

  HitIdMap ids(hits);
  std::vector<HitTruth> truth(hits.size());
  std::vector<std::uint8_t> filled(hits.size(), 0);
  while (csv.next()) {
    std::uint64_t hitId = csv.getInteger<std::uint64_t>(cHitId);
    HitIndex index = ids.find(hitId);
    if (index == kInvalidIndex) {
      csv.fail("truth for hit_id " + std::to_string(hitId) +
               ", which is not in the hits file");
    }
    if (filled[index] != 0) {
      csv.fail("second truth row for hit_id " + std::to_string(hitId));
    }
    filled[index] = 1;
    HitTruth& t = truth[index];
    t.particleId = csv.getInteger<std::uint64_t>(cParticle);
    t.position = cPos.read(csv, units::mm);
    t.momentum = cMom.read(csv, units::GeV);
    t.weight = cWeight ? nonNegative(csv, *cWeight) : 0.0;
    t.time = cTime ? csv.getDouble(*cTime) * units::ns : 0.0;
  }
  auto missing = std::find(filled.begin(), filled.end(), 0);
  if (missing != filled.end()) {
    std::size_t n =
        static_cast<std::size_t>(std::count(filled.begin(), filled.end(), 0));
    throw InputError(location(csv.fileName()),
                     "no truth row for hit_id " +
                         std::to_string(hits[missing - filled.begin()].id) +
                         " (" + std::to_string(n) +
                         " hits without truth; every hit needs one row)");
  }
  return truth;
}

std::vector<Particle> parseParticles(std::string text,
                                     const std::string& source) {
  namespace c = trackml::particles;
  CsvReader csv(std::move(text), source);
  const std::size_t cId = csv.requireColumn(c::kParticleId);
  const auto cVertex = VectorColumns::require(csv, c::kVx, c::kVy, c::kVz);
  const auto cMom = VectorColumns::require(csv, c::kPx, c::kPy, c::kPz);
  const std::size_t cQ = csv.requireColumn(c::kQ);
  const std::size_t cNHits = csv.requireColumn(c::kNHits);
  // Kaggle files lack particle_type; conftrack's extras are optional too.
  const auto cType = csv.findColumn(c::kParticleType);
  const auto cVt = csv.findColumn(c::kVt);
  const auto cStatus = csv.findColumn(c::kStatus);
  const auto cParent = csv.findColumn(c::kParentId);
  const auto cBackground = csv.findColumn(c::kBackground);

  std::vector<Particle> particles;
  particles.reserve(csv.estimateRows());
  std::unordered_set<std::uint64_t> seen;
  seen.reserve(particles.capacity());
  while (csv.next()) {
    Particle& p = particles.emplace_back();
    p.id = csv.getInteger<std::uint64_t>(cId);
    if (p.id == 0) {
      csv.fail("particle_id 0 is reserved for noise hits");
    }
    if (!seen.insert(p.id).second) {
      csv.fail("duplicate particle_id " + std::to_string(p.id));
    }
    p.pdg = cType ? csv.getInteger<std::int32_t>(*cType) : 0;
    p.vertex = cVertex.read(csv, units::mm);
    p.momentum = cMom.read(csv, units::GeV);
    p.charge = csv.getDouble(cQ);
    p.nHits = csv.getInteger<std::uint32_t>(cNHits);
    p.time = cVt ? csv.getDouble(*cVt) * units::ns : 0.0;
    p.status = cStatus ? csv.getInteger<std::int32_t>(*cStatus) : 1;
    p.parentId = cParent ? csv.getInteger<std::uint64_t>(*cParent) : 0;
    if (cBackground) {
      int background = csv.getInteger<int>(*cBackground);
      if (background != 0 && background != 1) {
        csv.failField(*cBackground, "is not 0 (signal) or 1 (background)");
      }
      p.origin = background == 1 ? ParticleOrigin::eBackground
                                 : ParticleOrigin::eSignal;
    }
  }
  std::sort(particles.begin(), particles.end(),
            [](const Particle& a, const Particle& b) { return a.id < b.id; });
  return particles;
}

std::vector<Hit> readHits(const std::filesystem::path& file,
                          const TrackmlLayerMap* layers) {
  return parseHits(readTextFile(file), file.string(), layers);
}

std::vector<HitTruth> readTruth(const std::filesystem::path& file,
                                const std::vector<Hit>& hits) {
  return parseTruth(readTextFile(file), file.string(), hits);
}

std::vector<Particle> readParticles(const std::filesystem::path& file) {
  return parseParticles(readTextFile(file), file.string());
}

Event readEvent(const std::filesystem::path& dir, std::uint64_t eventNumber,
                const TrackmlLayerMap* layers, const ReadOptions& options) {
  EventFiles files = EventFiles::locate(dir, eventNumber);
  if (!files.hits) {
    throw MissingFileError(
        location((dir / eventFileName(eventNumber, EventFileKind::eHits, false))
                     .string()),
        "no such file (nor with .gz)");
  }
  Event event;
  event.number = eventNumber;
  event.hits = readHits(*files.hits, layers);
  if (options.truth && files.truth) {
    event.truth = readTruth(*files.truth, event.hits);
  }
  if (options.particles && files.particles) {
    event.particles = readParticles(*files.particles);
  }
  return event;
}

}  // namespace conftrack

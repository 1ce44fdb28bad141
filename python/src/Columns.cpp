#include "Columns.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/io/HitRows.hpp"
#include "conftrack/io/TrackmlFormat.hpp"
#include "conftrack/io/TrackmlIds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace conftrack::python {

namespace {

std::string str(std::string_view s) { return std::string(s); }

/// A column name as a dict key.
py::str key(std::string_view s) { return py::str(s.data(), s.size()); }

std::string formatDouble(double value) {
  std::ostringstream os;
  os.precision(17);
  os << value;
  return os.str();
}

/// One 1-D column of a table in memory, read as double or as integer.
class Column {
 public:
  Column(std::string table, std::string name, py::array array)
      : m_table(std::move(table)), m_name(std::move(name)) {
    if (array.ndim() != 1) {
      throw InputError(m_table + ": column '" + m_name +
                       "' is not one-dimensional");
    }
    m_kind = array.dtype().kind();
    if (m_kind == 'b') {
      m_kind = 'u';
      array = py::array_t<std::uint64_t, py::array::forcecast>::ensure(array);
    }
    if (m_kind == 'i') {
      m_signed = py::array_t<std::int64_t, py::array::forcecast>::ensure(array);
    } else if (m_kind == 'u') {
      m_unsigned =
          py::array_t<std::uint64_t, py::array::forcecast>::ensure(array);
    } else if (m_kind == 'f') {
      m_double = py::array_t<double, py::array::forcecast>::ensure(array);
    } else {
      throw InputError(m_table + ": column '" + m_name +
                       "' is not numeric (dtype " +
                       py::str(array.dtype()).cast<std::string>() + ")");
    }
    m_size = static_cast<std::size_t>(array.shape(0));
  }

  std::size_t size() const { return m_size; }
  const std::string& name() const { return m_name; }

  /// Finite double of row i.
  double real(std::size_t i) const {
    double v = 0.0;
    if (m_kind == 'f') {
      v = m_double.data()[i];
    } else if (m_kind == 'i') {
      v = static_cast<double>(m_signed.data()[i]);
    } else {
      v = static_cast<double>(m_unsigned.data()[i]);
    }
    if (!std::isfinite(v)) {
      fail(i, "'" + formatDouble(v) + "' is not finite");
    }
    return v;
  }

  /// Integer of row i in [0, max] (an integer dtype, or a float one with a
  /// whole value, as pandas makes of integer columns with missing values).
  std::uint64_t integer(std::size_t i, std::uint64_t max) const {
    std::uint64_t v = 0;
    bool ok = true;
    if (m_kind == 'i') {
      const std::int64_t s = m_signed.data()[i];
      ok = s >= 0;
      v = static_cast<std::uint64_t>(s);
    } else if (m_kind == 'u') {
      v = m_unsigned.data()[i];
    } else {
      const double d = m_double.data()[i];
      ok = std::isfinite(d) && d >= 0.0 && d == std::floor(d) &&
           d < 18446744073709551616.0;
      v = ok ? static_cast<std::uint64_t>(d) : 0;
    }
    if (!ok || v > max) {
      fail(i, "'" + text(i) + "' is not an integer in [0, " +
                  std::to_string(max) + "]");
    }
    return v;
  }

  /// The row's value as the error messages quote it.
  std::string text(std::size_t i) const {
    if (m_kind == 'i') {
      return std::to_string(m_signed.data()[i]);
    }
    if (m_kind == 'u') {
      return std::to_string(m_unsigned.data()[i]);
    }
    return formatDouble(m_double.data()[i]);
  }

  [[noreturn]] void fail(std::size_t row, const std::string& what) const {
    throw InputError(m_table + " row " + std::to_string(row),
                     "column '" + m_name + "': " + what);
  }

 private:
  std::string m_table;
  std::string m_name;
  char m_kind = 'f';
  std::size_t m_size = 0;
  py::array_t<double> m_double;
  py::array_t<std::int64_t> m_signed;
  py::array_t<std::uint64_t> m_unsigned;
};

/// The columns of one table (a mapping name -> 1-D array).
class Table {
 public:
  Table(const py::handle& columns, std::string name)
      : m_columns(columns), m_name(std::move(name)) {
    if (!PyMapping_Check(columns.ptr())) {
      throw InputError(m_name + ": expected a DataFrame or a dict of arrays");
    }
  }

  bool has(std::string_view column) const {
    return PyMapping_HasKeyString(m_columns.ptr(), str(column).c_str()) == 1;
  }

  Column require(std::string_view column) {
    if (!has(column)) {
      throw InputError(m_name + ": missing column '" + str(column) + "'");
    }
    return get(column);
  }

  std::optional<Column> find(std::string_view column) {
    if (!has(column)) {
      return std::nullopt;
    }
    return get(column);
  }

  /// Number of rows (0 before any column was read).
  std::size_t rows() const { return m_rows.value_or(0); }

 private:
  Column get(std::string_view name) {
    py::object value = m_columns[py::str(str(name))];
    py::array array = py::array::ensure(value);
    if (!array) {
      PyErr_Clear();
      throw InputError(m_name + ": column '" + str(name) +
                       "' is not an array of numbers");
    }
    Column c(m_name, str(name), array);
    if (m_rows && *m_rows != c.size()) {
      throw InputError(m_name + ": column '" + str(name) + "' has " +
                       std::to_string(c.size()) + " rows, the columns before " +
                       std::to_string(*m_rows));
    }
    m_rows = c.size();
    return c;
  }

  py::handle m_columns;
  std::string m_name;
  std::optional<std::size_t> m_rows;
};

/// The problems of row `row` of a hits table.
class ArrayRowErrors : public HitRowErrors {
 public:
  ArrayRowErrors(std::size_t row, const Column& module)
      : m_row(row), m_module(module) {}
  [[noreturn]] void fail(std::string_view what) const override {
    throw InputError("hits row " + std::to_string(m_row), what);
  }
  [[noreturn]] void failField(std::string_view column,
                              std::string_view what) const override {
    std::string value = column == m_module.name() ? m_module.text(m_row) : "";
    fail("column '" + str(column) + "': '" + value + "' " + str(what));
  }

 private:
  std::size_t m_row;
  const Column& m_module;
};

constexpr std::uint64_t kMaxU32 = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint64_t kMaxU64 = std::numeric_limits<std::uint64_t>::max();

double nonNegative(const Column& c, std::size_t i) {
  double v = c.real(i);
  if (v < 0.0) {
    c.fail(i, "'" + c.text(i) + "' is negative");
  }
  return v;
}

}  // namespace

py::dict hitColumns(std::span<const Hit> hits, const Detector* detector) {
  namespace c = trackml::hits;
  const std::size_t n = hits.size();
  std::vector<TrackmlId> ids(n);
  DetectorId lastLayer;
  std::optional<TrackmlId> last;
  for (std::size_t i = 0; i < n; ++i) {
    if (!last || !hits[i].detId.sameLayer(lastLayer)) {
      last = toTrackml(hits[i].detId, trackmlLayerMapOf(detector));
      lastLayer = hits[i].detId;
      if (!last) {
        throw InputError("hit_id " + std::to_string(hits[i].id) +
                         ": detector id has no TrackML volume and layer");
      }
    }
    ids[i] = {last->volume, last->layer, hits[i].detId.module};
  }
  py::dict d;
  d[key(c::kHitId)] =
      column<std::int64_t>(n, [&](auto i) { return hits[i].id; });
  d[key(c::kX)] = column<double>(
      n, [&](auto i) { return hits[i].position.x() / units::mm; });
  d[key(c::kY)] = column<double>(
      n, [&](auto i) { return hits[i].position.y() / units::mm; });
  d[key(c::kZ)] = column<double>(
      n, [&](auto i) { return hits[i].position.z() / units::mm; });
  d[key(c::kVolumeId)] =
      column<std::int64_t>(n, [&](auto i) { return ids[i].volume; });
  d[key(c::kLayerId)] =
      column<std::int64_t>(n, [&](auto i) { return ids[i].layer; });
  d[key(c::kModuleId)] =
      column<std::int64_t>(n, [&](auto i) { return ids[i].module; });
  const bool withSigmas = std::any_of(
      hits.begin(), hits.end(),
      [](const Hit& h) { return h.sigmaU != 0.0 || h.sigmaV != 0.0; });
  if (withSigmas) {
    d[key(c::kSigmaU)] =
        column<double>(n, [&](auto i) { return hits[i].sigmaU / units::mm; });
    d[key(c::kSigmaV)] =
        column<double>(n, [&](auto i) { return hits[i].sigmaV / units::mm; });
  }
  return d;
}

py::dict truthColumns(const std::vector<Hit>& hits,
                      const std::vector<HitTruth>& truth) {
  namespace c = trackml::truth;
  const std::size_t n = truth.size();
  py::dict d;
  d[key(c::kHitId)] =
      column<std::int64_t>(n, [&](auto i) { return hits[i].id; });
  d[key(c::kParticleId)] =
      column<std::int64_t>(n, [&](auto i) { return truth[i].particleId; });
  d[key(c::kTx)] = column<double>(
      n, [&](auto i) { return truth[i].position.x() / units::mm; });
  d[key(c::kTy)] = column<double>(
      n, [&](auto i) { return truth[i].position.y() / units::mm; });
  d[key(c::kTz)] = column<double>(
      n, [&](auto i) { return truth[i].position.z() / units::mm; });
  d[key(c::kTpx)] = column<double>(
      n, [&](auto i) { return truth[i].momentum.x() / units::GeV; });
  d[key(c::kTpy)] = column<double>(
      n, [&](auto i) { return truth[i].momentum.y() / units::GeV; });
  d[key(c::kTpz)] = column<double>(
      n, [&](auto i) { return truth[i].momentum.z() / units::GeV; });
  d[key(c::kWeight)] =
      column<double>(n, [&](auto i) { return truth[i].weight; });
  d[key(c::kTime)] =
      column<double>(n, [&](auto i) { return truth[i].time / units::ns; });
  return d;
}

py::dict particleColumns(const std::vector<Particle>& particles) {
  namespace c = trackml::particles;
  const auto& p = particles;
  const std::size_t n = p.size();
  py::dict d;
  d[key(c::kParticleId)] =
      column<std::int64_t>(n, [&](auto i) { return p[i].id; });
  d[key(c::kParticleType)] =
      column<std::int64_t>(n, [&](auto i) { return p[i].pdg; });
  d[key(c::kVx)] =
      column<double>(n, [&](auto i) { return p[i].vertex.x() / units::mm; });
  d[key(c::kVy)] =
      column<double>(n, [&](auto i) { return p[i].vertex.y() / units::mm; });
  d[key(c::kVz)] =
      column<double>(n, [&](auto i) { return p[i].vertex.z() / units::mm; });
  d[key(c::kPx)] =
      column<double>(n, [&](auto i) { return p[i].momentum.x() / units::GeV; });
  d[key(c::kPy)] =
      column<double>(n, [&](auto i) { return p[i].momentum.y() / units::GeV; });
  d[key(c::kPz)] =
      column<double>(n, [&](auto i) { return p[i].momentum.z() / units::GeV; });
  d[key(c::kQ)] = column<double>(n, [&](auto i) { return p[i].charge; });
  d[key(c::kNHits)] =
      column<std::int64_t>(n, [&](auto i) { return p[i].nHits; });
  d[key(c::kVt)] =
      column<double>(n, [&](auto i) { return p[i].time / units::ns; });
  d[key(c::kStatus)] =
      column<std::int64_t>(n, [&](auto i) { return p[i].status; });
  d[key(c::kParentId)] =
      column<std::int64_t>(n, [&](auto i) { return p[i].parentId; });
  d[key(c::kBackground)] = column<std::int64_t>(
      n, [&](auto i) { return p[i].isBackground() ? 1 : 0; });
  return d;
}

std::vector<Hit> hitsFromColumns(const py::handle& columns,
                                 const Detector* detector) {
  namespace c = trackml::hits;
  Table table(columns, "hits");
  const Column id = table.require(c::kHitId);
  const Column x = table.require(c::kX);
  const Column y = table.require(c::kY);
  const Column z = table.require(c::kZ);
  const Column volume = table.require(c::kVolumeId);
  const Column layer = table.require(c::kLayerId);
  const Column module = table.require(c::kModuleId);
  const std::optional<Column> sigmaU = table.find(c::kSigmaU);
  const std::optional<Column> sigmaV = table.find(c::kSigmaV);
  const std::size_t n = table.rows();
  HitRowBuilder builder(trackmlLayerMapOf(detector));
  std::vector<Hit> hits;
  hits.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    HitRow row;
    row.id = id.integer(i, kMaxU64);
    row.position = Vector3(x.real(i), y.real(i), z.real(i));
    row.trackml = {static_cast<std::uint32_t>(volume.integer(i, kMaxU32)),
                   static_cast<std::uint32_t>(layer.integer(i, kMaxU32)),
                   static_cast<std::uint32_t>(module.integer(i, kMaxU32))};
    if (sigmaU) {
      row.sigmaU = nonNegative(*sigmaU, i);
    }
    if (sigmaV) {
      row.sigmaV = nonNegative(*sigmaV, i);
    }
    hits.push_back(builder.build(row, ArrayRowErrors(i, module)));
  }
  return hits;
}

std::vector<HitTruth> truthFromColumns(const py::handle& columns,
                                       const std::vector<Hit>& hits) {
  namespace c = trackml::truth;
  Table table(columns, "truth");
  const Column hitId = table.require(c::kHitId);
  const Column particle = table.require(c::kParticleId);
  const std::string_view optionalNames[] = {
      c::kTx, c::kTy, c::kTz, c::kTpx, c::kTpy, c::kTpz, c::kWeight, c::kTime};
  std::vector<std::optional<Column>> optional;
  for (std::string_view name : optionalNames) {
    optional.push_back(table.find(name));
  }
  auto value = [&](std::size_t k, std::size_t i) {
    return optional[k] ? optional[k]->real(i) : 0.0;
  };
  std::unordered_map<std::uint64_t, std::size_t> index;
  index.reserve(hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    index.emplace(hits[i].id, i);
  }
  std::vector<HitTruth> truth(hits.size());
  std::vector<std::uint8_t> filled(hits.size(), 0);
  for (std::size_t i = 0; i < table.rows(); ++i) {
    const std::uint64_t id = hitId.integer(i, kMaxU64);
    auto it = index.find(id);
    if (it == index.end()) {
      hitId.fail(i, "truth for hit_id " + std::to_string(id) +
                        ", which is not in the hits");
    }
    if (filled[it->second] != 0) {
      hitId.fail(i, "second truth row for hit_id " + std::to_string(id));
    }
    filled[it->second] = 1;
    HitTruth& t = truth[it->second];
    t.particleId = particle.integer(i, kMaxU64);
    t.position = Vector3(value(0, i), value(1, i), value(2, i)) * units::mm;
    t.momentum = Vector3(value(3, i), value(4, i), value(5, i)) * units::GeV;
    t.weight = value(6, i);
    if (t.weight < 0.0) {
      optional[6]->fail(i, "'" + optional[6]->text(i) + "' is negative");
    }
    t.time = value(7, i) * units::ns;
  }
  auto missing = std::find(filled.begin(), filled.end(), 0);
  if (missing != filled.end()) {
    throw InputError("truth",
                     "no truth row for hit_id " +
                         std::to_string(hits[missing - filled.begin()].id));
  }
  return truth;
}

std::vector<Particle> particlesFromColumns(const py::handle& columns) {
  namespace c = trackml::particles;
  Table table(columns, "particles");
  const Column id = table.require(c::kParticleId);
  const std::string_view names[] = {c::kVx, c::kVy, c::kVz, c::kPx,
                                    c::kPy, c::kPz, c::kQ,  c::kVt};
  std::vector<std::optional<Column>> reals;
  for (std::string_view name : names) {
    reals.push_back(table.find(name));
  }
  auto real = [&](std::size_t k, std::size_t i) {
    return reals[k] ? reals[k]->real(i) : 0.0;
  };
  const auto type = table.find(c::kParticleType);
  const auto nHits = table.find(c::kNHits);
  const auto status = table.find(c::kStatus);
  const auto parent = table.find(c::kParentId);
  const auto background = table.find(c::kBackground);
  std::vector<Particle> particles(table.rows());
  std::unordered_set<std::uint64_t> seen;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    Particle& p = particles[i];
    p.id = id.integer(i, kMaxU64);
    if (p.id == 0) {
      id.fail(i, "particle_id 0 is reserved for noise hits");
    }
    if (!seen.insert(p.id).second) {
      id.fail(i, "duplicate particle_id " + std::to_string(p.id));
    }
    p.pdg = type ? static_cast<std::int32_t>(type->real(i)) : 0;
    p.vertex = Vector3(real(0, i), real(1, i), real(2, i)) * units::mm;
    p.momentum = Vector3(real(3, i), real(4, i), real(5, i)) * units::GeV;
    p.charge = real(6, i);
    p.time = real(7, i) * units::ns;
    p.nHits =
        nHits ? static_cast<std::uint32_t>(nHits->integer(i, kMaxU32)) : 0;
    p.status = status ? static_cast<std::int32_t>(status->real(i)) : 1;
    p.parentId = parent ? parent->integer(i, kMaxU64) : 0;
    if (background) {
      std::uint64_t b = background->integer(i, 1);
      p.origin = b == 1 ? ParticleOrigin::eBackground : ParticleOrigin::eSignal;
    }
  }
  std::sort(particles.begin(), particles.end(),
            [](const Particle& a, const Particle& b) { return a.id < b.id; });
  return particles;
}

std::vector<Hit> hitIdsFromColumns(const py::handle& columns,
                                   const std::string& tableName) {
  Table table(columns, tableName);
  const Column id = table.require(trackml::truth::kHitId);
  std::vector<Hit> hits(table.rows());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    hits[i].id = id.integer(i, kMaxU64);
  }
  return hits;
}

std::vector<std::uint64_t> labelsFromColumns(const py::handle& submission,
                                             const std::vector<Hit>& hits) {
  Table table(submission, "submission");
  const Column hitId = table.require("hit_id");
  const Column trackId = table.require("track_id");
  std::unordered_map<std::uint64_t, std::size_t> index;
  index.reserve(hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    index.emplace(hits[i].id, i);
  }
  std::vector<std::uint64_t> labels(hits.size());
  std::vector<std::uint8_t> filled(hits.size(), 0);
  for (std::size_t i = 0; i < table.rows(); ++i) {
    const std::uint64_t id = hitId.integer(i, kMaxU64);
    auto it = index.find(id);
    if (it == index.end()) {
      hitId.fail(i, "hit_id " + std::to_string(id) + " is not in the truth");
    }
    if (filled[it->second] != 0) {
      hitId.fail(i, "hit_id " + std::to_string(id) + " appears twice");
    }
    filled[it->second] = 1;
    labels[it->second] = trackId.integer(i, kMaxU64);
  }
  auto missing = std::find(filled.begin(), filled.end(), 0);
  if (missing != filled.end()) {
    throw InputError("submission",
                     "no row for hit_id " +
                         std::to_string(hits[missing - filled.begin()].id) +
                         " (every hit needs one)");
  }
  return labels;
}

}  // namespace conftrack::python

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFields.hpp"
#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/TrackmlDetector.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <set>
#include <string>

// The TrackML module table (detectors.csv): a strict CSV parser and the
// module geometry. The geometry module has no CSV reader of its own (it
// lives in io, which geometry does not depend on), so a minimal one is here.

namespace conftrack {

namespace {

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    std::size_t comma = line.find(',', start);
    fields.push_back(trimField(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) {
      break;
    }
    start = comma + 1;
  }
  return fields;
}

class ModuleCsv {
 public:
  ModuleCsv(std::string_view text, const std::string& source)
      : m_text(text), m_source(source) {}

  std::vector<TrackmlModule> parse() {
    if (!nextLine()) {
      throw InputError(location(m_source), "empty file (no header line)");
    }
    m_header = splitFields(m_line);
    const std::size_t cVolume = column("volume_id");
    const std::size_t cLayer = column("layer_id");
    const std::size_t cModule = column("module_id");
    const std::array<std::size_t, 3> cCenter = {column("cx"), column("cy"),
                                                column("cz")};
    static constexpr std::array<std::array<const char*, 3>, 3> kRot = {
        {{"rot_xu", "rot_xv", "rot_xw"},
         {"rot_yu", "rot_yv", "rot_yw"},
         {"rot_zu", "rot_zv", "rot_zw"}}};
    std::array<std::array<std::size_t, 3>, 3> cRot{};
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j) {
        cRot[i][j] = column(kRot[i][j]);
      }
    }
    const std::size_t cT = column("module_t");
    const std::size_t cMinHu = column("module_minhu");
    const std::size_t cMaxHu = column("module_maxhu");
    const std::size_t cHv = column("module_hv");
    const std::size_t cPitchU = column("pitch_u");
    const std::size_t cPitchV = column("pitch_v");

    std::vector<TrackmlModule> modules;
    std::set<std::array<std::uint32_t, 3>> seen;
    while (nextLine()) {
      m_fields = splitFields(m_line);
      if (m_fields.size() != m_header.size()) {
        fail(std::to_string(m_fields.size()) + " fields, the header has " +
             std::to_string(m_header.size()));
      }
      TrackmlModule& m = modules.emplace_back();
      m.volume = integer(cVolume);
      m.layer = integer(cLayer);
      m.module = integer(cModule);
      if (!seen.insert({m.volume, m.layer, m.module}).second) {
        fail("duplicate module (volume_id, layer_id, module_id) = (" +
             std::to_string(m.volume) + ", " + std::to_string(m.layer) + ", " +
             std::to_string(m.module) + ")");
      }
      for (std::size_t i = 0; i < 3; ++i) {
        m.center[static_cast<Eigen::Index>(i)] = number(cCenter[i]) * units::mm;
        for (std::size_t j = 0; j < 3; ++j) {
          m.rotation(static_cast<Eigen::Index>(i),
                     static_cast<Eigen::Index>(j)) = number(cRot[i][j]);
        }
      }
      m.thickness = positive(cT) * units::mm;
      m.minHalfU = positive(cMinHu) * units::mm;
      m.maxHalfU = positive(cMaxHu) * units::mm;
      m.halfV = positive(cHv) * units::mm;
      m.pitchU = positive(cPitchU) * units::mm;
      m.pitchV = positive(cPitchV) * units::mm;
      // A rotation must be orthonormal, else local coordinates are
      // meaningless; 1e-3 accepts the 6 printed digits.
      if (!(m.rotation.transpose() * m.rotation)
               .isApprox(Matrix3::Identity(), 1e-3)) {
        fail("the rotation matrix (rot_*) is not orthonormal");
      }
    }
    if (modules.empty()) {
      throw InputError(location(m_source), "no modules (header line only)");
    }
    return modules;
  }

 private:
  bool nextLine() {
    while (m_pos < m_text.size()) {
      std::size_t end = m_text.find('\n', m_pos);
      if (end == std::string_view::npos) {
        end = m_text.size();
      }
      m_line = trimField(m_text.substr(m_pos, end - m_pos));
      m_pos = end + 1;
      ++m_lineNumber;
      if (!m_line.empty()) {
        return true;
      }
    }
    return false;
  }

  std::size_t column(std::string_view name) const {
    auto it = std::find(m_header.begin(), m_header.end(), name);
    if (it == m_header.end()) {
      throw InputError(location(m_source, 1),
                       "missing column '" + std::string(name) + "'");
    }
    return static_cast<std::size_t>(it - m_header.begin());
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(location(m_source, m_lineNumber), what);
  }

  [[noreturn]] void failField(std::size_t c, const std::string& what) const {
    fail("column '" + std::string(m_header[c]) + "': '" +
         std::string(m_fields[c]) + "' " + what);
  }

  std::uint32_t integer(std::size_t c) const {
    std::string_view s = m_fields[c];
    std::uint32_t value = 0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || ec != std::errc{} || ptr != s.data() + s.size()) {
      failField(c, "is not a non-negative 32-bit integer");
    }
    return value;
  }

  double number(std::size_t c) const {
    std::string_view s = m_fields[c];
    double value = 0.0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || ec != std::errc{} || ptr != s.data() + s.size()) {
      failField(c, "is not a number");
    }
    if (!std::isfinite(value)) {
      failField(c, "is not finite");
    }
    return value;
  }

  double positive(std::size_t c) const {
    double value = number(c);
    if (!(value > 0.0)) {
      failField(c, "must be positive");
    }
    return value;
  }

  std::string_view m_text;
  const std::string& m_source;
  std::size_t m_pos = 0;
  std::size_t m_lineNumber = 0;
  std::string_view m_line;
  std::vector<std::string_view> m_header;
  std::vector<std::string_view> m_fields;
};

}  // namespace

std::array<Vector3, 4> TrackmlModule::corners() const {
  const Vector3 u = rotation.col(0);
  const Vector3 v = rotation.col(1);
  return {center - minHalfU * u - halfV * v, center + minHalfU * u - halfV * v,
          center + maxHalfU * u + halfV * v, center - maxHalfU * u + halfV * v};
}

std::vector<TrackmlModule> parseTrackmlModules(std::string_view csvText,
                                               const std::string& sourceName) {
  return ModuleCsv(csvText, sourceName).parse();
}

}  // namespace conftrack

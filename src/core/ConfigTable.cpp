// This file compiles the toml++ parser (TOML_IMPLEMENTATION). Debian's
// toml++ 3.3.0 states internal assumptions about its input with
// TOML_ASSERT_ASSUME (__builtin_assume in a release build) and
// TOML_UNREACHABLE (__builtin_unreachable), and malformed input can break
// them (found by fuzzing, docs/fuzzing.md; fixed in later toml++): undefined
// behaviour. Here both throw instead, and ConfigTable::parse reports the
// input as refused. They are redefined after toml++'s preprocessor header
// and before the parser, which only this file compiles.
#include <stdexcept>

namespace conftrack::detail {
/// A toml++ parser assumption failed on the input.
struct TomlAssumptionFailed : std::logic_error {
  TomlAssumptionFailed() : std::logic_error("toml++ assumption failed") {}
};
}  // namespace conftrack::detail

// In toml++'s noexcept functions (node and table accessors, not the
// parser) the throw becomes std::terminate: still defined behaviour, which
// GCC warns about.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wterminate"
#endif

#define TOML_IMPLEMENTATION
#include <toml++/impl/preprocessor.h>
#undef TOML_ASSERT_ASSUME
#define TOML_ASSERT_ASSUME(expr) \
  ((expr) ? static_cast<void>(0) \
          : throw ::conftrack::detail::TomlAssumptionFailed())
#undef TOML_UNREACHABLE
#define TOML_UNREACHABLE throw ::conftrack::detail::TomlAssumptionFailed()

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/Error.hpp"
#include "conftrack/core/TomlInputCheck.hpp"

#include <cmath>
#include <sstream>

namespace conftrack {

std::shared_ptr<toml::table> ConfigTable::parse(std::string_view text,
                                                const std::string& file) {
  requireSafeToml(text, file);
  try {
    return std::make_shared<toml::table>(toml::parse(text, file));
  } catch (const toml::parse_error& e) {
    throw InputError(
        location(file, e.source().begin.line),
        std::string("TOML syntax: ") + std::string(e.description()));
  } catch (const detail::TomlAssumptionFailed&) {
    throw InputError(location(file),
                     "TOML syntax: malformed input that the TOML parser "
                     "(toml++ 3.3.0) cannot read safely");
  }
}

ConfigTable::ConfigTable(const toml::table& table, std::string file,
                         std::string path)
    : m_table(&table),
      m_file(std::move(file)),
      m_path(std::move(path)),
      m_used(std::make_shared<std::set<std::string, std::less<>>>()) {}

bool ConfigTable::has(std::string_view key) const {
  return m_table->contains(key);
}

std::string ConfigTable::qualified(std::string_view key) const {
  return m_path.empty() ? std::string(key) : m_path + "." + std::string(key);
}

std::size_t ConfigTable::line() const {
  std::size_t l = m_table->source().begin.line;
  if (l == 0) {
    for (const auto& [k, v] : *m_table) {
      std::size_t kl = v.source().begin.line;
      if (kl != 0 && (l == 0 || kl < l)) {
        l = kl;
      }
    }
  }
  return l;
}

std::size_t ConfigTable::lineOf(std::string_view key) const {
  if (const toml::node* n = m_table->get(key)) {
    if (n->source().begin.line != 0) {
      return n->source().begin.line;
    }
  }
  return line();
}

void ConfigTable::fail(std::string_view key, std::string_view what) const {
  std::string msg;
  if (!key.empty()) {
    msg = "key '" + qualified(key) + "': ";
  } else if (!m_path.empty()) {
    msg = "table '" + m_path + "': ";
  }
  msg += what;
  throw InputError(location(m_file, key.empty() ? line() : lineOf(key)), msg);
}

const toml::node& ConfigTable::require(std::string_view key) const {
  const toml::node* n = m_table->get(key);
  if (n == nullptr) {
    fail(key, "missing");
  }
  m_used->emplace(key);
  return *n;
}

std::string rangeViolation(double value, const Range& range) {
  if (std::isnan(value)) {
    return "must not be NaN";
  }
  bool lowOk = range.minInclusive ? value >= range.min : value > range.min;
  bool highOk = range.maxInclusive ? value <= range.max : value < range.max;
  if (lowOk && highOk) {
    return "";
  }
  std::ostringstream os;
  os << "value " << value << " out of range ";
  os << (range.minInclusive ? '[' : '(') << range.min << ", " << range.max
     << (range.maxInclusive ? ']' : ')');
  return os.str();
}

void ConfigTable::checkRange(std::string_view key, double value,
                             const Range& range) const {
  // A file value is always finite: "inf" and "nan" in TOML are typos.
  if (!std::isfinite(value)) {
    fail(key, "must be finite");
  }
  if (std::string problem = rangeViolation(value, range); !problem.empty()) {
    fail(key, problem);
  }
}

double ConfigTable::getDouble(std::string_view key, Range range) const {
  const toml::node& n = require(key);
  std::optional<double> v = n.value<double>();
  if (!v || !(n.is_floating_point() || n.is_integer())) {
    fail(key, "expected a number");
  }
  checkRange(key, *v, range);
  return *v;
}

double ConfigTable::getDouble(std::string_view key, double fallback,
                              Range range) const {
  if (!has(key)) {
    return fallback;
  }
  return getDouble(key, range);
}

std::int64_t ConfigTable::getInt(std::string_view key, Range range) const {
  const toml::node& n = require(key);
  if (!n.is_integer()) {
    fail(key, "expected an integer");
  }
  std::int64_t v = *n.value<std::int64_t>();
  checkRange(key, static_cast<double>(v), range);
  return v;
}

std::int64_t ConfigTable::getInt(std::string_view key, std::int64_t fallback,
                                 Range range) const {
  if (!has(key)) {
    return fallback;
  }
  return getInt(key, range);
}

std::string ConfigTable::getString(std::string_view key) const {
  const toml::node& n = require(key);
  if (!n.is_string()) {
    fail(key, "expected a string");
  }
  return *n.value<std::string>();
}

std::string ConfigTable::getString(std::string_view key,
                                   std::string fallback) const {
  if (!has(key)) {
    return fallback;
  }
  return getString(key);
}

bool ConfigTable::getBool(std::string_view key) const {
  const toml::node& n = require(key);
  if (!n.is_boolean()) {
    fail(key, "expected true or false");
  }
  return *n.value<bool>();
}

bool ConfigTable::getBool(std::string_view key, bool fallback) const {
  if (!has(key)) {
    return fallback;
  }
  return getBool(key);
}

std::vector<std::string> ConfigTable::getStringArray(
    std::string_view key) const {
  const toml::node& n = require(key);
  const toml::array* arr = n.as_array();
  if (arr == nullptr) {
    fail(key, "expected an array of strings");
  }
  std::vector<std::string> out;
  for (const toml::node& e : *arr) {
    if (!e.is_string()) {
      fail(key, "expected an array of strings");
    }
    out.push_back(*e.value<std::string>());
  }
  return out;
}

std::vector<double> ConfigTable::getDoubleArray(std::string_view key,
                                                Range range) const {
  const toml::node& n = require(key);
  const toml::array* arr = n.as_array();
  if (arr == nullptr) {
    fail(key, "expected an array of numbers");
  }
  std::vector<double> out;
  for (const toml::node& e : *arr) {
    std::optional<double> v = e.value<double>();
    if (!v || !(e.is_floating_point() || e.is_integer())) {
      fail(key, "expected an array of numbers");
    }
    checkRange(key, *v, range);
    out.push_back(*v);
  }
  return out;
}

ConfigTable ConfigTable::getTable(std::string_view key) const {
  const toml::node& n = require(key);
  const toml::table* t = n.as_table();
  if (t == nullptr) {
    fail(key, "expected a table");
  }
  return ConfigTable(*t, m_file, qualified(key));
}

std::optional<ConfigTable> ConfigTable::findTable(std::string_view key) const {
  if (!has(key)) {
    return std::nullopt;
  }
  return getTable(key);
}

std::vector<ConfigTable> ConfigTable::getTableArray(
    std::string_view key) const {
  std::vector<ConfigTable> out;
  if (!has(key)) {
    return out;
  }
  const toml::node& n = require(key);
  const toml::array* arr = n.as_array();
  if (arr == nullptr || !arr->is_array_of_tables()) {
    fail(key, "expected an array of tables [[" + qualified(key) + "]]");
  }
  std::size_t i = 0;
  for (const toml::node& e : *arr) {
    out.emplace_back(*e.as_table(), m_file,
                     qualified(key) + "[" + std::to_string(i++) + "]");
  }
  return out;
}

void ConfigTable::rejectUnknownKeys() const {
  std::string_view worst;
  std::size_t worstLine = 0;
  for (const auto& [k, v] : *m_table) {
    if (m_used->count(k.str()) == 0) {
      std::size_t l = v.source().begin.line;
      if (worst.empty() || (l != 0 && l < worstLine)) {
        worst = k.str();
        worstLine = l;
      }
    }
  }
  if (!worst.empty()) {
    fail(worst, "unknown key");
  }
}

}  // namespace conftrack

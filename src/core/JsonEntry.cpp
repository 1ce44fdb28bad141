#include "conftrack/core/JsonEntry.hpp"

#include "conftrack/core/Error.hpp"

#include <cmath>
#include <limits>

namespace conftrack {

using nlohmann::json;

namespace {

/// A whole number >= 0: parsed text gives unsigned JSON numbers, values
/// built in code signed ones.
bool isWholeNumber(const json& v) {
  return v.is_number_unsigned() ||
         (v.is_number_integer() && v.get<std::int64_t>() >= 0);
}

}  // namespace

json parseJsonObject(std::string_view text, const std::string& source) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::exception& error) {
    // "[json.exception.parse_error.101] parse error at line 1, column 2:
    // ..." names the place; keep it on one line. A number beyond the range
    // of a double is an out_of_range error ("number overflow parsing
    // '1e9999'"), not a parse_error.
    std::string what = error.what();
    const auto colon = what.find("] ");
    throw InputError(source, "invalid JSON: " + (colon == std::string::npos
                                                     ? what
                                                     : what.substr(colon + 2)));
  }
  if (!document.is_object()) {
    throw InputError(source, "expected a JSON object");
  }
  return document;
}

JsonEntry::JsonEntry(const json& value, std::string path,
                     const std::string& source)
    : m_value(value), m_path(std::move(path)), m_source(source) {}

std::string JsonEntry::keyPath(std::string_view key) const {
  return m_path.empty() ? std::string(key) : m_path + "." + std::string(key);
}

void JsonEntry::fail(std::string_view key, std::string_view problem) const {
  throw InputError(m_source,
                   "key '" + keyPath(key) + "': " + std::string(problem));
}

bool JsonEntry::has(std::string_view key) const {
  return m_value.contains(key);
}

const json& JsonEntry::get(std::string_view key) const {
  const auto it = m_value.find(key);
  if (it == m_value.end()) {
    fail(key, "missing");
  }
  return *it;
}

std::string JsonEntry::text(std::string_view key) const {
  const json& v = get(key);
  if (!v.is_string()) {
    fail(key, "expected a string");
  }
  return v.get<std::string>();
}

bool JsonEntry::boolean(std::string_view key) const {
  const json& v = get(key);
  if (!v.is_boolean()) {
    fail(key, "expected true or false");
  }
  return v.get<bool>();
}

double JsonEntry::number(std::string_view key) const {
  const json& v = get(key);
  if (!v.is_number()) {
    fail(key, "expected a number");
  }
  const double x = v.get<double>();
  if (!std::isfinite(x)) {
    fail(key, "must be finite");
  }
  return x;
}

double JsonEntry::numberOrNull(std::string_view key) const {
  if (get(key).is_null()) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return number(key);
}

double JsonEntry::positive(std::string_view key) const {
  const double x = number(key);
  if (!(x > 0.0)) {
    fail(key, "must be positive");
  }
  return x;
}

double JsonEntry::nonNegative(std::string_view key) const {
  const double x = number(key);
  if (!(x >= 0.0)) {
    fail(key, "must not be negative");
  }
  return x;
}

std::uint64_t JsonEntry::count(std::string_view key, std::uint64_t minimum,
                               std::uint64_t maximum) const {
  const json& v = get(key);
  if (!isWholeNumber(v) || v.get<std::uint64_t>() < minimum ||
      v.get<std::uint64_t>() > maximum) {
    fail(key, "expected a whole number between " + std::to_string(minimum) +
                  " and " + std::to_string(maximum));
  }
  return v.get<std::uint64_t>();
}

const json& JsonEntry::array(std::string_view key, std::size_t size,
                             std::string_view what) const {
  const json& v = get(key);
  if (!v.is_array() || (size > 0 && v.size() != size)) {
    fail(key, size > 0 ? "expected an array of " + std::to_string(size) + " " +
                             std::string(what)
                       : "expected an array of " + std::string(what));
  }
  return v;
}

std::vector<double> JsonEntry::numbers(std::string_view key,
                                       std::size_t size) const {
  const json& v = array(key, size, "numbers");
  std::vector<double> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>())) {
      fail(std::string(key) + "[" + std::to_string(i) + "]",
           "expected a finite number");
    }
    out.push_back(v[i].get<double>());
  }
  return out;
}

std::vector<std::uint64_t> JsonEntry::counts(std::string_view key,
                                             std::size_t size) const {
  const json& v = array(key, size, "whole numbers");
  std::vector<std::uint64_t> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!isWholeNumber(v[i])) {
      fail(std::string(key) + "[" + std::to_string(i) + "]",
           "expected a whole number >= 0");
    }
    out.push_back(v[i].get<std::uint64_t>());
  }
  return out;
}

JsonEntry JsonEntry::object(std::string_view key) const {
  const json& v = get(key);
  if (!v.is_object()) {
    fail(key, "expected an object");
  }
  return JsonEntry(v, keyPath(key), m_source);
}

std::vector<JsonEntry> JsonEntry::objects(std::string_view key) const {
  const json& v = array(key, 0, "objects");
  std::vector<JsonEntry> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string path = keyPath(key) + "[" + std::to_string(i) + "]";
    if (!v[i].is_object()) {
      throw InputError(m_source, "key '" + path + "': expected an object");
    }
    out.emplace_back(v[i], path, m_source);
  }
  return out;
}

}  // namespace conftrack

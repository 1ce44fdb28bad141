#pragma once

/// @file JsonEntry.hpp
/// Strict reading of JSON input (layout files, saved performance data):
/// typed getters that name the key path in one-line errors
/// "source: key 'barrel_layers[6].r_mm': problem".

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack {

/// Parses JSON text that must hold an object. Throws InputError "source:
/// invalid JSON: <parser message>" (one line) or "source: expected a JSON
/// object".
nlohmann::json parseJsonObject(std::string_view text,
                               const std::string& source);

/// A JSON object of an input with its key path.
///
/// Holds references to the value and the source name: both must outlive
/// the entry.
class JsonEntry {
 public:
  /// @param value the object
  /// @param path its key path ("" for the root)
  /// @param source the file name used in errors
  JsonEntry(const nlohmann::json& value, std::string path,
            const std::string& source);

  /// The dotted path of `key` in this object.
  std::string keyPath(std::string_view key) const;
  /// Throws InputError "source: key 'path.key': problem".
  [[noreturn]] void fail(std::string_view key, std::string_view problem) const;

  bool has(std::string_view key) const;
  /// The value of a required key.
  const nlohmann::json& get(std::string_view key) const;
  std::string text(std::string_view key) const;
  bool boolean(std::string_view key) const;
  /// A finite number.
  double number(std::string_view key) const;
  /// A finite number or null (read as NaN: how NaN is written).
  double numberOrNull(std::string_view key) const;
  double positive(std::string_view key) const;
  double nonNegative(std::string_view key) const;
  /// A whole number in [minimum, maximum].
  std::uint64_t count(std::string_view key, std::uint64_t minimum,
                      std::uint64_t maximum) const;
  /// An array of finite numbers; `size` > 0 requires exactly that many.
  std::vector<double> numbers(std::string_view key, std::size_t size = 0) const;
  /// An array of whole numbers >= 0; `size` > 0 requires exactly that many.
  std::vector<std::uint64_t> counts(std::string_view key,
                                    std::size_t size = 0) const;
  /// A nested object.
  JsonEntry object(std::string_view key) const;
  /// The objects of an array.
  std::vector<JsonEntry> objects(std::string_view key) const;

 private:
  const nlohmann::json& array(std::string_view key, std::size_t size,
                              std::string_view what) const;

  const nlohmann::json& m_value;
  std::string m_path;
  const std::string& m_source;
};

}  // namespace conftrack

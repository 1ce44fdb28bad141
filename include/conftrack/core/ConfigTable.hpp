#pragma once

/// @file ConfigTable.hpp
/// Strict access to a TOML table for configuration readers (detectors,
/// chains, generators): typed getters with range checks, one-line errors
/// "file:line: key 'a.b': problem", and rejection of unknown keys.

#include <toml++/toml.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack {

/// Numeric constraint of a getter.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool minInclusive = true;
  bool maxInclusive = true;

  static Range positive() { return {0.0, Range{}.max, false, true}; }
  static Range nonNegative() { return {0.0, Range{}.max, true, true}; }
  static Range closed(double lo, double hi) { return {lo, hi, true, true}; }
  /// (0, inf): positive and finite.
  static Range positiveFinite() { return {0.0, Range{}.max, false, false}; }
};

/// Empty if `value` lies in `range` (an infinite bound that is inclusive
/// admits infinity), else the problem: "must not be NaN" or "value -1 out
/// of range (0, inf]". Shared by ConfigTable and the validation of
/// configurations built in code, so that both say the same.
std::string rangeViolation(double value, const Range& range);

/// A view on one TOML table that remembers which keys were read.
class ConfigTable {
 public:
  /// Parses TOML text; throws InputError "file:line: ..." on syntax errors,
  /// on any non-ASCII byte or control character, and on a table header
  /// without a key after its '[' (refused before toml++ sees them: Debian's
  /// toml++ 3.3.0 has undefined behaviour on some of them).
  static std::shared_ptr<toml::table> parse(std::string_view text,
                                            const std::string& file);

  /// `path` is the dotted key of this table ("" for the root).
  ConfigTable(const toml::table& table, std::string file, std::string path);

  bool has(std::string_view key) const;
  /// Required value. Throws if missing, of the wrong type, non-finite or
  /// outside the range.
  double getDouble(std::string_view key, Range range = {}) const;
  /// Optional value with default.
  double getDouble(std::string_view key, double fallback, Range range) const;
  std::int64_t getInt(std::string_view key, Range range = {}) const;
  std::int64_t getInt(std::string_view key, std::int64_t fallback,
                      Range range) const;
  std::string getString(std::string_view key) const;
  std::string getString(std::string_view key, std::string fallback) const;
  bool getBool(std::string_view key) const;
  bool getBool(std::string_view key, bool fallback) const;
  std::vector<std::string> getStringArray(std::string_view key) const;
  std::vector<double> getDoubleArray(std::string_view key,
                                     Range range = {}) const;
  /// A sub-table (required / optional).
  ConfigTable getTable(std::string_view key) const;
  std::optional<ConfigTable> findTable(std::string_view key) const;
  /// An array of tables ([[key]]); empty if absent.
  std::vector<ConfigTable> getTableArray(std::string_view key) const;

  /// Throws for the first key (in file order) that no getter asked for.
  void rejectUnknownKeys() const;

  /// Throws InputError located at `key` (or the table if absent).
  [[noreturn]] void fail(std::string_view key, std::string_view what) const;

  /// Line of the table's header or first key (0 if unknown).
  std::size_t line() const;
  /// Line of a key (the table's line if absent).
  std::size_t lineOf(std::string_view key) const;
  /// Dotted name of a key in this table.
  std::string qualified(std::string_view key) const;
  const std::string& file() const { return m_file; }

 private:
  const toml::node& require(std::string_view key) const;
  void checkRange(std::string_view key, double value, const Range& range) const;

  const toml::table* m_table;
  std::string m_file;
  std::string m_path;
  std::shared_ptr<std::set<std::string, std::less<>>> m_used;
};

}  // namespace conftrack

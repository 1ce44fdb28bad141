#pragma once

/// @file CsvReader.hpp
/// A fast, strict reader of numeric CSV tables with a header line.
///
/// The whole file is held in memory and split in place into string_views;
/// numbers are parsed with std::from_chars. Every problem is reported as a
/// one-line InputError "file:line: problem". Lines are numbered from 1 (the
/// header). Empty lines are skipped, "\r\n" line ends and blanks around
/// fields are accepted; quoting is not (the formats read here are numeric).
/// CR-only line ends (classic Mac OS) are refused at line 1. Field text in
/// messages is cut at 40 bytes, with control characters and bytes that are
/// not UTF-8 shown as '?'.

#include <charconv>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack {

/// Row-by-row access to a CSV table whose columns are found by header name.
class CsvReader {
 public:
  /// Reads `file` (plain or gzip, see readTextFile) and parses its header.
  static CsvReader open(const std::filesystem::path& file);

  /// Parses the header of `text`; `fileName` is used in error messages.
  /// Throws InputError for an empty file (no header), an empty or a
  /// duplicate column name.
  CsvReader(std::string text, std::string fileName);
  /// Not copyable or movable: the fields point into the owned text (a moved
  /// short string would leave them dangling).
  CsvReader(const CsvReader&) = delete;
  CsvReader& operator=(const CsvReader&) = delete;

  /// Column names, in file order.
  const std::vector<std::string>& columns() const { return m_columns; }
  /// Index of the column with this name, if present.
  std::optional<std::size_t> findColumn(std::string_view name) const;
  /// Index of a required column; throws InputError naming it if missing.
  std::size_t requireColumn(std::string_view name) const;

  /// Upper bound of the number of data rows (for reserving memory).
  std::size_t estimateRows() const;

  /// Advances to the next data row; false at the end of the file. Throws if
  /// the row does not have as many fields as the header.
  bool next();
  /// Line number of the current row (1 = header).
  std::size_t line() const { return m_line; }
  /// Raw text of a field of the current row, blanks removed.
  std::string_view field(std::size_t column) const { return m_fields[column]; }

  /// A field as a finite double; throws if it is not a number, NaN or
  /// infinite.
  double getDouble(std::size_t column) const;
  /// A field as an integer of type T; throws if it is not an integer or does
  /// not fit T (e.g. negative for an unsigned type).
  template <std::integral T>
  T getInteger(std::size_t column) const;

  /// Throws InputError "file:line: what" at the current line.
  [[noreturn]] void fail(std::string_view what) const;
  /// Throws InputError "file:line: column 'c': 'text' what".
  [[noreturn]] void failField(std::size_t column, std::string_view what) const;
  /// The file name used in messages.
  const std::string& fileName() const { return m_file; }

 private:
  /// Splits the line starting at m_pos into m_fields and moves m_pos past it.
  void splitLine();

  std::string m_text;
  std::string m_file;
  std::size_t m_pos = 0;
  std::size_t m_line = 0;
  std::vector<std::string> m_columns;
  std::vector<std::string_view> m_fields;
};

template <std::integral T>
T CsvReader::getInteger(std::size_t column) const {
  std::string_view s = m_fields[column];
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  // from_chars rejects a leading '+', which other writers may produce.
  if (begin != end && *begin == '+' && end - begin > 1 && begin[1] != '-') {
    ++begin;
  }
  T value{};
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (s.empty() || ec != std::errc{} || ptr != end) {
    failField(column, "is not an integer in [" +
                          std::to_string(std::numeric_limits<T>::min()) + ", " +
                          std::to_string(std::numeric_limits<T>::max()) + "]");
  }
  return value;
}

inline double CsvReader::getDouble(std::size_t column) const {
  std::string_view s = m_fields[column];
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  if (begin != end && *begin == '+' && end - begin > 1 && begin[1] != '-') {
    ++begin;
  }
  double value = 0.0;
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec == std::errc::result_out_of_range && ptr == end) {
    failField(column, "is out of the range of a double");
  }
  if (s.empty() || ec != std::errc{} || ptr != end) {
    failField(column, "is not a number");
  }
  if (!std::isfinite(value)) {
    failField(column, "is not finite");
  }
  return value;
}

}  // namespace conftrack

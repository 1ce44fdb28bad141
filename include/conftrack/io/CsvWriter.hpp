#pragma once

/// @file CsvWriter.hpp
/// Builds a numeric CSV table in memory, fast and exactly.
///
/// Doubles are written with std::to_chars in the shortest form that reads
/// back to the same bits (so write/read round trips are exact); integers in
/// decimal. The text is written out with writeTextFile.

#include "conftrack/core/TextFile.hpp"

#include <charconv>
#include <concepts>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack {

/// Appends rows of numbers to a CSV text buffer.
class CsvWriter {
 public:
  /// `fileName` is used in error messages; `columns` is the header.
  /// `expectedRows` reserves memory.
  CsvWriter(std::string fileName, const std::vector<std::string_view>& columns,
            std::size_t expectedRows = 0);

  /// Appends a double field. Throws InputError for NaN or infinity: the
  /// readers reject them, so they must not be written.
  void add(double value);
  /// Appends an integer field.
  template <std::integral T>
  void add(T value);
  /// Ends the current row; throws std::logic_error if it has the wrong number
  /// of fields (a bug of the caller).
  void endRow();

  /// Line number the current row will have in the file (1 = header).
  std::size_t line() const { return m_line; }
  /// Throws InputError "file:line: what" at the current row.
  [[noreturn]] void fail(std::string_view what) const;

  /// The finished text.
  const std::string& text() const { return m_text; }
  /// Writes the text to `file` (gzip if `gzip`), see writeTextFile.
  void write(const std::filesystem::path& file, bool gzip,
             int gzipLevel = kDefaultGzipLevel) const;

 private:
  /// Adds the separator before a new field.
  void separate();

  std::string m_file;
  std::vector<std::string> m_columns;
  std::string m_text;
  std::size_t m_field = 0;
  std::size_t m_line = 2;
};

template <std::integral T>
void CsvWriter::add(T value) {
  separate();
  char buffer[24];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  m_text.append(buffer, ptr);
}

}  // namespace conftrack

#include "conftrack/io/CsvWriter.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"

#include <cmath>
#include <stdexcept>

namespace conftrack {

CsvWriter::CsvWriter(std::string fileName,
                     const std::vector<std::string_view>& columns,
                     std::size_t expectedRows)
    : m_file(std::move(fileName)) {
  // ~12 characters per field is typical for TrackML-like tables.
  m_text.reserve((expectedRows + 1) * columns.size() * 12);
  for (std::string_view c : columns) {
    m_text += m_columns.empty() ? "" : ",";
    m_text += c;
    m_columns.emplace_back(c);
  }
  m_text += '\n';
}

void CsvWriter::separate() {
  if (m_field > 0) {
    m_text += ',';
  }
  ++m_field;
}

void CsvWriter::add(double value) {
  if (!std::isfinite(value)) {
    std::size_t column = m_field < m_columns.size() ? m_field : 0;
    fail("column '" + m_columns[column] + "': refusing to write the " +
         "non-finite value " + std::to_string(value));
  }
  separate();
  // Shortest representation that round-trips: at most 24 characters.
  char buffer[32];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  m_text.append(buffer, ptr);
}

void CsvWriter::endRow() {
  if (m_field != m_columns.size()) {
    throw std::logic_error("CsvWriter: row with " + std::to_string(m_field) +
                           " fields for " + std::to_string(m_columns.size()) +
                           " columns in " + m_file);
  }
  m_text += '\n';
  m_field = 0;
  ++m_line;
}

void CsvWriter::fail(std::string_view what) const {
  throw InputError(location(m_file, m_line), what);
}

void CsvWriter::write(const std::filesystem::path& file, bool gzip,
                      int gzipLevel) const {
  writeTextFile(file, m_text, gzip, gzipLevel);
}

}  // namespace conftrack

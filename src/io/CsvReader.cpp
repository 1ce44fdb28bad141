#include "conftrack/io/CsvReader.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFields.hpp"
#include "conftrack/core/TextFile.hpp"

#include <algorithm>
#include <cstring>

namespace conftrack {

namespace {

/// Length of the valid UTF-8 sequence at the start of `s` (0: invalid).
std::size_t utf8Length(std::string_view s) {
  const auto byte = [&](std::size_t i) {
    return static_cast<unsigned char>(s[i]);
  };
  const unsigned char lead = byte(0);
  std::size_t n = lead < 0x80                      ? 1
                  : (lead >= 0xC2 && lead <= 0xDF) ? 2
                  : (lead >= 0xE0 && lead <= 0xEF) ? 3
                  : (lead >= 0xF0 && lead <= 0xF4) ? 4
                                                   : 0;
  if (n == 0 || n > s.size()) {
    return 0;
  }
  for (std::size_t i = 1; i < n; ++i) {
    if ((byte(i) & 0xC0) != 0x80) {
      return 0;
    }
  }
  return n;
}

/// Shortens long field text in messages and masks control characters and
/// bytes that are not UTF-8, so that messages stay one printable line.
std::string excerpt(std::string_view s) {
  constexpr std::size_t kMax = 40;
  const bool longer = s.size() > kMax;
  s = s.substr(0, kMax);
  std::string out;
  while (!s.empty()) {
    const std::size_t n = utf8Length(s);
    const auto c = static_cast<unsigned char>(s[0]);
    if (n == 0 || (n == 1 && (c < 0x20 || c == 0x7f))) {
      out += '?';
      s.remove_prefix(1);
    } else {
      out += s.substr(0, n);
      s.remove_prefix(n);
    }
  }
  if (longer) {
    out += "...";
  }
  return out;
}

}  // namespace

CsvReader CsvReader::open(const std::filesystem::path& file) {
  return CsvReader(readTextFile(file), file.string());
}

CsvReader::CsvReader(std::string text, std::string fileName)
    : m_text(std::move(text)), m_file(std::move(fileName)) {
  // A UTF-8 byte-order mark (spreadsheet exports) is not part of the header.
  if (m_text.starts_with("\xEF\xBB\xBF")) {
    m_pos = 3;
  }
  if (m_text.find('\0') != std::string::npos) {
    throw InputError(location(m_file), "binary data (NUL byte) in a CSV file");
  }
  // Lines end in LF or CRLF. A CR elsewhere in the first line means CR-only
  // line ends (classic Mac OS): the whole file would be one line, and the
  // first problem found would be a misleading one in the "header".
  const std::size_t headerEnd =
      std::min(m_text.find('\n', m_pos), m_text.size());
  const std::size_t cr = m_text.find('\r', m_pos);
  if (cr != std::string::npos && cr + 1 < headerEnd) {
    throw InputError(location(m_file, 1),
                     "line ends are CR only (classic Mac OS); expected LF or "
                     "CRLF line ends");
  }
  // The header is the first line; leading empty lines are not allowed since
  // an empty file must be reported as such.
  m_line = 0;
  splitLine();
  if (m_fields.size() == 1 && m_fields[0].empty()) {
    throw InputError(location(m_file, 1),
                     "no header line (empty file or empty first line)");
  }
  for (std::string_view name : m_fields) {
    if (name.empty()) {
      fail("empty column name in the header");
    }
    if (std::find(m_columns.begin(), m_columns.end(), name) !=
        m_columns.end()) {
      fail("duplicate column '" + excerpt(name) + "' in the header");
    }
    m_columns.emplace_back(name);
  }
}

std::optional<std::size_t> CsvReader::findColumn(std::string_view name) const {
  auto it = std::find(m_columns.begin(), m_columns.end(), name);
  if (it == m_columns.end()) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(it - m_columns.begin());
}

std::size_t CsvReader::requireColumn(std::string_view name) const {
  if (auto i = findColumn(name)) {
    return *i;
  }
  std::string header;
  for (const std::string& c : m_columns) {
    header += header.empty() ? "" : ",";
    header += c;
  }
  throw InputError(location(m_file, 1),
                   "missing required column '" + std::string(name) +
                       "' (header: " + excerpt(header) + ")");
}

std::size_t CsvReader::estimateRows() const {
  return static_cast<std::size_t>(
             std::count(m_text.begin() + m_pos, m_text.end(), '\n')) +
         1;
}

void CsvReader::splitLine() {
  ++m_line;
  m_fields.clear();
  const char* begin = m_text.data() + m_pos;
  const char* end = m_text.data() + m_text.size();
  const char* eol = static_cast<const char*>(
      std::memchr(begin, '\n', static_cast<std::size_t>(end - begin)));
  if (eol == nullptr) {
    eol = end;
  }
  const char* fieldBegin = begin;
  for (;;) {
    const char* comma = static_cast<const char*>(std::memchr(
        fieldBegin, ',', static_cast<std::size_t>(eol - fieldBegin)));
    const char* fieldEnd = comma != nullptr ? comma : eol;
    m_fields.push_back(trimField(std::string_view(
        fieldBegin, static_cast<std::size_t>(fieldEnd - fieldBegin))));
    if (comma == nullptr) {
      break;
    }
    fieldBegin = comma + 1;
  }
  m_pos = static_cast<std::size_t>(eol - m_text.data()) + (eol < end ? 1 : 0);
}

bool CsvReader::next() {
  while (m_pos < m_text.size()) {
    splitLine();
    if (m_fields.size() == 1 && m_fields[0].empty()) {
      continue;  // blank line
    }
    if (m_fields.size() != m_columns.size()) {
      fail("expected " + std::to_string(m_columns.size()) +
           " fields as in the header, found " +
           std::to_string(m_fields.size()));
    }
    return true;
  }
  m_fields.clear();
  return false;
}

void CsvReader::fail(std::string_view what) const {
  throw InputError(location(m_file, m_line), what);
}

void CsvReader::failField(std::size_t column, std::string_view what) const {
  fail("column '" + m_columns[column] + "': '" + excerpt(m_fields[column]) +
       "' " + std::string(what));
}

}  // namespace conftrack

/// @file HepMCTextCheck.hpp
/// Internal to the HepMC text validation (HepMCText.cpp): the line
/// tokenizer, the located-error checker and the graph check shared by the
/// two format validators (HepMCIoGenEvent.cpp, HepMCAsciiV3.cpp).
#pragma once

#include "conftrack/core/Error.hpp"
#include "conftrack/simulation/generators/HepMCText.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack::hepmc::detail {

/// The Debian readers read lines into a 512*512-byte buffer; a longer
/// line would be split silently.
inline constexpr std::size_t kMaxLineLength = 512 * 512 - 1;

bool startsWith(std::string_view s, std::string_view prefix);

/// Fields separated by spaces, tabs or carriage returns.
std::vector<std::string_view> tokenize(std::string_view s);

/// The whole token as an integer, or nothing.
std::optional<long long> toInt(std::string_view token);

/// The whole token as a floating-point number, or nothing.
std::optional<double> toDouble(std::string_view token);

/// Line-by-line checker with located errors.
class Checker {
 public:
  explicit Checker(std::string source) : m_source(std::move(source)) {}

  [[noreturn]] void fail(std::size_t line, const std::string& what) const {
    throw InputError(location(m_source, line), what);
  }

  /// "event N: " prefix for messages inside an event.
  std::string inEvent(long long number) const {
    return "event " + std::to_string(number) + ": ";
  }

  /// Field `i` as an integer of the readers' `int` range. The readers
  /// convert with atoi, which wraps a wider value (-4294967298 becomes -2):
  /// two barcodes that differ here would be one vertex there, and the
  /// reader's graph would no longer be the one checked (a vertex left
  /// without incoming particles, a null dereference; found by fuzzing,
  /// docs/fuzzing.md). `wide` allows any 64-bit value, for fields whose
  /// wrapping only changes a stored number (random states).
  long long integer(const std::vector<std::string_view>& t, std::size_t i,
                    std::size_t line, const char* what,
                    bool wide = false) const {
    if (i >= t.size()) {
      fail(line, std::string("missing ") + what);
    }
    auto v = toInt(t[i]);
    if (!v) {
      fail(line, std::string("bad ") + what + " '" + std::string(t[i]) + "'");
    }
    if (!wide && (*v < std::numeric_limits<int>::min() ||
                  *v > std::numeric_limits<int>::max())) {
      fail(line, std::string("bad ") + what + " " + std::to_string(*v) +
                     " (outside the reader's 32-bit integer range)");
    }
    return *v;
  }

  long long count(const std::vector<std::string_view>& t, std::size_t i,
                  std::size_t line, const char* what) const {
    const long long v = integer(t, i, line, what);
    // Bounded so that the reader's resize() calls stay reasonable.
    if (v < 0 || v > 100000000) {
      fail(line, std::string("bad ") + what + " " + std::to_string(v));
    }
    return v;
  }

  double real(const std::vector<std::string_view>& t, std::size_t i,
              std::size_t line, const char* what, bool finite = true) const {
    if (i >= t.size()) {
      fail(line, std::string("missing ") + what);
    }
    auto v = toDouble(t[i]);
    if (!v || (finite && !std::isfinite(*v))) {
      fail(line, std::string("bad ") + what + " '" + std::string(t[i]) + "'");
    }
    return *v;
  }

  void units(const std::vector<std::string_view>& t, std::size_t line) const {
    if (t.size() < 3 || (t[1] != "GEV" && t[1] != "MEV") ||
        (t[2] != "MM" && t[2] != "CM")) {
      // The reader would silently fall back to GEV / CM.
      fail(line, "bad units line (expected 'U GEV|MEV MM|CM')");
    }
  }

 private:
  std::string m_source;
};

/// Splits text into lines with 1-based numbers.
struct Line {
  std::string_view text;
  std::size_t number = 0;
};

std::vector<Line> splitLines(std::string_view text);

/// Cycle check on a directed graph given as adjacency lists (iterative DFS:
/// event records can be deep).
bool hasCycle(const std::vector<std::vector<std::size_t>>& adjacency);

/// A "HepMC..." line of `format`: version, start or end marker. Anything
/// else there would stop the library's reader, so it is an error. The
/// line's canonical form is appended to `summary.canonical`.
void headerLine(std::string_view s, const std::string& format,
                std::size_t lineNumber, const Checker& c, TextSummary& summary);

/// Builds the canonical text (TextSummary::canonical) one record at a
/// time: fields separated by single spaces, integers in decimal, reals in
/// their shortest round-trip form (std::to_chars), so that the reader's
/// atoi/atof see exactly the values the validator checked.
class CanonicalLine {
 public:
  CanonicalLine(std::string& out, char key) : m_out(out) { m_out += key; }
  CanonicalLine(const CanonicalLine&) = delete;
  CanonicalLine& operator=(const CanonicalLine&) = delete;
  ~CanonicalLine() { m_out += '\n'; }

  CanonicalLine& integer(long long v);
  CanonicalLine& real(double v);
  CanonicalLine& word(std::string_view w);

 private:
  template <typename T>
  CanonicalLine& number(T v);

  std::string& m_out;
};

/// Walks the lines of a HepMC text of `format`: empty lines are skipped; a
/// "HepMC..." line is checked by headerLine and ends the open event, as the
/// reader ends it there (ReaderAsciiHepMC2 3.1.2 crashed on the vertices
/// it then left without particles, found by fuzzing, docs/fuzzing.md), by
/// calling endEvent(); every other line goes to record(line). endEvent()
/// is called once more after the last line.
template <typename EndEvent, typename Record>
void forEachRecord(const std::vector<Line>& lines, const std::string& format,
                   const Checker& c, TextSummary& summary, EndEvent&& endEvent,
                   Record&& record) {
  for (const Line& line : lines) {
    const std::string_view s = line.text;
    if (s.empty() || s == "\r") {
      continue;
    }
    if (startsWith(s, "HepMC")) {
      headerLine(s, format, line.number, c, summary);
      endEvent();
      continue;
    }
    record(line);
  }
  endEvent();
}

/// Refuses a line whose fields are not separated by single spaces (see
/// HepMCTextCheck.cpp).
void requireSingleSpaces(std::string_view s, std::size_t lineNumber,
                         const Checker& c);

/// HepMC2 IO_GenEvent records (HepMCIoGenEvent.cpp).
TextSummary validateIoGenEvent(const std::vector<Line>& lines,
                               const Checker& c);

/// HepMC3 Asciiv3 records (HepMCAsciiV3.cpp).
TextSummary validateAsciiV3(const std::vector<Line>& lines, const Checker& c);

}  // namespace conftrack::hepmc::detail

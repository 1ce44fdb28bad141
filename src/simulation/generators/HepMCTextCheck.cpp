#include "HepMCTextCheck.hpp"

#include <array>
#include <charconv>
#include <cstdint>
#include <utility>

namespace conftrack::hepmc::detail {

bool startsWith(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

std::vector<std::string_view> tokenize(std::string_view s) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (i < s.size()) {
    while (i < s.size() && isSpace(s[i])) {
      ++i;
    }
    const std::size_t start = i;
    while (i < s.size() && !isSpace(s[i])) {
      ++i;
    }
    if (i > start) {
      tokens.push_back(s.substr(start, i - start));
    }
  }
  return tokens;
}

std::optional<long long> toInt(std::string_view token) {
  long long v = 0;
  auto [ptr, ec] =
      std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size()) {
    return std::nullopt;
  }
  return v;
}

std::optional<double> toDouble(std::string_view token) {
  double v = 0.0;
  auto [ptr, ec] =
      std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size()) {
    return std::nullopt;
  }
  return v;
}

std::vector<Line> splitLines(std::string_view text) {
  std::vector<Line> lines;
  std::size_t pos = 0;
  std::size_t number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) {
      end = text.size();
    }
    lines.push_back({text.substr(pos, end - pos), ++number});
    pos = end + 1;
  }
  return lines;
}

/// Cycle check on a directed graph given as adjacency lists (iterative DFS:
/// event records can be deep).
bool hasCycle(const std::vector<std::vector<std::size_t>>& adjacency) {
  const std::size_t n = adjacency.size();
  std::vector<std::uint8_t> colour(n, 0);  // 0 new, 1 on stack, 2 done
  std::vector<std::pair<std::size_t, std::size_t>> stack;
  for (std::size_t start = 0; start < n; ++start) {
    if (colour[start] != 0) {
      continue;
    }
    stack.push_back({start, 0});
    colour[start] = 1;
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next < adjacency[node].size()) {
        const std::size_t child = adjacency[node][next++];
        if (colour[child] == 1) {
          return true;
        }
        if (colour[child] == 0) {
          colour[child] = 1;
          stack.push_back({child, 0});
        }
      } else {
        colour[node] = 2;
        stack.pop_back();
      }
    }
  }
  return false;
}

/// A "HepMC..." line of `format`: version, start or end marker. Anything
/// else there would stop the library's reader, so it is an error.
void headerLine(std::string_view s, const std::string& format,
                std::size_t lineNumber, const Checker& c,
                TextSummary& summary) {
  const std::string start = "HepMC::" + format + "-START_EVENT_LISTING";
  const std::string end = "HepMC::" + format + "-END_EVENT_LISTING";
  if (startsWith(s, end)) {
    summary.hasFooter = true;
    summary.canonical += end;
  } else if (startsWith(s, start)) {
    summary.canonical += start;
  } else if (startsWith(s, "HepMC::Version")) {
    summary.canonical += "HepMC::Version 3.1.2";
  } else {
    c.fail(lineNumber,
           "unexpected line '" + std::string(s.substr(0, 60)) + "'");
  }
  summary.canonical += '\n';
}

CanonicalLine& CanonicalLine::integer(long long v) { return number(v); }

CanonicalLine& CanonicalLine::real(double v) { return number(v); }

template <typename T>
CanonicalLine& CanonicalLine::number(T v) {
  // Large enough for any long long and for the shortest round-trip form of
  // any double ("-2.2250738585072014e-308": 24 characters).
  std::array<char, 32> buffer{};
  const auto result =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), v);
  m_out += ' ';
  m_out.append(buffer.data(), result.ptr);
  return *this;
}

CanonicalLine& CanonicalLine::word(std::string_view w) {
  m_out += ' ';
  m_out += w;
  return *this;
}

/// The HepMC3 3.1.2 readers find the fields of the numeric records by
/// searching for the next single space (strchr), so a repeated space or a
/// tab shifts every later field by one against what any other reader (and
/// this validator's tokenizer) sees: a vertex read with other particle
/// counts, a null vertex and a crash (found by fuzzing, docs/fuzzing.md).
/// Such lines are refused. A carriage return inside a line is the same
/// shift the other way (this tokenizer splits there, the reader does not);
/// one that ends the line (a CRLF file) is harmless.
void requireSingleSpaces(std::string_view s, std::size_t lineNumber,
                         const Checker& c) {
  if (s.find("  ") != std::string_view::npos ||
      s.find('\t') != std::string_view::npos) {
    c.fail(lineNumber,
           "fields must be separated by single spaces (the HepMC3 3.1.2 "
           "reader reads a repeated space or a tab as an extra field)");
  }
  const std::size_t cr = s.find('\r');
  if (cr != std::string_view::npos && cr + 1 != s.size()) {
    c.fail(lineNumber,
           "carriage return inside a line (the HepMC3 3.1.2 reader does not "
           "separate fields there)");
  }
}

}  // namespace conftrack::hepmc::detail

#include "conftrack/simulation/generators/HepMCText.hpp"

#include "conftrack/core/Error.hpp"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <unordered_map>

namespace conftrack::hepmc {

namespace {

/// The Debian readers read lines into a 512*512-byte buffer; a longer
/// line would be split silently.
constexpr std::size_t kMaxLineLength = 512 * 512 - 1;

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

  long long integer(const std::vector<std::string_view>& t, std::size_t i,
                    std::size_t line, const char* what) const {
    if (i >= t.size()) {
      fail(line, std::string("missing ") + what);
    }
    auto v = toInt(t[i]);
    if (!v) {
      fail(line, std::string("bad ") + what + " '" + std::string(t[i]) + "'");
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

// ---------------------------------------------------------------------------
// HepMC2 IO_GenEvent
//
// E n mpi scale aQCD aQED procId procVertex nVertices beam1 beam2
//   nRandom [random...] nWeights [weights...]
// V barcode id x y z t nOrphansIn nOut nWeights [weights...]
// P barcode pdg px py pz e m status theta phi endVertex nFlow [i v]...
// Particles listed after a vertex are its outgoing particles, or incoming
// "orphans" if their end vertex is that same vertex.
// ---------------------------------------------------------------------------

struct V2 {
  long long barcode = 0;
  long long nOrphans = 0;
  long long nOut = 0;
  std::size_t nListed = 0;
  std::size_t line = 0;
};

struct P2 {
  long long barcode = 0;
  long long status = 0;
  long long endBarcode = 0;
  std::size_t vertex = 0;  // index of the vertex it is listed under
};

struct Event2 {
  long long number = 0;
  std::size_t line = 0;
  long long nVertices = 0;
  std::vector<V2> vertices;
  std::vector<P2> particles;
};

void checkVertexListing(const Checker& c, const Event2& ev) {
  if (ev.vertices.empty()) {
    return;
  }
  const V2& v = ev.vertices.back();
  // The reader itself only requires nOut lines (Pythia 8 writes too many).
  if (static_cast<long long>(v.nListed) < v.nOrphans + v.nOut) {
    c.fail(v.line, c.inEvent(ev.number) + "vertex " +
                       std::to_string(v.barcode) + " announces " +
                       std::to_string(v.nOrphans + v.nOut) +
                       " particles, found " + std::to_string(v.nListed));
  }
}

void finishEvent2(const Checker& c, const Event2& ev) {
  checkVertexListing(c, ev);
  const std::string at = c.inEvent(ev.number);
  if (static_cast<long long>(ev.vertices.size()) != ev.nVertices) {
    c.fail(ev.line, at + "header announces " + std::to_string(ev.nVertices) +
                        " vertices, found " +
                        std::to_string(ev.vertices.size()));
  }
  std::unordered_map<long long, std::size_t> index;
  for (std::size_t i = 0; i < ev.vertices.size(); ++i) {
    if (!index.emplace(ev.vertices[i].barcode, i).second) {
      c.fail(ev.vertices[i].line, at + "duplicate vertex barcode " +
                                      std::to_string(ev.vertices[i].barcode));
    }
  }
  const std::size_t nv = ev.vertices.size();
  std::vector<std::size_t> nIn(nv, 0);
  std::vector<std::size_t> nOut(nv, 0);
  std::vector<bool> hasFreeBeam(nv, false);
  std::vector<std::vector<std::size_t>> adjacency(nv);
  for (const P2& p : ev.particles) {
    const V2& v = ev.vertices[p.vertex];
    if (p.endBarcode != 0 && p.endBarcode == v.barcode) {
      ++nIn[p.vertex];
      continue;
    }
    ++nOut[p.vertex];
    if (p.endBarcode == 0) {
      hasFreeBeam[p.vertex] = hasFreeBeam[p.vertex] || p.status == 4;
      continue;
    }
    auto it = index.find(p.endBarcode);
    if (it == index.end()) {
      c.fail(v.line, at + "particle " + std::to_string(p.barcode) +
                         " ends at unknown vertex " +
                         std::to_string(p.endBarcode));
    }
    ++nIn[it->second];
    adjacency[p.vertex].push_back(it->second);
  }
  // The crash of inputSherpa140Crash.hepmc: ReaderAsciiHepMC2 3.1.2 drops
  // a vertex without incoming particles (unless it has status-4 beam
  // particles it can move in) or without outgoing ones by setting its cache
  // entry to nullptr, and then attaches the vertex weights to every cache
  // entry, dereferencing that nullptr (GenVertex::add_attribute).
  for (std::size_t i = 0; i < nv; ++i) {
    const V2& v = ev.vertices[i];
    if (nIn[i] == 0 && !hasFreeBeam[i]) {
      c.fail(v.line, at + "vertex " + std::to_string(v.barcode) +
                         " has no incoming particles (a malformed record that "
                         "crashes the HepMC3 3.1.2 reader)");
    }
    if (nIn[i] > 0 && nOut[i] == 0) {
      c.fail(v.line, at + "vertex " + std::to_string(v.barcode) +
                         " has no outgoing particles (a malformed record that "
                         "crashes the HepMC3 3.1.2 reader)");
    }
  }
  // A cycle makes GenVertex::position() recurse forever.
  if (hasCycle(adjacency)) {
    c.fail(ev.line, at + "the decay graph has a cycle");
  }
}

/// A "HepMC..." line of `format`: version, start or end marker. Anything
/// else there would stop the library's reader, so it is an error.
void headerLine(std::string_view s, const std::string& format,
                std::size_t lineNumber, const Checker& c,
                TextSummary& summary) {
  if (startsWith(s, "HepMC::" + format + "-END_EVENT_LISTING")) {
    summary.hasFooter = true;
  } else if (!startsWith(s, "HepMC::Version") &&
             !startsWith(s, "HepMC::" + format + "-START_EVENT_LISTING")) {
    c.fail(lineNumber,
           "unexpected line '" + std::string(s.substr(0, 60)) + "'");
  }
}

/// The HepMC3 3.1.2 readers find the fields of the numeric records by
/// searching for the next single space (strchr), so a repeated space or a
/// tab shifts every later field by one against what any other reader (and
/// this validator's tokenizer) sees: a vertex read with other particle
/// counts, a null vertex and a crash (found by fuzzing, docs/fuzzing.md).
/// Such lines are refused.
void requireSingleSpaces(std::string_view s, std::size_t lineNumber,
                         const Checker& c) {
  if (s.find("  ") != std::string_view::npos ||
      s.find('\t') != std::string_view::npos) {
    c.fail(lineNumber,
           "fields must be separated by single spaces (the HepMC3 3.1.2 "
           "reader reads a repeated space or a tab as an extra field)");
  }
}

TextSummary validateIoGenEvent(const std::vector<Line>& lines,
                               const Checker& c) {
  TextSummary summary;
  summary.format = Format::eIoGenEvent;
  std::optional<Event2> ev;
  auto finish = [&]() {
    if (ev) {
      finishEvent2(c, *ev);
      summary.particlesPerEvent.push_back(ev->particles.size());
      ++summary.numEvents;
    }
  };
  for (const Line& line : lines) {
    const std::string_view s = line.text;
    if (s.empty() || s == "\r") {
      continue;
    }
    if (startsWith(s, "HepMC")) {
      headerLine(s, "IO_GenEvent", line.number, c, summary);
      // The reader ends the event at a "HepMC" line: what follows belongs
      // to no event (ReaderAsciiHepMC2 3.1.2 then crashes on the vertices
      // left without particles, found by fuzzing, docs/fuzzing.md).
      finish();
      ev.reset();
      continue;
    }
    const auto t = tokenize(s);
    const char key = s[0];
    if (key != 'E' && !ev) {
      c.fail(line.number, "line before the first event ('E') line");
    }
    if (std::string_view("EVPCHFU").find(key) != std::string_view::npos) {
      requireSingleSpaces(s, line.number, c);
    }
    switch (key) {
      case 'E': {
        finish();
        ev.emplace();
        ev->line = line.number;
        ev->number = c.integer(t, 1, line.number, "event number");
        for (std::size_t i = 2; i <= 5; ++i) {
          c.real(t, i, line.number, "event scale/coupling", false);
        }
        c.integer(t, 6, line.number, "signal process id");
        c.integer(t, 7, line.number, "signal process vertex");
        ev->nVertices = c.count(t, 8, line.number, "vertex count");
        c.integer(t, 9, line.number, "beam 1 barcode");
        c.integer(t, 10, line.number, "beam 2 barcode");
        const long long nRandom = c.count(t, 11, line.number, "random count");
        for (long long i = 0; i < nRandom; ++i) {
          c.integer(t, 12 + i, line.number, "random state");
        }
        const std::size_t w = 12 + nRandom;
        const long long nWeights = c.count(t, w, line.number, "weight count");
        for (long long i = 0; i < nWeights; ++i) {
          c.real(t, w + 1 + i, line.number, "event weight", false);
        }
        break;
      }
      case 'N': {
        const long long n = c.count(t, 1, line.number, "weight-name count");
        const auto quotes = std::count(s.begin(), s.end(), '"');
        if (n < 1 || quotes < 2 * n) {
          c.fail(line.number, "bad weight-name line");
        }
        break;
      }
      case 'U':
        c.units(t, line.number);
        break;
      case 'C':
        c.real(t, 1, line.number, "cross section", false);
        c.real(t, 2, line.number, "cross-section error", false);
        break;
      case 'H':
        for (std::size_t i = 1; i <= 13; ++i) {
          c.real(t, i, line.number, "heavy-ion field", false);
        }
        break;
      case 'F':
        for (std::size_t i = 1; i <= 7; ++i) {
          c.real(t, i, line.number, "PDF-info field", false);
        }
        break;
      case 'V': {
        checkVertexListing(c, *ev);
        V2 v;
        v.line = line.number;
        v.barcode = c.integer(t, 1, line.number, "vertex barcode");
        c.integer(t, 2, line.number, "vertex id");
        for (std::size_t i = 3; i <= 6; ++i) {
          c.real(t, i, line.number, "vertex position");
        }
        v.nOrphans = c.count(t, 7, line.number, "orphan count");
        v.nOut = c.count(t, 8, line.number, "outgoing count");
        const long long nWeights = c.count(t, 9, line.number, "weight count");
        for (long long i = 0; i < nWeights; ++i) {
          c.real(t, 10 + i, line.number, "vertex weight", false);
        }
        ev->vertices.push_back(v);
        break;
      }
      case 'P': {
        if (ev->vertices.empty()) {
          // The reader would call back() on its empty vertex cache.
          c.fail(line.number, c.inEvent(ev->number) +
                                  "particle line before any vertex line");
        }
        P2 p;
        p.barcode = c.integer(t, 1, line.number, "particle barcode");
        c.integer(t, 2, line.number, "PDG code");
        for (std::size_t i = 3; i <= 7; ++i) {
          c.real(t, i, line.number, "particle momentum/mass");
        }
        p.status = c.integer(t, 8, line.number, "particle status");
        c.real(t, 9, line.number, "polarisation theta", false);
        c.real(t, 10, line.number, "polarisation phi", false);
        p.endBarcode = c.integer(t, 11, line.number, "end-vertex barcode");
        const long long nFlow = c.count(t, 12, line.number, "flow count");
        for (long long i = 0; i < 2 * nFlow; ++i) {
          c.integer(t, 13 + i, line.number, "flow entry");
        }
        p.vertex = ev->vertices.size() - 1;
        ++ev->vertices.back().nListed;
        ev->particles.push_back(p);
        break;
      }
      default:
        c.fail(line.number, "unknown line type '" + std::string(1, key) + "'");
    }
  }
  finish();
  return summary;
}

// ---------------------------------------------------------------------------
// HepMC3 Asciiv3
//
// E n nVertices nParticles [@ x y z t]
// V id status [in1,in2,...] [@ x y z t]
// P id motherId pdg px py pz e m status
// Particle ids run 1..n; motherId > 0 is an earlier particle, < 0 a vertex.
// ---------------------------------------------------------------------------

struct V3 {
  long long id = 0;
  std::vector<long long> incoming;
  std::size_t line = 0;
};

struct Event3 {
  long long number = 0;
  std::size_t line = 0;
  long long nVertices = 0;
  long long nParticles = 0;
  std::vector<V3> vertices;
  std::vector<long long> mothers;  // per particle
  std::vector<std::size_t> particleLines;
  /// Per particle: has an end vertex at this point of the reading.
  std::vector<bool> hasEndVertex;
  /// Vertices the reader creates for "P id motherParticle" lines.
  long long implicitVertices = 0;
};

void finishEvent3(const Checker& c, const Event3& ev) {
  const std::string at = c.inEvent(ev.number);
  if (static_cast<long long>(ev.mothers.size()) != ev.nParticles) {
    c.fail(ev.line,
           at + "header announces " + std::to_string(ev.nParticles) +
               " particles, found " + std::to_string(ev.mothers.size()) +
               (ev.mothers.size() < static_cast<std::size_t>(ev.nParticles)
                    ? " (truncated?)"
                    : ""));
  }
  // The reader counts explicit and implicit vertices against the header.
  const long long nVertices =
      static_cast<long long>(ev.vertices.size()) + ev.implicitVertices;
  if (nVertices != ev.nVertices) {
    c.fail(ev.line, at + "header announces " + std::to_string(ev.nVertices) +
                        " vertices, the record has " +
                        std::to_string(nVertices));
  }
  // Nodes: particles 0..n-1, then the explicit vertices.
  const std::size_t np = ev.mothers.size();
  std::unordered_map<long long, std::size_t> vertexIndex;
  for (std::size_t i = 0; i < ev.vertices.size(); ++i) {
    if (!vertexIndex.emplace(ev.vertices[i].id, np + i).second) {
      c.fail(ev.vertices[i].line,
             at + "duplicate vertex id " + std::to_string(ev.vertices[i].id));
    }
  }
  std::vector<std::vector<std::size_t>> adjacency(np + ev.vertices.size());
  for (std::size_t i = 0; i < np; ++i) {
    const long long mother = ev.mothers[i];
    if (mother > 0) {
      adjacency[static_cast<std::size_t>(mother - 1)].push_back(i);
    } else if (mother < 0) {
      auto it = vertexIndex.find(mother);
      if (it == vertexIndex.end()) {
        c.fail(ev.particleLines[i], at + "particle " + std::to_string(i + 1) +
                                        " comes from unknown vertex " +
                                        std::to_string(mother));
      }
      adjacency[it->second].push_back(i);
    }
  }
  for (std::size_t v = 0; v < ev.vertices.size(); ++v) {
    for (long long in : ev.vertices[v].incoming) {
      // The reader indexes its particle vector with these ids unchecked.
      if (in < 1 || in > ev.nParticles) {
        c.fail(ev.vertices[v].line,
               at + "vertex " + std::to_string(ev.vertices[v].id) +
                   " lists particle " + std::to_string(in) + " outside 1.." +
                   std::to_string(ev.nParticles));
      }
      adjacency[static_cast<std::size_t>(in - 1)].push_back(np + v);
    }
  }
  if (hasCycle(adjacency)) {
    c.fail(ev.line, at + "the decay graph has a cycle");
  }
}

/// True if an odd run of backslashes ends a whitespace-separated field of
/// `s`. ReaderAscii::unescape (HepMC3 3.1.2) then steps past the end of the
/// field's string and reads on until it faults (found by fuzzing,
/// docs/fuzzing.md); it unescapes weight names, tool lines and attribute
/// values.
bool endsFieldWithEscape(std::string_view s) {
  std::size_t run = 0;
  for (std::size_t i = 0; i <= s.size(); ++i) {
    const bool end =
        i == s.size() || std::isspace(static_cast<unsigned char>(s[i])) != 0;
    if (end && run % 2 == 1) {
      return true;
    }
    run = (i < s.size() && s[i] == '\\') ? run + 1 : 0;
  }
  return false;
}

TextSummary validateAsciiV3(const std::vector<Line>& lines, const Checker& c) {
  TextSummary summary;
  summary.format = Format::eAsciiV3;
  std::optional<Event3> ev;
  std::optional<std::size_t> nWeightNames;
  auto finish = [&]() {
    if (ev) {
      finishEvent3(c, *ev);
      summary.particlesPerEvent.push_back(ev->mothers.size());
      ++summary.numEvents;
    }
  };
  for (const Line& line : lines) {
    const std::string_view s = line.text;
    if (s.empty() || s == "\r") {
      continue;
    }
    if (startsWith(s, "HepMC")) {
      headerLine(s, "Asciiv3", line.number, c, summary);
      // The reader ends the event at a "HepMC" line: what follows belongs
      // to no event (ReaderAsciiHepMC2 3.1.2 then crashes on the vertices
      // left without particles, found by fuzzing, docs/fuzzing.md).
      finish();
      ev.reset();
      continue;
    }
    const auto t = tokenize(s);
    const char key = s[0];
    if (endsFieldWithEscape(s)) {
      c.fail(line.number,
             "a field ends with an escaping backslash (crashes the HepMC3 "
             "3.1.2 reader)");
    }
    if (std::string_view("EVPU").find(key) != std::string_view::npos) {
      requireSingleSpaces(s, line.number, c);
    }
    switch (key) {
      case 'E': {
        finish();
        ev.emplace();
        ev->line = line.number;
        ev->number = c.integer(t, 1, line.number, "event number");
        ev->nVertices = c.count(t, 2, line.number, "vertex count");
        ev->nParticles = c.count(t, 3, line.number, "particle count");
        if (t.size() > 4) {
          if (t[4] != "@") {
            c.fail(line.number, "bad event line");
          }
          for (std::size_t i = 5; i <= 8; ++i) {
            c.real(t, i, line.number, "event position");
          }
        }
        ev->mothers.reserve(static_cast<std::size_t>(ev->nParticles));
        break;
      }
      case 'W':
        if (!ev) {
          nWeightNames = t.size() - 1;
        } else {
          for (std::size_t i = 1; i < t.size(); ++i) {
            c.real(t, i, line.number, "event weight", false);
          }
          // The reader throws std::logic_error on a mismatch.
          if (nWeightNames && *nWeightNames > 0 &&
              *nWeightNames != t.size() - 1) {
            c.fail(line.number,
                   c.inEvent(ev->number) + std::to_string(t.size() - 1) +
                       " weights for " + std::to_string(*nWeightNames) +
                       " weight names");
          }
        }
        break;
      case 'A': {
        if (t.size() < 3 || (ev && !toInt(t[1]))) {
          c.fail(line.number, "bad attribute line");
        }
        // The reader copies the attribute name into a char[64] with
        // sprintf: a longer name overflows its stack (found by fuzzing,
        // docs/fuzzing.md). Its fields end at the next ' ': the name
        // follows the first space of a run attribute ("A name value"), the
        // second one in an event ("A id name value").
        std::size_t nameBegin = s.find(' ', 1);
        if (ev && nameBegin != std::string_view::npos) {
          nameBegin = s.find(' ', nameBegin + 1);
        }
        if (nameBegin != std::string_view::npos) {
          const std::size_t nameEnd = s.find(' ', nameBegin + 1);
          if (nameEnd != std::string_view::npos &&
              nameEnd - nameBegin - 1 >= 64) {
            c.fail(line.number, "attribute name longer than 63 characters");
          }
        }
        break;
      }
      case 'T':
        if (ev) {
          c.fail(line.number, "tool line inside an event");
        }
        break;
      case 'U':
        if (!ev) {
          c.fail(line.number, "units line before the first event");
        }
        c.units(t, line.number);
        break;
      case 'V': {
        if (!ev) {
          c.fail(line.number, "vertex line before the first event");
        }
        V3 v;
        v.line = line.number;
        v.id = c.integer(t, 1, line.number, "vertex id");
        if (v.id >= 0) {
          c.fail(line.number, "vertex id must be negative");
        }
        c.integer(t, 2, line.number, "vertex status");
        const auto open = s.find('[');
        const auto close = s.find(']');
        if (open == std::string_view::npos || close == std::string_view::npos ||
            close < open) {
          c.fail(line.number, "vertex line without a [particle list]");
        }
        std::string_view list = s.substr(open + 1, close - open - 1);
        while (!list.empty()) {
          const auto comma = list.find(',');
          const auto item = tokenize(list.substr(0, comma));
          if (item.size() != 1 || !toInt(item[0])) {
            c.fail(line.number,
                   "bad particle list of vertex " + std::to_string(v.id));
          }
          const long long in = *toInt(item[0]);
          v.incoming.push_back(in);
          // Particles already read get this vertex as end vertex now;
          // later ones only after the event (the reader's forward list).
          if (in >= 1 && in <= static_cast<long long>(ev->mothers.size())) {
            ev->hasEndVertex[static_cast<std::size_t>(in - 1)] = true;
          }
          if (comma == std::string_view::npos) {
            break;
          }
          list.remove_prefix(comma + 1);
        }
        const auto rest = tokenize(s.substr(close + 1));
        if (!rest.empty()) {
          if (rest[0] != "@") {
            c.fail(line.number, "bad vertex line");
          }
          for (std::size_t i = 1; i <= 4; ++i) {
            c.real(rest, i, line.number, "vertex position");
          }
        }
        ev->vertices.push_back(std::move(v));
        break;
      }
      case 'P': {
        if (!ev) {
          c.fail(line.number, "particle line before the first event");
        }
        const long long id = c.integer(t, 1, line.number, "particle id");
        if (id != static_cast<long long>(ev->mothers.size()) + 1) {
          c.fail(line.number, c.inEvent(ev->number) + "particle id " +
                                  std::to_string(id) + " out of sequence");
        }
        const long long mother = c.integer(t, 2, line.number, "mother id");
        if (mother >= id) {
          c.fail(line.number, c.inEvent(ev->number) + "particle " +
                                  std::to_string(id) +
                                  " has a mother particle that is not earlier");
        }
        c.integer(t, 3, line.number, "PDG code");
        for (std::size_t i = 4; i <= 8; ++i) {
          c.real(t, i, line.number, "particle momentum/mass");
        }
        c.integer(t, 9, line.number, "particle status");
        if (mother > 0 &&
            !ev->hasEndVertex[static_cast<std::size_t>(mother - 1)]) {
          // The reader creates a vertex with the mother as incoming.
          ++ev->implicitVertices;
          ev->hasEndVertex[static_cast<std::size_t>(mother - 1)] = true;
        }
        ev->mothers.push_back(mother);
        ev->particleLines.push_back(line.number);
        ev->hasEndVertex.push_back(false);
        break;
      }
      default:
        c.fail(line.number, "unknown line type '" + std::string(1, key) + "'");
    }
  }
  finish();
  return summary;
}

}  // namespace

std::string formatName(Format format) {
  switch (format) {
    case Format::eAsciiV3:
      return "Asciiv3";
    case Format::eIoGenEvent:
      return "IO_GenEvent";
    default:
      return "unknown";
  }
}

std::string gunzip(std::string_view data, const std::string& source,
                   std::size_t maxBytes) {
  std::string out;
  z_stream zs{};
  // 16 + MAX_WBITS: gzip wrapper only.
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) {
    throw InputError(source, "zlib initialisation failed");
  }
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = static_cast<uInt>(data.size());
  // Not zero-filled, and no larger than the limit allows: a 256 kB
  // zeroed buffer per call cost 1.5 ms (most of the gzip fuzz target's
  // time, under ASan) on inputs of a few bytes.
  constexpr std::size_t kChunk = std::size_t{1} << 18;
  const std::size_t chunk = maxBytes < kChunk ? maxBytes + 1 : kChunk;
  const std::unique_ptr<char[]> buffer =
      std::make_unique_for_overwrite<char[]>(chunk);
  int ret = Z_OK;
  while (true) {
    zs.next_out = reinterpret_cast<Bytef*>(buffer.get());
    zs.avail_out = static_cast<uInt>(chunk);
    ret = inflate(&zs, Z_NO_FLUSH);
    if (ret != Z_OK && ret != Z_STREAM_END && ret != Z_BUF_ERROR) {
      const std::string msg = zs.msg != nullptr ? zs.msg : "error";
      inflateEnd(&zs);
      throw InputError(source, "corrupt gzip data (" + msg + ")");
    }
    out.append(buffer.get(), chunk - zs.avail_out);
    if (out.size() > maxBytes) {
      inflateEnd(&zs);
      throw InputError(source, "decompressed data larger than " +
                                   std::to_string(maxBytes) + " bytes");
    }
    if (ret == Z_STREAM_END) {
      // Another gzip member may follow (as zcat reads them).
      if (zs.avail_in == 0) {
        break;
      }
      if (inflateReset(&zs) != Z_OK) {
        inflateEnd(&zs);
        throw InputError(source, "corrupt gzip data");
      }
      continue;
    }
    if (ret == Z_BUF_ERROR || (zs.avail_in == 0 && zs.avail_out != 0)) {
      // No progress possible: the input ended inside a member.
      inflateEnd(&zs);
      throw InputError(source, "truncated gzip data (unexpected end of file)");
    }
  }
  inflateEnd(&zs);
  return out;
}

std::string loadFile(const std::filesystem::path& path, std::size_t maxBytes) {
  const std::string source = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw MissingFileError(source, "no such file");
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(source, "not a regular file");
  }
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) {
    throw InputError(source, "cannot determine the file size");
  }
  if (size > maxBytes) {
    throw InputError(source,
                     "file larger than " + std::to_string(maxBytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(source, "cannot open the file");
  }
  std::string data(size, '\0');
  in.read(data.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in.gcount()) != size) {
    throw InputError(source, "cannot read the file");
  }
  if (data.empty()) {
    throw InputError(source, "empty file");
  }
  if (data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f &&
      static_cast<unsigned char>(data[1]) == 0x8b) {
    data = gunzip(data, source, maxBytes);
    if (data.empty()) {
      throw InputError(source, "empty file (after decompression)");
    }
  }
  return data;
}

Format detectFormat(std::string_view text) {
  std::size_t pos = 0;
  for (int n = 0; n < 20 && pos < text.size(); ++n) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) {
      end = text.size();
    }
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
      line.remove_suffix(1);
    }
    if (line.empty() || startsWith(line, "HepMC::Version")) {
      continue;
    }
    if (line == "HepMC::Asciiv3-START_EVENT_LISTING") {
      return Format::eAsciiV3;
    }
    if (line == "HepMC::IO_GenEvent-START_EVENT_LISTING") {
      return Format::eIoGenEvent;
    }
    return Format::eUnknown;
  }
  return Format::eUnknown;
}

TextSummary validate(std::string_view text, const std::string& source) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw InputError(source, "empty file");
  }
  if (text.find('\0') != std::string_view::npos) {
    throw InputError(source, "binary data, not a HepMC text file");
  }
  const Format format = detectFormat(text);
  if (format == Format::eUnknown) {
    throw InputError(source,
                     "unknown format (expected a 'HepMC::Asciiv3' or "
                     "'HepMC::IO_GenEvent' START_EVENT_LISTING line)");
  }
  const std::vector<Line> lines = splitLines(text);
  const Checker checker(source);
  for (const Line& line : lines) {
    if (line.text.size() > kMaxLineLength) {
      checker.fail(line.number, "line longer than the HepMC3 reader's " +
                                    std::to_string(kMaxLineLength) +
                                    "-character buffer");
    }
  }
  TextSummary summary = format == Format::eAsciiV3
                            ? validateAsciiV3(lines, checker)
                            : validateIoGenEvent(lines, checker);
  if (summary.numEvents == 0) {
    throw InputError(source, "no events");
  }
  return summary;
}

}  // namespace conftrack::hepmc

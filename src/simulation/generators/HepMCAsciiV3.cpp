#include <algorithm>
#include <cctype>
#include <limits>
#include <unordered_map>

#include "HepMCTextCheck.hpp"

namespace conftrack::hepmc::detail {

namespace {

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

}  // namespace

TextSummary validateAsciiV3(const std::vector<Line>& lines, const Checker& c) {
  TextSummary summary;
  summary.format = Format::eAsciiV3;
  std::optional<Event3> ev;
  std::optional<std::size_t> nWeightNames;
  // Checks the open event, counts it and closes it.
  auto endEvent = [&]() {
    if (ev) {
      finishEvent3(c, *ev);
      summary.particlesPerEvent.push_back(ev->mothers.size());
      ++summary.numEvents;
    }
    ev.reset();
  };
  auto record = [&](const Line& line) {
    const std::string_view s = line.text;
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
        endEvent();
        ev.emplace();
        ev->line = line.number;
        ev->number = c.integer(t, 1, line.number, "event number");
        ev->nVertices = c.count(t, 2, line.number, "vertex count");
        ev->nParticles = c.count(t, 3, line.number, "particle count");
        CanonicalLine canonical(summary.canonical, 'E');
        canonical.integer(ev->number)
            .integer(ev->nVertices)
            .integer(ev->nParticles);
        if (t.size() > 4) {
          if (t[4] != "@") {
            c.fail(line.number, "bad event line");
          }
          canonical.word("@");
          for (std::size_t i = 5; i <= 8; ++i) {
            canonical.real(c.real(t, i, line.number, "event position"));
          }
        }
        // Bounded by the lines: every particle needs one, and a header may
        // announce 10^8 (a fuzzer's 0.8 GB reservation per event header
        // took the 10 s of an input under ASan).
        ev->mothers.reserve(
            std::min(static_cast<std::size_t>(ev->nParticles), lines.size()));
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
        if (ev) {
          // GenEvent::add_attribute (3.1.2) negates a vertex id and indexes
          // its vertex vector with it: -2147483648 stays negative there and
          // reads far outside the vector (SEGV, docs/fuzzing.md).
          const long long id = c.integer(t, 1, line.number, "attribute id");
          if (id == std::numeric_limits<int>::min()) {
            c.fail(line.number, "bad attribute id " + std::to_string(id) +
                                    " (the reader cannot negate it)");
          }
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
        CanonicalLine(summary.canonical, 'U').word(t[1]).word(t[2]);
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
        const long long status = c.integer(t, 2, line.number, "vertex status");
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
        std::string particleList = "[";
        for (std::size_t i = 0; i < v.incoming.size(); ++i) {
          particleList += (i == 0 ? "" : ",") + std::to_string(v.incoming[i]);
        }
        particleList += ']';
        CanonicalLine canonical(summary.canonical, 'V');
        canonical.integer(v.id).integer(status).word(particleList);
        const auto rest = tokenize(s.substr(close + 1));
        if (!rest.empty()) {
          if (rest[0] != "@") {
            c.fail(line.number, "bad vertex line");
          }
          canonical.word("@");
          for (std::size_t i = 1; i <= 4; ++i) {
            canonical.real(c.real(rest, i, line.number, "vertex position"));
          }
          // The reader looks for the list's next ',' anywhere up to the
          // line's end: "... @ x y z t ,9]" adds particle 9, which it
          // later takes from its particle vector unchecked (a read past
          // the vector's end).
          if (rest.size() > 5) {
            c.fail(line.number, "text after the vertex position '" +
                                    std::string(rest[5].substr(0, 20)) + "'");
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
        CanonicalLine canonical(summary.canonical, 'P');
        canonical.integer(id).integer(mother).integer(
            c.integer(t, 3, line.number, "PDG code"));
        for (std::size_t i = 4; i <= 8; ++i) {
          canonical.real(c.real(t, i, line.number, "particle momentum/mass"));
        }
        canonical.integer(c.integer(t, 9, line.number, "particle status"));
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
  };
  forEachRecord(lines, "Asciiv3", c, summary, endEvent, record);
  return summary;
}

}  // namespace conftrack::hepmc::detail

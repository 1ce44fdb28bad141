#include <algorithm>
#include <array>
#include <unordered_map>

#include "HepMCTextCheck.hpp"

namespace conftrack::hepmc::detail {

namespace {

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
  long long nWeights = 0;
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
  // a vertex without incoming particles or without outgoing ones by
  // setting its cache entry to nullptr, and then attaches the vertex
  // weights to every cache entry, dereferencing that nullptr
  // (GenVertex::add_attribute). A vertex whose only particles are free
  // status-4 beams (no end vertex) is dropped too; without weights nothing
  // dereferences the null entry (the fuzzer's record then came back short
  // of particles and readHepMCEvents refused it by its count), with
  // weights the reader crashes (found by fuzzing, docs/fuzzing.md finding
  // 9).
  for (std::size_t i = 0; i < nv; ++i) {
    const V2& v = ev.vertices[i];
    if (nIn[i] == 0 && !hasFreeBeam[i]) {
      c.fail(v.line, at + "vertex " + std::to_string(v.barcode) +
                         " has no incoming particles (a malformed record that "
                         "crashes the HepMC3 3.1.2 reader)");
    }
    if (nIn[i] == 0 && v.nWeights > 0) {
      c.fail(v.line, at + "vertex " + std::to_string(v.barcode) +
                         " has weights but no incoming particles (a "
                         "malformed record that crashes the HepMC3 3.1.2 "
                         "reader)");
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

}  // namespace

TextSummary validateIoGenEvent(const std::vector<Line>& lines,
                               const Checker& c) {
  TextSummary summary;
  summary.format = Format::eIoGenEvent;
  std::optional<Event2> ev;
  // Checks the open event, counts it and closes it.
  auto endEvent = [&]() {
    if (ev) {
      finishEvent2(c, *ev);
      summary.particlesPerEvent.push_back(ev->particles.size());
      ++summary.numEvents;
    }
    ev.reset();
  };
  auto record = [&](const Line& line) {
    const std::string_view s = line.text;
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
        endEvent();
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
          c.integer(t, 12 + i, line.number, "random state", true);
        }
        const std::size_t w = 12 + nRandom;
        const long long nWeights = c.count(t, w, line.number, "weight count");
        for (long long i = 0; i < nWeights; ++i) {
          c.real(t, w + 1 + i, line.number, "event weight", false);
        }
        // Scales, couplings, process, signal vertex, beams, random states
        // and weights are not used by conftrack: MPI -1, the next five 0;
        // then no beams, no random states, no weights.
        CanonicalLine(summary.canonical, 'E')
            .integer(ev->number)
            .word("-1 0 0 0 0 0")
            .integer(ev->nVertices)
            .word("0 0 0 0");
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
        CanonicalLine(summary.canonical, 'U').word(t[1]).word(t[2]);
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
        const long long id = c.integer(t, 2, line.number, "vertex id");
        std::array<double, 4> position{};
        for (std::size_t i = 0; i < 4; ++i) {
          position[i] = c.real(t, 3 + i, line.number, "vertex position");
        }
        v.nOrphans = c.count(t, 7, line.number, "orphan count");
        v.nOut = c.count(t, 8, line.number, "outgoing count");
        const long long nWeights = c.count(t, 9, line.number, "weight count");
        v.nWeights = nWeights;
        for (long long i = 0; i < nWeights; ++i) {
          c.real(t, 10 + i, line.number, "vertex weight", false);
        }
        CanonicalLine(summary.canonical, 'V')
            .integer(v.barcode)
            .integer(id)
            .real(position[0])
            .real(position[1])
            .real(position[2])
            .real(position[3])
            .integer(v.nOrphans)
            .integer(v.nOut)
            .integer(0);
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
        const long long pdg = c.integer(t, 2, line.number, "PDG code");
        std::array<double, 5> momentumAndMass{};
        for (std::size_t i = 0; i < 5; ++i) {
          momentumAndMass[i] =
              c.real(t, 3 + i, line.number, "particle momentum/mass");
        }
        p.status = c.integer(t, 8, line.number, "particle status");
        c.real(t, 9, line.number, "polarisation theta", false);
        c.real(t, 10, line.number, "polarisation phi", false);
        p.endBarcode = c.integer(t, 11, line.number, "end-vertex barcode");
        const long long nFlow = c.count(t, 12, line.number, "flow count");
        for (long long i = 0; i < 2 * nFlow; ++i) {
          c.integer(t, 13 + i, line.number, "flow entry");
        }
        CanonicalLine canonical(summary.canonical, 'P');
        canonical.integer(p.barcode).integer(pdg);
        for (const double value : momentumAndMass) {
          canonical.real(value);
        }
        // No polarisation, no flow.
        canonical.integer(p.status)
            .integer(0)
            .integer(0)
            .integer(p.endBarcode)
            .integer(0);
        p.vertex = ev->vertices.size() - 1;
        ++ev->vertices.back().nListed;
        ev->particles.push_back(p);
        break;
      }
      default:
        c.fail(line.number, "unknown line type '" + std::string(1, key) + "'");
    }
  };
  forEachRecord(lines, "IO_GenEvent", c, summary, endEvent, record);
  return summary;
}

}  // namespace conftrack::hepmc::detail

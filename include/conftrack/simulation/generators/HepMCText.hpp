#pragma once

/// @file HepMCText.hpp
/// Loading and structural validation of HepMC text files before they reach
/// the HepMC3 library.
///
/// Why a validator: the Debian HepMC3 3.1.2 readers trust their input. A
/// malformed file can make them dereference null or out-of-range pointers
/// (e.g. inputSherpa140Crash.hepmc segfaults ReaderAsciiHepMC2), and a
/// crash would take the whole conftrack process down. Everything that can
/// crash the library is rejected here with a one-line InputError
/// "file:line: event N: problem", and the library reads only the
/// validator's re-printing of what it accepted (TextSummary::canonical).

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace conftrack::hepmc {

/// HepMC text formats.
enum class Format {
  eUnknown,     ///< neither of the below
  eAsciiV3,     ///< HepMC3 "HepMC::Asciiv3" (ReaderAscii)
  eIoGenEvent,  ///< HepMC2 "HepMC::IO_GenEvent" (ReaderAsciiHepMC2)
};

/// Name of a format ("Asciiv3", "IO_GenEvent", "unknown").
std::string formatName(Format format);

/// Upper limit on the (decompressed) size of a file, against gzip bombs.
inline constexpr std::size_t kMaxFileBytes = std::size_t{1} << 30;

/// Reads a whole file; data starting with the gzip magic bytes (1f 8b) are
/// decompressed with zlib (several concatenated members as zcat does).
/// Throws InputError for a missing or unreadable file, an empty file, and
/// corrupt or truncated gzip data.
std::string loadFile(const std::filesystem::path& path,
                     std::size_t maxBytes = kMaxFileBytes);

/// Decompresses gzip data; `source` names it in error messages.
std::string gunzip(std::string_view data, const std::string& source,
                   std::size_t maxBytes = kMaxFileBytes);

/// The format announced by the "HepMC::<format>-START_EVENT_LISTING" line
/// among the first lines (after an optional "HepMC::Version" line).
Format detectFormat(std::string_view text);

/// What the validator learned about a file.
struct TextSummary {
  /// The format.
  Format format = Format::eUnknown;
  /// Number of events ("E" lines).
  std::size_t numEvents = 0;
  /// Number of particle ("P") lines per event.
  std::vector<std::size_t> particlesPerEvent;
  /// True if the file ends with an END_EVENT_LISTING line (the Debian
  /// readers still return the last event without it).
  bool hasFooter = false;
  /// The text the HepMC3 reader is given: the header lines, events,
  /// units, vertices and particles of the file, re-printed from the
  /// validated values with single spaces; without weights, weight names,
  /// random states, polarisations, flows, attributes, tool, cross-section,
  /// heavy-ion and PDF records, none of which conftrack uses. Every crash
  /// the fuzzers found in the 3.1.2 readers came from text the validator
  /// had modelled differently from the reader (field splitting, integer
  /// wrapping, escapes) or from those auxiliary records (vertex weights on
  /// a dropped vertex, attribute names and ids): the reader sees only
  /// records of conftrack's own printing, of the shape its writers emit.
  std::string canonical;
};

/// Checks the structure of a whole HepMC text: format header, line syntax
/// (numbers parse, field counts), per-event counts against the headers,
/// references (vertex barcodes / particle ids exist), no cycles in the
/// decay graph, and the specific patterns the 3.1.2 readers crash on (see
/// the implementation). Throws InputError "source:line: problem" at the
/// first problem; returns a summary otherwise. An unknown format or a
/// file without events is rejected too.
TextSummary validate(std::string_view text, const std::string& source);

}  // namespace conftrack::hepmc

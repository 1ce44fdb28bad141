/// @file HepMCReaderCrashTests.cpp
/// Input that crashes the HepMC3 3.1.2 reader, found by fuzzing
/// (docs/fuzzing.md), is refused by the validator with its line: attribute
/// names that overflow the reader's fixed buffer, and fields ending with an
/// escaping backslash (the reader's unescape() runs past the string's end),
/// numeric records with repeated spaces (the reader's fields shift), and
/// integers outside the reader's int range (barcodes that wrap onto
/// another vertex's).

#include "conftrack/core/Error.hpp"
#include "conftrack/simulation/generators/HepMC3Generator.hpp"

#include <gtest/gtest.h>

#include <string>

#include "InputErrorOf.hpp"

namespace conftrack {
namespace {

const std::string kHead =
    "HepMC::Version 3.02.01\nHepMC::Asciiv3-START_EVENT_LISTING\n"
    "W Weight\n";
const std::string kEvent =
    "E 0 1 3\nU GEV MM\nW 1.0\n"
    "P 1 0 2212 0 0 7000 7000 0.938 4\n"
    "V -1 0 [1]\n"
    "P 2 -1 211 1.0 0 0 1.0096 0.1396 1\n"
    "P 3 -1 -211 0 2 0 2.005 0.1396 1\n";
const std::string kTail = "HepMC::Asciiv3-END_EVENT_LISTING\n";

std::string errorOf(const std::string& text) {
  return test::inputErrorOf([&] { readHepMCEvents(text, "a.hepmc"); });
}

TEST(HepMCAttributes, NamesUpTo63CharactersAreRead) {
  ASSERT_EQ(errorOf(kHead + kEvent + kTail), "(accepted)");
  EXPECT_EQ(errorOf(kHead + "A " + std::string(63, 'r') + " 1\n" + kEvent +
                    "A 0 " + std::string(63, 'e') + " 2\n" + kTail),
            "(accepted)");
}

TEST(HepMCAttributes, LongerNamesAreRefusedWithTheirLine) {
  EXPECT_EQ(
      errorOf(kHead + "A " + std::string(64, 'r') + " 1\n" + kEvent + kTail),
      "a.hepmc:4: attribute name longer than 63 characters");
  EXPECT_EQ(
      errorOf(kHead + kEvent + "A 0 " + std::string(100, 'e') + " 2\n" + kTail),
      "a.hepmc:11: attribute name longer than 63 characters");
}

TEST(HepMCEscapes, FieldEndingWithBackslashIsRefused) {
  const std::string expected =
      "a field ends with an escaping backslash (crashes the HepMC3 3.1.2 "
      "reader)";
  EXPECT_EQ(errorOf("HepMC::Version 3.02.01\nHepMC::Asciiv3-START_EVENT_"
                    "LISTING\nW Weight\\\n" +
                    kEvent + kTail),
            "a.hepmc:3: " + expected);
  EXPECT_EQ(errorOf(kHead + "T Pythia8 8.3 a\\\\\\\t\n" + kEvent + kTail),
            "a.hepmc:4: " + expected);
  EXPECT_EQ(errorOf(kHead + kEvent + "A 0 note x\\ y\n" + kTail),
            "a.hepmc:11: " + expected);
  // An escaped backslash is a field's last character legitimately.
  EXPECT_EQ(errorOf(kHead + "T Pythia8 8.3 a\\\\\n" + kEvent +
                    "A 0 note x\\\\ y\\|z\n" + kTail),
            "(accepted)");
}

TEST(HepMCSpaces, RepeatedSpacesInNumericRecordsAreRefused) {
  const std::string expected =
      "fields must be separated by single spaces (the HepMC3 3.1.2 reader "
      "reads a repeated space or a tab as an extra field)";
  // Asciiv3: a vertex line with a double space (line 8).
  std::string event = kEvent;
  event.replace(event.find("V -1"), 4, "V  -1");
  EXPECT_EQ(errorOf(kHead + event + kTail), "a.hepmc:8: " + expected);
  // A tab in a particle line.
  event = kEvent;
  event.replace(event.find("P 2 -1"), 6, "P 2\t-1");
  EXPECT_EQ(errorOf(kHead + event + kTail), "a.hepmc:9: " + expected);
  // IO_GenEvent, the fuzzer's input: "VC  -1 ..." read by HepMC3 as a
  // vertex with other counts, then a null vertex (SEGV).
  const std::string ioGenEvent =
      "HepMC::Version 2.06.09\nHepMC::IO_GenEvent-START_EVENT_LISTING\n"
      "E 1 -1 -1 -1 -1 0 0 2 1 2 0 1 1.0\nU MEV CM\n"
      "V  -1 0 0 0 0 0 2 1 0\n"
      "P 1 11 0 0 1000 1000 0.511 4 0 0 -1 0\n"
      "P 2 -11 0 0 -1000 1000 0.511 4 0 0 -1 0\n"
      "P 3 23 0 0 0 2000 2000 2 0 0 0 0\n"
      "HepMC::IO_GenEvent-END_EVENT_LISTING\n";
  EXPECT_EQ(errorOf(ioGenEvent), "a.hepmc:5: " + expected);
  // A carriage return inside a record splits a field for the tokenizer
  // but not for the reader; at the end of every line (CRLF) it is read.
  event = kEvent;
  event.replace(event.find("P 2 -1 211"), 10, "P 2 -1\r211");
  EXPECT_EQ(errorOf(kHead + event + kTail),
            "a.hepmc:9: carriage return inside a line (the HepMC3 3.1.2 "
            "reader does not separate fields there)");
  std::string crlf = kHead + kEvent + kTail;
  for (std::size_t at = crlf.find('\n'); at != std::string::npos;
       at = crlf.find('\n', at + 2)) {
    crlf.insert(at, "\r");
  }
  EXPECT_EQ(errorOf(crlf), "(accepted)");
  // Repeated spaces inside the quoted weight names of an N line stay
  // legal (the shipped inputConvert1.hepmc has them: HepMCSharedFiles).
}

TEST(HepMCVertexLists, TextAfterTheVertexPositionIsRefused) {
  // The reader's particle list ends at the last ',' of the whole line:
  // ",9]" after the position would add particle 9 of 3 to the vertex.
  std::string event = kEvent;
  event.replace(event.find("V -1 0 [1]"), 10, "V -1 0 [1] @ 1 2 3 4 ,9]");
  EXPECT_EQ(errorOf(kHead + event + kTail),
            "a.hepmc:8: text after the vertex position ',9]'");
  event = kEvent;
  event.replace(event.find("V -1 0 [1]"), 10, "V -1 0 [1] @ 1 2 3 4");
  EXPECT_EQ(errorOf(kHead + event + kTail), "(accepted)");
}

TEST(HepMCVertices, WeightedVertexWithoutIncomingParticlesIsRefused) {
  // The fuzzer's record (fuzz/regressions/hepmc_text/
  // fuzzer-weighted-vertex-of-free-beams.hepmc): vertex -1 holds only a
  // free status-4 beam and the Z, so the reader drops it (a null cache
  // entry) and then attaches its two weights to it (SEGV).
  const std::string head =
      "HepMC::Version 2.06.09\nHepMC::IO_GenEvent-START_EVENT_LISTING\n"
      "E 1 -1 -1 -1 -1 0 0 2 1 2 0 1 1.0\nU GEV MM\n";
  const std::string tail =
      "P 2 -11 0 0 -1000 1000 0.511 4 0 0 0 0\n"
      "P 3 23 0 0 0 2000 2000 2 0 0 -2 0\n"
      "V -2 0 1 2 3 5 0 1 0\n"
      "P 5 13 0 0 10 10.5 0.1057 1 0 0 0 0\n"
      "HepMC::IO_GenEvent-END_EVENT_LISTING\n";
  EXPECT_EQ(errorOf(head + "V -1 0 0 0 0 0 0 2 2 0.5 1.0\n" + tail),
            "a.hepmc:5: event 1: vertex -1 has weights but no incoming "
            "particles (a malformed record that crashes the HepMC3 3.1.2 "
            "reader)");
  // Without weights the reader survives it and the event comes back short
  // of its beam: refused after the reader, not by the validator.
  EXPECT_EQ(errorOf(head + "V -1 0 0 0 0 0 0 2 0\n" + tail),
            "a.hepmc: HepMC3 reader failed on event 1 of 1");
}

TEST(HepMCIntegers, ValuesOutsideTheReadersIntRangeAreRefused) {
  // The fuzzer's kind of input (fuzz/regressions/hepmc_text/
  // barcode-wider-than-int.hepmc): atoi reads end-vertex barcode
  // -4294967298 as -2, so the Z ends at vertex -2 in the reader and vertex
  // -4294967298 is left without incoming particles (a null vertex, SEGV).
  const std::string head =
      "HepMC::Version 2.06.09\nHepMC::IO_GenEvent-START_EVENT_LISTING\n"
      "E 1 -1 -1 -1 -1 0 0 3 1 2 0 1 1.0\nU GEV MM\n"
      "V -1 0 0 0 0 0 2 1 0\n"
      "P 1 11 0 0 1000 1000 0.511 4 0 0 -1 0\n"
      "P 2 -11 0 0 -1000 1000 0.511 4 0 0 -1 0\n";
  auto event = [&](const std::string& barcode) {
    return head + "P 3 23 0 0 0 2000 2000 2 0 0 " + barcode + " 0\n" +
           "V -2 0 1 2 3 30 0 1 0\n"
           "P 4 11 0 0 10 10 0.000511 4 0 0 0 0\n"
           "V " +
           barcode +
           " 0 1 2 3 30 0 2 1 0.5\n"
           "P 5 13 500 0 0 510 0.1057 1 0 0 0 0\n"
           "P 6 -13 -500 0 0 510 0.1057 1 0 0 0 0\n"
           "HepMC::IO_GenEvent-END_EVENT_LISTING\n";
  };
  EXPECT_EQ(errorOf(event("-4294967298")),
            "a.hepmc:8: bad end-vertex barcode -4294967298 (outside the "
            "reader's 32-bit integer range)");
  // The int range itself is legal: the smallest vertex id.
  std::string smallest = kEvent;
  smallest.replace(smallest.find("V -1 0"), 6, "V -2147483648 0");
  smallest.replace(smallest.find("P 2 -1 "), 7, "P 2 -2147483648 ");
  smallest.replace(smallest.find("P 3 -1 "), 7, "P 3 -2147483648 ");
  EXPECT_EQ(errorOf(kHead + smallest + kTail), "(accepted)");
  // Asciiv3: a particle id that wraps (4294967297 reads as 1).
  std::string v3 = kEvent;
  v3.replace(v3.find("P 1 0"), 5, "P 4294967297 0");
  EXPECT_EQ(errorOf(kHead + v3 + kTail),
            "a.hepmc:7: bad particle id 4294967297 (outside the reader's "
            "32-bit integer range)");
  // An attribute id is negated by the reader for a vertex: the smallest
  // int cannot be, and a wider id would wrap onto it or onto another.
  EXPECT_EQ(errorOf(kHead + kEvent + "A -2147483648 note x\n" + kTail),
            "a.hepmc:11: bad attribute id -2147483648 (the reader cannot "
            "negate it)");
  EXPECT_EQ(errorOf(kHead + kEvent + "A 2147483648 note x\n" + kTail),
            "a.hepmc:11: bad attribute id 2147483648 (outside the reader's "
            "32-bit integer range)");
  EXPECT_EQ(errorOf(kHead + kEvent + "A -2147483647 note x\n" + kTail),
            "(accepted)");
  // Random states are stored, not used as references: any 64-bit value.
  EXPECT_EQ(errorOf("HepMC::Version 2.06.09\n"
                    "HepMC::IO_GenEvent-START_EVENT_LISTING\n"
                    "E 1 -1 -1 -1 -1 0 0 1 1 2 1 9000000000 1 1.0\n"
                    "V -1 0 0 0 0 0 2 1 0\n"
                    "P 1 11 0 0 1000 1000 0.511 4 0 0 -1 0\n"
                    "P 2 -11 0 0 -1000 1000 0.511 4 0 0 -1 0\n"
                    "P 3 23 0 0 0 2000 2000 1 0 0 0 0\n"
                    "HepMC::IO_GenEvent-END_EVENT_LISTING\n"),
            "(accepted)");
}

}  // namespace
}  // namespace conftrack

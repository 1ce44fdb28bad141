/// @file HepMCReaderCrashTests.cpp
/// Input that crashes the HepMC3 3.1.2 reader, found by fuzzing
/// (docs/fuzzing.md), is refused by the validator with its line: attribute
/// names that overflow the reader's fixed buffer, and fields ending with an
/// escaping backslash (the reader's unescape() runs past the string's end),
/// and numeric records with repeated spaces (the reader's fields shift).

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
  // Repeated spaces inside the quoted weight names of an N line stay
  // legal (the shipped inputConvert1.hepmc has them: HepMCSharedFiles).
}

}  // namespace
}  // namespace conftrack

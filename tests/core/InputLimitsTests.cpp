/// @file InputLimitsTests.cpp
/// Configuration input that once crashed or hung conftrack (found by the
/// fuzzers, docs/fuzzing.md) is refused with a one-line InputError.

#include "conftrack/core/ConfigTable.hpp"
#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/Error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "InputErrorOf.hpp"
#include "TempDir.hpp"

namespace conftrack {
namespace {

std::string parseError(std::string_view text) {
  return test::inputErrorOf([&] { ConfigTable::parse(text, "cfg.toml"); });
}

// Debian's toml++ 3.3.0 reaches __builtin_unreachable on these (a UTF-8
// letter at a line start, an incomplete UTF-8 sequence, a lone
// continuation of a BOM-like sequence), so no non-ASCII byte reaches it.
TEST(ConfigTableInput, NonAsciiBytesAreRefusedWithTheirLine) {
  EXPECT_EQ(parseError("a = 1\n\xc3\xa9 = 1\n"),
            "cfg.toml:2: non-ASCII byte 0xc3 (conftrack config files are "
            "ASCII)");
  EXPECT_EQ(parseError("\xcc\x8b"),
            "cfg.toml:1: non-ASCII byte 0xcc (conftrack config files are "
            "ASCII)");
  EXPECT_EQ(parseError("a = 1\nb = 2\n\xef\xbb\xbb"),
            "cfg.toml:3: non-ASCII byte 0xef (conftrack config files are "
            "ASCII)");
  // Also inside comments and strings, where TOML would allow UTF-8.
  EXPECT_EQ(parseError("# caf\xc3\xa9\n"),
            "cfg.toml:1: non-ASCII byte 0xc3 (conftrack config files are "
            "ASCII)");
  EXPECT_EQ(parseError("[generator]\n\xc3\xa9 = 1\n"),
            "cfg.toml:2: non-ASCII byte 0xc3 (conftrack config files are "
            "ASCII)");
  EXPECT_EQ(parseError("a = \"x\" # ok\n"), "(accepted)");
}

// The table-header parser of toml++ 3.3.0 assumes a key after '[' (a failed
// TOML_ASSERT_ASSUME, undefined behaviour in a release build).
TEST(ConfigTableInput, TableHeaderWithoutKeyIsRefused) {
  const std::string expected =
      "TOML syntax: expected a key after '[' of a table header";
  EXPECT_EQ(parseError("a = 1\n[@]\n"), "cfg.toml:2: " + expected);
  EXPECT_EQ(parseError("[\nx = 1\n"), "cfg.toml:1: " + expected);
  EXPECT_EQ(parseError("  [[ =]]\n"), "cfg.toml:1: " + expected);
  EXPECT_EQ(parseError("[generator]\n[[ step ]]\n[ \"q\" ]\n[x.y]\n"),
            "(accepted)");
  EXPECT_EQ(parseError("a = [\n  [1, 2],\n  [3],\n]\n"), "(accepted)");
}

// toml++ 3.3.0 assumes that an array element does not start with '}'.
TEST(ConfigTableInput, UnmatchedClosingBraceIsRefused) {
  const std::string expected = "TOML syntax: '}' without a matching '{'";
  EXPECT_EQ(parseError("a = 1\nb = [}\n"), "cfg.toml:2: " + expected);
  EXPECT_EQ(parseError("b = [1,\n # c\n }]\n"), "cfg.toml:3: " + expected);
  EXPECT_EQ(parseError("}\n"), "cfg.toml:1: " + expected);
  EXPECT_EQ(parseError("a = { b = [1, 2], c = { d = \"}\" } } # }\n"
                       "e = '}'\nf = \"\"\"\n}\n\"\"\"\ng = '''}'''\n"),
            "(accepted)");
}

// Other inputs that break a toml++ 3.3.0 assumption (TOML_ASSERT_ASSUME,
// TOML_UNREACHABLE) are refused through the exception ConfigTable.cpp
// substitutes for them.
TEST(ConfigTableInput, BrokenParserAssumptionIsRefused) {
  // A date-time whose time part does not start with a digit (parse_time).
  EXPECT_EQ(parseError("_GeV = 3009-05-27T[e60c2.eV:32z1a"),
            "cfg.toml: TOML syntax: malformed input that the TOML parser "
            "(toml++ 3.3.0) cannot read safely");
  EXPECT_EQ(parseError("t = 3009-05-27T07:32:00Z\n"), "(accepted)");
}

TEST(ConfigTableInput, ControlCharactersAreRefusedWithTheirLine) {
  EXPECT_EQ(parseError("a = 1\nb = \"\x07\"\n"),
            "cfg.toml:2: control character 0x07 (not allowed in TOML)");
  EXPECT_EQ(parseError(std::string("a = 1\0", 6)),
            "cfg.toml:1: control character 0x00 (not allowed in TOML)");
  EXPECT_EQ(parseError("a = 1\r\n\tb = 2\r\n"), "(accepted)");
}

TEST(ConfigFileInput, EndlessFileIsRefusedAtTheSizeLimit) {
  try {
    readConfigText("/dev/zero", "detector");
    FAIL() << "read /dev/zero";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: detector file larger than " +
                                         std::to_string(kMaxConfigFileBytes) +
                                         " bytes");
  }
}

TEST(ConfigFileInput, SmallFileIsReadWhole) {
  test::TempDir dir;
  const std::string text = "a = 1\n# no newline at the end";
  test::writeText(dir.path() / "c.toml", text);
  EXPECT_EQ(readConfigText(dir.path() / "c.toml", "chain"), text);
}

}  // namespace
}  // namespace conftrack

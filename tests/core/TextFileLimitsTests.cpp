/// @file TextFileLimitsTests.cpp
/// The event-file readers read at most kMaxTextFileBytes, before and after
/// decompression: an endless file (a link to /dev/zero) or a gzip bomb is
/// refused with a one-line InputError instead of exhausting the memory.

#include "conftrack/core/Error.hpp"
#include "conftrack/core/TextFile.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "InputErrorOf.hpp"
#include "TempDir.hpp"

namespace conftrack {
namespace {

using ::testing::HasSubstr;

constexpr std::size_t kSmallLimit = std::size_t{1} << 20;

std::string errorOf(const std::function<void()>& f) {
  return test::inputErrorOf(f);
}

TEST(TextFileLimits, LinkToDevZeroIsRefusedAtTheLimit) {
  test::TempDir dir;
  const auto link = dir.path() / "event000000001-hits.csv";
  std::filesystem::create_symlink("/dev/zero", link);
  EXPECT_EQ(errorOf([&] { readTextFile(link, kSmallLimit); }),
            link.string() +
                ": larger than 1048576 bytes (the limit of "
                "conftrack's text files)");
}

TEST(TextFileLimits, LargeRegularFileIsRefusedBeforeReading) {
  test::TempDir dir;
  const auto file = dir.path() / "big.csv";
  std::filesystem::resize_file(test::writeText(file, "x"), kSmallLimit + 1);
  EXPECT_THAT(errorOf([&] { readTextFile(file, kSmallLimit); }),
              HasSubstr("larger than 1048576 bytes"));
  std::filesystem::resize_file(file, kSmallLimit);
  EXPECT_EQ(readTextFile(file, kSmallLimit).size(), kSmallLimit);
}

TEST(TextFileLimits, GzipBombIsRefusedAtTheLimit) {
  test::TempDir dir;
  const auto file = dir.path() / "bomb.csv.gz";
  // 8 MiB of zeros compress to about 8 kB.
  writeTextFile(file, std::string(8 * kSmallLimit, '0'), true, 9);
  EXPECT_EQ(errorOf([&] { readTextFile(file, kSmallLimit); }),
            file.string() +
                ": decompressed data larger than 1048576 bytes "
                "(the limit of conftrack's text files)");
  EXPECT_EQ(readTextFile(file).size(), 8 * kSmallLimit);
}

TEST(TextFileLimits, DecompressIfGzipPassesPlainTextThrough) {
  EXPECT_EQ(decompressIfGzip("hit_id\n1\n", "x.csv"), "hit_id\n1\n");
  EXPECT_THAT(errorOf([] { decompressIfGzip("\x1f\x8b", "x.csv.gz"); }),
              HasSubstr("x.csv.gz: "));
}

}  // namespace
}  // namespace conftrack

// Input that looks odd but is valid (docs/bad-input.md, "Valid"): CRLF
// line ends, header-only hits files, more threads than cores, and the
// read-only output folder that only a non-root user can test.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "BadInputFixtures.hpp"

namespace {

using namespace clitest;

/// Reconstructs dir/ev and returns the tracks file text ("" on failure).
std::string reconstructTracks(const fs::path& dir) {
  const Outcome r = runConftrack("reconstruct -i " + (dir / "ev").string() +
                                 " -o " + (dir / "tracks").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  return slurp(dir / "tracks" / "event000000001-tracks.csv");
}

TEST(ValidInput, CrLfLineEndsReadLikeLf) {
  const fs::path lf = processDir() / "lf";
  const fs::path crlf = processDir() / "crlf";
  fs::remove_all(lf);
  fs::remove_all(crlf);
  copyBase("ev", lf / "ev");
  std::string text;
  for (char c : slurp(lf / "ev" / kHitsName)) {
    text += c == '\n' ? std::string("\r\n") : std::string(1, c);
  }
  writeHits(crlf, text);
  const std::string a = reconstructTracks(lf);
  EXPECT_NE(a.find('\n'), a.rfind('\n')) << "no tracks: " << a;
  EXPECT_EQ(a, reconstructTracks(crlf));
  fs::remove_all(lf);
  fs::remove_all(crlf);
}

TEST(ValidInput, HeaderOnlyHitsFileIsAnEmptyEvent) {
  const fs::path dir = processDir() / "header-only";
  fs::remove_all(dir);
  writeHits(dir, kHeader);
  const std::string tracks = reconstructTracks(dir);
  // The header line and no track.
  EXPECT_EQ(std::count(tracks.begin(), tracks.end(), '\n'), 1) << tracks;
  fs::remove_all(dir);
}

TEST(ValidInput, ThreadsBeyondTheCoresRunQuietly) {
  const fs::path dir = processDir() / "threads";
  fs::remove_all(dir);
  copyBase("ev", dir / "ev");
  const Outcome r =
      runConftrack("reconstruct -j 8 -i " + (dir / "ev").string() + " -o " +
                   (dir / "tracks").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no TBB warning about the worker limit
  fs::remove_all(dir);
}

TEST(ValidInput, UnwritableOutputFolder) {
  if (::geteuid() == 0) {
    GTEST_SKIP() << "root writes into read-only folders";
  }
  const fs::path dir = processDir() / "readonly";
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  writeHits(dir, kHeader + kRows);
  fs::permissions(dir / "out", fs::perms::owner_read | fs::perms::owner_exec);
  const Outcome r = runConftrack("reconstruct -i " + (dir / "ev").string() +
                                 " -o " + (dir / "out").string());
  fs::permissions(dir / "out", fs::perms::owner_all);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("cannot write into the folder: Permission denied"),
            std::string::npos)
      << r.err;
  fs::remove_all(dir);
}

}  // namespace

/// @file FuzzRegressionTests.cpp
/// Replays every stored fuzzing input through the bodies of the libFuzzer
/// targets (fuzz/targets/FuzzTargets.cpp, the same code the fuzzers run):
/// the minimized inputs of fixed crashes (fuzz/regressions/<target>/) and
/// the seed corpora (fuzz/corpus/<target>/). Each must be accepted or
/// refused with an InputError; any other exception fails the test, and a
/// crash fails the test executable. The seeds are real formats: they must
/// be accepted, so that the fuzzers start from inputs that reach deep into
/// the readers.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "FuzzTargets.hpp"

namespace conftrack::fuzz {
namespace {

namespace fs = std::filesystem;

const fs::path kFuzzDir = CONFTRACK_FUZZ_DIR;

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> files;
  if (fs::is_directory(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.is_regular_file()) {
        files.push_back(entry.path());
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class FuzzInputs : public ::testing::TestWithParam<Target> {};

TEST_P(FuzzInputs, RegressionInputsAreAcceptedOrRefused) {
  const Target& target = GetParam();
  for (const fs::path& file : filesIn(kFuzzDir / "regressions" / target.name)) {
    SCOPED_TRACE(file.string());
    EXPECT_NO_THROW(target.run(contents(file)));
  }
}

TEST_P(FuzzInputs, SeedsAreAccepted) {
  const Target& target = GetParam();
  const std::vector<fs::path> seeds =
      filesIn(kFuzzDir / "corpus" / target.name);
  ASSERT_FALSE(seeds.empty()) << "no seeds in fuzz/corpus/" << target.name;
  for (const fs::path& file : seeds) {
    SCOPED_TRACE(file.string());
    Outcome outcome = Outcome::eRefused;
    EXPECT_NO_THROW(outcome = target.run(contents(file)));
    EXPECT_EQ(outcome, Outcome::eAccepted);
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzInputs,
                         ::testing::ValuesIn(targets().begin(),
                                             targets().end()),
                         [](const ::testing::TestParamInfo<Target>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace conftrack::fuzz

#pragma once

// Test support shared by the suites: a fresh folder per test and a writer
// for small text files.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace conftrack::test {

/// A path in the test temporary folder that no other test can use: ctest runs
/// the cases of one suite in parallel processes, so a fixed file name (for a
/// captured stdout, say) would be overwritten by a neighbour.
inline std::filesystem::path perTestPath(const std::string& stem) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "conftrack-" + std::string(info->test_suite_name()) + "-" +
                     info->name() + "-" + std::to_string(::getpid()) + "-" +
                     stem;
  for (char& c : name) {
    if (c == '/') c = '_';  // parameterised tests: "Suite/Name/Param"
  }
  return std::filesystem::path(::testing::TempDir()) / name;
}

/// A fresh, empty folder named after the running test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_path = std::filesystem::temp_directory_path() /
             ("conftrack_" + std::string(info->test_suite_name()) + "_" +
              info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(m_path);
    std::filesystem::create_directories(m_path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return m_path; }

 private:
  std::filesystem::path m_path;
};

/// Writes `text` (bytes as given) to `file`; returns the path.
inline std::filesystem::path writeText(const std::filesystem::path& file,
                                       const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

}  // namespace conftrack::test

#pragma once

// Test support shared by the suites: a fresh folder per test and a writer
// for small text files.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace conftrack::test {

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

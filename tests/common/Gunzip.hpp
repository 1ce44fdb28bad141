#pragma once

// Test support: the text of a gzip file (geometry tests read the shipped
// data without the io module).

#include <zlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace conftrack::test {

/// The decompressed content of `file`; std::runtime_error if it cannot be
/// opened.
inline std::string gunzip(const std::filesystem::path& file) {
  gzFile in = gzopen(file.string().c_str(), "rb");
  if (in == nullptr) {
    throw std::runtime_error("cannot open " + file.string());
  }
  std::string text;
  char buffer[1 << 16];
  int n = 0;
  while ((n = gzread(in, buffer, sizeof buffer)) > 0) {
    text.append(buffer, static_cast<std::size_t>(n));
  }
  gzclose(in);
  return text;
}

}  // namespace conftrack::test

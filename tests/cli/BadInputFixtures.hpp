#pragma once

/// @file BadInputFixtures.hpp
/// What the bad-input CLI tests share: running the built conftrack, a
/// valid sample to break, and small CSV helpers. Folders are per process,
/// since ctest runs the test cases in parallel processes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace clitest {

namespace fs = std::filesystem;

/// Exit code and stderr of one run.
struct Outcome {
  int code;
  std::string err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void writeFile(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary);
  out << bytes;
}

/// A folder of this process (ctest runs the cases in parallel processes).
inline fs::path processDir() {
  return fs::path(::testing::TempDir()) /
         ("conftrack-badinput-" + std::to_string(::getpid()));
}

/// Runs `conftrack -q args` (-q: no progress or info lines); returns the
/// exit code and stderr.
inline Outcome runConftrack(const std::string& args) {
  fs::create_directories(processDir());
  const fs::path err = processDir() / "stderr.txt";
  const std::string cmd = std::string(CONFTRACK_BINARY) + " -q " + args +
                          " > /dev/null 2> " + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(err)};
}

/// A valid sample made once per process: one CLICdet muon event with truth
/// ("ev"), its tracks ("tracks") and TrackML submission ("submission").
inline const fs::path& base() {
  static const fs::path dir = [] {
    const fs::path d = processDir() / "base";
    fs::remove_all(d);
    const std::string ev = (d / "ev").string();
    EXPECT_EQ(
        runConftrack("simulate --sample muons -n 1 --seed 4 -o " + ev).code, 0);
    EXPECT_EQ(
        runConftrack("reconstruct -i " + ev + " -o " + (d / "tracks").string())
            .code,
        0);
    EXPECT_EQ(runConftrack("reconstruct --submission -i " + ev + " -o " +
                           (d / "submission").string())
                  .code,
              0);
    return d;
  }();
  return dir;
}

/// Copies a folder of the base sample into `to`.
inline void copyBase(const std::string& what, const fs::path& to) {
  fs::create_directories(to.parent_path());
  fs::copy(base() / what, to, fs::copy_options::recursive);
}

/// Replaces column `column` of data row `row` (1 = first data row) of a CSV
/// file.
inline void setField(const fs::path& file, std::size_t row,
                     const std::string& column, const std::string& value) {
  std::vector<std::string> lines;
  std::stringstream in(slurp(file));
  for (std::string line; std::getline(in, line);) {
    lines.push_back(line);
  }
  auto split = [](const std::string& line) {
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string x; std::getline(s, x, ',');) {
      f.push_back(x);
    }
    return f;
  };
  const std::vector<std::string> header = split(lines.at(0));
  const auto c = static_cast<std::size_t>(
      std::find(header.begin(), header.end(), column) - header.begin());
  ASSERT_LT(c, header.size()) << column;
  std::vector<std::string> fields = split(lines.at(row));
  fields.at(c) = value;
  std::string joined;
  for (const std::string& f : fields) {
    joined += (joined.empty() ? "" : ",") + f;
  }
  lines[row] = joined;
  std::string out;
  for (const std::string& l : lines) {
    out += l + "\n";
  }
  writeFile(file, out);
}

inline const std::string kHeader =
    "hit_id,x,y,z,volume_id,layer_id,module_id\n";
/// Two CLICdet hits on vertex-barrel layers 0 and 1 (TrackML volume 1,
/// layers 2 and 4).
inline const std::string kRows =
    "1,31.165,0,10,1,2,0\n2,33.215,0.5,10.5,1,4,0\n";
inline const std::string kHitsName = "event000000001-hits.csv";

/// Writes the hits file of event 1 into dir/ev.
inline void writeHits(const fs::path& dir, const std::string& text) {
  writeFile(dir / "ev" / kHitsName, text);
}

}  // namespace clitest

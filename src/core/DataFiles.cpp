#include "conftrack/core/DataFiles.hpp"

#include "conftrack/core/Error.hpp"

#include <cstdlib>
#include <fstream>
#include <string>

namespace conftrack {

std::filesystem::path dataDirectory() {
  const char* env = std::getenv("CONFTRACK_DATA_DIR");
  return env != nullptr ? std::filesystem::path(env)
                        : std::filesystem::path(CONFTRACK_DATA_DIR);
}

std::filesystem::path resolveShippedFile(const std::string& folder,
                                         const std::string& nameOrPath,
                                         const std::string& what) {
  namespace fs = std::filesystem;
  fs::path asPath(nameOrPath);
  if (nameOrPath.find('/') != std::string::npos ||
      asPath.extension() == ".toml") {
    return asPath;
  }
  fs::path candidate = dataDirectory() / folder / (nameOrPath + ".toml");
  if (!fs::exists(candidate)) {
    throw MissingFileError(what + " '" + nameOrPath + "': no such shipped " +
                           what + " (looked for " + candidate.string() +
                           "); give a path to a TOML file");
  }
  return candidate;
}

std::string readConfigText(const std::filesystem::path& file,
                           const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) {
      throw MissingFileError(file.string(), "cannot open " + what + " file");
    }
    throw InputError(file.string(), "cannot open " + what + " file");
  }
  // Read at most one byte more than the limit: a link to /dev/zero or a
  // huge file must not be read without bound.
  std::string text;
  char buffer[1 << 14];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxConfigFileBytes) {
      throw InputError(file.string(), what + " file larger than " +
                                          std::to_string(kMaxConfigFileBytes) +
                                          " bytes");
    }
  }
  if (in.bad()) {
    throw InputError(file.string(), "cannot read " + what + " file");
  }
  return text;
}

}  // namespace conftrack

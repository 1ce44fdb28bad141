#include "conftrack/core/DataFiles.hpp"

#include "conftrack/core/Error.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

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
    throw InputError(what + " '" + nameOrPath + "': no such shipped " + what +
                     " (looked for " + candidate.string() +
                     "); give a path to a TOML file");
  }
  return candidate;
}

std::string readConfigText(const std::filesystem::path& file,
                           const std::string& what) {
  std::ifstream in(file);
  if (!in) {
    throw InputError(file.string(), "cannot open " + what + " file");
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace conftrack

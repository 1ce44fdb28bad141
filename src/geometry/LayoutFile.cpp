#include "conftrack/geometry/LayoutFile.hpp"

#include "conftrack/core/DataFiles.hpp"
#include "conftrack/core/TextFile.hpp"
#include "conftrack/geometry/LayoutModules.hpp"

#include <cctype>
#include <string>

namespace conftrack {

std::filesystem::path shippedLayoutFile(const Detector& detector) {
  // "CLICdet" -> clicdet, "CLD (FCC-ee)" -> cld.
  std::string name;
  for (const char c : detector.name()) {
    if (c == ' ' || c == '(') {
      break;
    }
    name += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return dataDirectory() / "data" / "layouts" / (name + "_layout.json.gz");
}

ModuleLayout readLayoutModules(const std::filesystem::path& file,
                               const Detector& detector) {
  // The shipped files are about 10 kB; the configuration-file limit is
  // plenty.
  return buildLayoutModules(readTextFile(file, kMaxConfigFileBytes), detector,
                            file.string());
}

}  // namespace conftrack

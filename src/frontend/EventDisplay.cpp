#include "conftrack/frontend/EventDisplay.hpp"

#include "conftrack/core/Error.hpp"
#include "conftrack/frontend/ReportFiles.hpp"

#include <cstdlib>
#include <fstream>

namespace conftrack {

void writeDisplayCsv(const std::filesystem::path& file,
                     std::span<const Hit> hits, std::span<const Track> tracks) {
  std::vector<long> trackOf(hits.size(), -1);
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    for (HitIndex h : tracks[t].hits) {
      if (trackOf[h] < 0) {
        trackOf[h] = static_cast<long>(t);
      }
    }
  }
  std::ofstream out(file);
  if (!out) {
    throw InputError(file.string(), "cannot write display file");
  }
  out << "x,y,z,track\n";
  for (std::size_t h = 0; h < hits.size(); ++h) {
    const Vector3& p = hits[h].position;
    out << p.x() << ',' << p.y() << ',' << p.z() << ',' << trackOf[h] << '\n';
  }
}

bool drawEventDisplay(const std::filesystem::path& png,
                      std::span<const Hit> hits, std::span<const Track> tracks,
                      const std::string& title, std::ostream& log) {
  std::filesystem::path csv = png;
  csv.replace_extension(".csv");
  writeDisplayCsv(csv, hits, tracks);
  std::string python = findPlotInterpreter();
  if (python.empty()) {
    log << "conftrack: no python3 with matplotlib: the event display was "
           "not drawn (data in "
        << csv.string()
        << "); install with: apt-get install python3-matplotlib "
           "python3-numpy\n";
    return false;
  }
  std::filesystem::path script =
      plotScriptPath().parent_path() / "conftrack_display.py";
  auto quote = [](const std::string& s) {
    std::string q = "'";
    for (char c : s) {
      q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return q + "'";
  };
  std::string cmd = quote(python) + " " + quote(script.string()) + " " +
                    quote(csv.string()) + " " + quote(png.string()) + " " +
                    quote(title);
  if (std::system(cmd.c_str()) != 0) {
    log << "conftrack: the event display script failed (" << script.string()
        << ")\n";
    return false;
  }
  return true;
}

}  // namespace conftrack

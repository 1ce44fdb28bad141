#include "conftrack/evaluation/ResourceUsage.hpp"

#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace conftrack {

double peakRssMb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    // "VmHWM:     123456 kB": the high-water mark of the resident set.
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream fields(line.substr(6));
      double kilobytes = 0.0;
      std::string unit;
      if (fields >> kilobytes >> unit && unit == "kB") {
        return kilobytes / 1024.0;  // kB there means KiB
      }
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace conftrack

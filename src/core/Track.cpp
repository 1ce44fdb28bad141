#include "conftrack/core/Track.hpp"

#include <algorithm>

namespace conftrack {

std::uint32_t Track::numOutliers() const {
  return static_cast<std::uint32_t>(
      std::count(outlier.begin(), outlier.end(), std::uint8_t{1}));
}

std::uint32_t Track::numMeasurements() const {
  return static_cast<std::uint32_t>(hits.size()) - numOutliers();
}

}  // namespace conftrack

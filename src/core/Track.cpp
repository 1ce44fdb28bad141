#include "conftrack/core/Track.hpp"

#include <algorithm>

namespace conftrack {

std::uint32_t Track::numOutliers() const {
  return static_cast<std::uint32_t>(
      std::count(outlier.begin(), outlier.end(), kOutlierHit));
}

std::uint32_t Track::numTurnHits() const {
  return static_cast<std::uint32_t>(
      std::count(outlier.begin(), outlier.end(), kTurnHit));
}

std::uint32_t Track::numMeasurements() const {
  return static_cast<std::uint32_t>(hits.size()) - numOutliers() -
         numTurnHits();
}

}  // namespace conftrack

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

void Track::takeFit(const Track& fitted) {
  std::copy_n(fitted.outlier.begin(),
              std::min(fitted.outlier.size(), outlier.size()), outlier.begin());
  this->fitted = fitted.fitted;
  atIp = fitted.atIp;
  atFirstHit = fitted.atFirstHit;
  atLastHit = fitted.atLastHit;
  chi2 = fitted.chi2;
  ndf = fitted.ndf;
}

void Track::fittedHits(std::vector<HitIndex>& out) const {
  out.clear();
  for (std::size_t k = 0; k < hits.size(); ++k) {
    if (outlier[k] == kFittedHit) {
      out.push_back(hits[k]);
    }
  }
}

std::uint32_t Track::numMeasurements() const {
  return static_cast<std::uint32_t>(hits.size()) - numOutliers() -
         numTurnHits();
}

}  // namespace conftrack

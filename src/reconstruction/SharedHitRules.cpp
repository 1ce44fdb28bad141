// Clone and ambiguity rules for tracks sharing hits (SharedHitRules.hpp).

#include "conftrack/reconstruction/SharedHitRules.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace conftrack {

SharedHitRules::SharedHitRules(std::uint32_t cloneSharedHits,
                               std::uint32_t minUniqueHits,
                               std::size_t hitCount)
    : m_cloneSharedHits(cloneSharedHits),
      m_minUniqueHits(minUniqueHits),
      m_firstOwner(hitCount, kNoLink),
      m_claimed(hitCount, 0) {}

void SharedHitRules::checkHits(std::span<const std::uint32_t> hits) const {
  for (std::uint32_t hit : hits) {
    if (hit >= m_firstOwner.size()) {
      throw std::out_of_range(
          "SharedHitRules: hit index " + std::to_string(hit) +
          " not below the hit count " + std::to_string(m_firstOwner.size()));
    }
  }
}

bool SharedHitRules::isClone(std::span<const std::uint32_t> matched) {
  m_sharedCounts.clear();
  for (std::uint32_t hit : matched) {
    for (std::uint32_t link = m_firstOwner[hit]; link != kNoLink;
         link = m_links[link].next) {
      const std::uint32_t owner = m_links[link].owner;
      auto it = std::find_if(m_sharedCounts.begin(), m_sharedCounts.end(),
                             [&](const auto& c) { return c.first == owner; });
      if (it == m_sharedCounts.end()) {
        it = m_sharedCounts.emplace(m_sharedCounts.end(), owner, 0);
      }
      if (++it->second >= m_cloneSharedHits) {
        return true;
      }
    }
  }
  return false;
}

SharedHitRules::Verdict SharedHitRules::judge(
    std::span<const std::uint32_t> matched, std::span<const std::uint32_t> all,
    std::uint32_t index) {
  // Checked once here; the loops below index the arrays directly.
  checkHits(matched);
  checkHits(all);
  if (m_cloneSharedHits > 0 && isClone(matched)) {
    return Verdict::eClone;
  }
  if (m_minUniqueHits > 0) {
    // All hits count here, outliers included: the finder put them on the
    // track, and an outlier-rich track is no fake for that (a fit pulled
    // off by one wrong hit flags many good ones).
    std::size_t unique = 0;
    for (std::uint32_t hit : all) {
      unique += m_claimed[hit] != 0 ? 0 : 1;
    }
    // A track that shares no hit is no ambiguity (minHits judges it).
    if (unique < all.size() && unique < m_minUniqueHits) {
      return Verdict::eAmbiguous;
    }
    for (std::uint32_t hit : all) {
      m_claimed[hit] = 1;
    }
  }
  for (std::uint32_t hit : matched) {
    m_links.push_back({index, m_firstOwner[hit]});
    m_firstOwner[hit] = static_cast<std::uint32_t>(m_links.size() - 1);
  }
  return Verdict::eKeep;
}

}  // namespace conftrack

// Clone and ambiguity rules for tracks sharing hits (SharedHitRules.hpp).

#include "conftrack/reconstruction/SharedHitRules.hpp"

namespace conftrack {

SharedHitRules::Verdict SharedHitRules::judge(
    std::span<const std::uint64_t> matched, std::span<const std::uint64_t> all,
    std::uint32_t index) {
  if (m_cloneSharedHits > 0) {
    m_shared.clear();
    for (std::uint64_t id : matched) {
      auto it = m_owners.find(id);
      if (it == m_owners.end()) {
        continue;
      }
      for (std::uint32_t owner : it->second) {
        if (++m_shared[owner] >= m_cloneSharedHits) {
          return Verdict::eClone;
        }
      }
    }
  }
  if (m_minUniqueHits > 0) {
    // All hits count here, outliers included: the finder put them on the
    // track, and an outlier-rich track is no fake for that (a fit pulled
    // off by one wrong hit flags many good ones).
    std::size_t unique = 0;
    for (std::uint64_t id : all) {
      unique += m_claimed.contains(id) ? 0 : 1;
    }
    // A track that shares no hit is no ambiguity (minHits judges it).
    if (unique < all.size() && unique < m_minUniqueHits) {
      return Verdict::eAmbiguous;
    }
    m_claimed.insert(all.begin(), all.end());
  }
  for (std::uint64_t id : matched) {
    m_owners[id].push_back(index);
  }
  return Verdict::eKeep;
}

}  // namespace conftrack

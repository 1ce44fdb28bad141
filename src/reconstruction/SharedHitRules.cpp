// Clone and ambiguity rules for tracks sharing hits (SharedHitRules.hpp).

#include "conftrack/reconstruction/SharedHitRules.hpp"

#include <stdexcept>
#include <string>

namespace conftrack {

SharedHitRules::SharedHitRules(std::uint32_t cloneSharedHits,
                               std::uint32_t minUniqueHits,
                               std::size_t keyBound)
    : m_cloneSharedHits(cloneSharedHits),
      m_minUniqueHits(minUniqueHits),
      m_keyBound(keyBound) {
  if (m_keyBound > 0) {
    m_firstOwner.assign(m_keyBound, kNoLink);
    m_claimedFlags.assign(m_keyBound, 0);
  }
}

void SharedHitRules::checkKey(std::uint64_t key) const {
  if (key >= m_keyBound) {
    throw std::out_of_range("SharedHitRules: key " + std::to_string(key) +
                            " not below the bound " +
                            std::to_string(m_keyBound));
  }
}

bool SharedHitRules::claimed(std::uint64_t id) const {
  if (m_keyBound > 0) {
    return id < m_keyBound && m_claimedFlags[id] != 0;
  }
  return m_claimed.contains(id);
}

bool SharedHitRules::isClone(std::span<const std::uint64_t> matched) {
  if (m_keyBound > 0) {
    // A track shares hits with few kept tracks: a linear list of counts.
    m_sharedCounts.clear();
    for (std::uint64_t id : matched) {
      checkKey(id);
      for (std::uint32_t link = m_firstOwner[id]; link != kNoLink;
           link = m_links[link].next) {
        const std::uint32_t owner = m_links[link].owner;
        std::uint32_t* count = nullptr;
        for (auto& [kept, n] : m_sharedCounts) {
          if (kept == owner) {
            count = &n;
            break;
          }
        }
        if (count == nullptr) {
          m_sharedCounts.emplace_back(owner, 0);
          count = &m_sharedCounts.back().second;
        }
        if (++*count >= m_cloneSharedHits) {
          return true;
        }
      }
    }
    return false;
  }
  m_shared.clear();
  for (std::uint64_t id : matched) {
    auto it = m_owners.find(id);
    if (it == m_owners.end()) {
      continue;
    }
    for (std::uint32_t owner : it->second) {
      if (++m_shared[owner] >= m_cloneSharedHits) {
        return true;
      }
    }
  }
  return false;
}

SharedHitRules::Verdict SharedHitRules::judge(
    std::span<const std::uint64_t> matched, std::span<const std::uint64_t> all,
    std::uint32_t index) {
  if (m_cloneSharedHits > 0 && isClone(matched)) {
    return Verdict::eClone;
  }
  if (m_minUniqueHits > 0) {
    // All hits count here, outliers included: the finder put them on the
    // track, and an outlier-rich track is no fake for that (a fit pulled
    // off by one wrong hit flags many good ones).
    std::size_t unique = 0;
    for (std::uint64_t id : all) {
      unique += claimed(id) ? 0 : 1;
    }
    // A track that shares no hit is no ambiguity (minHits judges it).
    if (unique < all.size() && unique < m_minUniqueHits) {
      return Verdict::eAmbiguous;
    }
    if (m_keyBound > 0) {
      for (std::uint64_t id : all) {
        checkKey(id);
        m_claimedFlags[id] = 1;
      }
    } else {
      m_claimed.insert(all.begin(), all.end());
    }
  }
  for (std::uint64_t id : matched) {
    if (m_keyBound > 0) {
      checkKey(id);
      m_links.push_back({index, m_firstOwner[id]});
      m_firstOwner[id] = static_cast<std::uint32_t>(m_links.size() - 1);
    } else {
      m_owners[id].push_back(index);
    }
  }
  return Verdict::eKeep;
}

}  // namespace conftrack

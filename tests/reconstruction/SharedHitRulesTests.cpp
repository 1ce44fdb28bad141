/// @file SharedHitRulesTests.cpp
/// The clone and ambiguity rules (SharedHitRules.hpp): the verdicts on hand
/// made tracks; on random tracks the verdicts of a brute-force reference
/// (every kept track's hits searched for each new track); a hit index at or
/// above the hit count is refused.

#include "conftrack/reconstruction/SharedHitRules.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace conftrack {
namespace {

using Hits = std::vector<std::uint32_t>;
using Verdict = SharedHitRules::Verdict;

TEST(SharedHitRules, ClonesAndShortAmbiguousTracks) {
  SharedHitRules rules(2, 3, 100);
  const Hits first{1, 2, 3, 4, 5};
  EXPECT_EQ(rules.judge(first, first, 0), Verdict::eKeep);
  // Two hits of the first: its clone.
  const Hits clone{4, 5, 6, 7, 8};
  EXPECT_EQ(rules.judge(clone, clone, 1), Verdict::eClone);
  // One shared hit and two of its own: below three unique hits.
  const Hits shortOne{5, 9, 10};
  EXPECT_EQ(rules.judge(shortOne, shortOne, 2), Verdict::eAmbiguous);
  // One shared hit and three of its own: kept.
  const Hits kept{5, 11, 12, 13};
  EXPECT_EQ(rules.judge(kept, kept, 3), Verdict::eKeep);
  // A track that shares nothing is no ambiguity however short.
  const Hits alone{20, 21};
  EXPECT_EQ(rules.judge(alone, alone, 4), Verdict::eKeep);
  EXPECT_TRUE(rules.claimed(12));
  EXPECT_FALSE(rules.claimed(9));  // of a refused track
  EXPECT_FALSE(rules.claimed(99));
  EXPECT_FALSE(rules.claimed(100));  // beyond the hit count: held by none
  // The clone rule counts the matched hits (none shared here), the unique
  // count all of them (three of five held by a kept track).
  const Hits matched{30, 31};
  const Hits all{30, 31, 13, 12, 11};
  EXPECT_EQ(rules.judge(matched, all, 5), Verdict::eAmbiguous);
  // Two matched hits of the first track: a clone, whatever the rest.
  const Hits twoOfFirst{1, 2};
  const Hits withOwn{1, 2, 40, 41, 42, 43};
  EXPECT_EQ(rules.judge(twoOfFirst, withOwn, 6), Verdict::eClone);
}

/// The rules written out: each new track against every kept one.
class ReferenceRules {
 public:
  ReferenceRules(std::uint32_t clone, std::uint32_t unique)
      : m_clone(clone), m_unique(unique) {}

  Verdict judge(const Hits& matched, const Hits& all) {
    if (m_clone > 0) {
      for (const Hits& kept : m_keptMatched) {
        std::uint32_t shared = 0;
        for (std::uint32_t h : matched) {
          shared += std::count(kept.begin(), kept.end(), h) > 0 ? 1 : 0;
        }
        if (shared >= m_clone) {
          return Verdict::eClone;
        }
      }
    }
    if (m_unique > 0) {
      std::size_t own = 0;
      for (std::uint32_t h : all) {
        own += std::count(m_claimed.begin(), m_claimed.end(), h) > 0 ? 0 : 1;
      }
      if (own < all.size() && own < m_unique) {
        return Verdict::eAmbiguous;
      }
      m_claimed.insert(m_claimed.end(), all.begin(), all.end());
    }
    m_keptMatched.push_back(matched);
    return Verdict::eKeep;
  }

 private:
  std::uint32_t m_clone;
  std::uint32_t m_unique;
  std::vector<Hits> m_keptMatched;
  Hits m_claimed;
};

TEST(SharedHitRules, AgreeWithTheRulesWrittenOut) {
  // Random tracks of 3-12 distinct hits out of 300 (many shared), judged
  // in order under several rule settings; the first half of a track is its
  // fitted ("matched") hits.
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::uint32_t> hit(0, 299);
  std::uniform_int_distribution<int> length(3, 12);
  std::vector<Hits> tracks(1000);
  for (Hits& t : tracks) {
    const auto n = static_cast<std::size_t>(length(rng));
    while (t.size() < n) {
      const std::uint32_t h = hit(rng);
      if (std::find(t.begin(), t.end(), h) == t.end()) {
        t.push_back(h);
      }
    }
  }
  for (auto [clone, unique] :
       {std::pair{2u, 6u}, std::pair{3u, 0u}, std::pair{0u, 4u}}) {
    SharedHitRules rules(clone, unique, 300);
    ReferenceRules reference(clone, unique);
    int kept = 0;
    for (std::size_t i = 0; i < tracks.size(); ++i) {
      const Hits& t = tracks[i];
      const Hits matched(t.begin(), t.begin() + t.size() / 2 + 1);
      const Verdict expected = reference.judge(matched, t);
      ASSERT_EQ(rules.judge(matched, t, static_cast<std::uint32_t>(i)),
                expected)
          << "track " << i << ", rules " << clone << " / " << unique;
      kept += expected == Verdict::eKeep ? 1 : 0;
    }
    // Neither everything kept nor everything refused.
    EXPECT_GT(kept, 0);
    EXPECT_LT(kept, static_cast<int>(tracks.size()));
  }
}

TEST(SharedHitRules, RefusesAHitBeyondTheHitCount) {
  SharedHitRules rules(2, 3, 10);
  const Hits inside{1, 2, 3};
  EXPECT_EQ(rules.judge(inside, inside, 0), Verdict::eKeep);
  const Hits beyond{4, 10};
  EXPECT_THROW(rules.judge(beyond, beyond, 1), std::out_of_range);
  EXPECT_FALSE(rules.claimed(10));
}

}  // namespace
}  // namespace conftrack

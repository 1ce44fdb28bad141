/// @file SharedHitRulesTests.cpp
/// The clone and ambiguity rules (SharedHitRules.hpp): the verdicts on hand
/// made tracks, and the array storage for keys below a bound (the finder's)
/// giving the hash storage's verdicts on random tracks; a key at or above
/// the bound is refused.

#include "conftrack/reconstruction/SharedHitRules.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace conftrack {
namespace {

using Keys = std::vector<std::uint64_t>;
using Verdict = SharedHitRules::Verdict;

TEST(SharedHitRules, ClonesAndShortAmbiguousTracksInBothStorages) {
  for (std::size_t bound : {std::size_t{0}, std::size_t{100}}) {
    SharedHitRules rules(2, 3, bound);
    const Keys first{1, 2, 3, 4, 5};
    EXPECT_EQ(rules.judge(first, first, 0), Verdict::eKeep) << bound;
    // Two hits of the first: its clone.
    const Keys clone{4, 5, 6, 7, 8};
    EXPECT_EQ(rules.judge(clone, clone, 1), Verdict::eClone) << bound;
    // One shared hit and two of its own: below three unique hits.
    const Keys shortOne{5, 9, 10};
    EXPECT_EQ(rules.judge(shortOne, shortOne, 2), Verdict::eAmbiguous) << bound;
    // One shared hit and three of its own: kept.
    const Keys kept{5, 11, 12, 13};
    EXPECT_EQ(rules.judge(kept, kept, 3), Verdict::eKeep) << bound;
    // A track that shares nothing is no ambiguity however short.
    const Keys alone{20, 21};
    EXPECT_EQ(rules.judge(alone, alone, 4), Verdict::eKeep) << bound;
    EXPECT_TRUE(rules.claimed(12)) << bound;
    EXPECT_FALSE(rules.claimed(9)) << bound;  // of a refused track
    EXPECT_FALSE(rules.claimed(99)) << bound;
    // The clone rule counts the matched hits (none shared here), the
    // unique count all of them (three of five held by a kept track).
    const Keys matched{30, 31};
    const Keys all{30, 31, 13, 12, 11};
    EXPECT_EQ(rules.judge(matched, all, 5), Verdict::eAmbiguous) << bound;
    // Two matched hits of the first track: a clone, whatever the rest.
    const Keys twoOfFirst{1, 2};
    const Keys withOwn{1, 2, 40, 41, 42, 43};
    EXPECT_EQ(rules.judge(twoOfFirst, withOwn, 6), Verdict::eClone) << bound;
  }
}

TEST(SharedHitRules, ArrayStorageGivesTheHashStoragesVerdicts) {
  // Random tracks of 3-12 hits out of 300 (many shared), judged in order
  // by both storages under several rule settings.
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::uint64_t> key(0, 299);
  std::uniform_int_distribution<int> length(3, 12);
  std::vector<Keys> tracks(2000);
  for (Keys& t : tracks) {
    t.resize(static_cast<std::size_t>(length(rng)));
    for (std::uint64_t& k : t) {
      k = key(rng);
    }
  }
  for (auto [clone, unique] :
       {std::pair{2u, 6u}, std::pair{3u, 0u}, std::pair{0u, 4u}}) {
    SharedHitRules hashed(clone, unique);
    SharedHitRules arrays(clone, unique, 300);
    int kept = 0;
    for (std::size_t i = 0; i < tracks.size(); ++i) {
      const Keys& t = tracks[i];
      // The first half of a track is its "matched" (fitted) hits.
      const std::span<const std::uint64_t> matched(t.data(), t.size() / 2 + 1);
      const auto index = static_cast<std::uint32_t>(i);
      const Verdict expected = hashed.judge(matched, t, index);
      ASSERT_EQ(arrays.judge(matched, t, index), expected)
          << "track " << i << ", rules " << clone << " / " << unique;
      kept += expected == Verdict::eKeep ? 1 : 0;
    }
    for (std::uint64_t k = 0; k < 300; ++k) {
      EXPECT_EQ(arrays.claimed(k), hashed.claimed(k)) << k;
    }
    // Not a trivial comparison: some tracks are kept, some refused.
    EXPECT_GT(kept, 0);
    EXPECT_LT(kept, static_cast<int>(tracks.size()));
  }
}

TEST(SharedHitRules, ArrayStorageRefusesAKeyBeyondItsBound) {
  SharedHitRules rules(2, 3, 10);
  const Keys inside{1, 2, 3};
  EXPECT_EQ(rules.judge(inside, inside, 0), Verdict::eKeep);
  const Keys beyond{4, 10};
  EXPECT_THROW(rules.judge(beyond, beyond, 1), std::out_of_range);
  EXPECT_FALSE(rules.claimed(10));
}

}  // namespace
}  // namespace conftrack

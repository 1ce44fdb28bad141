/// @file SharedHitResolutionTests.cpp
/// The finder's shared-hit resolution (detail/SharedHitResolution.hpp): of
/// tracks sharing hits, a short one with too few hits of its own and a
/// clone of a better track are dropped and their hits released; a track
/// that shares nothing stays however short; the result does not depend on
/// the order of the tracks. The tracks are hit lists in a FinderState
/// (the resolution reads only their hits, and their fits to rank them).

#include "conftrack/reconstruction/finding/FindingChain.hpp"
#include "conftrack/reconstruction/finding/detail/SharedHitResolution.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "SyntheticHits.hpp"

namespace conftrack {
namespace {

/// Three helices of eight hits (ids 1-8, 101-108, 201-208) in conformal
/// form, and tracks made of hit ids, all marked used as the finder leaves
/// them.
struct Fixture {
  Detector det = test::barrelDetector();
  FinderConfig cfg;
  std::vector<Hit> hits;
  ConformalHits conformal;
  std::unique_ptr<detail::FinderState> state;

  explicit Fixture(FinderConfig config = {}) : cfg(std::move(config)) {
    for (int k = 0; k < 3; ++k) {
      const std::vector<Hit> h = test::helixHits(
          det, 3000.0, 0.4 + 0.5 * k, 1, 0.3, 1 + 100 * std::uint64_t(k));
      hits.insert(hits.end(), h.begin(), h.end());
    }
    conformal = makeConformalHits(hits, det);
    state = std::make_unique<detail::FinderState>(conformal, det, cfg, 4.0);
  }
  ConfIndex index(std::uint64_t id) const {
    for (ConfIndex c = 0; c < conformal.size(); ++c) {
      if (conformal.id[c] == id) {
        return c;
      }
    }
    ADD_FAILURE() << "no hit " << id;
    return 0;
  }
  void add(const std::vector<std::uint64_t>& ids) {
    TrackCandidate t;
    for (std::uint64_t id : ids) {
      t.hits.push_back(index(id));
      state->used[index(id)] = 1;
    }
    state->tracks.push_back(t);
  }
  std::uint32_t resolve(std::uint32_t minUnique, bool trim = false) {
    return detail::SharedHitResolution({2, minUnique, trim}).run(*state);
  }
  bool used(std::uint64_t id) const { return state->used[index(id)] != 0; }
  std::vector<std::size_t> sizes() const {
    std::vector<std::size_t> out;
    for (const TrackCandidate& t : state->tracks) {
      out.push_back(t.hits.size());
    }
    std::sort(out.begin(), out.end());
    return out;
  }
};

TEST(SharedHitResolution, ShortTrackThroughARealOneIsDroppedAndItsHitsFreed) {
  // A short track holds a hit of the eight-hit track and three others: it
  // has 3 < 6 hits of its own.
  Fixture f;
  f.add({1, 2, 3, 4, 5, 6, 7, 8});
  f.add({3, 101, 102, 103});
  EXPECT_EQ(f.resolve(6), 1u);
  EXPECT_EQ(f.sizes(), (std::vector<std::size_t>{8}));
  EXPECT_TRUE(f.used(3));  // on the kept track
  EXPECT_FALSE(f.used(101));
  EXPECT_FALSE(f.used(103));
  // With a lower requirement it stays, and so do its hits.
  Fixture g;
  g.add({1, 2, 3, 4, 5, 6, 7, 8});
  g.add({3, 101, 102, 103});
  EXPECT_EQ(g.resolve(3), 0u);
  EXPECT_EQ(g.sizes(), (std::vector<std::size_t>{4, 8}));
  EXPECT_TRUE(g.used(101));
}

TEST(SharedHitResolution, TrackSharingNothingStaysHoweverShort) {
  Fixture f;
  f.add({1, 2, 3, 4, 5, 6, 7, 8});
  f.add({101, 102, 103});
  EXPECT_EQ(f.resolve(6), 0u);
  EXPECT_EQ(f.sizes(), (std::vector<std::size_t>{3, 8}));
  EXPECT_TRUE(f.used(102));
}

TEST(SharedHitResolution, CloneOfABetterTrackIsDropped) {
  // Two hits shared with one better track make a clone, whatever its own
  // hits (five here, against a requirement of one); one hit shared with
  // each of two tracks does not.
  Fixture f;
  f.add({1, 2, 3, 4, 5, 6, 7, 8});
  f.add({101, 102, 103, 104, 105, 106, 107, 108});
  f.add({1, 2, 201, 202, 203, 204, 205});
  EXPECT_EQ(f.resolve(1), 1u);
  EXPECT_EQ(f.sizes(), (std::vector<std::size_t>{8, 8}));
  EXPECT_TRUE(f.used(1));
  EXPECT_FALSE(f.used(201));
  Fixture g;
  g.add({1, 2, 3, 4, 5, 6, 7, 8});
  g.add({101, 102, 103, 104, 105, 106, 107, 108});
  g.add({1, 101, 201, 202, 203, 204, 205});
  EXPECT_EQ(g.resolve(1), 0u);
  EXPECT_EQ(g.sizes(), (std::vector<std::size_t>{7, 8, 8}));
}

TEST(SharedHitResolution, TrimmedTrackKeepsItsOwnHits) {
  // A track that took two hits of a better one (a clone by the rule) but
  // has five of its own keeps those, refitted, with trimSharedHits and a
  // requirement of five; one with four of its own is dropped all the same,
  // and without the option both are.
  for (bool trim : {false, true}) {
    Fixture f(test::oneBuildStep());
    f.add({1, 2, 3, 4, 5, 6, 7, 8});
    f.add({101, 102, 103, 104, 105, 7, 8});
    f.add({201, 202, 203, 204, 3, 4});
    EXPECT_EQ(f.resolve(5, trim), trim ? 1u : 2u);
    EXPECT_EQ(f.sizes(), trim ? (std::vector<std::size_t>{5, 8})
                              : (std::vector<std::size_t>{8}));
    EXPECT_TRUE(f.used(7));  // on the better track
    EXPECT_EQ(f.used(101), trim);
    EXPECT_FALSE(f.used(201));
    // No hit on two tracks; the trimmed track is refitted.
    std::vector<ConfIndex> all;
    for (const TrackCandidate& t : f.state->tracks) {
      if (t.hits.size() == 5) {
        EXPECT_TRUE(t.uv.valid);
        EXPECT_TRUE(t.sz.valid);
        EXPECT_GT(t.pt, 0.0);
      }
      all.insert(all.end(), t.hits.begin(), t.hits.end());
    }
    std::sort(all.begin(), all.end());
    EXPECT_EQ(std::adjacent_find(all.begin(), all.end()), all.end());
  }
}

TEST(SharedHitResolution, OrderOfTheTracksDoesNotMatter) {
  // The longer of two tracks sharing a hit is kept, whichever comes
  // first.
  for (bool longFirst : {true, false}) {
    Fixture f;
    if (longFirst) {
      f.add({1, 2, 3, 4, 5, 6, 7, 8});
      f.add({8, 101, 102, 103, 104});
    } else {
      f.add({8, 101, 102, 103, 104});
      f.add({1, 2, 3, 4, 5, 6, 7, 8});
    }
    EXPECT_EQ(f.resolve(6), 1u);
    EXPECT_EQ(f.sizes(), (std::vector<std::size_t>{8}));
    EXPECT_TRUE(f.used(8));
    EXPECT_FALSE(f.used(104));
  }
}

TEST(SharedHitResolution, ConfigIsValidated) {
  EXPECT_THROW(detail::SharedHitResolution({2, 0}), std::invalid_argument);
  const Detector det = test::barrelDetector();
  FinderConfig cfg = test::oneBuildStep();
  cfg.finalMinUniqueHits = 101;
  const auto p = findChainProblem(cfg, det);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->key, "finder.final_min_unique_hits");
  // Trimming needs the requirement it keeps to.
  cfg.finalMinUniqueHits = 0;
  cfg.finalTrimSharedHits = true;
  const auto q = findChainProblem(cfg, det);
  ASSERT_TRUE(q.has_value());
  EXPECT_EQ(q->key, "finder.final_trim_shared_hits");
  cfg.finalMinUniqueHits = 6;
  EXPECT_FALSE(findChainProblem(cfg, det).has_value());
}

}  // namespace
}  // namespace conftrack

// Helix-triplet building of displaced tracks (a conftrack addition; the
// paper and upstream have no such step).
//
// The conformal map is taken about the beam line: a track's circle maps to
// a line only if it passes through the origin, and to a circle of radius
// about 1 / (2 d0) otherwise. Particles produced tens of mm or more from the
// beam line (secondaries of the material, decays) have impact parameters
// comparable to the radii of the layers they cross, so their hits are far
// from any line or parabola in (u, v) and the cellular automaton cannot
// build them. This builder works in real space instead:
// - Seeds are triplets of unused hits on consecutive layers with a free
//   circle (detail::HelixSeeds, HelixSeeds.hpp).
// - The straightest triplets of a seed hit (at most maxSeedCells) are
//   followed outwards along the helix of the circle fitted to all their hits
//   and of z filtered along the arc length with each layer's scattering.
//   At the first predicted layer crossing with compatible hits, the one
//   with the lowest chi2, taken at the hit itself (sensors lie off the
//   layer's nominal surface), is added with its overlap partners; the chi2
//   has the hit resolution and the extrapolation error of the path's
//   hits and of the scattering in every layer it crossed
//   (HelixPredictionError). At most maxMissedLayers crossings well inside
//   a layer pass without a hit.
// - Of the candidates of one seed hit with at least minHits hits, the
//   longest (then lowest chi2 per hit) is kept, followed on with up to
//   continueMissedLayers crossings without a hit, and claims its hits at once;
//   seed hits are taken innermost first, so the result does not depend on
//   the input order. With firstPassMinHits, only candidates that long claim
//   at once; the shorter wait for a second pass over the seeds. With
//   inwardCollections, an accepted candidate is also followed back from
//   its first hit, against its motion, into those collections' hits.
// - Once the triplets of the step exceed its budget (cellsPerHitOf) per
//   pool hit, the remaining seed hits are skipped (counted): the triplets
//   of a seed grow with the square of the hit density.
// This file runs the seeds' paths and accepts; the following is
// detail::HelixFollower (HelixFollower.hpp) and the circle and (s, z) fits
// are in HelixPath.hpp.

#include "conftrack/core/Units.hpp"
#include "conftrack/geometry/Helix.hpp"
#include "conftrack/reconstruction/finding/detail/FinderState.hpp"
#include "conftrack/reconstruction/finding/detail/HelixFollower.hpp"
#include "conftrack/reconstruction/finding/detail/HelixPath.hpp"
#include "conftrack/reconstruction/finding/detail/HelixSeeds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace conftrack::detail {

namespace {

class HelixBuilder {
 public:
  /// `inwardPool`: the hits of the inward following (with
  /// FindingStep::inwardCollections), else null.
  HelixBuilder(FinderState& state, const FindingStep& step,
               std::uint16_t stepIndex, const HitPool& pool, StepStats& stats,
               const HitPool* inwardPool)
      : m_state(state),
        m_hits(state.hits),
        m_layers(state.detector.layers()),
        m_step(step),
        m_stepIndex(stepIndex),
        m_pool(pool),
        m_stats(stats),
        m_follower(state, step, pool),
        m_seeds(state, step, pool, m_follower),
        m_build{step.maxMissedLayers, step.chi2Cut},
        m_continue{std::max(step.maxMissedLayers, step.continueMissedLayers),
                   std::max(step.chi2Cut, step.continueChi2Cut)} {
    if (inwardPool != nullptr) {
      m_inward.emplace(state, step, *inwardPool);
    }
  }

  void run() {
    // The step's work budget (FinderConfig::cellsPerHitOf), in triplets:
    // their number per seed grows with the square of the hit density.
    const double budget = double(m_state.config.cellsPerHitOf(m_step)) *
                          double(m_pool.members().size());
    const std::vector<ConfIndex>& members = m_pool.members();
    // With first_pass_min_hits, the first pass accepts only candidates of
    // that many hits and keeps the shorter ones (those of minHits or more)
    // for the second.
    const bool twoPasses = m_step.firstPassMinHits > m_step.minHits;
    const std::uint32_t firstMin =
        twoPasses ? m_step.firstPassMinHits : m_step.minHits;
    std::vector<std::pair<std::size_t, HelixPath>> waiting;
    for (std::size_t k = 0; k < members.size(); ++k) {
      const ConfIndex seed = members[k];
      if (m_state.used[seed] != 0 || !seedAllowed(seed)) {
        continue;
      }
      if (double(m_stats.cells) > budget) {
        std::uint64_t skipped = 0;
        for (std::size_t j = k; j < members.size(); ++j) {
          skipped +=
              m_state.used[members[j]] == 0 && seedAllowed(members[j]) ? 1 : 0;
        }
        m_stats.guard(Guard::eCellsPerHit).add(skipped);
        break;
      }
      ++m_stats.seeds;
      HelixPath best;
      followSeed(seed, best);
      if (best.hits.size() >= firstMin) {
        acceptFollowedOn(best);
      } else if (best.hits.size() >= m_step.minHits) {
        waiting.emplace_back(k, std::move(best));
      }
    }
    // The second pass, innermost seeds first as before. A candidate whose
    // hits are all still free is taken as it is; otherwise its seed is
    // followed again, within the step's work budget (counted like the
    // first pass's skipped seeds). A seed without a candidate in the first
    // pass is not followed again: a hit claimed since could have misled
    // its follower, but following every remaining seed again gave the
    // same TrackML score at 1.6 times the triplets.
    for (auto& [k, best] : waiting) {
      const ConfIndex seed = members[k];
      if (m_state.used[seed] != 0) {
        continue;
      }
      const bool intact =
          std::none_of(best.hits.begin(), best.hits.end(),
                       [&](ConfIndex h) { return m_state.used[h] != 0; });
      if (!intact && double(m_stats.cells) > budget) {
        m_stats.guard(Guard::eCellsPerHit).add(1);
        continue;
      }
      if (!intact) {
        best = HelixPath{};
        followSeed(seed, best);
        if (best.hits.size() < m_step.minHits) {
          continue;
        }
      }
      acceptFollowedOn(best);
    }
  }

 private:
  bool seedAllowed(ConfIndex h) const {
    const auto& seeds = m_step.seedCollections;
    return seeds.empty() || std::find(seeds.begin(), seeds.end(),
                                      m_hits.subdetector[h]) != seeds.end();
  }

  void followSeed(ConfIndex h1, HelixPath& best) {
    m_seeds.triplets(h1, m_triplets, m_stats);
    // The straightest triplets first; at most maxSeedCells (the step's
    // setting) and maxTripletsPerSeed (the guard) are followed.
    const std::size_t guard = m_state.config.maxTripletsPerSeed;
    std::size_t followed = 0;
    for (std::size_t k = 0; k < m_triplets.size(); ++k) {
      if (m_step.maxSeedCells > 0 && followed >= m_step.maxSeedCells) {
        break;
      }
      HelixTriplet& tr = m_triplets[k];
      if (m_follower.skipsLayer(tr.path, tr.circle)) {
        continue;
      }
      if (followed >= guard) {
        // Checked after skipsLayer(): a seed whose remaining triplets it
        // would all refuse is not cut. The cut counts the triplets left
        // unexamined, not those skipsLayer() would have passed.
        m_stats.guard(Guard::eTriplets).add(m_triplets.size() - k);
        break;
      }
      ++followed;
      HelixPath& path = tr.path;
      m_follower.follow(path, m_build);
      m_follower.addSeedPartners(path);
      ++m_stats.paths;
      if (path.hits.size() >= m_step.minHits) {
        ++m_stats.candidates;
        if (better(path, best)) {
          best = std::move(path);
        }
      }
    }
  }

  static bool better(const HelixPath& a, const HelixPath& b) {
    if (a.hits.size() != b.hits.size()) {
      return a.hits.size() > b.hits.size();
    }
    const double qa = a.chi2 / static_cast<double>(a.hits.size());
    const double qb = b.chi2 / static_cast<double>(b.hits.size());
    if (qa != qb) {
      return qa < qb;
    }
    return a.hits < b.hits;
  }

  /// Follows an accepted candidate on past gaps (continue_missed_layers:
  /// it already is a track, and only its further hits are at stake) and
  /// accepts it.
  void acceptFollowedOn(HelixPath& best) {
    if (m_continue.maxMissedLayers > m_build.maxMissedLayers ||
        m_continue.chi2Cut > m_build.chi2Cut) {
      m_follower.follow(best, m_continue);
    }
    // Back towards the production point, into the inward collections
    // (FindingStep::inwardCollections).
    if (m_inward) {
      m_inward->followInward(best, m_continue);
      if (m_step.pastTurnMinHits > 0) {
        m_inward->followPastTurn(best, m_continue, m_step.pastTurnMinHits);
      }
    }
    accept(best);
  }

  void accept(const HelixPath& p) {
    TrackCandidate t;
    t.hits = p.hits;
    TransverseCircle c;
    const std::size_t n = p.hits.size();
    fitCircle(m_hits, p.hits, c);
    t.uv.valid = true;
    t.uv.centreX = c.cx;
    t.uv.centreY = c.cy;
    t.uv.radius = c.rho;
    t.uv.orientation = c.orientation;
    t.uv.chi2 = p.chi2;
    t.uv.ndf = static_cast<int>(n) - 3;
    t.sz.valid = true;
    t.sz.z0 = p.z0;
    t.sz.tanLambda = p.t;
    t.sz.lastS = p.s.back();
    t.pt = t.uv.pt(m_state.bzForPt);
    t.step = m_stepIndex;
    t.fitBackward = m_step.fitBackward;
    t.helix = true;
    const auto index = static_cast<std::uint32_t>(m_state.tracks.size());
    for (ConfIndex h : p.hits) {
      m_state.used[h] = 1;
      m_state.clones.addHit(h, index);
    }
    m_state.tracks.push_back(std::move(t));
    ++m_stats.accepted;
  }

  FinderState& m_state;
  const ConformalHits& m_hits;
  const std::vector<SensitiveLayer>& m_layers;
  const FindingStep& m_step;
  std::uint16_t m_stepIndex;
  const HitPool& m_pool;
  StepStats& m_stats;
  HelixFollower m_follower;
  HelixSeeds m_seeds;
  /// The follower over the inward pool (FindingStep::inwardCollections).
  std::optional<HelixFollower> m_inward;
  /// The follower's limits while building and when an accepted candidate
  /// is followed on (continue_missed_layers, continue_chi2_cut; 0: the
  /// building ones).
  HelixFollower::Limits m_build;
  HelixFollower::Limits m_continue;
  std::vector<HelixTriplet> m_triplets;
};

}  // namespace

void buildHelixTracks(FinderState& state, const FindingStep& step,
                      std::uint16_t stepIndex, const HitPool& pool,
                      StepStats& stats) {
  if (step.inwardCollections.empty()) {
    HelixBuilder(state, step, stepIndex, pool, stats, nullptr).run();
    return;
  }
  // The pool of the inward following: the step's hits and the unused hits
  // of its inward collections.
  std::vector<ConfIndex> members = pool.members();
  const ConformalHits& hits = state.hits;
  std::vector<std::uint8_t> inPool(hits.size(), 0);
  for (ConfIndex h : members) {
    inPool[h] = 1;
  }
  for (ConfIndex h = 0; h < hits.size(); ++h) {
    if (inPool[h] == 0 && state.used[h] == 0 &&
        std::find(step.inwardCollections.begin(), step.inwardCollections.end(),
                  hits.subdetector[h]) != step.inwardCollections.end()) {
      members.push_back(h);
    }
  }
  const HitPool inwardPool(hits, std::move(members));
  HelixBuilder(state, step, stepIndex, pool, stats, &inwardPool).run();
}

}  // namespace conftrack::detail

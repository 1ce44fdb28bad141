#include "conftrack/evaluation/TrackmlScore.hpp"

#include "conftrack/simulation/TrackmlEvents.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace conftrack {

std::vector<double> trackmlHitWeights(const Event& event, bool* computed) {
  std::vector<double> weights(event.truth.size());
  double total = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    weights[i] = event.truth[i].weight;
    total += weights[i];
  }
  if (total == 0.0) {
    weights = computeTrackmlWeights(event.truth, event.particles);
    if (computed != nullptr) {
      *computed = true;
    }
  }
  return weights;
}

TrackmlScore scoreTrackml(const Event& event,
                          std::span<const std::uint64_t> labels,
                          const TrackmlScoreConfig& config) {
  if (!event.hasTruth()) {
    throw std::invalid_argument("scoreTrackml: the event has no truth");
  }
  if (labels.size() != event.hits.size()) {
    throw std::invalid_argument(
        "scoreTrackml: " + std::to_string(labels.size()) + " labels for " +
        std::to_string(event.hits.size()) + " hits");
  }
  const std::size_t n = event.hits.size();
  TrackmlScore result;

  const std::vector<double> weights =
      trackmlHitWeights(event, &result.weightsComputed);
  result.totalWeight = std::accumulate(weights.begin(), weights.end(), 0.0);

  // True number of hits per particle (score.py: value_counts of the truth),
  // noise (particle 0) included as if it were a particle.
  std::unordered_map<std::uint64_t, std::uint32_t> particleHits;
  for (const HitTruth& t : event.truth) {
    ++particleHits[t.particleId];
  }

  // score.py sorts the hits by (track_id, particle_id) and walks the runs.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (labels[a] != labels[b]) {
      return labels[a] < labels[b];
    }
    return event.truth[a].particleId < event.truth[b].particleId;
  });

  double goodWeight = 0.0;
  std::unordered_set<std::uint64_t> reconstructed;
  for (std::size_t first = 0; first < n;) {
    const std::uint64_t label = labels[order[first]];
    std::size_t end = first;
    while (end < n && labels[order[end]] == label) {
      ++end;
    }
    const std::size_t trackHits = end - first;
    // Majority particle: most hits; on a tie the smaller id (the first run
    // in the sort order, as score.py's strict comparison keeps it).
    std::uint64_t majority = 0;
    std::size_t majorityHits = 0;
    double majorityWeight = 0.0;
    for (std::size_t run = first; run < end;) {
      const std::uint64_t particle = event.truth[order[run]].particleId;
      std::size_t runEnd = run;
      double runWeight = 0.0;
      while (runEnd < end &&
             event.truth[order[runEnd]].particleId == particle) {
        runWeight += weights[order[runEnd]];
        ++runEnd;
      }
      if (runEnd - run > majorityHits) {
        majority = particle;
        majorityHits = runEnd - run;
        majorityWeight = runWeight;
      }
      run = runEnd;
    }
    // Strict double majority: > 50 % of the track and > 50 % of the
    // particle.
    const bool good = 2 * majorityHits > trackHits &&
                      2 * majorityHits > particleHits[majority];
    ++result.nTracks;
    if (good) {
      ++result.nGoodTracks;
      goodWeight += majorityWeight;
    }
    if (label != 0) {
      if (good && majority != 0) {
        reconstructed.insert(majority);
      }
      if (trackHits >= config.minTrackHits) {
        ++result.nSelectedTracks;
        if (!good || majority == 0) {
          ++result.nFakeTracks;
        }
      }
    }
    first = end;
  }
  result.score =
      result.totalWeight > 0.0 ? goodWeight / result.totalWeight : 0.0;

  for (const auto& [particle, hits] : particleHits) {
    if (particle == 0 || hits < config.minParticleHits) {
      continue;
    }
    if (config.minPt > 0.0) {
      ParticleIndex p = event.findParticle(particle);
      if (p == kInvalidIndex || event.particles[p].pt() < config.minPt) {
        continue;
      }
    }
    ++result.nReconstructable;
    if (reconstructed.contains(particle)) {
      ++result.nReconstructed;
    }
  }
  if (result.nReconstructable > 0) {
    result.efficiency = static_cast<double>(result.nReconstructed) /
                        static_cast<double>(result.nReconstructable);
  }
  if (result.nSelectedTracks > 0) {
    result.fakeRate = static_cast<double>(result.nFakeTracks) /
                      static_cast<double>(result.nSelectedTracks);
  }
  return result;
}

TrackmlScore scoreTrackml(const Event& event,
                          std::span<const std::vector<HitIndex>> tracks,
                          const TrackmlScoreConfig& config) {
  std::vector<std::uint64_t> labels = trackmlLabels(event.hits.size(), tracks);
  return scoreTrackml(event, std::span<const std::uint64_t>(labels), config);
}

}  // namespace conftrack

#include "conftrack/evaluation/TrackmlDiagnostics.hpp"

#include "conftrack/evaluation/TrackmlScore.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace conftrack {

double WeightBreakdown::total() const { return found + lost(); }

double WeightBreakdown::lost() const {
  return leftOffSameLayer + leftOffNewLayer + otherTracks + neverFound + split +
         partial + impure + noise;
}

void WeightBreakdown::add(const WeightBreakdown& other, double scale) {
  found += scale * other.found;
  leftOffSameLayer += scale * other.leftOffSameLayer;
  leftOffNewLayer += scale * other.leftOffNewLayer;
  otherTracks += scale * other.otherTracks;
  neverFound += scale * other.neverFound;
  split += scale * other.split;
  partial += scale * other.partial;
  impure += scale * other.impure;
  noise += scale * other.noise;
}

void LostHitPlaces::add(const LostHitPlaces& other, double scale) {
  leftOffBefore += scale * other.leftOffBefore;
  leftOffBetween += scale * other.leftOffBetween;
  leftOffAfter += scale * other.leftOffAfter;
  otherAtHolderEnd += scale * other.otherAtHolderEnd;
  otherInsideHolder += scale * other.otherInsideHolder;
}

namespace {

DiagnosticsHistogram emptyHistogram(std::string quantity,
                                    const std::vector<double>& edges) {
  if (edges.size() < 2 || !std::is_sorted(edges.begin(), edges.end()) ||
      std::adjacent_find(edges.begin(), edges.end()) != edges.end() ||
      std::isnan(edges.front())) {
    throw std::invalid_argument("diagnoseTrackml: the " + quantity +
                                " bin edges are not ascending");
  }
  DiagnosticsHistogram h;
  h.quantity = std::move(quantity);
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    h.bins.push_back({edges[i], edges[i + 1], 0.0, {}});
  }
  return h;
}

/// Adds one particle's breakdown to the bin holding `value` (outside if
/// none or unknown).
void fill(DiagnosticsHistogram& h, bool known, double value,
          const WeightBreakdown& weight) {
  if (known) {
    for (DiagnosticsBin& b : h.bins) {
      if (value >= b.min && value < b.max) {
        b.particles += 1.0;
        b.weight.add(weight);
        return;
      }
    }
  }
  h.outside.add(weight);
}

/// The layer of a hit as one number: (subdetector, side, layer).
std::uint64_t layerKey(const DetectorId& id) {
  return (static_cast<std::uint64_t>(id.subdetector) << 32) |
         (static_cast<std::uint64_t>(static_cast<std::uint8_t>(id.side))
          << 16) |
         id.layer;
}

}  // namespace

TrackmlDiagnostics diagnoseTrackml(const Event& event,
                                   std::span<const std::uint64_t> labels,
                                   const TrackmlDiagnosticsConfig& config) {
  if (!event.hasTruth()) {
    throw std::invalid_argument("diagnoseTrackml: the event has no truth");
  }
  if (labels.size() != event.hits.size()) {
    throw std::invalid_argument(
        "diagnoseTrackml: " + std::to_string(labels.size()) + " labels for " +
        std::to_string(event.hits.size()) + " hits");
  }
  TrackmlDiagnostics result;
  result.pt = emptyHistogram("pt", config.ptEdges);
  result.absEta = emptyHistogram("abs_eta", config.absEtaEdges);
  result.radius = emptyHistogram("production_radius", config.radiusEdges);

  const std::vector<double> weights =
      trackmlHitWeights(event, &result.weightsComputed);
  result.totalWeight = std::accumulate(weights.begin(), weights.end(), 0.0);
  // Fractions of the total; an event without weight has none to lose.
  const double norm = result.totalWeight > 0.0 ? 1.0 / result.totalWeight : 0.0;

  // Hits per track (label 0 included, as in the score) and per particle.
  std::unordered_map<std::uint64_t, std::size_t> trackHits;
  std::unordered_map<std::uint64_t, double> trackWeight;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> particleHits;
  // Per track, the nearest and furthest of its hits from the origin: its
  // ends (LostHitPlaces).
  std::unordered_map<std::uint64_t, std::pair<double, double>> trackEnds;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    ++trackHits[labels[i]];
    trackWeight[labels[i]] += weights[i];
    particleHits[event.truth[i].particleId].push_back(i);
    const double r = event.hits[i].position.norm();
    auto [it, inserted] = trackEnds.try_emplace(labels[i], r, r);
    if (!inserted) {
      it->second.first = std::min(it->second.first, r);
      it->second.second = std::max(it->second.second, r);
    }
  }
  // Particles in id order: sums in a fixed order, the same on every run.
  std::vector<std::uint64_t> particles;
  particles.reserve(particleHits.size());
  for (const auto& entry : particleHits) {
    particles.push_back(entry.first);
  }
  std::sort(particles.begin(), particles.end());

  std::unordered_set<std::uint64_t> pureTracks;
  double hitFractionSum = 0.0;
  for (std::uint64_t particle : particles) {
    const std::vector<std::size_t>& hits = particleHits[particle];
    const std::size_t n = hits.size();
    // The particle's hits per track, in label order.
    std::vector<std::pair<std::uint64_t, std::size_t>> perTrack;
    for (std::size_t i : hits) {
      perTrack.emplace_back(labels[i], 0);
    }
    std::sort(perTrack.begin(), perTrack.end());
    perTrack.erase(std::unique(perTrack.begin(), perTrack.end()),
                   perTrack.end());
    for (std::size_t i : hits) {
      auto it = std::lower_bound(perTrack.begin(), perTrack.end(),
                                 std::make_pair(labels[i], std::size_t{0}));
      ++it->second;
    }
    // The score's double majority; at most one track has > 50 % of the
    // particle.
    bool matched = false;
    std::uint64_t track = 0;
    std::size_t onTrack = 0;
    std::size_t largest = 0;
    std::size_t pieces = 0;
    for (const auto& [label, count] : perTrack) {
      const std::size_t size = trackHits[label];
      if (particle != 0 && label != 0 && 2 * count > size) {
        pureTracks.insert(label);
      }
      if (2 * count > n && 2 * count > size) {
        matched = true;
        track = label;
        onTrack = count;
      }
      if (label != 0) {
        largest = std::max(largest, count);
        if (count > config.maxStrayHits) {
          ++pieces;
        }
      }
    }

    // Binned by the particle's production kinematics (below); its vertex
    // also orders its hits.
    const ParticleIndex p =
        particle == 0 ? kInvalidIndex : event.findParticle(particle);
    const bool known = p != kInvalidIndex;

    WeightBreakdown w;
    double particleWeight = 0.0;
    if (matched) {
      std::unordered_set<std::uint64_t> trackLayers;
      for (std::size_t i : hits) {
        if (labels[i] == track) {
          trackLayers.insert(layerKey(event.hits[i].detId));
        }
      }
      // Each hit's place along the particle (LostHitPlaces), and the span
      // of those on its matched track.
      bool timed = false;
      for (std::size_t i : hits) {
        timed = timed || event.truth[i].time != event.truth[hits[0]].time;
      }
      const Vector3 origin =
          known ? event.particles[p].vertex : Vector3::Zero();
      auto place = [&](std::size_t i) {
        return timed ? event.truth[i].time
                     : (event.truth[i].position - origin).norm();
      };
      double first = std::numeric_limits<double>::infinity();
      double last = -std::numeric_limits<double>::infinity();
      for (std::size_t i : hits) {
        if (labels[i] == track) {
          first = std::min(first, place(i));
          last = std::max(last, place(i));
        }
      }
      for (std::size_t i : hits) {
        const double wi = weights[i] * norm;
        particleWeight += weights[i];
        if (labels[i] == track) {
          w.found += wi;
          continue;
        }
        if (particle == 0) {
          w.noise += wi;
          continue;
        }
        if (labels[i] != 0) {
          w.otherTracks += wi;
          const auto& [nearest, furthest] = trackEnds[labels[i]];
          const double r = event.hits[i].position.norm();
          (r == nearest || r == furthest ? result.places.otherAtHolderEnd
                                         : result.places.otherInsideHolder) +=
              wi;
          continue;
        }
        if (trackLayers.contains(layerKey(event.hits[i].detId))) {
          w.leftOffSameLayer += wi;
        } else {
          w.leftOffNewLayer += wi;
        }
        const double at = place(i);
        (at < first  ? result.places.leftOffBefore
         : at > last ? result.places.leftOffAfter
                     : result.places.leftOffBetween) += wi;
      }
    } else {
      for (std::size_t i : hits) {
        particleWeight += weights[i];
      }
      const double wp = particleWeight * norm;
      if (particle == 0) {
        w.noise = wp;
      } else if (2 * largest > n) {
        w.impure = wp;
      } else if (largest <= config.maxStrayHits) {
        w.neverFound = wp;
      } else if (pieces >= 2) {
        w.split = wp;
      } else {
        w.partial = wp;
      }
    }
    result.weight.add(w);

    if (matched && particle != 0 && track != 0 && particleWeight > 0.0) {
      result.foundParticles += 1.0;
      hitFractionSum += static_cast<double>(onTrack) / static_cast<double>(n);
      result.foreignHitsOnMatched +=
          static_cast<double>(trackHits[track] - onTrack);
      result.foreignWeightOnMatched +=
          std::max(0.0, trackWeight[track] * norm - w.found);
    }

    double pt = 0.0;
    double absEta = 0.0;
    double radius = 0.0;
    if (known) {
      const Particle& q = event.particles[p];
      pt = q.pt();
      absEta = std::asinh(std::abs(q.momentum.z()) / pt);
      radius = q.vertex.head<2>().norm();
    }
    if (particleWeight > 0.0) {
      fill(result.pt, known, pt, w);
      fill(result.absEta, known, absEta, w);
      fill(result.radius, known, radius, w);
    }
  }
  for (const auto& [label, size] : trackHits) {
    if (label != 0) {
      result.tracks += 1.0;
      if (!pureTracks.contains(label)) {
        result.fakeTracks += 1.0;
      }
    }
  }
  if (result.tracks > 0.0) {
    result.fakeFraction = result.fakeTracks / result.tracks;
  }
  if (result.foundParticles > 0.0) {
    result.meanFoundHitFraction = hitFractionSum / result.foundParticles;
  }
  return result;
}

namespace {

/// Adds `scale` times the bins of `from` to those of `to`.
void addHistogram(DiagnosticsHistogram& to, const DiagnosticsHistogram& from,
                  double scale) {
  if (to.bins.size() != from.bins.size()) {
    throw std::invalid_argument(
        "averageDiagnostics: the events have different " + to.quantity +
        " bins");
  }
  for (std::size_t b = 0; b < to.bins.size(); ++b) {
    if (to.bins[b].min != from.bins[b].min ||
        to.bins[b].max != from.bins[b].max) {
      throw std::invalid_argument(
          "averageDiagnostics: the events have different " + to.quantity +
          " bins");
    }
    to.bins[b].particles += scale * from.bins[b].particles;
    to.bins[b].weight.add(from.bins[b].weight, scale);
  }
  to.outside.add(from.outside, scale);
}

/// `h` with the same bins, all counts 0.
DiagnosticsHistogram zeroed(DiagnosticsHistogram h) {
  for (DiagnosticsBin& b : h.bins) {
    b.particles = 0.0;
    b.weight = {};
  }
  h.outside = {};
  return h;
}

}  // namespace

TrackmlDiagnostics averageDiagnostics(
    std::span<const TrackmlDiagnostics> events) {
  TrackmlDiagnostics mean;
  if (events.empty()) {
    return mean;
  }
  mean.pt = zeroed(events.front().pt);
  mean.absEta = zeroed(events.front().absEta);
  mean.radius = zeroed(events.front().radius);
  const double scale = 1.0 / static_cast<double>(events.size());
  for (const TrackmlDiagnostics& e : events) {
    mean.totalWeight += scale * e.totalWeight;
    mean.weightsComputed = mean.weightsComputed || e.weightsComputed;
    mean.weight.add(e.weight, scale);
    mean.places.add(e.places, scale);
    addHistogram(mean.pt, e.pt, scale);
    addHistogram(mean.absEta, e.absEta, scale);
    addHistogram(mean.radius, e.radius, scale);
    mean.tracks += scale * e.tracks;
    mean.fakeTracks += scale * e.fakeTracks;
    mean.fakeFraction += scale * e.fakeFraction;
    mean.foundParticles += scale * e.foundParticles;
    mean.meanFoundHitFraction += scale * e.meanFoundHitFraction;
    mean.foreignHitsOnMatched += scale * e.foreignHitsOnMatched;
    mean.foreignWeightOnMatched += scale * e.foreignWeightOnMatched;
  }
  return mean;
}

}  // namespace conftrack

#include "conftrack/evaluation/TruthMatching.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace conftrack {

namespace {
double pseudorapidity(const Vector3& p) {
  double pt = p.head<2>().norm();
  return std::asinh(p.z() / std::max(pt, 1e-12));
}
}  // namespace

EventMatching matchTracks(const Event& event,
                          std::span<const std::vector<HitIndex>> tracks,
                          const ParticleSelection& selection,
                          const MatchingConfig& matching) {
  EventMatching out;
  const std::size_t nParticles = event.particles.size();
  out.particles.resize(nParticles);
  // Hit -> particle index.
  std::vector<ParticleIndex> hitParticle(event.hits.size(), kInvalidIndex);
  std::vector<std::vector<std::uint64_t>> layers(nParticles);
  for (std::size_t h = 0; h < event.hits.size() && h < event.truth.size();
       ++h) {
    ParticleIndex p = event.findParticle(event.truth[h].particleId);
    hitParticle[h] = p;
    if (p == kInvalidIndex) {
      continue;
    }
    ++out.particles[p].nHits;
    const DetectorId& id = event.hits[h].detId;
    layers[p].push_back(
        (static_cast<std::uint64_t>(id.subdetector) << 32) |
        (static_cast<std::uint64_t>(static_cast<std::uint8_t>(id.side)) << 16) |
        id.layer);
  }
  // Charged stable particles above the pT cut, for the proximity.
  std::vector<ParticleIndex> visible;
  for (ParticleIndex p = 0; p < nParticles; ++p) {
    const Particle& part = event.particles[p];
    if (part.isStable() && part.charge != 0.0 && part.pt() >= selection.minPt) {
      visible.push_back(p);
    }
  }
  for (ParticleIndex p = 0; p < nParticles; ++p) {
    auto& l = layers[p];
    std::sort(l.begin(), l.end());
    out.particles[p].nLayers =
        static_cast<std::uint32_t>(std::unique(l.begin(), l.end()) - l.begin());
    const Particle& part = event.particles[p];
    double pt = part.pt();
    double p3 = part.momentum.norm();
    double cosTheta = p3 > 0.0 ? part.momentum.z() / p3 : 1.0;
    out.particles[p].reconstructable =
        part.isStable() && part.charge != 0.0 && pt >= selection.minPt &&
        std::abs(cosTheta) < selection.maxAbsCosTheta &&
        out.particles[p].nLayers >= selection.minLayers;
    double best = std::numeric_limits<double>::infinity();
    if (out.particles[p].reconstructable) {
      double eta = pseudorapidity(part.momentum);
      double phi = std::atan2(part.momentum.y(), part.momentum.x());
      for (ParticleIndex q : visible) {
        if (q == p) {
          continue;
        }
        const Vector3& m = event.particles[q].momentum;
        double dphi = std::abs(phi - std::atan2(m.y(), m.x()));
        if (dphi > std::numbers::pi) {
          dphi = 2.0 * std::numbers::pi - dphi;
        }
        best = std::min(best, std::hypot(eta - pseudorapidity(m), dphi));
      }
    }
    out.particles[p].proximity = best;
  }

  out.tracks.reserve(tracks.size());
  std::vector<std::pair<ParticleIndex, std::uint32_t>> counts;
  for (const std::vector<HitIndex>& track : tracks) {
    counts.clear();
    for (HitIndex h : track) {
      ParticleIndex p = hitParticle[h];
      auto it = std::find_if(counts.begin(), counts.end(),
                             [p](const auto& c) { return c.first == p; });
      if (it == counts.end()) {
        counts.emplace_back(p, 1);
      } else {
        ++it->second;
      }
    }
    TrackMatch m;
    m.nHits = static_cast<std::uint32_t>(track.size());
    // Majority particle; ties go to the smaller particle index.
    for (const auto& [p, n] : counts) {
      if (n > m.nMajority || (n == m.nMajority && p < m.particle)) {
        m.particle = p;
        m.nMajority = n;
      }
    }
    m.purity = m.nHits > 0 ? double(m.nMajority) / m.nHits : 0.0;
    m.matched = m.particle != kInvalidIndex && m.purity >= matching.purity;
    if (m.matched && matching.doubleMatching) {
      std::uint32_t total = out.particles[m.particle].nHits;
      m.matched = total > 0 && double(m.nMajority) / total >= matching.purity;
    }
    if (m.matched) {
      ++out.particles[m.particle].nMatchedTracks;
    }
    out.tracks.push_back(m);
  }
  return out;
}

}  // namespace conftrack

#include "conftrack/reconstruction/finding/detail/FinderState.hpp"

#include "conftrack/geometry/MaterialInteractions.hpp"

#include <algorithm>
#include <cmath>

namespace conftrack::detail {

double layerTheta0(const SensitiveLayer& layer, double p, double tanLambda) {
  if (!(p > 0.0) || !(layer.thicknessX0 > 0.0)) {
    return 0.0;
  }
  const double secL = std::hypot(1.0, tanLambda);
  const double path =
      layer.isDisk() ? secL / std::max(std::abs(tanLambda), 0.1) : secL;
  return highlandTheta0(p, 1.0, 1.0, layer.thicknessX0 * std::min(path, 10.0));
}

namespace {
/// The order of betterCandidate on (number of hits, quality) of a and b,
/// the hit lists breaking ties.
bool betterOn(std::size_t hitsA, double qualityA, std::size_t hitsB,
              double qualityB, const TrackCandidate& a,
              const TrackCandidate& b) {
  if (hitsA != hitsB) {
    return hitsA > hitsB;
  }
  if (qualityA != qualityB) {
    return qualityA < qualityB;
  }
  return a.hits < b.hits;
}
}  // namespace

bool betterCandidate(const TrackCandidate& a, const TrackCandidate& b) {
  return betterOn(a.hits.size(), a.quality(), b.hits.size(), b.quality(), a, b);
}

bool betterThanBuilt(const TrackCandidate& a, const TrackCandidate& b) {
  return betterOn(a.hits.size(), a.quality(), b.builtHits, b.builtQuality, a,
                  b);
}

bool CloneIndex::offer(std::vector<TrackCandidate>& tracks,
                       TrackCandidate candidate, std::uint32_t minShared) {
  // Count shared hits per alive track (candidates have few hits: a small
  // linear map beats a hash map).
  // Tracks killed as clones are dropped from the lists on the way: within
  // a build step every candidate replaces the clones of its hits, and dead
  // entries would otherwise pile up on the hits of dense regions, making
  // each offer cost as much as all earlier ones together.
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& shared = m_shared;
  shared.clear();
  for (ConfIndex h : candidate.hits) {
    std::erase_if(m_hitTracks[h],
                  [&](std::uint32_t t) { return !tracks[t].alive; });
    for (std::uint32_t t : m_hitTracks[h]) {
      auto it = std::find_if(shared.begin(), shared.end(),
                             [t](const auto& p) { return p.first == t; });
      if (it == shared.end()) {
        shared.emplace_back(t, 1);
      } else {
        ++it->second;
      }
    }
  }
  m_killed.clear();
  for (const auto& [t, n] : shared) {
    if (n >= minShared) {
      const TrackCandidate& other = tracks[t];
      // builtHits is set only on the tracks of the build step now running.
      const bool better = other.builtHits > 0
                              ? betterThanBuilt(candidate, other)
                              : betterCandidate(candidate, other);
      if (!better) {
        m_killed.clear();
        return false;
      }
      m_killed.push_back(t);
    }
  }
  for (std::uint32_t t : m_killed) {
    tracks[t].alive = false;
  }
  m_dead += m_killed.size();
  auto index = static_cast<std::uint32_t>(tracks.size());
  for (ConfIndex h : candidate.hits) {
    m_hitTracks[h].push_back(index);
  }
  tracks.push_back(std::move(candidate));
  return true;
}

bool CloneIndex::held(ConfIndex h,
                      const std::vector<TrackCandidate>& tracks) const {
  return std::any_of(m_hitTracks[h].begin(), m_hitTracks[h].end(),
                     [&](std::uint32_t t) { return tracks[t].alive; });
}

void CloneIndex::rebuild(const std::vector<TrackCandidate>& tracks) {
  m_dead = 0;
  for (auto& v : m_hitTracks) {
    v.clear();
  }
  for (std::uint32_t t = 0; t < tracks.size(); ++t) {
    for (ConfIndex h : tracks[t].hits) {
      m_hitTracks[h].push_back(t);
    }
  }
}

void FinderState::compact() {
  std::erase_if(tracks, [](const TrackCandidate& t) { return !t.alive; });
  clones.rebuild(tracks);
}

bool fitCandidate(const FinderState& state, const FindingStep& step,
                  std::vector<ConfIndex> hits, TrackCandidate& out) {
  out.hits = std::move(hits);
  out.uv = fitConformal(state.hits, out.hits, !step.straightLineFit);
  if (!out.uv.valid) {
    return false;
  }
  out.pt = out.uv.pt(state.bzForPt);
  const double cut = step.chi2CutAt(out.pt);
  // Most paths fail; the (u, v) cut first spares their s-z fit.
  if (!step.onlySzChi2Cut && out.uv.chi2PerNdf() > cut) {
    return false;
  }
  out.sz = fitSz(state.hits, out.hits,
                 makeArcFrame(out.uv, state.hits, out.hits.front()));
  return out.sz.valid && out.sz.chi2PerNdf() <= cut;
}

}  // namespace conftrack::detail
